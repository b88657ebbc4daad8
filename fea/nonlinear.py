"""Geometrically nonlinear elasticity: total Lagrangian, St Venant-Kirchhoff material.

Small strains, large rotations: the Green-Lagrange strain E = (F^T F - I) / 2
with F = I + grad u, the second Piola-Kirchhoff stress S = D E (the linear
elastic D of :func:`fea.problem.stiffness_matrix`, plane-stress lambda in 2D),
the internal force f_a,i = int F_ik S_kl dN_a/dX_l dV and its consistent
tangent K = K_material + K_geometric. At u = 0 the tangent is exactly the
linear stiffness matrix (tested). A flexure bent through 0.07 rad sees a
spurious linear strain of omega^2 / 2 ~ 2.5e-3 (500 MPa of fake stress) that
E does not have: stresses of a nonlinear solution must come from E
(:func:`nodal_von_mises_green`). Vectorised over elements like
:func:`fea.problem.stiffness_matrix`; same DOF numbering (node * dim + component).
Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from fea.results import _grad, _stress


def _voigt(dim: int):
    """Voigt rows: normal components, then shear pairs (engineering shear)."""
    if dim == 3:
        return [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    return [(0, 0), (1, 1), (0, 1)]


def _D(lam: float, mu: float, dim: int) -> np.ndarray:
    nv = 6 if dim == 3 else 3
    D = np.zeros((nv, nv))
    D[:dim, :dim] = lam
    D[np.arange(dim), np.arange(dim)] += 2 * mu
    D[dim:, dim:] = mu * np.eye(nv - dim)
    return D


def internal_force(basis, u: np.ndarray, lam: float, mu: float, scale: float = 1.0,
                   tangent: bool = True, chunk: int = 4000):
    """Internal force vector (N) and, if ``tangent``, the tangent stiffness (N/mm, CSR).

    Args:
        basis: scalar quadratic scikit-fem ``CellBasis`` (its quadrature is used).
        u: displacement DOF vector (mm), DOF n * dim + i.
        lam, mu: Lame parameters (MPa); plane-stress lambda for 2D.
        scale: factor on every integral (2D: the thickness, mm).
    """
    from scipy.sparse import coo_matrix

    nloc = len(basis.basis)
    dim = basis.mesh.dim()
    G = np.stack([np.asarray(basis.basis[a][0].grad) for a in range(nloc)])  # (a, k, e, q)
    G = np.transpose(G, (2, 3, 1, 0))  # (e, q, k, a)
    dx = np.asarray(basis.dx) * scale
    ne, nq = dx.shape
    dofs = basis.element_dofs.T  # (e, a)
    U = u.reshape(-1, dim)[dofs]  # (e, a, i)
    D = _D(lam, mu, dim)
    rows = _voigt(dim)
    nv = len(rows)
    nd = nloc * dim
    f = np.zeros(basis.N * dim)
    vals = []
    gd = (dofs[:, :, None] * dim + np.arange(dim)).reshape(ne, nd)
    for e0 in range(0, ne, chunk):
        sl = slice(e0, min(ne, e0 + chunk))
        g = G[sl]
        m = g.shape[0]
        # batched small matrix products (matmul is much faster than einsum here)
        F = np.swapaxes(np.matmul(g, U[sl][:, None]), 2, 3) + np.eye(dim)  # F_ik = d_ik + du_i/dX_k
        E = 0.5 * (np.matmul(np.swapaxes(F, 2, 3), F) - np.eye(dim))
        Ev = np.stack([E[..., k, l] * (1.0 if k == l else 2.0) for k, l in rows], axis=-1)
        Sv = Ev @ D.T  # (e, q, nv)
        w = dx[sl]
        S = np.zeros((m, nq, dim, dim))
        for r, (k, l) in enumerate(rows):
            S[:, :, k, l] = Sv[:, :, r]
            S[:, :, l, k] = Sv[:, :, r]
        P = np.matmul(F, S) * w[:, :, None, None]  # first Piola-Kirchhoff stress x weight
        fe = np.swapaxes(np.matmul(P, g).sum(axis=1), 1, 2)  # (e, a, i)
        f += np.bincount(gd[sl].ravel(), weights=fe.ravel(), minlength=f.size)
        if tangent:
            # B0[e, q, r, a, i]: d E_r / d u_{a,i}
            B0 = np.zeros((m, nq, nv, nloc, dim))
            for r, (k, l) in enumerate(rows):
                if k == l:
                    B0[:, :, r] = F[:, :, :, k][:, :, None, :] * g[:, :, k, :, None]
                else:
                    B0[:, :, r] = (F[:, :, :, k][:, :, None, :] * g[:, :, l, :, None]
                                   + F[:, :, :, l][:, :, None, :] * g[:, :, k, :, None])
            B0 = B0.reshape(m, nq, nv, nd)
            DB = np.einsum("rs,eqsb->eqrb", D, B0)
            Bw = (B0 * w[:, :, None, None]).reshape(m, nq * nv, nd)
            Km = np.matmul(Bw.transpose(0, 2, 1), DB.reshape(m, nq * nv, nd))
            Kg = np.einsum("eqka,eqkl,eqlb,eq->eab", g, S, g, w)  # (e, a, b)
            Km = Km.reshape(m, nloc, dim, nloc, dim)
            Km += Kg[:, :, None, :, None] * np.eye(dim)[None, None, :, None, :]
            vals.append(Km.reshape(m, nd * nd).ravel())
    if not tangent:
        return f, None
    n = basis.N * dim
    r_ = np.repeat(gd, nd, axis=1).ravel()
    c_ = np.tile(gd, (1, nd)).ravel()
    K = coo_matrix((np.concatenate(vals), (r_, c_)), shape=(n, n)).tocsr()
    return f, K


def nodal_von_mises_green(system, u: np.ndarray) -> np.ndarray:
    """Nodal von Mises stress (MPa) of S = D E (Green-Lagrange E), averaged over the
    elements sharing each node, evaluated like :func:`fea.results.nodal_von_mises`.

    For small strains S equals the rotated Cauchy stress to O(strain), and the
    von Mises value is rotation invariant.
    """
    from skfem import CellBasis

    mesh = system.basis.mesh
    scalar = mesh.elem()
    X = np.asarray(scalar.doflocs, dtype=float).T
    sb = CellBasis(mesh, scalar, quadrature=(X, np.ones(X.shape[1])))
    H = _grad(sb, u, system.dim)  # (i, k, e, q)
    # a gradient whose symmetric part is E: H + H^T H / 2
    Hg = H + 0.5 * np.einsum("ike,ile->kle", H.reshape(*H.shape[:2], -1),
                             H.reshape(*H.shape[:2], -1)).reshape(H.shape)
    vm = _stress(Hg, system.lam, system.mu, system.plane_stress)
    dofs = sb.element_dofs
    total = np.bincount(dofs.ravel(), weights=vm.T.ravel(), minlength=sb.N)
    count = np.bincount(dofs.ravel(), minlength=sb.N)
    return total / np.maximum(count, 1)
