"""Post-processing: stiffness, von Mises stress, peak stress and where it is.

Stiffness
    K = T / theta, work-conjugate (see :mod:`fea.problem`). A sector model
    carries one flexure: the ring stiffness is N times the sector's.

Stress
    Von Mises stress at the spring's maximum deflection (the solution scaled to
    the torque K * theta_max). Reported value: the *nodal* von Mises stress,
    each element's stress evaluated at its own quadratic nodes (vertices and
    mid-edge nodes, i.e. on the surface where the peak is) and averaged over
    the elements sharing the node. The integration-point maximum is reported
    as well (``peak_ip``); it sits inside the elements and reads lower on a
    coarse mesh (about 10 % at a fillet); both converge to the same limit and
    the convergence study extrapolates the nodal one.

Peak search excludes
    - the neighbourhood of held faces (within half the rim thickness of a held
      outer rim, within half the hole radius of held rim holes): clamp corners
      are singular, and the held faces stand for a housing or dowels whose
      contact stresses this model does not resolve;
    - the contact patch on the tip ball (within twice the patch half-width of
      the contact point): its stresses belong to the idealised patch, not to
      the flexure; Hertz contact of ball and cam is a separate check.
Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fea.mesh import to_rows
from springcad.units import NMM_PER_NM

REGION_NAMES = {"root": "root fillet", "edge": "flexure flank", "neck": "tip-neck fillet",
                "ball": "tip ball", "rim": "rim", "side": "rim (sector cut)",
                "clamp": "rim (held face)", "hole": "rim hole", "face": "flexure flank"}


@dataclass(frozen=True, eq=False)
class Field:
    """The FE field of one solved mesh at the maximum deflection, as plain arrays.

    What a viewer or a report needs without scikit-fem: node rows, quadratic cells in
    VTK's local node order (scikit-fem's for quadratic triangles and tetrahedra), the
    nodal displacement and von Mises stress. The mesh is the modelled sector (a 3D
    model may be half the thickness, see ``thickness_fraction``). Units: mm, MPa.

    Attributes:
        points_mm: node coordinates, shape (n, 3) (z = 0 in 2D).
        cells: node indices of each cell, shape (e, 6) triangles or (e, 10) tetrahedra.
        displacement_mm: nodal displacement, shape (n, 3).
        von_mises_MPa: nodal von Mises stress, shape (n,).
        excluded: nodes excluded from the reported peak (supports, load), shape (n,).
        thickness_mm: disk thickness z (mm).
        thickness_fraction: share of the thickness modelled (0.5: mid-plane symmetry).
    """

    points_mm: np.ndarray
    cells: np.ndarray
    displacement_mm: np.ndarray
    von_mises_MPa: np.ndarray
    excluded: np.ndarray
    thickness_mm: float
    thickness_fraction: float = 1.0


@dataclass(eq=False)
class StaticResult:
    """One solved mesh.

    Attributes:
        stiffness_Nmm_per_rad: ring stiffness (N*mm/rad).
        torque_at_max_Nmm: ring torque at the maximum deflection (N*mm).
        peak_von_mises_MPa: nodal peak von Mises at max deflection, exclusions applied (MPa).
        peak_ip_von_mises_MPa: integration-point peak, same exclusions (MPa).
        peak_location_mm: (x, y, z) of the nodal peak (mm), flexure 0 along +y.
        peak_region: where the peak is ("root fillet", "flexure flank", ...).
        excluded_peak_MPa: largest stress inside the excluded zones (MPa).
        dofs, n_elements: model size.
        timings_s: "assemble", "solve", "post" wall times (s).
        solve_info: the :class:`~fea.solve.SolveInfo`.
        fields: point data for output: "displacement_mm" (n, 3) and "von_mises_MPa" (n,)
            on the mesh nodes at max deflection, "points_mm" (dim, n), "excluded" (n,),
            "cells" (e, local nodes) (not serialised); :attr:`field` gives them as a
            :class:`Field`.
    """

    stiffness_Nmm_per_rad: float
    torque_at_max_Nmm: float
    max_deflection_rad: float
    peak_von_mises_MPa: float
    peak_ip_von_mises_MPa: float
    peak_location_mm: tuple[float, float, float]
    peak_region: str
    excluded_peak_MPa: float
    dofs: int
    n_elements: int
    dim: int
    level: int
    timings_s: dict
    solve_info: object
    fields: dict = field(default_factory=dict, repr=False)
    mesh: object = field(default=None, repr=False)
    peak_by_region_MPa: dict = field(default_factory=dict)
    """Largest nodal von Mises on each kind of boundary (root fillet, flank, neck, ...)."""

    @property
    def field(self) -> Field:
        """The field as plain arrays (:class:`Field`).

        Raises:
            ValueError: the result was solved without ``keep_fields``.
        """
        f = self.fields
        if not f:
            raise ValueError("the result carries no fields: verify (or solve) with keep_fields=True")
        rows = to_rows(f["points_mm"])
        points = np.zeros((len(rows), 3))
        points[:, :rows.shape[1]] = rows
        return Field(points, f["cells"], f["displacement_mm"], f["von_mises_MPa"],
                     np.asarray(f["excluded"], dtype=bool), self.mesh.thickness_mm,
                     self.mesh.thickness_fraction)

    def to_dict(self) -> dict:
        return {"stiffness_Nm_per_rad": self.stiffness_Nmm_per_rad / NMM_PER_NM,
                "peak_von_mises_MPa": self.peak_von_mises_MPa,
                "peak_ip_von_mises_MPa": self.peak_ip_von_mises_MPa,
                "peak_location_mm": list(self.peak_location_mm),
                "peak_region": self.peak_region,
                "dofs": self.dofs, "n_elements": self.n_elements, "dim": self.dim,
                "level": self.level,
                "residual": self.solve_info.residual,
                "timings_s": dict(self.timings_s)}


def stiffness(system, u: np.ndarray) -> float:
    """Work-conjugate stiffness of the modelled part (N*mm/rad).

    Traction: K = T^2 / (f . u); rigid cam (unit rotation): K = u . A u.
    """
    if system.constraints is None:
        return system.torque_Nmm ** 2 / float(system.f @ u)
    return float(u @ (system.A @ u))


def _stress(grad, lam, mu, plane_stress):
    """Von Mises stress from displacement gradients (dim, dim, ...) (MPa)."""
    eps = 0.5 * (grad + np.swapaxes(grad, 0, 1))
    tr = np.trace(eps, axis1=0, axis2=1)
    dim = grad.shape[0]
    sig = 2 * mu * eps + lam * tr * np.eye(dim).reshape(dim, dim, *([1] * (grad.ndim - 2)))
    if dim == 2:  # plane stress: s_zz = 0
        sx, sy, txy = sig[0, 0], sig[1, 1], sig[0, 1]
        return np.sqrt(np.maximum(sx ** 2 - sx * sy + sy ** 2 + 3 * txy ** 2, 0.0))
    sx, sy, sz = sig[0, 0], sig[1, 1], sig[2, 2]
    txy, tyz, tzx = sig[0, 1], sig[1, 2], sig[2, 0]
    return np.sqrt(np.maximum(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2)
                              + 3 * (txy ** 2 + tyz ** 2 + tzx ** 2), 0.0))


def _grad(basis, u: np.ndarray, dim: int) -> np.ndarray:
    """Displacement gradient d u_i / d x_k at the basis' quadrature points, (i, k, e, q)."""
    return np.stack([np.asarray(basis.interpolate(u[i::dim]).grad) for i in range(dim)])


