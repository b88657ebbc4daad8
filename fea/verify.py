"""FEA verification of designed springs, the correction loop, and stacks.

For each spring (:func:`verify_spring`):

1. The one-flexure sector (free sides, outer rim held, smooth tangential cam
   traction patch; see :mod:`fea.problem`) is meshed on nested levels and
   solved; K and the peak stress are Richardson-extrapolated with a stated
   discretisation error (:mod:`fea.convergence`).
2. Model (``VerifyOptions.model``):

   ``"2d3d"`` (default): the convergence study runs on 2D plane-stress
   quadratic triangles (0.1 s per solve), and quadratic tetrahedra of the
   same face, extruded through the thickness, give the 3D factors
   rho_K = K_3D / K_2D and rho_sigma = sigma_3D / sigma_2D on the same
   in-plane meshes (two levels, the layers doubling with the level). The
   reported values are the 2D extrapolations times these factors; the error
   combines the 2D Richardson error with the change of the factors between
   the two 3D levels. The 3D factor is ~+0.4 % on K for the paper springs (the
   4.5 mm thick disk is not quite plane stress near the thin tips).
   ``"3d"``: the convergence study itself on quadratic tets (slow, ~10x).
   ``"2d"``: plane stress only.
3. Correction: while |K_fea / K_target - 1| > tolerance, every flexure width is
   scaled by (K_target / K_fea)^(1/3) (K ~ w^3 on the same centreline,
   :func:`springcad.design.spring.with_width_scale`) and the spring is
   re-verified. Each iteration is reported. Stress cannot be corrected this
   way at a fixed target stiffness (sigma ~ w): a spring whose yield margin is
   below the required factor is reported as failing, with the reason.

:func:`verify_job` verifies every spring of a job and the stack (series K,
eq. 10 load case with the FEA stiffnesses, every spring's stress and margin).
Library code only; it never prints (progress goes to a callback).
Units: mm, N, MPa, N*mm, rad; JSON keys carry N*m where they say so.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

from fea import convergence as cv
from fea.geometry import sector_geometry
from fea.mesh import fea_mesh_2d, fea_mesh_3d, mesh_face_levels
from fea.mesh_size import DEFAULT_SIZE, MeshSize
from fea.problem import LoadCase, Material, assemble, solver_material
from fea.results import StaticResult, evaluate
from fea.solve import solve
from springcad.errors import DesignError, SpringcadError
from springcad.units import NMM_PER_NM

SCHEMA = "springcad.fea/1"
MODELS = ("2d3d", "2d", "3d")

#: default level-0 sizes: levels 1-3 of the 2D study have ~3k, 12k, 48k DOFs for the paper springs


class VerificationFailed(SpringcadError):
    """A verified spring or stack misses its stiffness target or its stress limit."""


def _noop(message: str, fraction: float | None = None) -> None:
    return None


@dataclass(frozen=True)
class VerifyOptions:
    """How to verify.

    Attributes:
        model: "2d3d" (default), "2d" or "3d" (see module docstring).
        levels: mesh levels in the convergence study (>= 3).
        size: level-0 mesh size rules (level 0 is only used by the 3D factor;
            the 2D study uses levels 1..levels).
        case: supports and cam load (:class:`~fea.problem.LoadCase`).
        tolerance: accepted |K_fea / K_target - 1| (-).
        max_iterations: stiffness correction iterations before giving up.
        max_stress_passes: redesigns at a lower beam stress when the FEA peak misses the
            required yield margin (each followed by stiffness correction).
        correct: run the correction loop (False: verify the design as is).
        keep_fields: keep displacement/stress fields of the final meshes for output.
        support_study: also solve the full ring with its rim holes held at the outer
            rim and at the holes only (2D, one mesh) and report the difference.
        mesher: "gmsh" (default: exact face, nested levels, extruded tets) or
            "pytetwild" (the build123d sector solid tetrahedralised by fTetWild at
            ``pytetwild_edge_fac`` levels; model "3d" only; ~1 min).
        pytetwild_edge_fac: fTetWild ideal edge lengths (fraction of the bounding
            box diagonal), coarse to fine.
        contact: also turn the rigid cam from 0 to +-theta_max against the final
            sector (:func:`fea.contact.contact_sweep`, on the 2D mesh of level 0).
    """

    model: str = "2d3d"
    levels: int = 3
    size: MeshSize = DEFAULT_SIZE
    case: LoadCase = LoadCase()
    tolerance: float = 0.01
    max_iterations: int = 4
    max_stress_passes: int = 3
    correct: bool = True
    keep_fields: bool = True
    support_study: bool = False
    mesher: str = "gmsh"
    pytetwild_edge_fac: tuple = (0.04, 0.028, 0.02)
    contact: bool = True

    def __post_init__(self):
        if self.mesher not in ("gmsh", "pytetwild"):
            raise SpringcadError(f"mesher '{self.mesher}' is not one of gmsh, pytetwild")
        if self.mesher == "pytetwild" and self.model != "3d":
            raise SpringcadError("the pytetwild mesher makes 3D meshes only: use model '3d'")
        if self.model not in MODELS:
            raise SpringcadError(f"FEA model '{self.model}' is not one of {', '.join(MODELS)}")
        if self.levels < 3:
            raise SpringcadError(f"a convergence study needs at least 3 mesh levels, got "
                                 f"{self.levels}")
        if not 0 < self.tolerance < 0.5:
            raise SpringcadError(f"stiffness tolerance {self.tolerance} must be in (0, 0.5)")


# ================================================================== one model
def solve_mesh(fm, material: Material, case: LoadCase, max_deflection_rad: float,
               keep_fields: bool = False, method: str | None = None) -> StaticResult:
    """Assemble, solve and post-process one mesh (timed)."""
    t0 = time.perf_counter()
    system = assemble(fm, material, case)
    t1 = time.perf_counter()
    u, info = solve(system, method)
    t2 = time.perf_counter()
    res = evaluate(fm, system, u, case, max_deflection_rad, {}, info, keep_fields=keep_fields)
    t3 = time.perf_counter()
    res.timings_s.update(assemble=t1 - t0, solve=t2 - t1, post=t3 - t2)
    return res


@dataclass
class ModelRun:
    """Solved levels of one spring geometry: the convergence study and the 3D factors."""

    study: cv.ConvergenceStudy
    geometry: object = None
    faces: tuple = ()
    factor_K: float = 1.0
    factor_stress: float = 1.0
    factor_K_error: float = 0.0
    factor_stress_error: float = 0.0
    check3d: tuple = ()
    base2d: tuple = ()
    mesh_time_s: float = 0.0

    @property
    def stiffness_Nmm_per_rad(self) -> float:
        return self.study.stiffness.extrapolated * self.factor_K

    @property
    def stiffness_error(self) -> float:
        return math.hypot(self.study.stiffness.error, self.factor_K_error)

    @property
    def peak_stress_MPa(self) -> float:
        return self.study.peak_stress.extrapolated * self.factor_stress

    @property
    def peak_stress_error(self) -> float:
        return math.hypot(self.study.peak_stress.error, self.factor_stress_error)

    @property
    def peak_result(self) -> StaticResult:
        """The solved mesh whose peak location is reported (3D when there is one)."""
        return self.check3d[-1] if self.check3d else self.study.finest

    def all_results(self) -> list:
        return list(self.base2d or self.study.results) + list(self.check3d)

    def carry_factor(self, other: "ModelRun") -> None:
        """Use another geometry's 3D factors (correction iterations between 3D checks)."""
        self.factor_K, self.factor_stress = other.factor_K, other.factor_stress
        self.factor_K_error, self.factor_stress_error = other.factor_K_error, \
            other.factor_stress_error


