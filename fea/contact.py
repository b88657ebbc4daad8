"""Cam-flexure contact over the full deflection: a rotation sweep of the rigid cam.

Model
    The one-flexure sector of the verification (2D plane stress, quadratic
    triangles, outer rim held; its level-0 mesh is reused) against the cam
    profile of the design, rigid (the cam is much stiffer than a slender
    flexure) and turned by a prescribed angle theta about the ring axis. The
    designed gap w_gap is in the geometry: no load is applied, the ring is
    loaded only by the frictionless contact forces. Sector periodicity: every
    flexure meets its tooth alike, so the sector meets the cam pockets -2..2
    around its own, and the gap to the neighbouring flexure is the gap between
    the deformed sector and itself turned by one pitch.
    Kinematics are total Lagrangian (:mod:`fea.nonlinear`; ``nonlinear=False``:
    linear): the ball's radial motion decides where it bears on the cam, and
    the flexure's foreshortening (~0.6 delta^2 / L, tens of um) is of the order
    of w_gap. A serpentine flexure can also couple tangential load and radial tip
    motion: pushed one way the ball climbs the flank, pushed the other it sinks
    into the pocket, and the linear FEA's tangential traction sees none of it.
    The design's serpentines are shaped to cancel that coupling
    (:func:`springcad.design.flexure.uncoupled_tilt`); this sweep is what checks
    that the ball then stays on its flank.

Contact
    Points on the quadratic boundary of ball, neck fillets and edges within
    reach of the cam (:mod:`fea.contact_solver`, 8 per element edge), the cam
    contour as a 1 um polyline; per Newton iteration the gaps of the points
    near the cam are linearised and the complementarity problem is solved
    exactly; converged on the true geometry (no penetration > 1e-7 mm,
    out-of-balance < 1e-7 of the contact force). The cam angle advances in
    steps of theta_max / steps with a linear predictor; a step that cannot be
    converged is halved, and past a limit point (the ball snapping over a tooth
    tip) the state is allowed to jump, which is flagged.

What each step reports and when the sweep is flagged: :mod:`fea.contact_result`.

Geometry access to the design's ring and cam profiles is confined to the adapter
section below. Units: mm, N, MPa, N*mm, rad inside; JSON keys carry N*m and deg
where they say so.
"""

from __future__ import annotations

import contextlib
import math
import time

import numpy as np

from fea.contact_path import AnglePath, Stuck, offset_path, onset_rad
from fea.contact_result import ContactOptions, ContactStep, ContactSweep, direction_flags
from fea.contact_solver import CamCurve, SectorContact, State, hertz_line_contact, rot
from fea.contact_tolerance import RING_TO_RING, BallLayout, ContactMaterial, EndState, assess
from fea.geometry import sector_geometry
from fea.mesh import fea_mesh_2d, mesh_face_levels
from fea.mesh_size import DEFAULT_SIZE
from fea.problem import LoadCase, solver_material
from fea.results import _region, evaluate
from springcad.errors import SolverError
from springcad.parallel import ahead, single_threaded_blas
from springcad.units import UM_PER_MM

#: the small-angle stiffness is the secant T / (theta - theta_onset) this far past the onset
#: (fraction of theta_max)
SMALL_ANGLE_FRACTION = 0.01


def _noop(message: str, fraction: float | None = None) -> None:
    return None


# ============================================================ geometry adapter
# Everything this module knows about how the design's profiles are laid out is here,
# so a change of the profile API touches only these functions.
def _cam_features(cam, n_flexures: int) -> list[tuple[str, int, object]]:
    """Cam segments around pocket 0 (the pocket of flexure 0, ball centre on +y).

    Returns (kind, unit k, segment) in contour order for the pockets k = -2..2:
    "flank_ccw" (pushes the ball towards -x when the cam turns counter-clockwise),
    "pocket" (the tooth root arc), "flank_cw", "tip" (the tooth tip arc between
    pocket k and k + 1).

    Raises:
        SolverError: the cam contour is not laid out as expected.
    """
    try:
        teeth = cam.loop("teeth")
        out = []
        for k in range(-2, 3):
            i = k % n_flexures
            (right,), (pocket,) = teeth.named("flank", i, "right"), teeth.named("pocket", i)
            (left,), (tip,) = teeth.named("flank", i, "left"), teeth.named("tip", i)
            out += [("flank_ccw", k, right), ("pocket", k, pocket), ("flank_cw", k, left),
                    ("tip", k, tip)]
    except (KeyError, ValueError) as err:
        raise SolverError(f"cam contour has no named flank, pocket and tip for each of its "
                          f"{n_flexures} teeth ({err}): cannot find the flanks") from err
    return out


