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
    """EN 10151 names 1.4310 spring strip by tensile class: +C1300 is Rm 1300-1500 MPa."""
    assert "1.4310" in SHIM.description and "EN 10151" in SHIM.description
    assert SHIM.hardness == "temper +C1300 (EN 10151: Rm 1300-1500 MPa)"


def test_rim_spacer_stock():
    """0.4 mm strip, Ø72 part: at least 72 mm wide; the temper of the material data; the
    strip's normal thickness tolerance inside the ±0.05 drawn; a note and the part's
    ``stock`` say the same."""
    part = _shim()
    stock = part.info.stock
    for text in ("strip to EN 10151, temper +C1300", "0.4 mm thick", "EN ISO 9445-1 normal",
                 "inside the ±0.05 drawn", "at least 72 mm wide", "carries no load"):
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


def test_bom_carries_the_stock(stack_4xs1):
    """Every sheet part's BOM row has its stock; the other parts' rows are empty."""
    from springcad.export.bom import bom_rows

    rows = {r["kind"]: r for r in bom_rows(stack_4xs1)}
    assert "EN 10151" in rows["rim_spacer"]["stock"]
    assert "ASTM D6100" in rows["centre_spacer"]["stock"]
    assert rows["flexure_ring"]["stock"] == "" and rows["fastener"]["stock"] == ""