def run_model(design, material: Material, options: VerifyOptions, with_3d: bool,
              progress=_noop) -> ModelRun:
    """Mesh and solve one spring geometry on all levels of the chosen model."""
    geometry = sector_geometry(design)
    theta = design.max_deflection_rad
    case = options.case
    n = options.levels
    if options.mesher == "pytetwild":
        return _run_pytetwild(design, geometry, material, options, progress)
    t0 = time.perf_counter()
    faces = tuple(mesh_face_levels(geometry, options.size, n + 1,
                                   case.patch_half_width_mm(geometry.tip_radius_mm)))
    mesh_time = time.perf_counter() - t0
    keep = options.keep_fields
    if options.model == "3d":  # levels 0 .. n-1, layers doubling: uniform 3D refinement
        res = []
        for k in range(n):
            progress(f"3D level {k}", None)
            t = time.perf_counter()
            fm = fea_mesh_3d(faces[k], geometry, options.size.layers * 2 ** k, k)
            mesh_time += time.perf_counter() - t
            res.append(solve_mesh(fm, material, case, theta, keep and k == n - 1))
        return ModelRun(study=cv.study(res, "3d"), geometry=geometry, faces=faces,
                        mesh_time_s=mesh_time)
    res2 = []
    for k in range(0, n + 1):
        progress(f"2D level {k}", None)
        t = time.perf_counter()
        fm = fea_mesh_2d(faces[k], geometry, k)
        mesh_time += time.perf_counter() - t
        res2.append(solve_mesh(fm, material, case, theta, keep and k == n))
    run = ModelRun(study=cv.study(res2[1:], "2d"), geometry=geometry, faces=faces,
                   base2d=tuple(res2), mesh_time_s=mesh_time)
    if with_3d:
        add_3d_factor(run, design, material, options, progress)
    return run