def _ball(design) -> tuple[np.ndarray, float]:
    """Tip-ball centre of flexure 0 and its radius (mm)."""
    return np.array([0.0, design.contact_radius_mm]), float(design.tip_radius_mm)


def _junction_mm(features, design) -> float:
    """Length of pocket arc next to the flank start over which the ball bears by design (mm).

    Below the flank's first roll angle psi* = rho / r_c the cam drives the ball at
    the pocket-flank junction, whose normal is tilted by up to psi* from the drive
    direction (:mod:`springcad.design.cam`); pocket contact within twice that angle
    of the junction is the intended drive, farther down it is the ball bottoming in
    the pocket.
    """
    pocket = next(seg for kind, k, seg in features if kind == "pocket" and k == 0)
    rho = float(pocket.radius)
    return 2.0 * rho * rho / float(design.contact_radius_mm)


def _cam_of(design):
    if design.cam is None:
        raise SolverError(f"spring '{design.name}' has no cam profile: no contact sweep")
    return design.cam


# ============================================================ what a step reports
def _contacts(sc: SectorContact, st: State, driving: str, sign: int, ball, material) -> list:
    """Active contact nodes grouped into contacts: where on the ball and on the tooth, force."""
    centre, rb = ball
    active = st.active[st.lam[st.active] > 0]
    if not len(active):
        return []
    X = sc.pX
    x = sc.positions(st.u)
    to_cam = rot(st.theta)
    info = {int(i): sc.cam.describe(int(st.foot_seg[i]), float(st.foot_t[i]), driving)
            for i in active}
    groups: list[list[int]] = []
    for i in active:  # nodes near each other on the same cam feature: one contact
        for grp in groups:
            if (info[grp[0]]["feature"] == info[int(i)]["feature"]
                    and np.linalg.norm(X[i] - X[grp[0]]) < 0.5 * rb):
                grp.append(int(i))
                break
        else:
            groups.append([int(i)])
    out = []
    for grp in groups:
        grp = np.asarray(grp)
        w = st.lam[grp]
        force = float(w.sum())
        ref = (w[:, None] * X[grp]).sum(0) / force
        cur = (w[:, None] * x[grp]).sum(0) / force
        top = int(grp[np.argmax(w)])
        label = str(sc.plabels[top])
        c = {"force_N": force, "ring_feature": label, "contact_points": len(grp),
             "ring_point_mm": [float(v) for v in ref],
             "cam_point_mm": [float(v) for v in cur @ to_cam], **info[top]}
        c["intended"] = label.startswith("ball") and sc.cam.intended(info[top], driving)
        if label.startswith("ball"):
            rel = ref - centre
            c["ball_angle_deg"] = math.degrees(math.atan2(rel[1], sign * rel[0]))
            c["hertz"] = hertz_line_contact(force / sc.fm.thickness_mm,
                                            1.0 / rb + info[top]["cam_curvature_per_mm"],
                                            material.youngs_modulus_MPa, material.poisson_ratio)
        out.append(c)
    return out


def _surface_gaps(sc: SectorContact, groups: dict, st: State, part: str | None = None) -> dict:
    """Smallest gap (mm) from the deformed flexure (or its ``part``: "ball", "neck", "edge")
    to each nominal cam surface (negative: inside the cam) and to the neighbouring flexure
    (the deformed sector turned by one pitch). Against a dilated cam
    (:meth:`CamCurve.dilated`) the gaps are still to the nominal surfaces: the offset
    moves the flexure, the caller subtracts the surfaces' own deviations."""
    bnd = sc.boundary(st.u, part=part)
    pts = np.vstack([bnd.A, bnd.B[-1:]])
    q = pts @ rot(st.theta)  # cam frame
    g_all = sc.cam.project(q)[0] + sc.cam.offset_mm
    out = {}
    to_ring = rot(st.theta)
    inside = g_all < 0
    for name, segs in groups.items():
        # a point inside the cam has a negative gap to the surface it is nearest to only;
        # the points outside count by their distance alone, and only the nearest of them
        # matters (:meth:`_Segments.min_distance`)
        gap = math.inf
        if inside.any():
            d = segs.project(q[inside])[0]
            into = d <= -g_all[inside] + 1e-9
            gap = float(np.min(np.where(into, -d, d)))
        if not inside.all():
            gap = segs.min_distance(q[~inside], gap)
        if gap > 0:  # also from the cam's side: convex against convex, sharp corners
            cam_pts = np.vstack([segs.A, segs.B[-1:]]) @ to_ring.T
            gap = bnd.min_distance(cam_pts, gap)
        out[name] = gap
    pitch = 2 * math.pi / sc.fm.geometry.n_flexures
    out["neighbour_flexure"] = bnd.min_distance(pts @ rot(pitch).T)
    return out


