"""Every purchased item in the BOM is a catalogue entry; dowels from the ISO 8734 series."""

import re

import pytest
from cad_fixtures import assembly

from springcad.design.catalogue import dowel_lengths, rim_dowel_length
from springcad.errors import DesignError
from springcad.export.bom import bom_rows


def test_dowel_length_by_hand():
    """Two 4.5 mm rims and a 0.5 mm spacer: 9.5 mm of room; Ø1.5 lengths 4-16: 8 is the
    longest that fits (recessed 0.75 each side, 3.75 mm in each rim >= 1.5)."""
    assert dowel_lengths()[1.5] == (4, 5, 6, 8, 10, 12, 14, 16)
    assert rim_dowel_length(1.5, 4.5, 0.5, 4.5) == 8
    assert rim_dowel_length(1.5, 5.0, 0.5, 5.0) == 10
    with pytest.raises(DesignError, match="not an ISO 8734 diameter"):
        rim_dowel_length(1.7, 5.0, 0.5, 5.0)
    with pytest.raises(DesignError, match="no ISO 8734 length"):
        rim_dowel_length(1.5, 1.0, 0.5, 1.0)


def _catalogue_match(standard: str) -> bool:
    """The designation names a size its standard's catalogue lists."""
    from bd_warehouse.fastener import HexNut, SocketHeadCapScrew

    if m := re.fullmatch(r"ISO 8734 - ([\d.]+) m6 x ([\d.]+)", standard):
        d, length = float(m[1]), float(m[2])
        return length in dowel_lengths().get(d, ())
    if m := re.fullmatch(r"ISO 4762 - (M[\d.]+) x ([\d.]+)", standard):
        size = next((s for s in SocketHeadCapScrew.sizes("iso4762")
                     if s.startswith(m[1] + "-")), None)
        return size is not None and float(m[2]) in SocketHeadCapScrew(
            size, 10, "iso4762", simple=True).nominal_lengths
    if m := re.fullmatch(r"ISO 4032 - (M[\d.]+)", standard):
        return any(s.startswith(m[1] + "-") for s in HexNut.sizes("iso4032"))
    return False


@pytest.mark.parametrize("stack", ["4xS1", "default", "2xS1"])
def test_every_purchased_item_is_in_its_catalogue(stack):
    a = assembly(stack)
    bought = [r for r in bom_rows(a) if r["make_or_buy"] == "buy"]
    assert bought
    for r in bought:
        assert _catalogue_match(r["standard"]), r["standard"]
    assert not _catalogue_match("ISO 8734 - 1.5 m6 x 10.5")  # the issue-26 item
    # dowels sit inside the two rims they join (recessed, never proud)
    for inst in a.instances:
        if inst.part.info.standard.startswith("ISO 8734"):
            rims = [i for i in a.instances if i.component.kind == "flexure_ring"
                    and i.z_range_mm[0] - 1e-9 <= inst.z_range_mm[0] <= i.z_range_mm[1]]
            assert rims, inst.name
            lo, hi = inst.z_range_mm
            ends = [i.z_range_mm for i in a.instances if i.component.kind == "flexure_ring"
                    and min(hi, i.z_range_mm[1]) - max(lo, i.z_range_mm[0]) > 1e-6]
            assert len(ends) == 2, inst.name
            assert min(e[0] for e in ends) <= lo + 1e-9 and hi <= max(e[1] for e in ends) + 1e-9