def _run_pytetwild(design, geometry, material, options, progress) -> ModelRun:
    """3D study on fTetWild meshes of the build123d sector solid (not nested)."""
    from springcad.geometry.profile import extrude_profile

    from fea.mesh_solid import mesh_solid

    solid = extrude_profile(geometry.profile, geometry.thickness_mm, f"{design.name} sector")
    res, mesh_time = [], 0.0
    facs = list(options.pytetwild_edge_fac)
    for k, fac in enumerate(facs):
        progress(f"pytetwild level {k} (edge length {fac:g} x diagonal)", None)
        t = time.perf_counter()
        fm = mesh_solid(solid, geometry, "pytetwild", edge_length_fac=fac)
        fm.level = k
        mesh_time += time.perf_counter() - t
        res.append(solve_mesh(fm, material, options.case, design.max_deflection_rad,
                              options.keep_fields and k == len(facs) - 1))
    return ModelRun(study=cv.study(res, "3d", nested=False), geometry=geometry,
                    mesh_time_s=mesh_time)


def add_3d_factor(run: ModelRun, design, material: Material, options: VerifyOptions,
                  progress=_noop) -> ModelRun:
    """3D/2D factors on levels 0 and 1 (extruded quadratic tets, layers doubling).

    The factor's error is its change between the two levels, taken as a
    second-order change with the GCI safety factor: 1.25 |r1 - r0| / 3.
    """
    res3 = []
    for k in (0, 1):
        progress(f"3D factor, level {k}", None)
        t = time.perf_counter()
        fm = fea_mesh_3d(run.faces[k], run.geometry, options.size.layers * 2 ** k, k)
        run.mesh_time_s += time.perf_counter() - t
        res3.append(solve_mesh(fm, material, options.case, design.max_deflection_rad,
                               options.keep_fields and k == 1))
    res2 = run.base2d
    rk = [r3.stiffness_Nmm_per_rad / r2.stiffness_Nmm_per_rad for r3, r2 in zip(res3, res2)]
    rs = [r3.peak_von_mises_MPa / r2.peak_von_mises_MPa for r3, r2 in zip(res3, res2)]
    run.factor_K, run.factor_stress = rk[1], rs[1]
    run.factor_K_error = cv.SAFETY_FACTOR * abs(rk[1] - rk[0]) / 3.0 / rk[1]
    run.factor_stress_error = cv.SAFETY_FACTOR * abs(rs[1] - rs[0]) / 3.0 / rs[1]
    run.check3d = tuple(res3)
    return run


