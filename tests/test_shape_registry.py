"""The flexure-shape registry: a third shape is one class and its registration.

The toy shape lives in this test alone (no springcad module knows it): a radial flexure
whose width tapers linearly from w_r at the root to tau w_r at the tip. It is registered,
a spring is designed with it through the ordinary config and design search, and the
design's beam stiffness (Castigliano over the design's own width function, web and width
factor included) is held to the closed form of a linearly tapered cantilever.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from springcad.config import ConfigError, job_from_dict
from springcad.design import flexure as fx
from springcad.design import shapes, stress
from springcad.design.search import design_spring
from springcad.design.shapes.base import FlexureRecord, FlexureShape, Sizing, SizingContext
from springcad.design.resize import with_root
from springcad.errors import DesignError

#: tip width over root width of the toy shape
TAU = 0.25


def taper_integral(tau: float) -> float:
    """integral_0^1 u^2 / (tau + (1 - tau) u)^3 du: the compliance of a linearly tapered
    cantilever in units of 12 L^3 / (E z w_r^3) (closed form; 1/3 at tau = 1)."""
    return (-math.log(tau) + 2 * tau - 1.5 - 0.5 * tau ** 2) / (1 - tau) ** 3


class Tapered(FlexureShape):
    """Radial flexures with a linear width taper, root width sized for the stiffness."""

    name = "tapered_toy"
    auto = False
    summary = "test shape: radial, width tapering linearly to the tip"

    def __init__(self, calibration: stress.StressCalibration):
        self._calibration = calibration

    def size(self, ctx: SizingContext) -> Sizing | None:
        lay, spec = ctx.layout, ctx.spec
        L, z = lay.rr - lay.rc, spec.thickness_mm
        w_r = (12 * L ** 3 * taper_integral(TAU) * ctx.target_stiffness_Nmm_per_rad
               / (lay.n * lay.rc ** 2 * ctx.youngs_modulus_MPa * z)) ** (1 / 3)
        # bending stress 6 F xi / (z w(xi)^2) peaks at xi = tau L / (1 - tau) for tau < 1/2
        peak_MPa = 6 * lay.load * L / (z * w_r ** 2) / (4 * TAU * (1 - TAU) if TAU < 0.5 else 1.0)
        if peak_MPa > ctx.stress_MPa:
            return None
        record = FlexureRecord(self.name, "linear taper", w_r, fx.Centreline.straight(lay.rc, lay.rr),
                               params=(("tip_width_ratio", TAU),))
        return Sizing(lay, record)

    def width_mm(self, design, y_mm):
        u = np.clip((np.asarray(y_mm, dtype=float) - design.contact_radius_mm)
                    / design.length_mm, 0.0, 1.0)
        tau = design.shape.param("tip_width_ratio")
        return design.root_width_mm * (tau + (1 - tau) * u)

    def calibration(self) -> stress.StressCalibration:
        return self._calibration


#: the toy shape's calibration data: the shipped coefficients with its own neck factor
TOY_CALIBRATION = replace(stress.calibration(), neck_factor=1.7, cases=0)


@pytest.fixture
def tapered():
    shape = shapes.register(Tapered(TOY_CALIBRATION))
    yield shape
    shapes.unregister(shape.name)


def _job(flexure: str):
    return job_from_dict({"material": {"design_stress_MPa": 912}, "springs": {"A": {
        "stiffness_Nm_per_rad": 150, "max_deflection_deg": 6, "outer_radius_mm": 33.5,
        "thickness_mm": 4.5, "contact_radius_mm": 5.5, "tip_radius_mm": 0.5, "n_flexures": 16,
        "flexure": flexure}}})


def test_config_names_follow_the_registry(tapered):
    assert _job("tapered_toy").springs["A"].flexure == "tapered_toy"
    with pytest.raises(ConfigError, match='one of "auto", "straight", "serpentine", "tapered_toy"$'):
        _job("curvy")
    shapes.unregister("tapered_toy")
    with pytest.raises(ConfigError, match='one of "auto", "straight", "serpentine"$'):
        _job("tapered_toy")


def test_builtin_names_are_registered():
    assert shapes.names()[:2] == ("straight", "serpentine")
    with pytest.raises(ConfigError, match='"auto", "straight", "serpentine"'):
        _job("curvy")


def test_tapered_spring_meets_the_tapered_cantilever(tapered):
    j = _job("tapered_toy")
    d = design_spring(j.springs["A"], j.material, j.manufacturing, j.hardware)
    assert d.flexure == "tapered_toy" and d.width_law == "linear taper"
    assert d.to_dict()["flexure_params"] == {"tip_width_ratio": TAU}
    assert d.ring is not None and d.ring.area_mm2() > 0  # the ring profile follows the shape
    s = with_root(d, 0.0)  # the plain taper: no root flare
    E, z, L = 200e3, s.thickness_mm, s.length_mm
    w_r = s.root_width_mm * s.width_scale
    # the design's width function is the taper (the smooth web floor adds 0.1 % at the tip)
    y = np.linspace(s.contact_radius_mm, s.root_radius_mm, 7)
    assert s.width_mm(y) == pytest.approx(w_r * (TAU + (1 - TAU) * (y - y[0]) / L), rel=2e-3)
    k_closed = s.n_flexures * s.contact_radius_mm ** 2 * E * z * w_r ** 3 / (
        12 * L ** 3 * taper_integral(TAU))
    assert s.stiffness_beam_Nmm_per_rad == pytest.approx(k_closed, rel=1e-3)
    assert s.stiffness_beam_Nmm_per_rad == pytest.approx(150e3, rel=2e-3)  # the target K

def test_taper_integral_closed_form():
    u = np.linspace(0.0, 1.0, 200001)
    for tau in (0.3, TAU, 0.9):
        assert taper_integral(tau) == pytest.approx(
            np.trapezoid(u ** 2 / (tau + (1 - tau) * u) ** 3, u), rel=1e-8)
    assert taper_integral(1 - 1e-4) == pytest.approx(1 / 3, rel=1e-3)  # the uniform beam


def test_tapered_spring_uses_its_own_calibration(tapered):
    j = _job("tapered_toy")
    d = design_spring(j.springs["A"], j.material, j.manufacturing, j.hardware)
    own, shipped = stress.predict(d), stress.predict(d, cal=stress.calibration())
    assert own == stress.predict(d, cal=TOY_CALIBRATION)
    assert own.neck_MPa == pytest.approx(shipped.neck_MPa * 1.7 / stress.calibration().neck_factor)


def test_request_that_no_shape_meets_is_refused(tapered):
    j = _job("tapered_toy")
    spec = replace(j.springs["A"], max_deflection_rad=math.radians(10))
    with pytest.raises(DesignError, match="no tapered_toy flexure reaches 0.1745 rad with 16 "):
        design_spring(spec, j.material, j.manufacturing, j.hardware, explain=False)
    # "auto" does not try a shape registered with auto = False
    auto = design_spring(replace(spec, flexure="auto"), j.material, j.manufacturing, j.hardware,
                         explain=False)
    assert auto.flexure in ("straight", "serpentine")


def test_config_knows_the_builtin_shapes_before_any_design_module():
    """A config loaded first thing in a fresh interpreter accepts every built-in shape, and
    naming them loaded no design math (the registry's names are light)."""
    import subprocess
    import sys
    from pathlib import Path

    code = ("import sys; from springcad.config import job_from_dict; "
            "j = job_from_dict({'springs': {'A': {'stiffness_Nm_per_rad': 100, "
            "'max_deflection_deg': 10, 'outer_radius_mm': 30, 'thickness_mm': 4, "
            "'flexure': 'serpentine'}}}); "
            "print(j.springs['A'].flexure, 'numpy' in sys.modules)")
    root = Path(__file__).resolve().parents[1]
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin"})
    assert out.stdout.split() == ["serpentine", "False"]


@pytest.mark.slow
def test_tapered_spring_goes_through_every_stage_of_the_api(tapered):
    """The registered toy shape, and nothing else, carries a job through the public API:
    design (design.json names it), the FEA verification of the uncorrected design (2D
    plane stress against the design's beam theory, i.e. the tapered cantilever) and the
    CAD build with its checks."""
    import springcad as sc
    from springcad.export.skeleton import part_volume_mm3

    doc = {"material": {"design_stress_MPa": 912}, "springs": {"A": {
        "target_stiffness_Nm_per_rad": 150, "max_deflection_deg": 6, "outer_radius_mm": 33.5,
        "thickness_mm": 4.5, "contact_radius_mm": 5.5, "tip_radius_mm": 0.5, "n_flexures": 16,
        "flexure": "tapered_toy"}}}
    d = sc.design_job(doc)
    entry = d.to_dict()["springs"]["A"]
    assert entry["flexure"] == "tapered_toy" and entry["flexure_params"] == {"tip_width_ratio": TAU}
    assert "tapered_toy" in d.summary()
    v = sc.verify(d, model="2d", levels=3, contact=False, correct=False)
    row = v.spring_table()[0]
    # 2D FEA of the tapered ring against beam theory (measured +1.6 %: the rim and the
    # root and tip ends, which beam theory leaves out); converged to < 0.01 %
    assert row["discretisation_error_pct"] < 0.01
    assert row["stiffness_fea_Nm_per_rad"] == pytest.approx(row["stiffness_beam_Nm_per_rad"],
                                                            rel=0.03)
    assert v.design.springs["A"].raw.flexure == "tapered_toy"
    built = sc.build(d, accept_violations=True)
    assert built.checks.passed(accept_violations=True), built.checks.summary()
    assert "0 geometry errors" in built.checks.summary()
    # the CAD ring is the design's tapered profile extruded: volume = area x thickness
    ring = next(p for p in built.assembly.parts.values() if p.info.kind == "flexure_ring")
    s = d.springs["A"].raw
    assert part_volume_mm3(ring) == pytest.approx(s.ring.area_mm2() * s.thickness_mm, rel=1e-6)
