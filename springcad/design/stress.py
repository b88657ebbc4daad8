"""Peak stress of the real flexure geometry, predicted on the design side.

The flexure is sized as a constant-stress Euler-Bernoulli beam (nominal stress
``sigma_nom(y) = 6 F (y - r_c) / (z w(y)^2)``), but the FEA of the real ring sees
two raisers the beam does not:

* **curvature** of the serpentine centreline: the concave edge of a curved beam
  carries more than 6M/(z w^2). The Winkler-Bach factor of a rectangular
  section (exact for a curved bar in pure bending) gives it from w and the
  centreline curvature at each station;
* the **root fillet** between the flexure edge and the rim.

The prediction is

    flank:  sigma = c_flank * (z / w(y_t))^e * max_y sigma_nom(y) * k_inner(w(y), kappa(y))
    root:   sigma = sigma_nom(y_t) * a * (w(y_t) / r_f)^b * k_inner(y_t)^c

on both edges, with y_t the station where the root fillet meets the edge, F the
tip load of the spring's *target* stiffness at theta_max (:func:`tip_load_N`) and
z the thickness. The coefficients come from the project's own FEA runs over the
templates' springs and root flares, solved as the verification solves them, and
compared region by region with the stresses the duty is judged on (2D Richardson
extrapolation times each region's 3D factor, :func:`fea.fatigue.region_peaks_MPa`):
``fea/calibrate.py`` makes the rows, ``bench/calibrate_stress.py`` writes
``springcad/data/stress_calibration.json``, a test re-runs part of it. ``a, b, c``
and the neck factor are shared by every flexure shape (the fillets are the same);
``c_flank`` and ``e`` are fitted per shape (:func:`flank_by_shape`): a straight
flexure's flank is the beam's within 0.3 %, a serpentine's Winkler-Bach flank misses
the 3D stress by a factor that grows with the section's thickness over width (the
plane-stress model's error: 3D factors 0.995 at z/w 1.3 to 1.04 at z/w 2.2). The
neck fillet is predicted as the nominal stress at the neck times its own factor.

Units: mm, N, MPa.
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import asdict, dataclass, replace
from importlib import resources

import numpy as np

from springcad.design import flexure as fx
from springcad.design.ring import neck_tangent_stations_mm, root_tangent_stations_mm


@dataclass(frozen=True)
class StressCalibration:
    """Coefficients of the stress model (dimensionless), fitted to FEA.

    Attributes:
        flank_factor: c_flank on the Winkler flank stress.
        flank_aspect_exponent: e of the flank's section-aspect term (z / w_r)^e, z the
            thickness and w_r the width at the root tangent station (0: none).
        root_coefficient, root_width_exponent, root_curvature_exponent: a, b, c.
        neck_factor: peak neck-fillet stress over the nominal stress at the neck.
        max_error_pct: largest |prediction/FEA - 1| over the calibration set (%).
        cases: number of FEA cases the fit used.
    """

    flank_factor: float
    root_coefficient: float
    root_width_exponent: float
    root_curvature_exponent: float
    neck_factor: float
    max_error_pct: float = float("nan")
    cases: int = 0
    flank_aspect_exponent: float = 0.0

    def to_dict(self) -> dict:
        return asdict(self)


@functools.cache
def calibration(shape: str | None = None) -> StressCalibration:
    """The shipped calibration (``springcad/data/stress_calibration.json``): the fit over
    every row, with the flank factor of ``shape``'s own rows when the file has one for
    that flexure shape (the fillet coefficients are shared: the fillets are the same)."""
    text = resources.files("springcad.data").joinpath("stress_calibration.json").read_text()
    data = json.loads(text)
    cal = StressCalibration(**data["coefficients"])
    return replace(cal, **data.get("flank_by_shape", {}).get(shape, {}))


@dataclass(frozen=True)
class StressPrediction:
    """Predicted peak von Mises stress of one flexure at the maximum deflection (MPa).

    Attributes:
        nominal_MPa: largest beam-theory stress 6M/(z w^2) along the flexure.
        flank_MPa: curved-beam flank peak.
        root_MPa: root-fillet peak.
        neck_MPa: tip-neck fillet peak.
        peak_MPa: the largest of the three.
        region: where the peak is ("flexure flank", "root fillet", "tip-neck fillet").
    """

    nominal_MPa: float
    flank_MPa: float
    root_MPa: float
    neck_MPa: float

    @property
    def peak_MPa(self) -> float:
        return max(self.flank_MPa, self.root_MPa, self.neck_MPa)

    @property
    def region(self) -> str:
        return max((self.flank_MPa, "flexure flank"), (self.root_MPa, "root fillet"),
                   (self.neck_MPa, "tip-neck fillet"))[1]

    def to_dict(self) -> dict:
        return {"nominal_beam_MPa": self.nominal_MPa, "flank_MPa": self.flank_MPa,
                "root_fillet_MPa": self.root_MPa, "neck_fillet_MPa": self.neck_MPa,
                "peak_MPa": self.peak_MPa, "region": self.region}


def winkler_factors(width_mm, curvature_per_mm):
    """Inner and outer fibre stress over 6M/(z w^2) for a curved rectangular bar (-).

    Winkler-Bach: neutral radius r_n = w / ln(r_o/r_i), eccentricity e = R - r_n,
    sigma_i = M (r_n - r_i) / (A e r_i). Tends to (1, 1) for a straight bar.
    """
    w = np.asarray(width_mm, dtype=float)
    kappa = np.abs(np.asarray(curvature_per_mm, dtype=float))
    inner, outer = np.ones_like(w * kappa), np.ones_like(w * kappa)
    curved = kappa * w > 1e-9
    if np.any(curved):
        wc = np.broadcast_to(w, inner.shape)[curved]
        R = 1.0 / np.broadcast_to(kappa, inner.shape)[curved]
        ri, ro = R - 0.5 * wc, R + 0.5 * wc
        ri = np.maximum(ri, 1e-9)
        # e = R - r_n with r_n = w / ln(r_o / r_i) = R x / atanh(x), x = w / (2 R): the
        # difference of two nearly equal numbers where the bar is nearly straight, so
        # there e / R = 1 - x / atanh(x) comes from its series (x^2/3 + 4x^4/45 + ...);
        # the direct difference gave a 24 % stress spike where the curvature changes sign
        x = np.minimum(0.5 * wc / R, 1.0 - 1e-12)
        series = x ** 2 / 3.0 + 4.0 * x ** 4 / 45.0 + 44.0 * x ** 6 / 945.0
        with np.errstate(divide="ignore", invalid="ignore"):
            direct = 1.0 - x / np.arctanh(x)
        e = R * np.where(x < 0.05, series, direct)
        # r_n - r_i = w/2 - e and r_o - r_n = w/2 + e, written so (no R - R cancellation)
        inner[curved] = (0.5 * wc - e) * wc / (6.0 * e * ri)
        outer[curved] = (0.5 * wc + e) * wc / (6.0 * e * ro)
    return inner, outer


def edge_stress_MPa(design, load_N: float, stations: int = 1500):
    """Nominal and curved-beam stress along both edges of flexure 0.

    Returns:
        (y (mm), nominal (MPa), right edge (MPa), left edge (MPa)), arrays of ``stations``.
    """
    rc = design.contact_radius_mm
    y, _, dx, ddx = fx.stations(design.centreline, rc, design.root_station_mm, stations)
    kappa = ddx / (1.0 + dx ** 2) ** 1.5
    w = np.asarray(design.width_mm(y))
    nominal = 6.0 * load_N * (y - rc) / (design.thickness_mm * w ** 2)
    inner, outer = winkler_factors(w, kappa)
    # centreline normal points to +x (right); x'' > 0 bends towards +x: the right edge is inner
    right = nominal * np.where(kappa > 0, inner, outer)
    left = nominal * np.where(kappa > 0, outer, inner)
    return y, nominal, right, left


def predict(design, load_N: float | None = None,
            cal: StressCalibration | None = None) -> StressPrediction:
    """Predicted peak stresses of a :class:`~springcad.design.spring.SpringDesign`.

    Args:
        design: the spring (its centreline, width law, root fillet and flare).
        load_N: tip load (N); default the load at the maximum deflection of the spring's
            target stiffness, ``K_target theta_max / (N r_c)`` (:func:`tip_load_N`).
        cal: coefficients; default the flexure shape's
            (:meth:`~springcad.design.shapes.FlexureShape.calibration`; the shipped
            :func:`calibration` for the built-in shapes).
    """
    cal = cal or design.flexure_shape.calibration()
    if load_N is None:
        load_N = tip_load_N(design)
    terms = root_terms(design, load_N)
    root = max(_root_model(t["nominal_MPa"], t["width_mm"], design.root_fillet_radius_mm,
                           t["curvature_factor"], cal) for t in terms)
    flank = _flank_model(max(t["flank_max_MPa"] for t in terms), design.thickness_mm,
                         root_width_mm(terms), cal)
    neck = cal.neck_factor * neck_nominal_MPa(design, load_N)
    return StressPrediction(nominal_MPa=terms[0]["nominal_max_MPa"], flank_MPa=float(flank),
                            root_MPa=float(root), neck_MPa=float(neck))


def root_width_mm(terms: list[dict]) -> float:
    """The width at the root tangent station of the edge whose root is the more loaded
    (nominal x curvature factor) (mm): the calibration rows' ``root_width_mm``."""
    return max(terms, key=lambda t: t["nominal_MPa"] * t["curvature_factor"])["width_mm"]


