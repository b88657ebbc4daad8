"""The duty judged on the verified stress field, and the release gate on it (issue 21)."""

import math
import tomllib
from dataclasses import replace
from types import SimpleNamespace

import pytest

from fea.verdict import JobVerification, SpringVerification
from springcad.config import job_from_dict
from springcad.design import duty
from springcad.design.job import design_job
from springcad.export.release import release_status
from tests.conftest import template


def _design(name="paper_S1", thickness_mm=None, **duty_table):
    data = tomllib.loads(template(name).read_text())
    data.pop("duty", None)
    if thickness_mm is not None:
        data["springs"]["S1"]["thickness_mm"] = thickness_mm
    if duty_table:
        data["duty"] = duty_table
    return design_job(job_from_dict(data))


def _verified(jd, regions: dict, peak_region: str):
    """A SpringVerification over a stand-in FEA run with these regional peaks (MPa)."""
    d = jd.springs["S1"]
    finest = SimpleNamespace(peak_by_region_MPa=dict(regions))
    run = SimpleNamespace(peak_stress_MPa=regions[peak_region],
                          study=SimpleNamespace(finest=finest, results=(finest,)),
                          check3d=(), base2d=(), faces=(),
                          peak_result=SimpleNamespace(peak_region=peak_region))
    return SpringVerification(name="S1", design=d, original=d, run=run, model="2d", tolerance=0.01,
                              iterations=[], required_safety_factor=1.0,
                              yield_strength_MPa=d.material.material.yield_strength_MPa,
                              timings_s={}, case=None)


class Job:
    """Only what the release gate reads of a JobVerification."""

    def __init__(self, v):
        self.springs = {"S1": v}
        self.ok = True

    def failures(self):
        return []

    def notes(self):
        return []

    def duty_failures(self):
        return [f for s in self.springs.values() for f in s.duty_failures()]

    def ratings(self):
        return [s.duty_check.rating_text() for s in self.springs.values()]


def test_the_critical_point_is_the_region_with_the_lowest_factor_and_gates_the_release():
    jd = _design("default", preset="robot_joint")
    d = jd.springs["S1"]
    allowed = duty.allowed_peak_MPa(d.material, d.max_deflection_rad)
    # the root fillet below the allowed peak, the flank just above it, a sector cut far above
    v = _verified(jd, {"root fillet": 0.9 * allowed, "flexure flank": 1.02 * allowed,
                       "rim (sector cut)": 5 * allowed}, "root fillet")
    c = v.duty_check
    assert c.where == "FEA flexure flank" and c.peak_MPa == pytest.approx(1.02 * allowed)
    assert not c.met and c.safety_factor == pytest.approx(1.2 / 1.02, rel=1e-6)
    status = release_status(jd, Job(v))
    assert not status.released
    assert any("duty" in r and "not met" in r and "rated life" in r for r in status.reasons)
    ok = _verified(jd, {"root fillet": 0.99 * allowed, "flexure flank": 0.5 * allowed},
                   "root fillet")
    assert ok.duty_failures() == []
    status = release_status(jd, Job(ok))
    assert status.released and "duty met" in status.ratings[0]


def test_region_peaks_extrapolate_each_region_with_its_own_3d_factor():
    """Each region: Richardson over the 2D levels (changes shrinking 4x per level: the
    exact limit of a + b h^2) times its own 3D/2D ratio on the finer 3D level. The
    verification's single peak would mix the flank's 3D factor into the root's 2D peak."""
    from fea.fatigue import region_peaks_MPa

    def level(flank, root, cut=50.0):
        return SimpleNamespace(peak_by_region_MPa={"flexure flank": flank, "root fillet": root,
                                                   "rim (sector cut)": cut})

    base2d = (level(1160.0, 900.0), level(1040.0, 950.0), level(1010.0, 962.5),
              level(1002.5, 965.625))
    check3d = (level(1200.0, 890.0), level(1040.0 * 1.03, 950.0 * 0.99))
    run = SimpleNamespace(study=SimpleNamespace(finest=base2d[-1], results=base2d[1:]),
                          base2d=base2d, check3d=check3d, faces=("nested",))
    peaks = region_peaks_MPa(run)
    assert set(peaks) == {"flexure flank", "root fillet"}
    assert peaks["flexure flank"] == pytest.approx(1000.0 * 1.03, rel=1e-12)
    assert peaks["root fillet"] == pytest.approx((965.625 + 3.125 / 3.0) * 0.99, rel=1e-12)
    # without a 3D check: the 2D extrapolation alone
    run2d = SimpleNamespace(study=run.study, base2d=(), check3d=(), faces=("nested",))
    assert region_peaks_MPa(run2d)["flexure flank"] == pytest.approx(1000.0, rel=1e-12)