# ================================================================== one spring
@dataclass(repr=False)
class SpringVerification:
    """The verified spring: FEA stiffness and stress with errors, and the correction history.

    Stiffness N*mm/rad, stress MPa, lengths mm; ``to_dict`` gives the ``fea.json`` entry.
    """

    name: str
    design: object
    """The final (corrected) :class:`~springcad.design.spring.SpringDesign`."""
    original: object
    run: ModelRun
    model: str
    tolerance: float
    iterations: list
    required_safety_factor: float
    yield_strength_MPa: float
    timings_s: dict
    case: LoadCase
    notes: list = field(default_factory=list)
    support: dict | None = None
    contact: object | None = None
    """The :class:`~fea.contact.ContactSweep` of the final design (None: not run)."""

    def __repr__(self) -> str:
        return (f"SpringVerification({self.name!r}, K_fea={self.stiffness_fea_Nmm_per_rad:.6g} "
                f"N*mm/rad ({100 * self.error_vs_target:+.2f} % vs target), peak "
                f"{self.peak_von_mises_MPa:.0f} MPa, ok={self.ok})")

    @property
    def stiffness_fea_Nmm_per_rad(self) -> float:
        return self.run.stiffness_Nmm_per_rad

    @property
    def stiffness_target_Nmm_per_rad(self) -> float:
        return self.design.target_stiffness_Nmm_per_rad

    @property
    def error_vs_target(self) -> float:
        return self.stiffness_fea_Nmm_per_rad / self.stiffness_target_Nmm_per_rad - 1.0

    @property
    def peak_von_mises_MPa(self) -> float:
        return self.run.peak_stress_MPa

    @property
    def yield_margin(self) -> float:
        return self.yield_strength_MPa / self.peak_von_mises_MPa

    @property
    def fatigue(self):
        """Fully reversed fatigue at +-theta_max from the FEA peak (or None without data)."""
        from springcad.design import fatigue

        return fatigue.check(self.design.material.material.name, self.peak_von_mises_MPa)

    @property
    def stiffness_ok(self) -> bool:
        return abs(self.error_vs_target) <= self.tolerance

    @property
    def stress_ok(self) -> bool:
        return self.yield_margin >= self.required_safety_factor

    @property
    def ok(self) -> bool:
        return self.stiffness_ok and self.stress_ok

    def failures(self) -> list[str]:
        return self.stiffness_failures() + self.stress_failures()

    def stiffness_failures(self) -> list[str]:
        out = []
        if not self.stiffness_ok:
            out.append(f"spring {self.name}: FEA stiffness "
                       f"{self.stiffness_fea_Nmm_per_rad / NMM_PER_NM:.2f} N*m/rad misses the "
                       f"target {self.stiffness_target_Nmm_per_rad / NMM_PER_NM:.2f} by "
                       f"{100 * self.error_vs_target:+.2f} % "
                       f"(tolerance {100 * self.tolerance:.2g} %)")
        return out

    def stress_failures(self) -> list[str]:
        out = []
        if not self.stress_ok:
            r = self.run.peak_result
            out.append(
                f"spring {self.name}: peak von Mises {self.peak_von_mises_MPa:.0f} MPa at the "
                f"{r.peak_region} gives a yield margin {self.yield_margin:.3f} below the required "
                f"{self.required_safety_factor:.3g} after the stress correction (see the "
                "correction iterations and notes): lower design_stress_MPa, thicken the disk "
                "or lower the deflection")
        return out

    def to_dict(self) -> dict:
        run, d = self.run, self.design
        st = run.study
        pr = run.peak_result
        finest = st.finest
        q2 = finest.mesh
        out = {
            "stiffness_fea_Nm_per_rad": self.stiffness_fea_Nmm_per_rad / NMM_PER_NM,
            "stiffness_beam_Nm_per_rad": d.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "stiffness_beam_original_Nm_per_rad":
                self.original.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "stiffness_target_Nm_per_rad": self.stiffness_target_Nmm_per_rad / NMM_PER_NM,
            "error_vs_target_pct": 100.0 * self.error_vs_target,
            "fea_vs_beam_pct": 100.0 * (self.stiffness_fea_Nmm_per_rad
                                        / d.stiffness_beam_Nmm_per_rad - 1.0),
            "discretisation_error_pct": 100.0 * run.stiffness_error,
            "tolerance_pct": 100.0 * self.tolerance,
            "peak_von_mises_MPa": self.peak_von_mises_MPa,
            "peak_von_mises_error_pct": 100.0 * run.peak_stress_error,
            "peak_stress_kind": "nodal (element stresses at their quadratic nodes, averaged); "
                                "excludes the held-face zone and the cam contact patch",
            "peak_ip_von_mises_MPa": pr.peak_ip_von_mises_MPa,
            "peak_location_mm": list(pr.peak_location_mm),
            "peak_region": pr.peak_region,
            "peak_by_region_MPa": dict(finest.peak_by_region_MPa),
            "peak_by_region_note": f"{st.model} finest level, not extrapolated",
            "max_deflection_rad": d.max_deflection_rad,
            "torque_at_max_deflection_Nm": self.stiffness_fea_Nmm_per_rad * d.max_deflection_rad
            / NMM_PER_NM,
            "design_stress_MPa": d.material.design_stress_MPa,
            "peak_stress_beam_MPa": d.peak_stress_MPa,
            "yield_strength_MPa": self.yield_strength_MPa,
            "yield_margin": self.yield_margin,
            "fatigue": self.fatigue.to_dict() if self.fatigue is not None else None,
            "required_safety_factor": self.required_safety_factor,
            "stiffness_ok": self.stiffness_ok,
            "stress_ok": self.stress_ok,
            "ok": self.ok,
            "failures": self.failures(),
            "width_scale": d.width_scale,
            "model": self.model,
            "factor_3d_over_2d": {"stiffness": run.factor_K, "peak_stress": run.factor_stress,
                                  "stiffness_error_pct": 100 * run.factor_K_error,
                                  "peak_stress_error_pct": 100 * run.factor_stress_error},
            "load_case": {"support": self.case.support, "load": self.case.load,
                          "patch_half_angle_deg": math.degrees(self.case.patch_half_angle_rad),
                          "model": "one-flexure sector, free sides, outer rim held"},
            "dofs": finest.dofs,
            "n_elements": finest.n_elements,
            "mesh_quality": q2.quality.to_dict() if q2 is not None else None,
            "convergence": st.to_list(),
            "richardson": st.to_dict(),
            "correction_iterations": list(self.iterations),
            "timings_s": dict(self.timings_s),
            "notes": list(self.notes),
        }
        if self.support is not None:
            out["support_study"] = dict(self.support)
        if self.contact is not None:
            out["contact_sweep"] = self.contact.to_dict()
        if run.check3d:
            c3 = run.check3d[-1]
            out["dofs_3d"] = c3.dofs
            out["n_elements_3d"] = c3.n_elements
            out["mesh_quality_3d"] = c3.mesh.quality.to_dict() if c3.mesh is not None else None
            out["mesh_quality_3d_note"] = (
                "quadratic tets from prisms of the extruded face mesh (upper half, mid-plane "
                "symmetry): long through the thickness by design, where the field varies "
                "slowly; small dihedral angles are that elongation, not slivers. The layer "
                "doubling between the two 3D levels measures its effect (factor error).")
            out["check_3d"] = [{"level": r.level, "dofs": r.dofs,
                                "stiffness_Nm_per_rad": r.stiffness_Nmm_per_rad / NMM_PER_NM,
                                "peak_von_mises_MPa": r.peak_von_mises_MPa,
                                "peak_location_mm": list(r.peak_location_mm)}
                               for r in run.check3d]
        return out


