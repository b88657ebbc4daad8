"""A thickness left to springcad: the thinnest stock plate at which the design search finds
a spring (springcad.design.stock), bounded by max_thickness_mm; the job carries the choice."""

from __future__ import annotations

import dataclasses
import re
from dataclasses import replace

import pytest

from springcad.config import job_from_dict
from springcad.config.schema import keys
from springcad.design import redesign, search
from springcad.design.job import design_job
from springcad.design.stock import _nearest_plate, _thinnest, plate_thicknesses_mm
from springcad.errors import ConfigError, DesignError


def _job(**spring):
    s = {"target_stiffness_Nm_per_rad": 20, "max_deflection_deg": 10, "outer_radius_mm": 20}
    s.update(spring)
    return job_from_dict({"material": {"name": "420_ht"}, "springs": {"A": s},
                          "duty": {"preset": "static"}})


@pytest.fixture(scope="module")
def chosen():
    return design_job(_job())


def test_stock_list_is_ascending_and_inside_the_schema_range():
    t = plate_thicknesses_mm()
    rng = keys("springs.<name>")["thickness_mm"]
    assert list(t) == sorted(set(t)) and rng.lo <= t[0] and t[-1] <= rng.hi


def test_the_thinnest_stock_plate_that_designs_is_chosen_and_the_job_carries_it(chosen):
    d = chosen.springs["A"]
    stock = plate_thicknesses_mm()
    assert d.thickness_mm in stock and d.spec.thickness_mm == d.thickness_mm
    assert chosen.job.springs["A"].thickness_mm == d.thickness_mm  # downstream sees it
    assert f"thickness {d.thickness_mm:g} mm chosen" in d.design_choice
    # the same spec with that thickness given designs the same spring
    fixed = design_job(_job(thickness_mm=d.thickness_mm)).springs["A"]
    assert fixed.n_flexures == d.n_flexures and fixed.width_scale == d.width_scale
    assert fixed.contact_radius_mm == pytest.approx(d.contact_radius_mm, rel=1e-12)
    # the next thinner stock plate: the feasibility probe finds nothing there
    thinner = stock[stock.index(d.thickness_mm) - 1]
    job = chosen.job
    spec = dataclasses.replace(job.springs["A"], thickness_mm=thinner)
    assert search.probe(spec, job.material, job.manufacturing, job.hardware, 1e9) is None


def test_a_bound_below_the_need_is_refused_with_the_bound_that_works(chosen):
    need = chosen.springs["A"].thickness_mm
    stock = plate_thicknesses_mm()
    low = stock[stock.index(need) - 2]
    with pytest.raises(DesignError) as err:
        design_job(_job(max_thickness_mm=low))
    text = str(err.value)
    assert f"springs.A.max_thickness_mm = {need:g} (now {low:g}" in text
    assert f"no stock plate up to {low:g} mm carries it" in text
    # the refusal found at that plate names the bound, not a thickness the config cannot
    # give beside it (ConfigError: "delete one of the two")
    assert "springs.A.thickness_mm =" not in text, text
    # the change, applied as written, designs at that plate
    assert design_job(_job(max_thickness_mm=need)).springs["A"].thickness_mm == need


def test_thickness_and_its_bound_together_are_refused():
    with pytest.raises(ConfigError, match="max_thickness_mm.*delete one of the two"):
        _job(thickness_mm=3, max_thickness_mm=5)


def test_chosen_thickness_carries_the_thicker_stock_plates_the_spec_allows(chosen):
    d = chosen.springs["A"]
    assert d.thicker_plates_mm == tuple(t for t in plate_thicknesses_mm() if t > d.thickness_mm)


@pytest.mark.parametrize("bias", [1.08, 1.2])
def test_stress_redesign_keeps_the_biased_margin_or_refuses(chosen, bias):
    """The FEA stress correction's redesign (redesign.redesign_for_margin): whatever layout or
    plate it moves to, its own prediction keeps the yield margin raised by the bias the FEA
    measured; it never hands back a spring that does not (before, the same layout came back
    unchanged at margin 2.014 against 2.07 on the default at 20 deg)."""
    from springcad.design import duty

    d = chosen.springs["A"]
    r = redesign.redesign_for_margin(d, bias)
    need = duty.required_margin(duty.biased(d.material, bias), d.max_deflection_rad)
    assert r.yield_margin >= need * (1 - 1e-3)
    assert r.thickness_mm in (d.thickness_mm, *d.thicker_plates_mm[:redesign.MARGIN_PLATES])
    assert r.thicker_plates_mm == tuple(t for t in d.thicker_plates_mm if t > r.thickness_mm)
    assert r.target_stiffness_Nmm_per_rad == d.target_stiffness_Nmm_per_rad