def tip_load_N(design) -> float:
    """Tip load of one flexure at the maximum deflection (N): K theta_max / (N r_c) with
    K the spring's *target* stiffness.

    The flexure is a cantilever loaded at its tip: its bending moment, and so every
    stress the model predicts, is proportional to the tip load whatever the rest of the
    ring adds in compliance, so the load must be the real spring's. The calibration
    rows take it from the FEA stiffness; a design's real stiffness is its target: the
    design search sizes the beam stiffness to it, and the FEA verification corrects the
    widths until the FEA stiffness is within its tolerance (1 %) of it. The beam
    stiffness of the corrected widths is off the target by what beam theory misses
    (paper S1 +2.8 %, the default -2.7 %, 2026-11-26), and put that error into the
    stress of the design handed to manufacture.
    """
    return (design.target_stiffness_Nmm_per_rad * design.max_deflection_rad
            / (design.n_flexures * design.contact_radius_mm))


def neck_nominal_MPa(design, load_N: float) -> float:
    """Beam stress 6 F (y_n - r_c) / (z w^2) where the neck fillets meet the edges (MPa)."""
    y_n = np.asarray(neck_tangent_stations_mm(design))
    w_n = np.asarray(design.width_mm(y_n))
    return float(np.max(6.0 * load_N * (y_n - design.contact_radius_mm)
                        / (design.thickness_mm * w_n ** 2)))