def test_a_static_prototype_duty_releases_rated_for_its_cycles():
    jd = _design("default", preset="static")
    d = jd.springs["S1"]
    allowed = duty.allowed_peak_MPa(d.material, d.max_deflection_rad)
    v = _verified(jd, {"root fillet": 0.95 * allowed}, "root fillet")
    status = release_status(jd, Job(v))
    assert status.released
    assert status.ratings[0].startswith(
        f"rated for 1e+03 cycles at +-{math.degrees(d.max_deflection_rad):.1f} deg")


def test_a_declared_duty_sizes_the_design_and_the_default_duty_does_not():
    """The default job at 99.99 % reliability: its yield-only layout (12 mm, predicted peak
    ~650 MPa) misses the 638 MPa the duty allows. Undeclared (springcad's default duty) the design is
    left alone; declared, the design search works to the duty's margin: it meets it, or its
    warnings name that margin (which stops the release)."""
    def springs(declared):
        data = tomllib.loads(template("default").read_text())
        data["duty"] = {"preset": "robot_joint", "reliability": 0.9999}
        data["springs"]["S1"]["thickness_mm"] = 12.0  # the plate the template's duty gets
        job = job_from_dict(data)
        if not declared:
            job = replace(job, material=replace(job.material, duty=replace(job.material.duty,
                                                                            declared=False)))
        return design_job(job).springs["S1"]

    plain, sized = springs(False), springs(True)
    allowed = duty.allowed_peak_MPa(sized.material, sized.max_deflection_rad)
    required = duty.required_margin(sized.material, sized.max_deflection_rad)
    assert plain.predicted_peak_stress_MPa > allowed and not plain.duty_check.met
    assert not plain.warnings
    assert required > 1.2 * 1.5
    assert sized.duty_check.met or any(f"required {required:.3f}" in w for w in sized.warnings)


def _with_contact(v, force_N, r_tip_mm, flank_radius_mm):
    """The verification with a stand-in contact sweep: both ends at +-theta_max press the
    ball with ``force_N`` on a flank of ``flank_radius_mm``; p0 by Hertz line contact."""
    from springcad.design.contact_stress import tip_contact

    d, m = v.design, v.design.material.material
    h = tip_contact(force_N, r_tip_mm, flank_radius_mm, d.thickness_mm, m.youngs_modulus_MPa,
                    m.poisson_ratio)
    end = SimpleNamespace(contact={"force_N": force_N, "ball_radius_mm": r_tip_mm,
                                   "flank_radius_mm": flank_radius_mm, "p0_MPa": h.p0_MPa})
    v.contact = SimpleNamespace(at_max=SimpleNamespace(ends={"+": end, "-": end}))
    return v


def test_contact_fatigue_of_the_ball_gates_the_release_with_the_change_in_numbers():
    """The default's duty on a ball too small for it (the 11 mm default's old layout: 283 N on
    a 0.3 mm ball, flank 1.21 mm, p0 ~1.9 GPa > the 1260 MPa allowed) stops the release and
    names a ball and a thickness; applying the named ball (Hertz, closed form) meets it."""
    from springcad.design import contact_fatigue
    from springcad.design.contact_stress import tip_contact

    jd = _design("default", preset="robot_joint")
    d = jd.springs["S1"]
    allowed = duty.allowed_peak_MPa(d.material, d.max_deflection_rad)
    v = _with_contact(_verified(jd, {"flexure flank": 0.9 * allowed}, "flexure flank"),
                      283.0 * d.thickness_mm / 11.0, 0.3, 1.21)
    c = v.contact_fatigue
    assert c.judged and not c.met and c.allowable_MPa == pytest.approx(1260, rel=0.01)
    fails = v.duty_failures()
    assert len(fails) == 1 and "contact fatigue" in fails[0]
    status = release_status(jd, Job(v))
    assert not status.released and any("contact fatigue" in r for r in status.reasons)
    # the named balls meet it on the flank radius each leaves, r_c theta - r_b - w_gap
    # (Hertz forwards at the window's ends), or the named contact radius opens a window
    m = d.material.material
    force, gap = 283.0 * d.thickness_mm / 11.0, d.manufacturing.w_gap_mm

    def p0(r_ball, rc):
        flank = rc * d.max_deflection_rad - r_ball - gap
        return tip_contact(force, r_ball, flank, d.thickness_mm, m.youngs_modulus_MPa,
                           m.poisson_ratio).p0_MPa

    if "tip_radius_mm between " in fails[0]:
        lo, hi = (float(x) for x in
                  fails[0].split("tip_radius_mm between ")[1].split(" (now")[0].split(" and "))
        for r in (lo, hi):
            assert p0(r, d.contact_radius_mm) == pytest.approx(c.allowable_MPa, rel=2e-3)
    else:
        rc_named = float(fails[0].split("contact_radius_mm >= ")[1].split(",")[0])
        assert rc_named > d.contact_radius_mm
        mid = 0.5 * (rc_named * 1.01 * d.max_deflection_rad - gap)
        assert p0(mid, rc_named * 1.01) <= c.allowable_MPa
    # and the named thickness: p0 ~ thickness^-1/2 at the same force
    z_named = float(fails[0].split("thickness_mm >= ")[1].split(" ")[0])
    assert z_named == pytest.approx(d.thickness_mm * (c.p0_max_MPa / c.allowable_MPa) ** 2,
                                    rel=3e-3)  # printed to 3 digits
    # a ball that carries it: no failure, a release note instead
    ok = _with_contact(_verified(jd, {"flexure flank": 0.9 * allowed}, "flexure flank"),
                       100.0, 0.5, 1.8)
    assert ok.contact_fatigue.met and ok.duty_failures() == []
    assert contact_fatigue.contact_check(d.material.duty, "420_ht", 1000.0, 0.2).met


