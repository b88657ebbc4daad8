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


def test_a_dowel_with_no_length_names_the_nearest_diameters_that_fit():
    """Two 3 mm rims and a 2 mm spacer: 8 mm of room. Ø3 (lengths from 8, at most
    8.3 long) does not fit and engage 3 mm; nor does Ø2.5 (x 6 recessed 1 mm leaves 2 mm
    in each rim < 2.5; x 8 is 8.3 long); Ø2 x 6 does (6.3 <= 8, 2 mm in each rim >= 2)
    and so does Ø1.5 x 6 (1.5 mm in each rim): the refusal names Ø2 first, and that
    diameter gives the length it names."""
    with pytest.raises(DesignError, match="no ISO 8734 length") as err:
        rim_dowel_length(3.0, 3.0, 2.0, 3.0)
    msg = str(err.value)
    first = re.search(r"use hardware\.fastener_diameter_mm = ([\d.]+) \(now 3; ISO 8734 "
                      r"[\d.]+ x ([\d.]+)\)", msg)
    assert first and float(first.group(1)) == 2.0, msg
    assert rim_dowel_length(2.0, 3.0, 2.0, 3.0) == float(first.group(2)) == 6
    assert "or hardware.fastener_diameter_mm = 1.5 (now 3; ISO 8734 1.5 x 6)" in msg, msg
    assert [c for c, _ in err.value.remedies] == [{"hardware.fastener_diameter_mm": 2.0},
                                                  {"hardware.fastener_diameter_mm": 1.5}]


#: ISO 8734:1997 Table 1, written here in the standard's own form and not copied from
#: springcad's table: each diameter's length range (l min, l max), the lengths being
#: the standard's preferred length series within it
ISO8734_RANGES = {1: (3, 10), 1.5: (4, 16), 2: (5, 20), 2.5: (6, 24), 3: (8, 30), 4: (10, 40),
                  5: (12, 50), 6: (14, 60), 8: (18, 80), 10: (22, 100), 12: (26, 100),
                  16: (40, 100), 20: (50, 100)}
ISO8734_SERIES = (3, 4, 5, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30, 32, 35, 40, 45, 50,
                  55, 60, 65, 70, 75, 80, 85, 90, 95, 100)


def _iso8734_lengths(d: float) -> tuple:
    lo, hi = ISO8734_RANGES.get(d, (1, 0))
    return tuple(x for x in ISO8734_SERIES if lo <= x <= hi)


def test_dowel_table_is_iso8734():
    """springcad's dowel table (springcad/data/iso8734_dowels.csv) is the standard's
    ranges and series, diameter by diameter."""
    table = dowel_lengths()
    assert set(table) == set(ISO8734_RANGES)
    for d, lengths in table.items():
        assert tuple(lengths) == _iso8734_lengths(d), d


def _catalogue_match(standard: str) -> bool:
    """The designation names a size its standard's catalogue lists (dowels: the ISO 8734
    table above; screws and nuts: bd_warehouse's ISO 4762 / ISO 4032 tables)."""
    from bd_warehouse.fastener import HexNut, SocketHeadCapScrew

    if m := re.fullmatch(r"ISO 8734 - ([\d.]+) x ([\d.]+) - (A - St|C1)", standard):
        d, length = float(m[1]), float(m[2])
        return length in _iso8734_lengths(d)
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
    # stainless rings (AISI 420) take ISO 8734 type C1 (martensitic stainless) pins
    ring = next(r for r in bom_rows(a) if r["kind"] == "flexure_ring")
    if "stainless" in ring["material"]:
        assert all(r["standard"].endswith("- C1") for r in bought
                   if r["standard"].startswith("ISO 8734")), bought
    assert not _catalogue_match("ISO 8734 - 1.5 x 10.5 - A - St")  # the issue-26 item
    assert not _catalogue_match("ISO 8734 - 1.5 m6 x 16")  # no type and material
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


def _pins_fit(hole_mm, pin_mm, zone_mm, rng, n_pins=7, trials=4000):
    """Monte Carlo of two rims' hole patterns, each hole anywhere in a Ø``zone_mm``
    pattern zone, holes at their smallest size and pins at their largest: the share of
    stacks in which some pin has no place that is inside both of its holes (a pin fits
    two holes when it fits their lens; for circles of radius R - r about centres
    ``a``, ``b`` that is |a - b| <= (R_a - r) + (R_b - r))."""
    import numpy as np

    jams = 0
    for _ in range(trials):
        ang = rng.uniform(0, 2 * np.pi, (2, n_pins))
        rad = 0.5 * zone_mm * np.sqrt(rng.uniform(0, 1, (2, n_pins)))
        off = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=-1)  # (rim, pin, xy)
        gap = np.linalg.norm(off[0] - off[1], axis=-1)
        jams += bool((gap > (hole_mm - pin_mm)).any())
    return jams / trials


def test_rim_pins_slip_and_cannot_jam():
    """Seven m6 dowels through two rims: with E7 holes (the springcad scheme) no pattern
    within its Ø0.006 zone jams a pin; with the H7 holes of the issue (press / transition
    fit) many do."""
    import numpy as np

    from springcad.design.catalogue import e7_deviation_mm, m6_deviation_mm, rim_pin_fit
    from springcad.design.processes import process

    zone = process("wire_edm").pattern_zone
    assert zone == pytest.approx(0.006)
    fit = rim_pin_fit(1.5, zone)
    assert fit.cannot_jam and fit.clearance_min_mm == pytest.approx(0.006)
    rng = np.random.default_rng(5)
    pin = 1.5 + m6_deviation_mm(1.5)[1]
    e7 = 1.5 + e7_deviation_mm(1.5)[0]
    assert _pins_fit(e7, pin, zone, rng) == 0.0
    assert _pins_fit(1.5, pin, zone, rng) == 1.0  # H7 at its smallest: every pin jams
    assert _pins_fit(1.5 + 0.010, pin, zone, rng) > 0.1  # H7 at its largest: often
    # every ISO 286 size range springcad tabulates keeps the rule
    for d in (1.0, 2.5, 4.0, 8.0, 12.0):
        assert rim_pin_fit(d, zone).cannot_jam, d