def _stress(sc: SectorContact, st: State, exclusion_mm: float):
    """Peak nodal von Mises outside the held zone and the contact zone, its region, the
    largest value inside the contact zone (MPa), and the nodal field."""
    vm = sc.von_mises(st.u)
    zone = np.zeros(vm.shape, bool)
    for p in sc.pX[st.active]:
        zone |= np.hypot(sc.X[0] - p[0], sc.X[1] - p[1]) < exclusion_mm
    ok = ~sc.near_held & ~zone
    i = int(np.argmax(np.where(ok, vm, -np.inf)))
    at_contact = float(vm[zone].max()) if zone.any() else 0.0
    return float(vm[i]), _region(sc.X[:, i], sc.fm), at_contact, vm


def _report(sc: SectorContact, st: State, tangent, theta_on, driving, sign, ball, groups,
            material, exclusion_mm, stress_scale, keep=False):
    """The :class:`ContactStep` of a converged state (and the picture data if ``keep``)."""
    theta = st.theta
    torque = sc.torque(st)
    contacts = _contacts(sc, st, driving, sign, ball, material)
    flex_peak, region, at_contact, vm = _stress(sc, st, exclusion_mm)
    flex_scaled = flex_peak * stress_scale
    hertz = [c["hertz"] for c in contacts if "hertz" in c]
    h = max(hertz, key=lambda v: v["von_mises_max_MPa"]) if hertz else None
    if h is not None:
        h = dict(h, fe_nodal_at_contact_MPa=at_contact)
    rim = sc.reaction_torque(st)
    # relative to the linear torque at this angle (the contact torque itself can be ~0)
    eq = abs(rim - torque) / (sc.stiffness_linear * abs(theta)) if theta else abs(rim - torque)
    engaged = None
    if theta_on is not None and sign * (theta - theta_on) > 1e-12:
        engaged = torque / (theta - theta_on)
    step = ContactStep(
        angle_rad=theta, torque_Nmm=torque,
        secant_Nmm_per_rad=torque / theta if theta else None,
        engaged_secant_Nmm_per_rad=engaged, tangent_Nmm_per_rad=tangent, contacts=contacts,
        gaps_mm=_surface_gaps(sc, groups, st),
        peak_von_mises_MPa=max(flex_scaled, h["von_mises_max_MPa"] if h else 0.0),
        flexure_peak_MPa=flex_peak, flexure_peak_scaled_MPa=flex_scaled,
        flexure_peak_region=region, hertz=h,
        iterations=st.iterations, equilibrium_error=eq)
    picture = None
    if keep:
        picture = {"points_mm": sc.X + st.u.reshape(-1, 2).T, "von_mises_MPa": vm,
                   "triangles": sc.basis.nodal_dofs[0][sc.basis.mesh.t[:3]].T,
                   "angle_rad": theta, "cam_mm": sc.cam.P @ rot(theta).T,
                   "contacts_mm": [rot(theta) @ np.asarray(c["cam_point_mm"])
                                   for c in contacts],
                   "ball_centre_mm": ball[0], "ball_radius_mm": ball[1],
                   "ball_centre_deformed_mm": _moved(sc, st, ball[0])}
    return step, picture


def _moved(sc: SectorContact, st: State, point) -> np.ndarray:
    """Where the material point nearest to ``point`` went (mm)."""
    i = int(np.argmin(np.hypot(sc.X[0] - point[0], sc.X[1] - point[1])))
    return sc.X[:, i] + st.u.reshape(-1, 2)[i] + (np.asarray(point) - sc.X[:, i])