@pytest.mark.slow
@pytest.mark.parametrize("name", ["default", "paper_S1"])
def test_design_json_and_fea_json_agree_on_the_damage(name):
    """Issue 21: design.json (the FEA-corrected design's own stress prediction, as a build
    writes it) and fea.json (the verified stress field's critical point) state Miner sums
    within 10 % of each other. The S-N slope (about 1/0.1) makes that a 1 % test of the
    design-side stress model against the verification."""
    import springcad as sc

    ver = sc.verify(template(name), cache=False)
    design_doc, fea_doc = ver.design.to_dict(), ver.to_dict()
    for spring, entry in fea_doc["springs"].items():
        fd, dd = entry["duty"], design_doc["springs"][spring]["duty"]
        # the same design: the verified widths are the ones design.json states
        assert design_doc["springs"][spring]["width_scale"] == pytest.approx(
            entry["correction_iterations"][-1]["width_scale"], rel=1e-9)
        assert fd["miner_sum"] > 0.0
        ratio = dd["miner_sum"] / fd["miner_sum"]
        assert 0.9 <= ratio <= 1.1, (spring, dd["peak_at_max_deflection_MPa"],
                                     fd["peak_at_max_deflection_MPa"], ratio)


def test_a_default_duty_failure_says_it_is_the_default_and_how_to_declare_one():
    """The same stress over the robot_joint duty fails the release whether the job declares
    it or gets it by default; only the default's reasons say that no [duty] was declared
    and how to declare the duty the spring will see."""
    declared = _design("default", preset="robot_joint")
    default = _design("default")
    assert not default.springs["S1"].material.duty.declared
    for jd, says in ((declared, False), (default, True)):
        d = jd.springs["S1"]
        allowed = duty.allowed_peak_MPa(d.material, d.max_deflection_rad)
        reasons = _verified(jd, {"root fillet": 1.3 * allowed}, "root fillet").duty_failures()
        assert reasons and "not met" in reasons[0]
        assert ("declares no [duty]" in reasons[-1]) is says
        assert ('preset = "static"' in " ".join(reasons)) is says


def test_a_contact_failure_says_what_the_correction_tried():
    """A release stopped by a contact clearance at +-theta_max carries the correction's own
    note (held-out g26: the cam redesign to N 42 opened the ball's gap but left the tooth
    tip to edge -27 um in the worst case, which only fea.json said); notes of other kinds
    stay out, and a spring without contact failures gets none."""
    tried = "cam redesign (N 42, r_c 11.000 mm) verified and not kept: " + "x" * 400
    failing = SimpleNamespace(contact=object(), contact_failures=lambda: ["gap A", "gap B"],
                              notes=["2D plane-stress Richardson extrapolation", tried])
    clean = SimpleNamespace(contact=object(), contact_failures=lambda: [], notes=[tried])
    stub = SimpleNamespace(springs={"A": failing, "B": clean},
                           options=SimpleNamespace(contact=True))
    out = JobVerification.release_failures(stub)
    assert out[0] == "gap A" and out[1].startswith("gap B; cam redesign (N 42")
    assert "Richardson" not in out[1] and len(out) == 2 and len(out[1]) < 320


def test_a_stack_without_a_duty_hears_of_the_default_once():
    """Two springs failing springcad's default duty: the job's reasons say once, after
    the last, that no [duty] was declared (the g02 report said it after each spring)."""
    jd = _design("default")
    d = jd.springs["S1"]
    allowed = duty.allowed_peak_MPa(d.material, d.max_deflection_rad)
    v = _verified(jd, {"root fillet": 1.3 * allowed}, "root fillet")
    job = JobVerification.__new__(JobVerification)
    job.springs = {"A": v, "B": v}
    reasons = job.duty_failures()
    assert len(reasons) >= 2
    assert sum("declares no [duty]" in r for r in reasons) == 1
    assert "declares no [duty]" in reasons[-1]