def _iteration_record(k, design, run: ModelRun, target, action) -> dict:
    return {"iteration": k, "width_scale": design.width_scale,
            "stiffness_fea_Nm_per_rad": run.stiffness_Nmm_per_rad / NMM_PER_NM,
            "stiffness_2d_Nm_per_rad": run.study.stiffness.extrapolated / NMM_PER_NM,
            "factor_3d_over_2d": run.factor_K,
            "stiffness_beam_Nm_per_rad": design.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "error_vs_target_pct": 100.0 * (run.stiffness_Nmm_per_rad / target - 1.0),
            "discretisation_error_pct": 100.0 * run.stiffness_error,
            "peak_von_mises_MPa": run.peak_stress_MPa,
            "action": action}


def verify_spring(design, options: VerifyOptions = VerifyOptions(), progress=_noop,
                  material: Material | None = None) -> SpringVerification:
    """Verify one designed spring and correct its widths until K meets the target.

    Args:
        design: :class:`~springcad.design.spring.SpringDesign` with its ring profile.
        options: :class:`VerifyOptions`.
        progress: callable ``(message, fraction or None)`` for long steps.
        material: override of the design's material (default: from the design).

    Raises:
        SolverError, MeshingError: the model cannot be built or solved (no number
            is produced from a failed solve).
    """
    t_start = time.perf_counter()
    material = material or solver_material(design.material)
    target = design.target_stiffness_Nmm_per_rad
    with_3d = options.model == "2d3d"
    original = design
    iterations: list[dict] = []
    notes: list[str] = []
    previous = None  # run whose 3D factors are carried between 3D checks
    k = 0
    stress_passes = 0
    while True:
        progress(f"spring {design.name}: iteration {k} (width scale {design.width_scale:.5f})",
                 None)
        need_3d = with_3d and previous is None
        run = run_model(design, material, options, need_3d, progress)
        if with_3d and not need_3d:
            run.carry_factor(previous)
        K = run.stiffness_Nmm_per_rad
        done = abs(K / target - 1.0) <= options.tolerance
        if done and with_3d and not need_3d:
            progress(f"spring {design.name}: 3D factor at the corrected geometry", None)
            add_3d_factor(run, design, material, options, progress)
            K = run.stiffness_Nmm_per_rad
            done = abs(K / target - 1.0) <= options.tolerance
        if with_3d and run.check3d:
            previous = run
        err = K / target - 1.0
        margin = material.yield_strength_MPa / run.peak_stress_MPa
        required = design.material.safety_factor
        if (done and options.correct and margin < required
                and stress_passes < options.max_stress_passes):
            # K is right but the real geometry is over-stressed: redesign at a lower beam
            # stress (the raisers scale with it), then correct K again
            stress_passes += 1
            bias = run.peak_stress_MPa / design.predicted_peak_stress_MPa
            iterations.append(_iteration_record(
                k, design, run, target, f"redesign for the FEA peak ({bias:.3f} x the design's "
                f"prediction; yield margin {margin:.3f} < {required:g})"))
            try:
                from springcad.design import spring as spring_design

                design = spring_design.redesign_for_margin(design, bias * (1.0 + 0.01 * stress_passes))
            except DesignError as exc:
                notes.append(f"stress correction stopped: {exc}")
                break
            previous = None
            k += 1
            continue
        if done or not options.correct:
            iterations.append(_iteration_record(k, design, run, target,
                                                "accepted" if done else "not corrected"))
            break
        if k >= options.max_iterations + stress_passes:
            iterations.append(_iteration_record(k, design, run, target, "stopped"))
            notes.append(f"correction stopped after {k} iterations at {100 * err:+.2f} % "
                         f"from the target")
            break
        new_scale = design.width_scale * (target / K) ** (1.0 / 3.0)
        iterations.append(_iteration_record(
            k, design, run, target, f"rescale widths x{new_scale / design.width_scale:.5f}"))
        try:
            from springcad.design.spring import with_width_scale

            design = with_width_scale(design, new_scale)
        except DesignError as exc:
            notes.append(f"correction stopped: {exc}")
            break
        k += 1
    if run.study.peak_stress.behaviour == "diverging" and not math.isfinite(
            run.study.peak_stress.error):
        notes.append(f"the peak stress at the {run.peak_result.peak_region} grows under mesh "
                     "refinement: a stress singularity (sharp corner?) in the geometry")
    if options.model == "2d3d" and run.check3d:
        notes.append("2D plane-stress Richardson extrapolation x 3D factor from extruded "
                     "quadratic tets on the same in-plane meshes")
    support = None
    if options.support_study:
        progress(f"spring {design.name}: support study on the full ring with its holes", None)
        support = support_study(design, material, options.size)
    contact = None
    if options.contact:
        from fea.contact import contact_sweep

        progress(f"spring {design.name}: cam contact sweep", None)
        try:
            contact = contact_sweep(design, material, run, progress=progress)
        except SpringcadError as exc:  # a check on top of the verification: never fatal
            notes.append(f"cam contact sweep failed: {exc}")
    total = time.perf_counter() - t_start
    timings = {"mesh": run.mesh_time_s,
               "assemble": sum(r.timings_s["assemble"] for r in run.all_results()),
               "solve": sum(r.timings_s["solve"] for r in run.all_results()),
               "post": sum(r.timings_s["post"] for r in run.all_results()),
               "total_with_correction": total}
    return SpringVerification(
        name=design.name, design=design, original=original, run=run, model=options.model,
        tolerance=options.tolerance, iterations=iterations,
        required_safety_factor=design.material.safety_factor,
        yield_strength_MPa=material.yield_strength_MPa, timings_s=timings, case=options.case,
        notes=notes, support=support, contact=contact)