# ============================================================ +-theta_max with tolerances
def _end_state(sc: SectorContact, st: State, driving: str, sign: int, ball, material,
               groups: dict) -> EndState:
    """Ball contact and every clearance (by ring part) of a converged end state."""
    contacts = [c for c in _contacts(sc, st, driving, sign, ball, material) if "hertz" in c]
    c = max(contacts, key=lambda c: c["hertz"]["von_mises_max_MPa"], default=None)
    parts = sorted({lab.split(":")[0] for lab in sc.facets})
    clear = {}
    for part in parts:
        for name, gap in _surface_gaps(sc, groups, st, part).items():
            if name in RING_TO_RING or (name == "driving_flank" and part == "ball"):
                continue
            clear[f"{name}/{part}"] = gap
    clear.update({k: v for k, v in _surface_gaps(sc, groups, st).items() if k in RING_TO_RING})
    return EndState(offset_mm=sc.cam.offset_mm, converged=True,
                    force_N=c["force_N"] if c else 0.0,
                    flank_curvature_per_mm=c["cam_curvature_per_mm"] if c else 0.0,
                    hertz=c["hertz"] if c else None, clearances_mm=clear)


def _ends(sc: SectorContact, curve: CamCurve, design, material, final, theta_max: float,
          steps: int, ball, rest_clearance_mm: float, sign: int) -> tuple:
    """The end states of one direction at theta_max (:mod:`fea.contact_tolerance`): the
    nominal one, and the path to it again against the cam dilated by -+T (T = t_spring +
    t_shaft, the largest deviation of ball and flank together); ``final`` is the sweep's
    converged state there, or None when it stopped short."""
    m = design.manufacturing
    T = float(m.t_spring_mm + m.t_shaft_mm)
    driving = "flank_ccw" if sign > 0 else "flank_cw"
    groups = curve.groups(driving)
    if final is None:
        return (sign * theta_max, [EndState(0.0, False, reason="the sweep stopped "
                                            "before theta_max")])
    rest: dict = {}
    states = [_end_state(sc, final, driving, sign, ball, material, groups)]
    for offset in ((-T, T) if T > 0 else ()):
        try:
            st = offset_path(sc, curve, offset, sign, theta_max, steps, end=final, rest=rest)
            states.append(_end_state(sc, st, driving, sign, ball, material, groups))
        except SolverError as err:
            why = f"no converged contact ({err})"
            if offset > rest_clearance_mm:
                why = (f"the cam grown by {UM_PER_MM * offset:.0f} um overlaps the ball at rest "
                       f"by {UM_PER_MM * (offset - rest_clearance_mm):.0f} um (designed clearance "
                       f"{UM_PER_MM * rest_clearance_mm:.0f} um < t_spring + t_shaft): the ball "
                       f"is pinched between both flanks and no contact state converges "
                       f"({err})")
            states.append(EndState(offset, False, reason=why))
        finally:
            sc.cam = curve
    return (sign * theta_max, states)


def _assess_ends(design, material, ends: dict, ball, seed: int):
    """The contact rules at +-theta_max from both directions' end states (:func:`_ends`)."""
    m = design.manufacturing
    props = ContactMaterial(material.youngs_modulus_MPa, material.poisson_ratio,
                            material.yield_strength_MPa, design.material.safety_factor)
    layout = BallLayout(float(design.contact_radius_mm), float(m.w_gap_mm),
                        float(design.thickness_mm), material.youngs_modulus_MPa,
                        material.poisson_ratio)
    return assess(design.name, ends, ball[1], float(design.thickness_mm), props,
                  float(m.t_spring_mm), float(m.t_shaft_mm), m.tolerance_distribution, seed,
                  layout)