def root_terms(design, load_N: float) -> list[dict]:
    """Per edge: the nominal stress, width and curvature factor at the root tangent station."""
    y, nominal, right, left = edge_stress_MPa(design, load_N)
    out = []
    for y_t, edge in zip(root_tangent_stations_mm(design), (right, left)):
        k = int(np.clip(np.searchsorted(y, y_t), 0, len(y) - 1))
        # the fillet feels the bend just before it: the largest curved-beam factor within
        # one fillet radius of the tangent station
        near = (y >= y[k]) & (y <= y_t + design.root_fillet_radius_mm)
        factor = float(np.max(edge[near] / nominal[near])) if np.any(near) else 1.0
        out.append({"station_mm": float(y[k]), "nominal_MPa": float(nominal[k]),
                    "width_mm": float(design.width_mm(y[k])), "curvature_factor": factor,
                    "flank_max_MPa": float(np.max(edge[: k + 1])),
                    "nominal_max_MPa": float(np.max(nominal))})
    return out


def _flank_fit(rows: list[dict], aspect: bool = True) -> dict:
    """Flank coefficients of some rows: over the rows where the flank is the FEA peak
    (elsewhere the root fillet's stress runs into the flank region and is not a flank
    stress; all rows when none is), least squares of log(FEA / Winkler flank) on
    log(z / w_r) when ``aspect`` and those rows span three geometries or more, else the
    median ratio with no aspect term."""
    governed = [r for r in rows if r["fea_peak_region"] == "flexure flank"] or rows
    y = np.log([r["fea_flank_MPa"] / r["model_flank_MPa"] for r in governed])
    if (not aspect or len({r["case"] for r in governed}) < 3
            or any("thickness_mm" not in r for r in governed)):
        return {"flank_factor": float(np.exp(np.median(y))), "flank_aspect_exponent": 0.0}
    X = np.array([[1.0, math.log(r["thickness_mm"] / r["root_width_mm"])] for r in governed])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    return {"flank_factor": float(math.exp(coef[0])), "flank_aspect_exponent": float(coef[1])}