def support_study(design, material: Material | None = None, size: MeshSize = DEFAULT_SIZE,
                  level: int = 0) -> dict:
    """How the rim is held: outer rim (housing) vs rim holes only (dowels/bolts).

    The full ring with its holes, 2D plane stress, one mesh, both supports.
    Measured for S1 (7 dowels, 28 flexures): K(holes) / K(rim) = 0.991, the free
    rim between dowels adding compliance. The sector model (outer rim held) is
    the verification default; this ratio says how far a dowel-held rim sits
    from it.
    """
    from fea.geometry import ring_geometry

    material = material or solver_material(design.material)
    g = ring_geometry(design, holes=True)
    if not g.hole_centres_mm:
        return {"note": "the ring has no rim holes; held at the outer rim only"}
    fm = fea_mesh_2d(mesh_face_levels(g, size, level + 1)[level], g, level)
    theta = design.max_deflection_rad
    out = {"model": "full ring with rim holes, 2D plane stress", "dofs": None}
    for sup in ("rim", "holes"):
        r = solve_mesh(fm, material, LoadCase(support=sup), theta)
        out["dofs"] = r.dofs
        out[sup] = {"stiffness_Nm_per_rad": r.stiffness_Nmm_per_rad / NMM_PER_NM,
                    "peak_von_mises_MPa": r.peak_von_mises_MPa, "peak_region": r.peak_region,
                    "peak_location_mm": list(r.peak_location_mm),
                    "excluded_zone_peak_MPa": r.excluded_peak_MPa}
    out["stiffness_holes_over_rim"] = (out["holes"]["stiffness_Nm_per_rad"]
                                       / out["rim"]["stiffness_Nm_per_rad"])
    return out


# ================================================================== stacks
@dataclass
class StackVerification:
    """A stack from verified springs: series K and the eq. 10 load case (N*mm, rad, MPa)."""

    sequence: tuple
    stiffness_Nmm_per_rad: float
    target_Nmm_per_rad: float
    max_deflection_rad: float
    torque_at_limit_Nmm: float
    limiting_spring: str
    springs: list
    required_safety_factor: float

    @property
    def ok(self) -> bool:
        return all(s["yield_margin"] >= self.required_safety_factor for s in self.springs)

    def failures(self) -> list[str]:
        return [f"stack: spring #{i + 1} ({s['spring']}) at the stack limit "
                f"{self.max_deflection_rad:.3f} rad carries {s['torque_Nm']:.2f} N*m, peak "
                f"{s['peak_von_mises_MPa']:.0f} MPa, yield margin {s['yield_margin']:.3f} < "
                f"{self.required_safety_factor:.3g}"
                for i, s in enumerate(self.springs)
                if s["yield_margin"] < self.required_safety_factor]

    def to_dict(self) -> dict:
        return {"sequence": list(self.sequence),
                "stiffness_fea_Nm_per_rad": self.stiffness_Nmm_per_rad / NMM_PER_NM,
                "stiffness_target_Nm_per_rad": self.target_Nmm_per_rad / NMM_PER_NM,
                "error_vs_target_pct": 100 * (self.stiffness_Nmm_per_rad / self.target_Nmm_per_rad
                                              - 1),
                "max_deflection_rad": self.max_deflection_rad,
                "torque_at_limit_Nm": self.torque_at_limit_Nmm / NMM_PER_NM,
                "limiting_spring": self.limiting_spring,
                "springs": self.springs, "ok": self.ok, "failures": self.failures()}