#: ISO 286-1 / -2 written in the standard's own form, not springcad's table: the fundamental
#: deviation es of shafts g and the grade IT6 by nominal size range (um); g6 = (es - IT6, es)
ISO286_G_ES_UM = {3: -2, 6: -4, 10: -5, 18: -6, 30: -7, 50: -9, 80: -10, 120: -12, 180: -14,
                  250: -15, 315: -17, 400: -18, 500: -20}
ISO286_IT6_UM = {3: 6, 6: 8, 10: 9, 18: 11, 30: 13, 50: 16, 80: 19, 120: 22, 180: 25, 250: 29,
                 315: 32, 400: 36, 500: 40}


def test_iso286_values_follow_the_standards_formulas():
    """The values above against ISO 286-1's formulas, per range of geometric mean D (mm): the
    tolerance unit i = 0.45 D^(1/3) + 0.001 D (um), IT6 = 10 i, and the g shafts' fundamental
    deviation es = -2.5 D^0.34 (um), within the standard's rounding (es to 1 um; IT to its
    series of preferred values, 38.9 -> 40 at 400-500 mm). The first range (up to 3 mm) is
    set by the standard apart from the formulas."""
    uppers = list(ISO286_G_ES_UM)
    for lower, upper in zip(uppers, uppers[1:]):
        D = (lower * upper) ** 0.5
        i = 0.45 * D ** (1 / 3) + 0.001 * D
        assert abs(ISO286_IT6_UM[upper] - 10 * i) <= 1.2, upper
        assert abs(ISO286_G_ES_UM[upper] + 2.5 * D ** 0.34) <= 0.6, upper


@pytest.mark.parametrize("d_mm", [1.5, 3.0, 4.0, 6.0, 8.0, 10.15, 14.15, 20.0, 40.0, 51.1184,
                                  100.0, 200.0, 450.0])
def test_g6_deviation_is_iso286(d_mm):
    from springcad.design.catalogue import g6_deviation_mm

    upper = next(u for u in ISO286_G_ES_UM if d_mm <= u)
    es, it6 = ISO286_G_ES_UM[upper], ISO286_IT6_UM[upper]
    assert g6_deviation_mm(d_mm) == pytest.approx(((es - it6) / 1000, es / 1000))


def test_d_shaft_across_flat_check_against_its_solid():
    """The default torque shaft's note gives the flat as the size across it (what a
    micrometer reads): by hand Ø4 g6 = 3.988-3.996, radius 1.994-1.998, flat 1.6 0/-0.02
    from the axis, so 3.574-3.598 mm; the solid's extent across the flat is the nominal
    2 + 1.6 = 3.6 mm, the top of that band less the g6 allowance."""
    shaft = next(p for p in assembly("default").parts.values()
                 if p.info.kind == "torque_shaft")
    assert shaft.style == "d_shaft"
    note = shaft.info.notes[0]
    assert "size across it (flat to the far side of the round): 3.574-3.598 mm" in note
    assert "g6 radius 1.994-1.998 + the flat's 1.580-1.600 from the axis" in note
    box = shaft.solid.bounding_box()  # a z-prism of the D: its x/y extents are the D's
    extents = sorted((box.max.X - box.min.X, box.max.Y - box.min.Y))
    assert extents[0] == pytest.approx(3.6, abs=1e-6)  # across the flat, nominal
    assert extents[1] == pytest.approx(4.0, abs=1e-6)


def test_d_hub_across_flat_check_by_hand():
    """The 4xS1 end camshaft's D hub (Ø10.15 g6, flat 4.06 0/-t_shaft from the axis, into the
    torque shaft's socket): by hand g6 over 10-18 mm is -0.017/-0.006, so the radius is
    5.0665-5.072 and across the flat 9.1165-t_shaft ... 9.132 mm; the hub's profile reaches
    5.075 + 4.06 = 9.135 mm across the flat at nominal."""
    import numpy as np

    cam = next(p for p in assembly("4xS1").parts.values()
               if p.info.kind == "camshaft" and getattr(p, "drive", "") == "hub_flat")
    t = cam.spring.manufacturing.t_shaft_mm
    assert cam.hub_radius == pytest.approx(5.075) and t == 0.02
    note = next(n for n in cam.info.notes if n.startswith("Hub:"))
    r_lo, r_hi = 5.075 - 0.017 / 2, 5.075 - 0.006 / 2
    assert (f"size across it (flat to the far side of the round): {r_lo + 4.06 - t:.3f}-"
            f"{r_hi + 4.06:.3f} mm (the g6 radius {r_lo:.3f}-{r_hi:.3f} + the flat's "
            f"{4.06 - t:.3f}-4.060 from the axis)") in note, note
    hub = cam.slabs[0].region.outer.sample(0.001)
    assert min(np.ptp(hub, axis=0)) == pytest.approx(5.075 + 4.06, abs=1e-3)
