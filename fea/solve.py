"""Checked linear solves: a singular system or a large residual is an error, never a number.

The solver is a sparse direct factorisation: MKL PARDISO through pypardiso when
it is installed (fastest here), SciPy's SuperLU otherwise. Smoothed-aggregation
AMG was measured to diverge on these systems unless given the 3x3 node blocks
and the rigid-body modes; a direct solver needs neither and is exact to
round-off at the sizes used (< 1e6 DOFs).
Units: mm, N.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np

from springcad.errors import SolverError

#: largest accepted normwise backward error ||r|| / (||M|| ||x|| + ||b||) (infinity norms):
#: a backward-stable direct solve with refinement reaches ~1e-16 whatever the size; the
#: relative residual ||r|| / ||b|| has a round-off floor ~eps ||M|| ||x|| / ||b|| that grows
#: with the mesh (a few 1e-9 at 85k DOFs), so it is not the test
RESIDUAL_TOLERANCE = 1e-10
#: largest accepted growth ||M|| ||x|| / ||b||, a lower bound on the condition number: a
#: model held against rigid motion stays far below it (~1e6-1e9 here); a singular one
#: (pivots perturbed to round-off) exceeds it
GROWTH_LIMIT = 1e13


@dataclass(frozen=True)
class SolveInfo:
    """How a linear solve went.

    Attributes:
        method: "pardiso" or "superlu".
        dofs: total DOFs; free: DOFs solved for; constraints: Lagrange rows.
        residual: normwise backward error ||M x - b|| / (||M|| ||x|| + ||b||) of the
            solved system, infinity norms (-).
        growth: ||M|| ||x|| / ||b||, a lower bound on the condition number (-).
        equilibrium_error: |applied + reaction torque| / applied torque (-).
        time_s: wall time of factorisation and solve (s).
    """

    method: str
    dofs: int
    free: int
    constraints: int
    residual: float
    growth: float
    equilibrium_error: float
    time_s: float


def available_method(n_dofs: int = 10 ** 9, dim: int = 3) -> str:
    """The faster direct solver for a system of this size.

    SuperLU is quicker for 2D and small systems (PARDISO's analysis phase
    costs ~0.5 s); PARDISO for 3D systems (10x faster than SuperLU at 36k DOFs).
    """
    import importlib.util

    if (dim == 2 and n_dofs < 50_000) or n_dofs < 8_000:
        return "superlu"
    return "pardiso" if importlib.util.find_spec("pypardiso") is not None else "superlu"


_PARDISO: dict = {}


def _pardiso(mtype: int):
    """One PARDISO handle per matrix type per process. pypardiso searches the whole
    Python prefix for the MKL library when it is not given (~1.5 s): look in
    ``<prefix>/lib`` first and tell it through ``PYPARDISO_MKL_RT``."""
    if mtype not in _PARDISO:
        import glob
        import os
        import sys

        if "PYPARDISO_MKL_RT" not in os.environ:  # skip pypardiso's recursive search
            found = sorted(glob.glob(f"{sys.prefix}/lib/libmkl_rt.so*"), key=len)
            if found:
                os.environ["PYPARDISO_MKL_RT"] = found[0]
        import pypardiso

        _PARDISO[mtype] = pypardiso.PyPardisoSolver(mtype=mtype)
    return _PARDISO[mtype]


def _direct(M, b, method: str, symmetric_pd: bool, tol: float):
    """Factorise M, solve M x = b, and refine iteratively (up to 3 steps) until the
    backward error is below ``tol``."""
    if method == "pardiso":
        solver = _pardiso(2 if symmetric_pd else 11)
        A_in = M
        if symmetric_pd:
            from scipy.sparse import triu

            A_in = triu(M, format="csr")
        solver.set_iparm(1, 1)   # non-default iparms
        solver.set_iparm(2, 2)   # METIS nested dissection
        solver.set_iparm(10, 13 if not symmetric_pd else 8)  # pivot perturbation
        solver.set_iparm(11, 1 if not symmetric_pd else 0)   # scaling
        solver.set_iparm(13, 1 if not symmetric_pd else 0)   # weighted matching
        A_in = A_in.tocsr()
        try:
            solver.factorize(A_in)
            step = lambda r: solver.solve(A_in, r)  # noqa: E731 - reuses the factorisation
            x = _refine(M, b, step, tol)
        finally:
            solver.free_memory(everything=True)
        return x
    from scipy.sparse.linalg import splu

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lu = splu(M.tocsc(), permc_spec="MMD_AT_PLUS_A" if symmetric_pd else "COLAMD")
    return _refine(M, b, lu.solve, tol)


def backward_error(M, x, b) -> tuple[float, float]:
    """Normwise backward error and growth of a solution of M x = b (infinity norms).

    Returns:
        (||M x - b|| / (||M|| ||x|| + ||b||), ||M|| ||x|| / ||b||), both dimensionless.
    """
    m_norm = float(abs(M).sum(axis=1).max())
    x_norm, b_norm = float(np.linalg.norm(x, np.inf)), float(np.linalg.norm(b, np.inf))
    r_norm = float(np.linalg.norm(M @ x - b, np.inf))
    backward = r_norm / max(m_norm * x_norm + b_norm, 1e-300)
    return backward, m_norm * x_norm / max(b_norm, 1e-300)


def _refine(M, b, step, tol):
    x = step(b)
    for _ in range(3):
        if not np.all(np.isfinite(x)) or backward_error(M, x, b)[0] <= tol:
            break
        x = x + step(b - M @ x)
    return x


def solve(system, method: str | None = None):
    """Solve a :class:`~fea.problem.System` for unit torque (traction) or unit rotation (cam).

    Returns:
        (u, info): displacement DOF vector (mm) and :class:`SolveInfo`.

    Raises:
        SolverError: the system is singular (e.g. unsupported), the factorisation
            failed, the solution is not finite, or the residual exceeds
            :data:`RESIDUAL_TOLERANCE`.
    """
    from scipy.sparse import bmat

    A, f = system.A.tocsr(), system.f
    method = method or available_method(A.shape[0], system.dim)
    N = A.shape[0]
    free = np.setdiff1d(np.arange(N), system.fixed)
    if free.size == N:
        raise SolverError("no DOFs are held: the stiffness matrix is singular (rigid-body motion)")
    A_ff = A[free][:, free].tocsr()
    t0 = time.perf_counter()
    u = np.zeros(N)
    if system.constraints is None:
        rhs = f[free]
        M, b, spd = A_ff, rhs, True
    else:
        from scipy.sparse import csr_matrix

        B, c, S = system.constraints
        B = B.tocsc()
        if abs(B[:, system.fixed]).sum() > 0:
            raise SolverError("the rigid-cam patch touches a held DOF; the load case is "
                              "impossible (patch on the support)")
        B_f = B[:, free]
        Sm = csr_matrix(S)
        # unknowns: free displacements, pad rotations beta, multipliers
        M = bmat([[A_ff, None, B_f.T], [None, None, Sm.T], [B_f, Sm, None]], format="csr")
        b = np.concatenate([np.zeros(free.size + S.shape[1]), c])
        spd = False
    try:
        x = _direct(M, b, method, spd, 0.01 * RESIDUAL_TOLERANCE)
    except (ImportError, OSError) as err:  # the solver library itself, not the model
        raise SolverError(f"the sparse direct solver '{method}' could not be loaded "
                          f"({type(err).__name__}: {err}): the install is broken (pypardiso "
                          "finds MKL's mkl_rt under the Python prefix; a virtual environment "
                          "without it breaks it); reinstall pypardiso and mkl") from err
    except Exception as err:  # pardiso / superlu failures: singular or not factorisable
        raise SolverError(f"the linear system could not be factorised ({type(err).__name__}: "
                          f"{err}); the model is probably not held against rigid motion") from err
    dt = time.perf_counter() - t0
    if not np.all(np.isfinite(x)):
        raise SolverError("the solution is not finite: singular stiffness matrix (check supports)")
    res, growth = backward_error(M, x, b)
    if not growth <= GROWTH_LIMIT:
        raise SolverError(f"the solution is {growth:.1e} times the load over the stiffness "
                          f"(limit {GROWTH_LIMIT:.0e}): the model is singular or not held "
                          "against rigid motion (check supports and mesh)")
    if not res <= RESIDUAL_TOLERANCE:
        raise SolverError(f"linear solve backward error {res:.2e} exceeds "
                          f"{RESIDUAL_TOLERANCE:.0e}: the factorisation is inaccurate "
                          "(ill-conditioned system; check supports and mesh)")
    u[free] = x[:free.size]
    # torque equilibrium: the reactions at the held DOFs balance the applied torque
    rot = system.rotation
    Au = A @ u
    applied = float(Au[free] @ rot[free])
    react = float(Au[system.fixed] @ rot[system.fixed])
    eq = abs(applied + react) / max(abs(applied), 1e-300)
    energy = float(u @ (A @ u))
    if not energy > 0:
        raise SolverError("the load does no work on the structure (zero or negative energy); "
                          "the load case is impossible")
    return u, SolveInfo(method=method, dofs=N, free=int(free.size),
                        constraints=0 if system.constraints is None else int(len(c)),
                        residual=float(res), growth=float(growth), equilibrium_error=float(eq),
                        time_s=dt)