def verify_stack(sequence, verified: dict, required_safety_factor: float) -> StackVerification:
    """Series stiffness and eq. 10 with FEA stiffnesses; each spring's torque, stress, margin.

    At the stack limit every spring carries the same torque T = min_i(theta_max,i K_i);
    a spring's peak stress scales linearly from its own verified value at its
    maximum deflection: sigma_i = sigma_i(theta_max,i) * T / (K_i theta_max,i).
    """
    from springcad.design.stack import eq10_limit, series_stiffness

    ks = [verified[n].stiffness_fea_Nmm_per_rad for n in sequence]
    limits = [verified[n].design.max_deflection_rad for n in sequence]
    limit, torque, shares = eq10_limit(limits, ks)
    springs = []
    for n, k, th_max, th in zip(sequence, ks, limits, shares):
        v = verified[n]
        sigma = v.peak_von_mises_MPa * torque / (k * th_max)
        springs.append({"spring": n, "deflection_rad": th, "fraction_of_own_limit": th / th_max,
                        "torque_Nm": torque / NMM_PER_NM, "peak_von_mises_MPa": sigma,
                        "yield_margin": v.yield_strength_MPa / sigma})
    t = [th * k for th, k in zip(limits, ks)]
    return StackVerification(
        sequence=tuple(sequence), stiffness_Nmm_per_rad=series_stiffness(ks),
        target_Nmm_per_rad=series_stiffness([verified[n].stiffness_target_Nmm_per_rad
                                             for n in sequence]),
        max_deflection_rad=limit, torque_at_limit_Nmm=torque,
        limiting_spring=sequence[t.index(min(t))], springs=springs,
        required_safety_factor=required_safety_factor)


