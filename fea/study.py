"""One spring geometry meshed and solved on nested levels: the study behind a verification.

:class:`VerifyOptions` says how to verify. :func:`run_model` meshes the
one-flexure sector (:mod:`fea.mesh`) on the levels of the chosen model
(``"2d3d"``, ``"2d"``, ``"3d"``, or pytetwild meshes of the CAD sector), solves
each with :func:`solve_mesh` and Richardson-extrapolates K and the peak stress
(:mod:`fea.convergence`) into a :class:`ModelRun`; :func:`add_3d_factor` adds the
3D/2D factors from extruded quadratic tets on the same in-plane meshes.
:func:`support_study` compares the full ring held at its outer rim with it held
at its rim holes. The correction loop that drives these studies is
:mod:`fea.verify`. Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time
from dataclasses import dataclass

from fea import convergence as cv
from fea.geometry import ring_geometry, sector_geometry
from fea.mesh import fea_mesh_2d, fea_mesh_3d, mesh_face_levels
from fea.mesh_size import DEFAULT_SIZE, MeshSize
from fea.mesh_solid import mesh_solid
from fea.problem import LoadCase, Material, assemble, solver_material
from fea.results import StaticResult, evaluate
from fea.solve import solve
from springcad import parallel
from springcad.geometry.profile import extrude_profile
from springcad.options import VERIFY, check_verify
from springcad.parallel import single_threaded
from springcad.units import NMM_PER_NM



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

    model: str = VERIFY.model
    levels: int = VERIFY.levels
    size: MeshSize = DEFAULT_SIZE
    case: LoadCase = LoadCase(load=VERIFY.load)
    tolerance: float = VERIFY.tolerance_pct / 100.0
    max_iterations: int = 4
    max_stress_passes: int = 3
    correct: bool = VERIFY.correct
    keep_fields: bool = True
    support_study: bool = VERIFY.support_study
    mesher: str = VERIFY.mesher
    pytetwild_edge_fac: tuple = (0.04, 0.028, 0.02)
    contact: bool = VERIFY.contact

    def __post_init__(self):
        check_verify(self.model, self.levels, self.mesher, 100.0 * self.tolerance,
                     self.case.load)


def verify_options(model: str = VERIFY.model, levels: int = VERIFY.levels,
                   mesher: str = VERIFY.mesher, tolerance_pct: float = VERIFY.tolerance_pct,
                   correct: bool = VERIFY.correct, load: str = VERIFY.load,
                   support_study: bool = VERIFY.support_study, contact: bool = VERIFY.contact,
                   keep_fields: bool = True) -> VerifyOptions:
    """The :class:`VerifyOptions` of the public options (:mod:`springcad.options`).

    ``mesher="pytetwild"`` implies ``model="3d"`` (it makes 3D meshes only).

    Raises:
        ConfigError: naming the public parameter and what is allowed.
    """
    model = "3d" if mesher == "pytetwild" else model
    check_verify(model, levels, mesher, tolerance_pct, load)
    return VerifyOptions(model=model, levels=levels, mesher=mesher,
                         tolerance=tolerance_pct / 100.0, correct=bool(correct),
                         case=LoadCase(load=load), keep_fields=bool(keep_fields),
                         support_study=bool(support_study), contact=bool(contact))


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
    #: the 3D factor's solves of this geometry started ahead (a Pending), or None
    factor_ahead: object = None

    @property
    def coarse(self) -> bool:
        """A 2D study without its finest level (:func:`run_model` with ``coarse=True``)."""
        return bool(self.base2d) and self.study.results[0] is self.base2d[0]

    @property
    def settled(self) -> bool:
        """Whether this run's study states K and the peak stress well enough without the
        finest 2D level (:func:`coarse_suffices`; a full run always does)."""
        return not self.coarse or coarse_suffices(self.study)

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


#: a 2D study over levels 0..n-1 is final, the finest level n not solved, when it states K
#: within this relative error and the peak stress within :data:`COARSE_STRESS_ERROR`, both
#: sequences converging (monotone or converged). bench/convergence_levels.py: the default
#: job states 0.0005 % and 0.0026 % on levels 0..2, and its studies with and without the
#: finest level differ by < 0.0001 % on K and 0.006 % on the peak; paper S1 states 0.003 %
#: and 0.92 % (its levels 0..2 peak 0.39 % above the full study's), so S1 keeps its finest
#: level
COARSE_K_ERROR = 0.001
COARSE_STRESS_ERROR = 0.005


def coarse_suffices(study: cv.ConvergenceStudy) -> bool:
    """Whether a coarse 2D study (levels 0..n-1) is accurate enough to be the final one
    (:data:`COARSE_K_ERROR`, :data:`COARSE_STRESS_ERROR`)."""
    good = ("monotone", "converged")
    k, s = study.stiffness, study.peak_stress
    return (k.behaviour in good and s.behaviour in good and k.error <= COARSE_K_ERROR
            and s.error <= COARSE_STRESS_ERROR)


def run_model(design, material: Material, options: VerifyOptions, with_3d: bool,
              progress=_noop, ahead: contextlib.ExitStack | None = None,
              coarse: bool = False) -> ModelRun:
    """Mesh and solve one spring geometry on all levels of the chosen model.

    Model ``"2d3d"``: the 3D factor's solves (:func:`solve_3d_factor_levels`) run in a second
    process beside the 2D levels (:func:`springcad.parallel.ahead`; in the caller after them
    where steps do not run in a second process), applied when ``with_3d``. With ``ahead``
    (an ExitStack that stops the second process when it closes) they are started even when
    ``with_3d`` is False, and left pending as ``run.factor_ahead`` for the caller to apply
    (:func:`apply_3d_factor`) if the correction loop needs the factor of this geometry.

    ``coarse`` (models "2d3d" and "2d"): the finest 2D level is left out and the study is
    extrapolated over levels 0..n-1 (:attr:`ModelRun.coarse`), e.g. for a correction step
    whose K is far from the target; :func:`complete_run` adds the finest level later. The
    3D factor uses levels 0 and 1 only, so it is the same either way.
    """
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
    with contextlib.ExitStack() as own:
        factor = None
        if with_3d or ahead is not None:
            factor = parallel.ahead(ahead if ahead is not None else own, solve_3d_factor_levels,
                                    faces, geometry, design, material, options,
                                    progress=progress)
        run = ModelRun(study=None, geometry=geometry, faces=faces, mesh_time_s=mesh_time)
        _solve_2d_levels(run, n if coarse else n + 1, material, options, theta, progress)
        if with_3d:
            apply_3d_factor(run, factor.result())
        elif factor is not None:
            run.factor_ahead = factor
    return run


def _solve_2d_levels(run: ModelRun, count: int, material: Material, options: VerifyOptions,
                     theta_rad: float, progress=_noop) -> ModelRun:
    """Solve ``run``'s 2D levels from the first not yet solved up to ``count`` levels (0 ..
    count-1) and extrapolate its study over the last three: levels 1..n when all n+1 are
    solved, 0..n-1 for a coarse run. The fields are kept on the finest two levels (n - 1
    and n: a coarse run may be final, :attr:`ModelRun.settled`)."""
    res2 = list(run.base2d)
    n = options.levels
    for k in range(len(res2), count):
        progress(f"2D level {k}", None)
        t = time.perf_counter()
        fm = fea_mesh_2d(run.faces[k], run.geometry, k)
        run.mesh_time_s += time.perf_counter() - t
        res2.append(solve_mesh(fm, material, options.case, theta_rad,
                               options.keep_fields and k >= n - 1))
    run.base2d = tuple(res2)
    run.study = cv.study(res2[-n:], "2d")
    if count <= n:
        run.study = _change_floor(run.study)
    return run


def _change_floor(study: cv.ConvergenceStudy) -> cv.ConvergenceStudy:
    """A coarse study (levels 0..n-1) whose stated errors are at least the last change
    between its two finest levels: the three-grid estimate alone is not a bound there
    (the default job's peak on levels 0..2 states 0.0026 %, and level 3 moves it by
    0.0057 %, below the last change of 0.0063 %; the nodal peak converges with sampling
    noise at that level)."""
    def floored(e: cv.Extrapolation) -> cv.Extrapolation:
        last = abs(e.values[-1] - e.values[-2]) / abs(e.values[-1])
        return dataclasses.replace(e, error=max(e.error, last))

    return dataclasses.replace(study, stiffness=floored(study.stiffness),
                               peak_stress=floored(study.peak_stress))


def complete_run(run: ModelRun, design, material: Material, options: VerifyOptions,
                 progress=_noop) -> ModelRun:
    """Add the finest 2D level a coarse run (:func:`run_model` with ``coarse=True``) left out:
    the study is then that of a full run of the same geometry (levels 1..n), the 3D factors
    as they were. A full run is returned as it is."""
    if run.coarse:
        _solve_2d_levels(run, options.levels + 1, material, options,
                         design.max_deflection_rad, progress)
    return run


def _run_pytetwild(design, geometry, material, options, progress) -> ModelRun:
    """3D study on fTetWild meshes of the build123d sector solid (not nested)."""
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


def solve_3d_factor_levels(faces, geometry, design, material: Material, options: VerifyOptions,
                           progress=_noop) -> tuple[list[StaticResult], float]:
    """The 3D factor's solves: levels 0 and 1 of ``faces`` extruded into quadratic tets (layers
    doubling), with one thread in every native pool, BLAS and OpenMP (the mesher's too), as
    a second process runs it (:func:`springcad.parallel.single_threaded`), so the factor is
    the same number whether it is solved here or there, beside the 2D levels
    (:func:`run_model`; with one BLAS thread only, the serial and parallel builds' 3D peaks
    differed by 0.2 % and the corrected widths by 1.7e-12); returns the results and the
    meshing time (s)."""
    res3, mesh_time = [], 0.0
    with single_threaded():
        for k in (0, 1):
            progress(f"3D factor, level {k}", None)
            t = time.perf_counter()
            fm = fea_mesh_3d(faces[k], geometry, options.size.layers * 2 ** k, k)
            mesh_time += time.perf_counter() - t
            res3.append(solve_mesh(fm, material, options.case, design.max_deflection_rad,
                                   options.keep_fields and k == 1))
    return res3, mesh_time


def apply_3d_factor(run: ModelRun, solved: tuple[list[StaticResult], float]) -> ModelRun:
    """Set the 3D/2D factors of ``run`` from the 3D factor's solves
    (:func:`solve_3d_factor_levels` on ``run``'s faces and geometry).

    The factor's error is its change between the two levels, taken as a
    second-order change with the GCI safety factor: 1.25 |r1 - r0| / 3.
    """
    res3, mesh_time = solved
    run.mesh_time_s += mesh_time
    res2 = run.base2d
    rk = [r3.stiffness_Nmm_per_rad / r2.stiffness_Nmm_per_rad for r3, r2 in zip(res3, res2)]
    rs = [r3.peak_von_mises_MPa / r2.peak_von_mises_MPa for r3, r2 in zip(res3, res2)]
    run.factor_K, run.factor_stress = rk[1], rs[1]
    run.factor_K_error = cv.SAFETY_FACTOR * abs(rk[1] - rk[0]) / 3.0 / rk[1]
    run.factor_stress_error = cv.SAFETY_FACTOR * abs(rs[1] - rs[0]) / 3.0 / rs[1]
    run.check3d = tuple(res3)
    return run


def add_3d_factor(run: ModelRun, design, material: Material, options: VerifyOptions,
                  progress=_noop) -> ModelRun:
    """3D/2D factors on levels 0 and 1 (extruded quadratic tets, layers doubling), solved
    here (:func:`solve_3d_factor_levels`, :func:`apply_3d_factor`)."""
    return apply_3d_factor(run, solve_3d_factor_levels(run.faces, run.geometry, design,
                                                       material, options, progress))


def support_study(design, material: Material | None = None, size: MeshSize = DEFAULT_SIZE,
                  level: int = 0) -> dict:
    """How the rim is held: outer rim (housing) vs rim holes only (dowels/bolts).

    The full ring with its holes, 2D plane stress, one mesh, both supports.
    Measured for S1 (7 dowels, 28 flexures): K(holes) / K(rim) = 0.991, the free
    rim between dowels adding compliance. The sector model (outer rim held) is
    the verification default; this ratio says how far a dowel-held rim sits
    from it.
    """
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