def _direction(sc: SectorContact, curve: CamCurve, design, material, ball, exclusion: float,
               stress_scale: float, options: ContactOptions, theta_max: float,
               rest_clearance_mm: float, sign: int, progress=_noop) -> dict:
    """The sweep of one direction (``sign`` +1 or -1) from rest to theta_max, and with
    ``options.tolerances`` its end states (:func:`_ends`): a dict of the onset (rad), the
    reported steps, the small-angle stiffness (or None), the picture at theta_max (or
    None), the flags, why the path stopped (or None), the jumps (rad), the converged state
    at theta_max (or None) and the end states (or None)."""
    key = "+" if sign > 0 else "-"
    n = options.steps
    driving = "flank_ccw" if sign > 0 else "flank_cw"
    groups = curve.groups(driving)
    progress(f"contact sweep {key}{math.degrees(theta_max):.1f} deg ({n} steps)", None)
    th_on = onset_rad(sc, sign, theta_max)
    targets = [sign * theta_max * i / n for i in range(n + 1)]
    h = sign * theta_max / (4 * n)  # tangent: slope over the last quarter step
    a = sign * SMALL_ANGLE_FRACTION * theta_max
    extra = {th - h for th in targets[1:]}
    if math.isfinite(th_on):
        extra.add(th_on + a)
    path = AnglePath(sc, sign, theta_max / n)
    out, torque = [], {}
    picture = final = stuck = None
    for th in sorted(set(targets) | extra, key=abs):
        try:
            st = path.to(th)
        except Stuck as err:
            stuck = str(err)
            break
        torque[th] = sc.torque(st)
        if th not in targets:
            continue
        tangent = None
        if th != 0 and not (abs(th - h) < abs(th_on) < abs(th)):  # not across the onset
            tangent = (torque[th] - torque[th - h]) / h
        step, pic = _report(sc, st, tangent, th_on if math.isfinite(th_on) else None,
                            driving, sign, ball, groups, material, exclusion, stress_scale,
                            keep=th == targets[-1])
        out.append(step)
        if th == targets[-1]:
            final = st
        if pic is not None:
            picture = pic
    small = None
    if math.isfinite(th_on) and th_on + a in torque:  # T(theta_onset) = 0 exactly
        small = torque[th_on + a] / a
    jumps = list(path.jumps)
    flags = direction_flags(key, out, th_on, small, sc.stiffness_linear, options, theta_max,
                            stuck, jumps)
    ends = None
    if options.tolerances:
        progress(f"contact at {key}{math.degrees(theta_max):.1f} deg with the profile "
                 "tolerances", None)
        ends = _ends(sc, curve, design, material, final, theta_max, n, ball,
                     rest_clearance_mm, sign)
    return {"onset": th_on, "steps": out, "small": small, "picture": picture, "flags": flags,
            "stuck": stuck, "jumps": jumps, "final": final, "ends": ends}


# ============================================================ the sweep
def _mesh(design, run, level: int):
    """The verification's 2D sector mesh at ``level`` (or a new one) and the linear K of that
    mesh from the verification (or None)."""
    if run is not None and getattr(run, "base2d", None):
        k = min(level, len(run.base2d) - 1)
        res = run.base2d[k]
        if res.mesh is not None and res.mesh.dim == 2:
            return res.mesh, res.stiffness_Nmm_per_rad
    faces = tuple(getattr(run, "faces", ()) or ()) if run is not None else ()
    g = getattr(run, "geometry", None)
    if not faces or g is None:
        g = sector_geometry(design)
        faces = mesh_face_levels(g, DEFAULT_SIZE, level + 1,
                                 LoadCase().patch_half_width_mm(g.tip_radius_mm))
    k = min(level, len(faces) - 1)
    return fea_mesh_2d(faces[k], g, k), None


def contact_sweep(design, material=None, run=None, options: ContactOptions = ContactOptions(),
                  cam=None, progress=_noop) -> ContactSweep:
    """Turn the rigid cam from 0 to +theta_max and to -theta_max against the sector.

    Args:
        design: :class:`~springcad.design.spring.SpringDesign` (ring and cam profiles).
        material: :class:`~fea.problem.Material` (default: the design's).
        run: the verification's :class:`~fea.study.ModelRun` whose 2D mesh of level
            ``options.level`` is reused (None: mesh the sector here).
        options: :class:`ContactOptions`.
        cam: a cam :class:`~springcad.design.curves.Profile` to use instead of the
            design's (to check a different cam against this ring).
        progress: callable ``(message, fraction or None)``.

    Runs with one BLAS thread: its Newton iterations are many small dense products, which
    a thread pool only slows (:func:`springcad.parallel.single_threaded_blas`).

    Raises:
        SolverError: the contact problem cannot be set up or does not converge.
    """
    with single_threaded_blas():
        return _contact_sweep(design, material, run, options, cam, progress)