def flank_by_shape(rows: list[dict]) -> dict[str, dict]:
    """The flank coefficients of each flexure shape's own rows (rows with a ``flexure``
    key, :func:`_flank_fit`): a straight flexure has no curvature to model, and a
    serpentine's Winkler-Bach flank misses the FEA (2D x the 3D factor) by a factor that
    grows with the section's thickness over width (the plane-stress model's error)."""
    shapes = sorted({r["flexure"] for r in rows if "flexure" in r})
    return {s: _flank_fit([r for r in rows if r.get("flexure") == s]) for s in shapes}


def fit_calibration(rows: list[dict]) -> StressCalibration:
    """Fit the coefficients to FEA rows (see ``fea/calibrate.py`` for the row keys).

    Root: least squares of log(sigma_fea / sigma_nom) on log(w/r_f) and log(k_inner).
    Flank: the median ratio FEA / model where the flank is the FEA peak
    (:func:`_flank_fit`; per shape with the aspect term: :func:`flank_by_shape`). Neck: the
    largest ratio FEA / nominal. ``max_error_pct`` is over every row with its shape's
    flank factor. Deterministic.
    """
    X, Y, neck = [], [], []
    for r in rows:
        X.append([1.0, math.log(r["root_width_mm"] / r["root_fillet_radius_mm"]),
                  math.log(r["root_curvature_factor"])])
        Y.append(math.log(r["fea_root_MPa"] / r["root_nominal_MPa"]))
        neck.append(r["fea_neck_MPa"] / r["neck_nominal_MPa"])
    coef, *_ = np.linalg.lstsq(np.asarray(X), np.asarray(Y), rcond=None)
    cal = StressCalibration(**_flank_fit(rows, aspect=False),
                            root_coefficient=float(math.exp(coef[0])),
                            root_width_exponent=float(coef[1]),
                            root_curvature_exponent=float(coef[2]),
                            neck_factor=float(np.max(neck)), cases=len(rows))
    by_shape = flank_by_shape(rows)
    errors = [abs(predict_row(r, replace(cal, **by_shape.get(r.get("flexure"), {})))
                  / r["fea_peak_MPa"] - 1.0) for r in rows]
    return replace(cal, max_error_pct=100.0 * max(errors))


def _root_model(nominal_MPa, width_mm, fillet_radius_mm, curvature_factor, cal) -> float:
    return (nominal_MPa * cal.root_coefficient
            * (width_mm / fillet_radius_mm) ** cal.root_width_exponent
            * max(curvature_factor, 1e-9) ** cal.root_curvature_exponent)


def predict_row(row: dict, cal: StressCalibration) -> float:
    """The model's peak for one calibration row (MPa)."""
    root = _root_model(row["root_nominal_MPa"], row["root_width_mm"],
                       row["root_fillet_radius_mm"], row["root_curvature_factor"], cal)
    flank = _flank_model(row["model_flank_MPa"], row.get("thickness_mm", 1.0),
                         row["root_width_mm"], cal)
    return max(root, flank, cal.neck_factor * row["neck_nominal_MPa"])


def _flank_model(winkler_MPa, thickness_mm, root_width_mm, cal) -> float:
    return (cal.flank_factor * winkler_MPa
            * (thickness_mm / root_width_mm) ** cal.flank_aspect_exponent)