def test_stress_redesign_that_nothing_carries_says_what_it_tried(chosen):
    d = dataclasses.replace(chosen.springs["A"], thicker_plates_mm=())
    with pytest.raises(DesignError, match="no redesign keeps the yield margin") as err:
        redesign.redesign_for_margin(d, 4.0)
    assert "the same layout at" in str(err.value) and "any layout at" in str(err.value)


def _interval(stock, first, last, probed):
    """A probe whose plates design from index ``first`` to ``last`` of ``stock`` (none when
    None), thicker ones failing for the webs; each probed index is appended to ``probed``."""
    def designs(t):
        i = stock.index(t)
        probed.append(i)
        inside = first is not None and first <= i <= last
        return inside, first is not None and i > last

    return designs


@pytest.mark.parametrize("first, last", [(0, 23), (5, 5), (3, 9), (0, 0), (23, 23), (10, 17),
                                         (None, None)])
def test_the_thinnest_plate_is_found_when_thick_plates_fail_too(first, last):
    """Feasibility as an interval of the stock list (thin plates fail the stress, thick ones
    the webs): the bisection finds its first plate, as a scan of every plate does, and names
    the next thinner plate it probed."""
    stock = list(plate_thicknesses_mm())
    probed = []
    designs = _interval(stock, first, last, probed)
    t, thinner = _thinnest(stock, designs)
    if first is None:
        assert (t, thinner) == (None, None)
        return
    assert t == stock[first]
    assert thinner == (stock[first - 1] if first > 0 else None)
    if thinner is not None:
        assert stock.index(thinner) in probed
    assert len(probed) <= 2 * 5 + 1  # two bisections of 24 plates, not a scan


@pytest.mark.parametrize("first, last", [(0, 23), (5, 5), (3, 9), (0, 0), (23, 23), (10, 17),
                                         (None, None)])
@pytest.mark.parametrize("start", [0, 2, 4, 5, 9, 10, 12, 17, 18, 23])
def test_a_first_guess_finds_the_same_plate_and_probes_its_thinner_neighbour(first, last, start):
    """The energy estimate's first guess (any plate, inside or outside the interval that
    designs) changes which plates are probed, never the answer: the bisection's plate and
    its next thinner one, which was probed and refused."""
    stock = list(plate_thicknesses_mm())
    probed = []
    designs = _interval(stock, first, last, probed)
    expected = _thinnest(stock, designs)
    probed.clear()
    t, thinner = _thinnest(stock, designs, start)
    assert (t, thinner) == expected
    assert probed[0] == start
    if thinner is not None:
        assert stock.index(thinner) in probed and designs(thinner)[0] is False
    if first is not None and start >= first and start <= last:  # a guess that designs
        assert len(set(probed)) == start - first + 1 + (first > 0)  # walked down, one each


def test_the_nearest_plate_is_the_thickest_too_thin_one_else_the_thinnest():
    """From the probes' outcomes (plate -> (designs, too thick)): the thickest plate refused
    as too thin, where the stress or reach rules bind; every probed plate held stiff by its
    webs, the thinnest of the list."""
    stock = [1.0, 2.0, 3.0, 5.0, 8.0, 100.0]
    assert _nearest_plate(stock, {100.0: (False, True), 3.0: (False, False),
                                  5.0: (False, True), 2.0: (False, False)}) == 3.0
    assert _nearest_plate(stock, {100.0: (False, True), 8.0: (False, True)}) == 1.0
    assert _nearest_plate(stock, {100.0: (False, False)}) == 100.0
    assert _nearest_plate([], {}) is None


@pytest.mark.slow
def test_a_small_soft_disk_is_refused_at_the_plate_nearest_to_designing():
    """Held-out B 9041 009 (R_o 12 mm, 15 N*m/rad over 5 deg, thickness free, M2 rim bolts):
    no plate designs; the refusal was searched at the 100 mm plate, whose webs hold it
    ~60 x too stiff, and named no change. It is searched at the plate between the too thin
    and the too stiff ones, and its change (a larger disk) designs with the thickness
    still free."""
    job = job_from_dict({
        "material": {"name": "420_ht"},
        "springs": {"S1": {"target_stiffness_Nm_per_rad": 15, "max_deflection_deg": 5.0,
                           "outer_radius_mm": 12.0}},
        "stack": {"sequence": ["S1"], "input": "rim"},
        "hardware": {"fastener": "bolt", "fastener_diameter_mm": 2.0},
        "duty": {"preset": "static"}})
    with pytest.raises(DesignError) as refused:
        design_job(job)
    text = str(refused.value)
    at = float(re.search(r"carries it; at ([\d.]+) mm \(the plate nearest", text).group(1))
    assert at < max(plate_thicknesses_mm())
    ro = float(re.search(r"springs\.S1\.outer_radius_mm = ([\d.]+) \(now 12\)", text).group(1))
    bigger = replace(job, springs={"S1": replace(job.springs["S1"], outer_radius_mm=ro)})
    assert design_job(bigger).springs["S1"].thickness_mm is not None