def _contact_sweep(design, material=None, run=None, options: ContactOptions = ContactOptions(),
                   cam=None, progress=_noop) -> ContactSweep:
    """The sweep of :func:`contact_sweep`."""
    t0 = time.perf_counter()
    material = material or solver_material(design.material)
    cam_profile = cam if cam is not None else _cam_of(design)
    theta_max = float(design.max_deflection_rad)
    ball = _ball(design)
    fm, k_same_mesh = _mesh(design, run, options.level)
    k_verified = getattr(run, "stiffness_Nmm_per_rad", None)
    features = _cam_features(cam_profile, design.n_flexures)
    curve = CamCurve(features, cam_profile.loop("teeth").signed_area() > 0,
                     _junction_mm(features, design))
    reach = float(np.max(np.hypot(*curve.P.T))) + 2 * ball[1] + 0.5
    sc = SectorContact(fm, material, curve, reach, nonlinear=options.nonlinear)
    if k_same_mesh is not None and abs(sc.stiffness_linear / k_same_mesh - 1) > 1e-6:
        raise SolverError("contact sweep: the sector model does not reproduce the linear FEA of "
                          f"the same mesh ({sc.stiffness_linear:.6g} vs {k_same_mesh:.6g} "
                          "N*mm/rad)")
    # flexure stresses of this (coarse) mesh scaled to the verified peak: the linear FEA of
    # the same mesh at theta_max is the common reference, so its discretisation error cancels
    peak_linear = evaluate(fm, sc.system, sc.u_traction, LoadCase(), theta_max, {},
                           None).peak_von_mises_MPa
    peak_verified = getattr(run, "peak_stress_MPa", None)
    stress_scale = peak_verified / peak_linear if peak_verified else 1.0
    t1 = time.perf_counter()
    exclusion = 2.0 * LoadCase().patch_half_width_mm(ball[1])
    rest = sc.boundary(None)
    rest_clearance = float(curve.project(np.vstack([rest.A, rest.B[-1:]]))[0].min())
    steps, onset, small, pictures, flags, stuck, jumps = {}, {}, {}, {}, [], {}, {}
    final, ends = {}, {}  # direction -> converged state at +-theta_max; its end states
    args = (sc, curve, design, material, ball, exclusion, stress_scale, options, theta_max,
            rest_clearance)
    with contextlib.ExitStack() as leaving:
        # the two directions are independent (each from rest, on its own solver state):
        # the "-" one in a second process beside the "+" one (serial: after it, on the
        # solver state reset), the same numbers either way
        minus = ahead(leaving, _direction, *args, -1, progress=progress)
        plus = _direction(*args, 1, progress=progress)
        sc.reset()
        for key, d in (("+", plus), ("-", minus.result())):
            onset[key], steps[key], jumps[key] = d["onset"], d["steps"], d["jumps"]
            flags += d["flags"]
            for into, name in ((small, "small"), (pictures, "picture"), (stuck, "stuck"),
                               (final, "final"), (ends, "ends")):
                if d[name] is not None:
                    into[key] = d[name]
    w_gap = float(design.manufacturing.w_gap_mm)
    if rest_clearance < w_gap * (1 - options.gap_tolerance):
        what = ("the cam overlaps the flexure" if rest_clearance < 0 else
                "the clearance is below the designed gap")
        flags.append({"code": "gap", "message":
                      f"at rest {what}: smallest flexure-cam clearance "
                      f"{UM_PER_MM * rest_clearance:.1f} um against w_gap_mm = {w_gap:g} "
                      f"(tolerance {100 * options.gap_tolerance:g} %)"})
    notes = ["geometrically nonlinear (total Lagrangian, St Venant-Kirchhoff): the flexure's "
             "large rotation and foreshortening are in the contact kinematics" if options.nonlinear
             else "linear elasticity with the contact on current positions: the flexure's "
             "geometric nonlinearity (foreshortening) is not modelled"]
    t2 = time.perf_counter()
    at_max = None
    if options.tolerances:
        at_max = _assess_ends(design, material, ends, ball, options.seed)
    t3 = time.perf_counter()
    return ContactSweep(
        name=design.name, max_deflection_rad=theta_max, n_flexures=design.n_flexures,
        level=fm.level, dofs=int(sc.system.n_dofs), candidates=len(sc.pX),
        stiffness_linear_Nmm_per_rad=sc.stiffness_linear,
        stiffness_verified_Nmm_per_rad=k_verified, design_gap_mm=w_gap,
        peak_linear_this_mesh_MPa=peak_linear, peak_verified_MPa=peak_verified,
        rest_clearance_mm=rest_clearance, onset_rad=onset, small_angle_Nmm_per_rad=small,
        steps=steps, flags=flags, options=options, stopped=stuck, jumps_rad=jumps,
        timings_s={"setup": t1 - t0, "sweep": t2 - t1, "tolerances": t3 - t2, "total": t3 - t0},
        notes=notes, pictures=pictures, at_max=at_max)
