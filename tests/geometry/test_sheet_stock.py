"""What a buyer orders for the sheet parts (issue 26): the 1.4310 strip's standard and temper,
the POM-C sheet's standard and thickness tolerance, on the part, its drawing note and the BOM."""

from __future__ import annotations

import pytest

from springcad.design.hardware import PLASTIC, RIM_SPACER_MATERIAL
from springcad.geometry.spacers import CentreSpacer, RimSpacer, RimWasher
from springcad.materials import material_table

SHIM = material_table()[RIM_SPACER_MATERIAL]


def _shim(thickness_mm=0.4):
    return RimSpacer("X", 33.5, 36.0, thickness_mm, (SHIM.description, 7900.0),
                     hardness=SHIM.hardness, heat_treatment=SHIM.heat_treatment,
                     process="wire_edm")


def test_shim_temper_is_named_in_the_material_data():
    """EN 10151 names 1.4310 spring strip by tensile class: +C1300 is Rm 1300-1500 MPa; the
    material's name (drawing note 3, the BOM's material column) carries the temper."""
    assert "1.4310+C1300" in SHIM.description and "EN 10151" in SHIM.description
    assert SHIM.hardness == "Rm 1300-1500 MPa (EN 10151 temper +C1300)"


def test_rim_spacer_stock():
    """0.4 mm strip, Ø72 part: at least 72 mm wide; the strip's normal thickness tolerance
    inside the ±0.05 drawn; any temper (no load); a note and the part's ``stock`` say the
    same."""
    part = _shim()
    stock = part.info.stock
    for text in ("strip 0.4 mm thick", "EN ISO 9445-1 normal", "inside the ±0.05 drawn",
                 "at least 72 mm wide", "carries no load: another EN 10151 temper will do"):
        assert text in stock, text
    assert f"Stock to order: {stock}." in part.info.notes
    # a plate is not sheet stock: no stock text (the material and thickness say it)
    assert _shim(1.5).info.stock == ""


@pytest.mark.parametrize("cls", [CentreSpacer, RimWasher])
def test_pom_sheet_stock(cls):
    """ASTM D6100 sheet: ±10 % of 0.4 mm = ±0.04, inside the ±0.05 drawn; of 0.6 mm = ±0.06,
    outside: the order asks for ±0.05."""
    thin = cls("X", 0.0 if cls is CentreSpacer else 31.0, 8.1 if cls is CentreSpacer else 33.5,
               0.4, PLASTIC).info.stock
    assert "POM-C (acetal copolymer) sheet or film to ASTM D6100, Type I (unfilled)" in thin
    assert "±10 % (±0.04) is inside the ±0.05 drawn" in thin
    assert ("at least 17 x 17 mm" if cls is CentreSpacer else "at least 67 x 67 mm") in thin
    thick = cls("X", 0.0 if cls is CentreSpacer else 31.0,
                8.1 if cls is CentreSpacer else 33.5, 0.6, PLASTIC).info.stock
    assert "order ±0.05, closer than ASTM D6100's ±10 % (±0.06)" in thick


def test_bom_and_vendor_readme_carry_the_stock(stack_4xs1):
    """Every sheet part's BOM row has its stock; the other parts' rows are empty; the vendor
    README gives it under the part, wrapped at 80 characters."""
    from springcad.export.bom import bom_rows
    from springcad.export.release import ReleaseStatus
    from springcad.export.vendor import readme_text

    rows = bom_rows(stack_4xs1)
    kinds = {r["kind"]: r for r in rows}
    assert "EN ISO 9445-1" in kinds["rim_spacer"]["stock"]
    assert "1.4310+C1300" in kinds["rim_spacer"]["material"]
    assert "ASTM D6100" in kinds["centre_spacer"]["stock"]
    assert kinds["flexure_ring"]["stock"] == "" and kinds["fastener"]["stock"] == ""
    text = readme_text(stack_4xs1, ReleaseStatus(()), "4xS1", rows, {})
    assert " ".join(kinds["rim_spacer"]["stock"].split()) in " ".join(text.split())
    assert text.count("stock to order:") == sum(1 for r in rows if r["stock"])
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if "stock to order:" in line)
    block = lines[start:next(i for i in range(start + 1, len(lines))
                             if not lines[i].startswith(" " * 19))]
    assert len(block) > 1 and max(len(line) for line in block) <= 80
