"""FEA calibration of the design-side stress model (:mod:`springcad.design.stress`).

One calibration row is one spring geometry solved as the verification solves it
(:func:`fea.study.run_model`, the default ``2d3d`` model: 2D plane-stress levels
Richardson-extrapolated, times the 3D factor of extruded quadratic tets), so the
design side is fitted to the very number ``fea.json`` reports. Per region of the
cut faces (flank, root fillet, neck fillet) the row holds the region's peak as the
duty judges it (:func:`fea.fatigue.region_peaks_MPa`: the region's 2D Richardson
extrapolation times its own 3D factor); next to them the model's terms at the same load (the tip load of the FEA stiffness at the
maximum deflection, so that a stiffness error does not leak into the stress fit). The set spans the templates' springs and
root flares 0-0.3 (the range the design chooses from); :func:`calibrate` fits
the coefficients. ``bench/calibrate_stress.py`` writes the shipped file;
``tests/fea/test_stress_calibration.py`` re-runs part of it.

Units: mm, N, MPa.
"""

from __future__ import annotations

from fea.fatigue import region_peaks_MPa
from fea.geometry import sector_geometry
from fea.mesh import fea_mesh_2d, mesh_face_levels
from fea.mesh_size import DEFAULT_SIZE
from fea.problem import LoadCase, solver_material
from fea.study import run_model, solve_mesh, verify_options
from springcad.design import stress
from springcad.design.resize import with_root
from springcad.design.stress import fit_calibration

#: root flares of the calibration set (the design chooses within this range)
FLARES = (0.0, 0.1, 0.2, 0.3)
#: mesh level of a single 2D solve (:func:`solve_2d`; the verification's level 2: K within
#: ~0.1 %)
LEVEL = 2


def solve_2d(design, level: int = LEVEL):
    """One 2D solve of the spring's sector at mesh ``level``: a :class:`~fea.results.StaticResult`."""
    geometry = sector_geometry(design)
    case = LoadCase()
    faces = mesh_face_levels(geometry, DEFAULT_SIZE, level + 1,
                             case.patch_half_width_mm(geometry.tip_radius_mm))
    fm = fea_mesh_2d(faces[level], geometry, level)
    return solve_mesh(fm, solver_material(design.material), case, design.max_deflection_rad)


#: the cut-face regions the model predicts
REGIONS = ("flexure flank", "root fillet", "tip-neck fillet")


def calibration_row(design, label: str = "") -> dict:
    """FEA peaks and model terms of one spring geometry (see the module docstring)."""
    options = verify_options(contact=False, keep_fields=False, correct=False)
    run = run_model(design, solver_material(design.material), options,
                    options.model == "2d3d")
    res = run.study.finest
    load = (run.stiffness_Nmm_per_rad * design.max_deflection_rad
            / (design.n_flexures * design.contact_radius_mm))
    terms = stress.root_terms(design, load)
    root = max(terms, key=lambda t: t["nominal_MPa"] * t["curvature_factor"])
    by_region = region_peaks_MPa(run)
    return {
        "case": label, "flexure": design.flexure, "thickness_mm": design.thickness_mm,
        "root_flare": design.root_flare,
        "n_flexures": design.n_flexures,
        "load_N": load, "root_fillet_radius_mm": design.root_fillet_radius_mm,
        "root_nominal_MPa": root["nominal_MPa"], "root_width_mm": root["width_mm"],
        "root_curvature_factor": root["curvature_factor"],
        "model_flank_MPa": max(t["flank_max_MPa"] for t in terms),
        "neck_nominal_MPa": stress.neck_nominal_MPa(design, load),
        "fea_root_MPa": by_region.get("root fillet", 0.0),
        "fea_flank_MPa": by_region.get("flexure flank", 0.0),
        "fea_neck_MPa": by_region.get("tip-neck fillet", 0.0),
        "fea_peak_MPa": max(by_region.get(r, 0.0) for r in REGIONS),
        "fea_peak_region": max(REGIONS, key=lambda r: by_region.get(r, 0.0)),
        "fea_verified_peak_MPa": run.peak_stress_MPa,
        "factor_3d_stress": run.factor_stress, "factor_3d_stiffness": run.factor_K,
        "mesh_level": len(run.study.results), "dofs": res.dofs,
    }


def calibration_rows(designs: dict, flares=FLARES, progress=None) -> list[dict]:
    """Rows for every (spring, flare) pair.

    Args:
        designs: label -> :class:`~springcad.design.spring.SpringDesign` (flare 0).
        flares: root flares to impose (:func:`springcad.design.resize.with_root`).
        progress: optional ``progress(message, fraction)`` callable.
    """
    rows = []
    total = len(designs) * len(flares)
    for i, (label, design) in enumerate(designs.items()):
        for j, flare in enumerate(flares):
            if progress:
                progress(f"{label} flare {flare:g}", (i * len(flares) + j) / total)
            d = with_root(design, flare)
            rows.append(calibration_row(d, label))
    return rows


def calibrate(rows: list[dict]):
    """Fitted :class:`~springcad.design.stress.StressCalibration` of the rows."""
    return fit_calibration(rows)
