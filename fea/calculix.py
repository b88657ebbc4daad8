"""Independent check: the same mesh, material, supports and loads solved by CalculiX.

The scikit-fem system of :func:`fea.problem.assemble` is exported node for
node: quadratic tets become C3D10 (scikit-fem's local node order is
CalculiX's: corners, then edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4), held DOFs
become ``*BOUNDARY``, the consistent nodal loads of the cam traction patch
become ``*CLOAD``. CalculiX integrates C3D10 with the same 4-point rule, so
stiffness agrees to round-off on the same mesh; its nodal stresses are
extrapolated from the integration points and averaged at the nodes, as ours.
The 2D plane-stress model is not exported: CalculiX expands plane-stress
elements into 3D wedges, a different discretisation.

``ccx`` runs in a temporary folder that is removed afterwards.
Units: mm, N, MPa.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fea.mesh import to_rows
from fea.problem import assemble
from fea.results import _excluded_mask, evaluate, stiffness
from fea.solve import solve
from springcad.errors import SolverError
from springcad.units import NMM_PER_NM


@dataclass(eq=False)
class CalculixResult:
    """CalculiX solution of an exported system.

    Attributes:
        u: displacement DOF vector in the scikit-fem numbering (mm).
        von_mises_nodal_MPa: CalculiX nodal von Mises for ``u`` (MPa), per scikit-fem node.
        time_s: wall time of the ``ccx`` run (s), the input writing excluded.
        write_time_s: time to write the input deck (s).
        version: ``ccx`` version line.
    """

    u: np.ndarray
    von_mises_nodal_MPa: np.ndarray
    time_s: float
    write_time_s: float
    version: str


def ccx_path() -> str | None:
    """The ``ccx`` executable, or None when CalculiX is not installed."""
    return shutil.which("ccx") or shutil.which("ccx_2.20")


def write_inp(system, material, path: Path, title: str = "springcad sector") -> None:
    """Write a CalculiX input deck of a 3D :class:`~fea.problem.System` (traction load)."""
    if system.dim != 3:
        raise SolverError("the CalculiX check runs on 3D quadratic tetrahedra only")
    if system.constraints is not None:
        raise SolverError("the CalculiX check supports the traction cam load only")
    basis = system.basis
    x = to_rows(basis.doflocs)
    elems = basis.element_dofs.T + 1
    n = len(x)
    with open(path, "w") as fh:
        fh.write(f"** {title}\n*HEADING\n{title}\n*NODE, NSET=NALL\n")
        ids = np.arange(1, n + 1)
        np.savetxt(fh, np.column_stack([ids, x]), fmt=["%d", "%.13e", "%.13e", "%.13e"],
                   delimiter=", ")
        fh.write("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
        np.savetxt(fh, np.column_stack([np.arange(1, len(elems) + 1), elems]), fmt="%d",
                   delimiter=", ")
        fh.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n"
                 f"{material.youngs_modulus_MPa:.12e}, {material.poisson_ratio:.12e}\n"
                 "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        fh.write("*BOUNDARY\n")
        fixed = np.unique(system.fixed)
        np.savetxt(fh, np.column_stack([fixed // 3 + 1, fixed % 3 + 1, fixed % 3 + 1]),
                   fmt="%d", delimiter=", ")
        fh.write("*STEP\n*STATIC\n*CLOAD\n")
        # CalculiX reads at most 20 characters per field: 13 significant digits
        nz = np.flatnonzero(np.abs(system.f) > 1e-13 * np.abs(system.f).max())
        nz = nz[~np.isin(nz, fixed)]
        np.savetxt(fh, np.column_stack([nz // 3 + 1, nz % 3 + 1, system.f[nz]]),
                   fmt=["%d", "%d", "%.12e"], delimiter=", ")
        fh.write("*NODE FILE, OUTPUT=3D\nU, S\n*END STEP\n")


def _frd_blocks(path: Path) -> dict:
    """Nodal result blocks of an ASCII .frd file: name -> (node ids, values)."""
    out: dict[str, tuple] = {}
    name = None
    ids, vals = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith(" -4"):
                name = line.split()[1]
                ids, vals = [], []
            elif name and line.startswith(" -1"):
                ids.append(int(line[3:13]))
                body = line[13:].rstrip("\n")
                vals.append([float(body[i:i + 12]) for i in range(0, len(body), 12)
                             if body[i:i + 12].strip()])
            elif name and line.startswith(" -3"):
                out[name] = (np.asarray(ids), np.asarray(vals))
                name = None
    return out


def solve_ccx(system, material, threads: int = 2, keep_dir: Path | None = None) -> CalculixResult:
    """Solve an exported system with CalculiX.

    Raises:
        SolverError: ``ccx`` is missing, fails, or returns no displacements.
    """
    exe = ccx_path()
    if exe is None:
        raise SolverError("CalculiX (ccx) is not installed; install the calculix-ccx package")
    tmp = Path(tempfile.mkdtemp(prefix="springcad-ccx-"))
    try:
        t0 = time.perf_counter()
        write_inp(system, material, tmp / "job.inp")
        t1 = time.perf_counter()
        env = dict(os.environ, OMP_NUM_THREADS=str(threads),
                   CCX_NPROC_EQUATION_SOLVER=str(threads), CCX_NPROC_STIFFNESS=str(threads))
        proc = subprocess.run([exe, "-i", "job"], cwd=tmp, env=env, capture_output=True,
                              text=True, timeout=3600)
        t2 = time.perf_counter()
        frd = tmp / "job.frd"
        if proc.returncode != 0 or not frd.exists():
            tail = (proc.stdout + proc.stderr).strip().splitlines()[-5:]
            raise SolverError("CalculiX failed: " + " | ".join(tail))
        blocks = _frd_blocks(frd)
        if "DISP" not in blocks or "STRESS" not in blocks:
            raise SolverError("CalculiX wrote no displacement/stress results")
        ids, disp = blocks["DISP"]
        n = system.basis.N
        u = np.zeros(n * 3)
        u[(ids - 1)[:, None] * 3 + np.arange(3)] = disp[:, :3]
        sid, s = blocks["STRESS"]
        sx, sy, sz, txy, tyz, tzx = s[:, :6].T
        vm = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2)
                     + 3 * (txy ** 2 + tyz ** 2 + tzx ** 2))
        vmn = np.zeros(n)
        vmn[sid - 1] = vm
        version = proc.stdout.strip().splitlines()[0] if proc.stdout.strip() else "ccx"
        if keep_dir is not None:
            shutil.copytree(tmp, keep_dir, dirs_exist_ok=True)
        return CalculixResult(u=u, von_mises_nodal_MPa=vmn, time_s=t2 - t1, write_time_s=t1 - t0,
                              version=version)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


@dataclass(frozen=True)
class CrossCheck:
    """scikit-fem vs CalculiX on one mesh (N*mm/rad, MPa, s)."""

    dofs: int
    stiffness_skfem: float
    stiffness_ccx: float
    peak_skfem_MPa: float
    peak_ccx_MPa: float
    time_skfem_s: float
    time_ccx_s: float

    @property
    def stiffness_rel_diff(self) -> float:
        return abs(self.stiffness_ccx / self.stiffness_skfem - 1.0)

    @property
    def peak_rel_diff(self) -> float:
        return abs(self.peak_ccx_MPa / self.peak_skfem_MPa - 1.0)

    def to_dict(self) -> dict:
        return {"dofs": self.dofs, "stiffness_skfem_Nm_per_rad": self.stiffness_skfem / NMM_PER_NM,
                "stiffness_ccx_Nm_per_rad": self.stiffness_ccx / NMM_PER_NM,
                "stiffness_rel_diff": self.stiffness_rel_diff,
                "peak_skfem_MPa": self.peak_skfem_MPa, "peak_ccx_MPa": self.peak_ccx_MPa,
                "peak_rel_diff": self.peak_rel_diff, "time_skfem_s": self.time_skfem_s,
                "time_ccx_s": self.time_ccx_s,
                "time_ratio_skfem_over_ccx": self.time_skfem_s / self.time_ccx_s}


def cross_check(fm, material, case, max_deflection_rad: float, threads: int = 2) -> CrossCheck:
    """Solve a 3D mesh with scikit-fem and CalculiX; compare K and the nodal peak stress.

    The CalculiX peak uses the same exclusion zones (held faces, contact patch) on
    CalculiX's own nodal von Mises. Times are wall times of the whole solve
    (scikit-fem: assembly, factorisation, stress recovery; CalculiX: the ``ccx``
    process).
    """
    t0 = time.perf_counter()
    system = assemble(fm, material, case)
    u, info = solve(system)
    res = evaluate(fm, system, u, case, max_deflection_rad, {}, info)
    t_sk = time.perf_counter() - t0
    cc = solve_ccx(system, material, threads)
    g = fm.geometry
    k_model = stiffness(system, cc.u)
    k_ccx = k_model * (g.n_flexures / len(g.flexure_angles_rad)) / fm.thickness_fraction
    scale = k_ccx * max_deflection_rad / g.n_flexures * fm.thickness_fraction
    pts = system.basis.doflocs
    excl = _excluded_mask(pts, system, fm, case, 0.5 * g.rim_thickness_mm)
    peak_ccx = float(np.max(np.where(excl, -np.inf, cc.von_mises_nodal_MPa * scale)))
    return CrossCheck(dofs=system.n_dofs, stiffness_skfem=res.stiffness_Nmm_per_rad,
                      stiffness_ccx=k_ccx, peak_skfem_MPa=res.peak_von_mises_MPa,
                      peak_ccx_MPa=peak_ccx, time_skfem_s=t_sk, time_ccx_s=cc.time_s)
