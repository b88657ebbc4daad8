"""The elasticity problem of a flexure ring: material, supports and the cam load.

Material
    Linear isotropic elasticity from the job's material (E, nu): the one
    :class:`~springcad.materials.Material` type, checked by
    :func:`solver_material`. The 2D model
    is plane stress with the disk thickness as its depth, so 2D forces are
    total forces (N) and torques N*mm, as in 3D.

Supports (``support``)
    ``"rim"``: the outer cylindrical face (circle R_o) is held in all
    directions. It stands for a rim clamped in a housing or bolted to the next
    spring's rim; it is the sector model's support (N-fold symmetric).
    ``"holes"``: only the rim holes' faces are held (press-fit dowels or
    bolts), the rim is otherwise free: the full ring is modelled because the
    holes break the N-fold symmetry. :func:`fea.study.support_study` reports
    the difference.

Cam load (``load``)
    ``"traction"`` (default): on each tip ball a smooth traction patch centred
    on the contact point (the ball's point at the contact radius on the cam
    side), magnitude cos^2(pi phi / (2 phi0)) over the ball angle |phi| < phi0
    from the contact point, uniform through the thickness, pointing along the
    direction of rotation (perpendicular to the flexure axis, as the cam
    profile keeps it). The patch is scaled to exactly one unit of torque about
    the ring axis per flexure. Its smooth, centred shape converges cleanly; a
    sharp-edged patch does not.
    ``"rigid_cam"``: the nodes of the same patch follow a rigid, flat cam pad
    driven by the cam rotated by a unit angle: along the push direction d the
    patch moves rigidly, d . u_i = theta (e_z x x_c) . d + beta s_i, with the
    pad's own rotation beta free (no moment through the contact, as for the
    real, very narrow Hertz contact: a bonded patch that must turn with the
    cam would clamp the tip and triple K); tangential sliding is free
    (frictionless flank). Imposed with Lagrange multipliers.
    Both give the same stiffness within the tolerance asserted in the tests.

Stiffness is work-conjugate: with the load vector f scaled to one unit of
torque T, the rotation is theta = f . u / T and K = T / theta = T^2 / (f . u);
for the rigid cam K = u . A u / theta^2 (twice the stored energy).
Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.errors import SolverError
from springcad.materials import Material

SUPPORTS = ("rim", "holes")
LOADS = ("traction", "rigid_cam")


def solver_material(spec) -> Material:
    """The job's material, checked for what the solver needs (E, nu, yield strength).

    Args:
        spec: a :class:`~springcad.config.MaterialSpec` or a
            :class:`~springcad.materials.Material`.

    Returns:
        The same :class:`~springcad.materials.Material` (the one material type).

    Raises:
        SolverError: a property is missing or not physical.
    """
    m = getattr(spec, "material", spec)
    name = getattr(m, "name", "?")
    for key in ("youngs_modulus_MPa", "poisson_ratio", "yield_strength_MPa"):
        v = getattr(m, key, None)
        if v is None or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise SolverError(f"material '{name}' has no valid {key} "
                              f"(got {v!r}); set it in the [material] table")
    if m.youngs_modulus_MPa <= 0 or m.yield_strength_MPa <= 0:
        raise SolverError(f"material '{name}': Young's modulus and yield "
                          "strength must be positive")
    if not -1.0 < m.poisson_ratio < 0.5:
        raise SolverError(f"material '{name}': Poisson ratio "
                          f"{m.poisson_ratio} is outside (-1, 0.5)")
    return m


def lame(material: Material, plane_stress: bool) -> tuple[float, float]:
    """Lame parameters (lambda, mu) of an isotropic material (MPa); plane-stress lambda for 2D."""
    E, nu = material.youngs_modulus_MPa, material.poisson_ratio
    mu = E / (2 * (1 + nu))
    lam = E * nu / (1 - nu ** 2) if plane_stress else E * nu / ((1 + nu) * (1 - 2 * nu))
    return lam, mu


@dataclass(frozen=True)
class LoadCase:
    """How the ring is held and loaded.

    Attributes:
        support: "rim" (outer face held) or "holes" (rim-hole faces held).
        load: "traction" (smooth tangential patch) or "rigid_cam" (patch nodes follow a
            rigid cam in the push direction).
        patch_half_angle_rad: half-angle phi0 of the contact patch on the tip ball (rad).
    """

    support: str = "rim"
    load: str = "traction"
    patch_half_angle_rad: float = math.radians(30.0)

    def __post_init__(self):
        if self.support not in SUPPORTS:
            raise SolverError(f"support '{self.support}' is not one of {', '.join(SUPPORTS)}")
        if self.load not in LOADS:
            raise SolverError(f"load '{self.load}' is not one of {', '.join(LOADS)}")
        if not 0.0 < self.patch_half_angle_rad <= math.pi / 2:
            raise SolverError(f"patch half-angle {self.patch_half_angle_rad:g} rad must be in "
                              "(0, pi/2]")

    def patch_half_width_mm(self, tip_radius_mm: float) -> float:
        return tip_radius_mm * self.patch_half_angle_rad


@dataclass(eq=False)
class System:
    """Assembled linear system of one mesh and load case.

    DOFs are interleaved by component: DOF ``n * dim + i`` is component i at
    the scalar quadratic node n of ``basis`` (the mesh's node order).

    Attributes:
        basis: scalar quadratic scikit-fem ``CellBasis`` (quadrature order 2, the
            rule CalculiX uses for C3D10/CPS6 too).
        dim: 2 or 3.
        A: stiffness matrix (N/mm).
        f: load vector for one unit of torque per loaded flexure (N).
        torque_Nmm: total torque of ``f`` about the ring axis (N*mm).
        fixed: DOFs set to zero (supports and symmetry).
        held: DOFs of the supports (clamp or holes) only.
        rotation: nodal values of the rigid rotation field e_z x x (unit angle) (mm).
        constraints: rigid-cam rows (B, c, S): B u + S beta = theta c with free pad
            rotations beta (one per flexure), or None.
    """

    basis: object
    dim: int
    A: object
    f: np.ndarray
    torque_Nmm: float
    fixed: np.ndarray
    held: np.ndarray
    rotation: np.ndarray
    constraints: tuple | None
    lam: float
    mu: float
    plane_stress: bool
    thickness_mm: float

    @property
    def n_dofs(self) -> int:
        return int(self.A.shape[0])


def stiffness_matrix(basis, lam: float, mu: float, scale: float = 1.0, chunk: int = 4000):
    """Isotropic elasticity stiffness matrix on a scalar quadratic basis (N/mm).

    Vectorised over elements with strain-displacement (B) matrices in Voigt
    form: K_e = sum_q B^T D B w_q |J_q|, times ``scale`` (2D: the thickness).
    scikit-fem's generic form kernel loops in Python over the 30 x 30 local DOF
    pairs of a P2 tet and is ~30x slower; the tests check both agree entry for
    entry. DOF numbering: scalar node * dim + component.
    """
    from scipy.sparse import coo_matrix

    nloc = len(basis.basis)
    dim = basis.mesh.dim()
    G = np.stack([np.asarray(basis.basis[a][0].grad) for a in range(nloc)])  # (a, k, e, q)
    G = np.transpose(G, (2, 3, 1, 0))  # (e, q, k, a)
    dx = np.asarray(basis.dx) * scale  # (e, q)
    ne, nq = dx.shape
    nd = nloc * dim
    if dim == 3:  # Voigt order xx yy zz yz xz xy (engineering shear strains)
        D = np.zeros((6, 6))
        D[:3, :3] = lam
        D[np.arange(3), np.arange(3)] += 2 * mu
        D[3:, 3:] = mu * np.eye(3)
        shear = [(1, 2), (0, 2), (0, 1)]
    else:  # xx yy xy
        D = np.array([[lam + 2 * mu, lam, 0.0], [lam, lam + 2 * mu, 0.0], [0.0, 0.0, mu]])
        shear = [(0, 1)]
    nv = D.shape[0]
    vals = []
    for e0 in range(0, ne, chunk):
        sl = slice(e0, min(ne, e0 + chunk))
        g = G[sl]
        m = g.shape[0]
        B = np.zeros((m, nq, nv, nloc, dim))
        for i in range(dim):
            B[:, :, i, :, i] = g[:, :, i, :]
        for r, (i, j) in enumerate(shear):
            B[:, :, dim + r, :, j] = g[:, :, i, :]
            B[:, :, dim + r, :, i] = g[:, :, j, :]
        B = B.reshape(m, nq, nv, nd)
        DB = np.einsum("kl,eqlb->eqkb", D, B)
        Bw = (B * dx[sl][:, :, None, None]).reshape(m, nq * nv, nd)
        vals.append(np.matmul(Bw.transpose(0, 2, 1), DB.reshape(m, nq * nv, nd)).ravel())
    n = basis.N * dim
    itype = np.int32 if n < 2 ** 31 else np.int64
    gd = (basis.element_dofs.T[:, :, None] * dim + np.arange(dim)).reshape(ne, nd).astype(itype)
    rows = np.repeat(gd, nd, axis=1).ravel()
    cols = np.tile(gd, (1, nd)).ravel()
    return coo_matrix((np.concatenate(vals), (rows, cols)), shape=(n, n)).tocsr()


def elasticity_form(lam: float, mu: float, scale: float = 1.0):
    """Linear elasticity bilinear form (scikit-fem, for ``ElementVector`` bases); used by the
    tests to check :func:`stiffness_matrix`."""
    from skfem import BilinearForm
    from skfem.helpers import ddot, sym_grad, trace, eye

    @BilinearForm
    def form(u, v, w):
        eps = sym_grad(u)
        sig = 2.0 * mu * eps + lam * eye(trace(eps), eps.shape[0])
        return scale * ddot(sig, sym_grad(v))

    return form


def _push_frames(geometry, flexure: int):
    """Ball centre, push direction d (rotation direction) and contact direction (unit)."""
    a = geometry.flexure_angles_rad[flexure]
    push = np.array([-math.sin(a), math.cos(a)])
    centre = geometry.ball_centres_mm()[flexure]
    return centre, push, -push


def _bell(x, centre, towards, phi0):
    """cos^2 patch weight at points x (dim, ...) on the ball around direction ``towards``."""
    dx, dy = x[0] - centre[0], x[1] - centre[1]
    ang = np.arctan2(dx * towards[1] - dy * towards[0], dx * towards[0] + dy * towards[1])
    w = np.cos(0.5 * math.pi * ang / phi0) ** 2
    return np.where(np.abs(ang) < phi0, w, 0.0)


def facet_load(basis, facets, weight) -> np.ndarray:
    """Scalar consistent nodal loads q_i = int_facets weight(x) N_i dS on quadratic facets.

    The trace of a quadratic element on a facet is the quadratic facet element
    (3-node line in 2D, 6-node triangle in 3D) on the same, curved, nodes, so
    the integral needs only the facets' own nodes. (scikit-fem's ``FacetBasis``
    inverts the isoparametric map by Newton iteration, which fails on the long
    thin tets of an extruded mesh.)

    Args:
        basis: scalar quadratic ``CellBasis``.
        facets: boundary facet indices.
        weight: callable, points (dim, n) -> values (n,) (load per unit area / length).
    """
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefLine, RefTri

    mesh = basis.mesh
    X = basis.doflocs
    facets = np.asarray(facets)
    v = basis.nodal_dofs[0][mesh.facets[:, facets]]  # corner nodes (k, m)
    if mesh.dim() == 2:
        mid = basis.facet_dofs[0][facets]
        nodes = np.vstack([v[0], v[1], mid])
        (s_,), w = get_quadrature(RefLine, 8)
        N = np.array([(1 - s_) * (1 - 2 * s_), s_ * (2 * s_ - 1), 4 * s_ * (1 - s_)])
        dN = np.array([4 * s_ - 3, 4 * s_ - 1, 4 - 8 * s_])
        P = X[:, nodes]  # (d, 3, m)
        x = np.einsum("aq,dam->dmq", N, P)
        jac = np.linalg.norm(np.einsum("aq,dam->dmq", dN, P), axis=0)
    else:
        e = mesh.f2e[:, facets]  # (3, m) edge ids, order unknown
        ev = np.sort(mesh.edges[:, e], axis=0)  # (2, 3, m)
        mids = []
        for i, j in ((0, 1), (1, 2), (0, 2)):  # P2 triangle edge order
            a = np.minimum(mesh.facets[i, facets], mesh.facets[j, facets])
            b = np.maximum(mesh.facets[i, facets], mesh.facets[j, facets])
            hit = (ev[0] == a) & (ev[1] == b)  # (3, m), one True per column
            mids.append(basis.edge_dofs[0][e[np.argmax(hit, axis=0), np.arange(len(facets))]])
        nodes = np.vstack([v, np.vstack(mids)])
        (xi, eta), w = get_quadrature(RefTri, 6)
        L = np.array([1 - xi - eta, xi, eta])
        dL = np.array([[-1, -1], [1, 0], [0, 1]], dtype=float)  # dL_i / d(xi, eta)
        N = np.vstack([L * (2 * L - 1), 4 * L[0] * L[1], 4 * L[1] * L[2], 4 * L[0] * L[2]])
        dN = np.zeros((6, 2, len(w)))
        for i in range(3):
            dN[i] = (4 * L[i] - 1) * dL[i][:, None]
        for k, (i, j) in enumerate(((0, 1), (1, 2), (0, 2))):
            dN[3 + k] = 4 * (L[i] * dL[j][:, None] + L[j] * dL[i][:, None])
        P = X[:, nodes]  # (3, 6, m)
        x = np.einsum("aq,dam->dmq", N, P)
        t1 = np.einsum("aq,dam->dmq", dN[:, 0], P)
        t2 = np.einsum("aq,dam->dmq", dN[:, 1], P)
        jac = np.linalg.norm(np.cross(t1, t2, axis=0), axis=0)
    val = weight(x.reshape(x.shape[0], -1)).reshape(jac.shape)  # (m, q)
    contrib = np.einsum("aq,mq,q->am", N, val * jac, w)
    q = np.zeros(basis.N)
    np.add.at(q, nodes.ravel(), contrib.ravel())
    return q


def _facet_nodes(basis, facets) -> np.ndarray:
    """Scalar DOF (node) indices on given facets."""
    return np.unique(basis.get_dofs(facets).flatten())


def assemble(fm, material: Material, case: LoadCase = LoadCase()) -> System:
    """Assemble stiffness, unit-torque cam load and supports on a :class:`~fea.mesh.FeaMesh`.

    Raises:
        SolverError: the supports or the loaded tip balls are not in the mesh.
    """
    from skfem import CellBasis

    g = fm.geometry
    mesh = fm.mesh
    dim = fm.dim
    elem = mesh.elem()
    basis = CellBasis(mesh, elem, intorder=2)
    plane = dim == 2
    lam, mu = lame(material, plane_stress=plane)
    A = stiffness_matrix(basis, lam, mu, fm.thickness_mm if plane else 1.0)

    def vec(nodes, comps=None):
        comps = range(dim) if comps is None else comps
        return np.sort(np.concatenate([nodes * dim + c for c in comps]))

    # supports
    if case.support == "rim":
        keys = ["clamp"]
    else:
        if g is not None and g.sector:
            raise SolverError("support 'holes' needs the full ring (the holes break the "
                              "N-fold symmetry of the sector model)")
        keys = [k for k in fm.boundaries if k.startswith("hole:")]
    facets = [fm.boundaries[k] for k in keys if k in fm.boundaries and len(fm.boundaries[k])]
    if not facets:
        raise SolverError(f"no '{case.support}' support faces in the mesh: the model would be "
                          "free to rotate (singular); check the mesh labels")
    held = vec(_facet_nodes(basis, np.concatenate(facets)))
    fixed = held
    if "symmetry" in fm.boundaries:  # mid-plane of a half-thickness model: u_z = 0
        fixed = np.union1d(held, vec(_facet_nodes(basis, fm.boundaries["symmetry"]), [2]))

    # rigid rotation e_z x x at the nodes (exact in the isoparametric P2 space)
    x = basis.doflocs
    rot = np.zeros(basis.N * dim)
    rot[0::dim] = -x[1]
    rot[1::dim] = x[0]

    phi0 = case.patch_half_angle_rad
    n_model = len(g.flexure_angles_rad)
    missing = [i for i in range(n_model) if f"ball:{i}" not in fm.boundaries]
    if missing:
        raise SolverError(f"tip ball(s) {missing} missing from the mesh; the cam load cannot "
                          "be applied")
    scale = fm.thickness_mm if plane else 1.0
    f = np.zeros(basis.N * dim)
    rows, rhs = [], []
    for i in range(n_model):
        centre, push, towards = _push_frames(g, i)
        q = scale * facet_load(basis, fm.boundaries[f"ball:{i}"],
                               lambda pts, c=centre, t=towards: _bell(pts, c, t, phi0))
        fi = np.zeros_like(f)
        fi[0::dim] = push[0] * q
        fi[1::dim] = push[1] * q
        ti = float(fi @ rot)
        if not ti > 0:
            raise SolverError(f"the contact patch on tip ball {i} carries no torque "
                              "(patch outside the mesh?)")
        f += fi / ti
        if case.load == "rigid_cam":
            nodes = _facet_nodes(basis, fm.boundaries[f"ball:{i}"])
            inside = nodes[_bell(x[:, nodes], centre, towards, phi0) > 0]
            cp = centre - g.tip_radius_mm * push  # contact point
            drive = push[0] * (-cp[1]) + push[1] * cp[0]  # (e_z x x_c) . d
            tangent = np.array([-push[1], push[0]])
            for n in inside:
                s_i = tangent @ (x[:2, n] - cp)
                rows.append((n * dim, n * dim + 1, push, i, s_i))
                rhs.append(drive)
    torque = float(f @ rot)
    constraints = None
    if case.load == "rigid_cam":
        from scipy.sparse import coo_matrix

        if not rows:
            raise SolverError("no mesh nodes inside the rigid-cam contact patch; refine the "
                              "mesh at the tip ball or widen the patch")
        r, c, v = [], [], []
        S = np.zeros((len(rows), n_model))
        for k, (dx_, dy_, push, flex, s_i) in enumerate(rows):
            r += [k, k]
            c += [dx_, dy_]
            v += [push[0], push[1]]
            S[k, flex] = -s_i
        B = coo_matrix((v, (r, c)), shape=(len(rows), basis.N * dim)).tocsr()
        constraints = (B, np.asarray(rhs), S)
    return System(basis=basis, dim=dim, A=A, f=f, torque_Nmm=torque, fixed=fixed, held=held,
                  rotation=rot, constraints=constraints, lam=lam, mu=mu, plane_stress=plane,
                  thickness_mm=fm.thickness_mm)