def nodal_von_mises(system, u: np.ndarray):
    """Von Mises stress at every quadratic node (MPa), averaged over the elements sharing it.

    Each element's stress is evaluated at its own local nodes (vertices and
    mid-edge nodes: on the surface where peaks are), then averaged.

    Returns:
        (nodal values (n,), element-node values (e, local nodes), the evaluation basis).
    """
    from skfem import CellBasis

    mesh = system.basis.mesh
    scalar = mesh.elem()
    X = np.asarray(scalar.doflocs, dtype=float).T  # reference coordinates of the local nodes
    sb = CellBasis(mesh, scalar, quadrature=(X, np.ones(X.shape[1])))
    vm = _stress(_grad(sb, u, system.dim), system.lam, system.mu, system.plane_stress)
    dofs = sb.element_dofs  # (local nodes, elements)
    n = sb.N
    total = np.bincount(dofs.ravel(), weights=vm.T.ravel(), minlength=n)
    count = np.bincount(dofs.ravel(), minlength=n)
    return total / np.maximum(count, 1), vm, sb


def _excluded_mask(points, system, fm, case, support_exclusion_mm):
    """True for points (dim, n) in the excluded zones (near held faces, in the load patch)."""
    from scipy.spatial import cKDTree

    g = fm.geometry
    held_nodes = np.unique(system.held // system.dim)
    held_xy = system.basis.doflocs[:2, held_nodes]
    tree = cKDTree(to_rows(held_xy))  # distance in the plane: held faces span the thickness
    # only whether a held node is nearer than the exclusion: a bounded search (the same
    # nearest distance where there is one within it, inf elsewhere) skips the far points
    d, _ = tree.query(to_rows(points[:2]), distance_upper_bound=support_exclusion_mm)
    mask = d < support_exclusion_mm
    patch = 2.0 * case.patch_half_width_mm(g.tip_radius_mm)
    for c in g.contact_points_mm():
        mask |= np.hypot(points[0] - c[0], points[1] - c[1]) < patch
    return mask


def _region(point, fm) -> str:
    """Name of the labelled in-plane boundary nearest to a point (in the plane of the disk).

    The faces of the 3D model's thickness (its mid-plane "symmetry" face and the disk
    faces) are skipped: every point lies on them in plan view.
    """
    mesh = fm.mesh
    best, name = np.inf, "interior"
    for lab, facets in fm.boundaries.items():
        if not len(facets) or lab in ("symmetry", "bottom", "top"):
            continue
        pts = mesh.p[:, np.unique(mesh.facets[:, facets])]
        d = np.min(np.linalg.norm(pts[:2] - np.asarray(point[:2])[:, None], axis=0))
        if d < best:
            best, name = d, lab
    kind = name.split(":")[0]
    return REGION_NAMES.get(kind, kind)


def evaluate(fm, system, u: np.ndarray, case, max_deflection_rad: float, timings: dict,
             info, support_exclusion_mm: float | None = None,
             keep_fields: bool = False) -> StaticResult:
    """Stiffness and stresses of one solved mesh, scaled to the maximum deflection."""
    g = fm.geometry
    n_model = len(g.flexure_angles_rad)
    k_model = stiffness(system, u)
    k_ring = k_model * (g.n_flexures / n_model) / fm.thickness_fraction
    torque_ring = k_ring * max_deflection_rad
    if system.constraints is None:
        # unit torque per modelled flexure (and thickness fraction) -> torque at max deflection
        scale = torque_ring / g.n_flexures * fm.thickness_fraction
    else:
        scale = max_deflection_rad  # unit rotation -> max rotation
    if support_exclusion_mm is None:
        support_exclusion_mm = (0.5 * g.hole_radius_mm if case.support == "holes"
                                else 0.5 * g.rim_thickness_mm)
    vm_nodes, vm_elem, sb = nodal_von_mises(system, u * scale)
    xyz = sb.doflocs
    excl = _excluded_mask(xyz, system, fm, case, support_exclusion_mm)
    ok = ~excl
    i_peak = int(np.argmax(np.where(ok, vm_nodes, -np.inf)))
    peak = float(vm_nodes[i_peak])
    loc = np.zeros(3)
    loc[:xyz.shape[0]] = xyz[:, i_peak]
    excluded_peak = float(np.max(vm_nodes[excl])) if np.any(excl) else 0.0
    by_region: dict[str, float] = {}
    for lab, facets in fm.boundaries.items():
        name = REGION_NAMES.get(lab.split(":")[0])
        if name is None or not len(facets) or lab == "symmetry":
            continue
        nodes = np.unique(sb.get_dofs(facets).flatten())
        nodes = nodes[ok[nodes]]
        if len(nodes):
            by_region[name] = max(by_region.get(name, 0.0), float(vm_nodes[nodes].max()))
    # integration points of the assembly quadrature (the 3- / 4-point rule of CPS6 / C3D10)
    basis = system.basis
    vm_ip = _stress(_grad(basis, u * scale, system.dim), system.lam, system.mu,
                    system.plane_stress)
    xq = np.asarray(basis.mapping.F(basis.X))  # (dim, elements, points)
    excl_ip = _excluded_mask(xq.reshape(xq.shape[0], -1), system, fm, case,
                             support_exclusion_mm).reshape(vm_ip.shape)
    peak_ip = float(np.max(np.where(excl_ip, -np.inf, vm_ip)))
    fields = {}
    if keep_fields:
        disp = np.zeros((sb.N, 3))
        disp[:, :system.dim] = (u * scale).reshape(-1, system.dim)
        fields = {"displacement_mm": disp, "von_mises_MPa": vm_nodes, "points_mm": xyz,
                  "excluded": excl, "cells": np.ascontiguousarray(sb.element_dofs.T)}
    return StaticResult(
        stiffness_Nmm_per_rad=k_ring, torque_at_max_Nmm=torque_ring,
        max_deflection_rad=max_deflection_rad, peak_von_mises_MPa=peak,
        peak_ip_von_mises_MPa=peak_ip, peak_location_mm=tuple(float(v) for v in loc),
        peak_region=_region(loc, fm), excluded_peak_MPa=excluded_peak, dofs=system.n_dofs,
        n_elements=fm.n_elements, dim=fm.dim, level=fm.level, timings_s=dict(timings),
        solve_info=info, fields=fields, mesh=fm, peak_by_region_MPa=by_region)