@dataclass(repr=False)
class JobVerification:
    """Every spring of a job verified (and corrected), and the stack."""

    job_name: str
    springs: dict
    stack: StackVerification
    options: VerifyOptions
    timings_s: dict

    @property
    def ok(self) -> bool:
        """Every spring meets its stiffness target and every spring's yield margin in the
        stack's eq. 10 load case meets the required factor (a spring that the stack never
        drives to its own limit is judged at the load it actually carries)."""
        return all(v.stiffness_ok for v in self.springs.values()) and self.stack.ok

    def __repr__(self) -> str:
        return (f"JobVerification({self.job_name!r}, springs={list(self.springs.values())!r}, "
                f"ok={self.ok})")

    def failures(self) -> list[str]:
        out = []
        for v in self.springs.values():
            out += v.stiffness_failures()
        return out + self.stack.failures()

    def notes(self) -> list[str]:
        """Spring-level stress failures that the stack load case does not reach."""
        out = []
        shares = {s["spring"]: s for s in self.stack.springs}
        for n, v in self.springs.items():
            if not v.stress_ok and n in shares and shares[n]["yield_margin"] >= \
                    self.stack.required_safety_factor:
                out.append(f"spring {n} alone, at its own limit, has yield margin "
                           f"{v.yield_margin:.3f} < {v.required_safety_factor:.3g}; in this "
                           f"stack it reaches {100 * shares[n]['fraction_of_own_limit']:.0f} % "
                           f"of that limit (margin {shares[n]['yield_margin']:.3f})")
        return out

    def raise_for_failures(self) -> None:
        """Raise :class:`VerificationFailed` listing every failure (for ``springcad build``)."""
        if not self.ok:
            raise VerificationFailed("FEA verification failed: " + "; ".join(self.failures()))

    def corrected_designs(self) -> dict:
        """Spring name -> the corrected :class:`SpringDesign` (what ``build`` should export)."""
        return {n: v.design for n, v in self.springs.items()}

    def corrected_job_design(self, job_design):
        """The job design with every spring replaced by its corrected design and the stack
        rebuilt from them (what ``springcad build`` should export after verification)."""
        from dataclasses import replace as dc_replace

        from springcad.design.stack import design_stack

        springs = {n: self.springs[n].design if n in self.springs else d
                   for n, d in job_design.springs.items()}
        job = job_design.job
        stack = design_stack([springs[n] for n in job.stack.sequence], job.stack.input,
                             job.analysis.monte_carlo_samples, job.analysis.seed)
        return dc_replace(job_design, springs=springs, stack=stack)

    def to_dict(self) -> dict:
        from springcad.version import __version__

        return {"schema": SCHEMA, "springcad_version": __version__, "job": self.job_name,
                "options": {"model": self.options.model, "levels": self.options.levels,
                            "mesher": self.options.mesher,
                            "tolerance_pct": 100 * self.options.tolerance,
                            "support": self.options.case.support,
                            "load": self.options.case.load},
                "springs": {n: v.to_dict() for n, v in self.springs.items()},
                "stack": self.stack.to_dict(), "ok": self.ok, "failures": self.failures(),
                "notes": self.notes(), "timings_s": dict(self.timings_s)}

    def summary(self) -> str:
        rows = [("spring", "K_fea", "K_beam", "target", "err %", "disc %", "sigma MPa", "design",
                 "where", "margin", "req", "fatigue", "iters", "ok alone")]
        for n, v in self.springs.items():
            r = v.run.peak_result
            fat = v.fatigue
            fat_txt = ("-" if fat is None else f"{fat.margin:.2f}" if fat.margin >= 1
                       else f"{fat.life_cycles:.2g} cyc")
            rows.append((n, f"{v.stiffness_fea_Nmm_per_rad / 1e3:.2f}",
                         f"{v.design.stiffness_beam_Nmm_per_rad / 1e3:.2f}",
                         f"{v.stiffness_target_Nmm_per_rad / 1e3:.2f}",
                         f"{100 * v.error_vs_target:+.2f}", f"{100 * v.run.stiffness_error:.3f}",
                         f"{v.peak_von_mises_MPa:.0f}", f"{v.design.predicted_peak_stress_MPa:.0f}",
                         r.peak_region, f"{v.yield_margin:.3f}", f"{v.required_safety_factor:.2f}",
                         fat_txt, str(len(v.iterations) - 1), "yes" if v.ok else "NO"))
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]
        st = self.stack
        lines.append(f"stack {' + '.join(st.sequence)}: K_fea {st.stiffness_Nmm_per_rad / 1e3:.2f} "
                     f"N*m/rad (target {st.target_Nmm_per_rad / 1e3:.2f}), limit "
                     f"{st.max_deflection_rad:.3f} rad at {st.torque_at_limit_Nmm / 1e3:.2f} N*m")
        lines.append("sigma: FEA peak von Mises at the max deflection; design: the design's "
                     "prediction for the same geometry; fatigue: endurance margin at +-theta_max "
                     "(R = -1, wire-EDM surface), or the finite life")
        lines += [f"FAIL: {f}" for f in self.failures()]
        lines += [f"note: {n}" for n in self.notes()]
        lines += [f"contact {n}: {f['message']}" for n, v in self.springs.items()
                  if v.contact is not None for f in v.contact.flags]
        return "\n".join(lines)


def verify_job(job_design, options: VerifyOptions = VerifyOptions(), progress=_noop
               ) -> JobVerification:
    """Verify (and correct) every spring of a :class:`~springcad.design.job.JobDesign`.

    Returns a :class:`JobVerification` with ``.to_dict()`` (the ``fea.json``
    document), ``.ok``, ``.failures()``, ``.raise_for_failures()`` and
    ``.corrected_designs()``. Springs used several times in the stack are
    verified once.
    """
    t0 = time.perf_counter()
    springs = {}
    names = list(job_design.springs)
    for i, name in enumerate(names):
        progress(f"verifying spring {name} ({i + 1}/{len(names)})", i / len(names))
        springs[name] = verify_spring(job_design.springs[name], options, progress)
    progress("stack", 1.0)
    sf = job_design.job.material.safety_factor
    stack = verify_stack(job_design.stack.sequence, springs, sf)
    return JobVerification(job_name=job_design.job.name, springs=springs, stack=stack,
                           options=options, timings_s={"total": time.perf_counter() - t0})


def with_options(options: VerifyOptions, **kw) -> VerifyOptions:
    """``dataclasses.replace`` for options (convenience for the CLI and tests)."""
    return replace(options, **kw)


__all__ = ["VerifyOptions", "SpringVerification", "StackVerification", "JobVerification",
           "VerificationFailed", "verify_spring", "verify_stack", "verify_job", "run_model",
           "support_study",
           "solve_mesh", "DEFAULT_SIZE"]
