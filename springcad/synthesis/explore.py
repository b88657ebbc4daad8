"""The design-space map (paper Fig. 8): what peak torque and deflection stacks can reach.

A grid of stack targets (stiffness K x deflection theta, log-spaced) times stacks
of 1 ... N identical disks times the disk parameters (thickness, contact radius)
is swept with the same screening as ``synthesize`` (no envelope height limit:
the map shows what the disk radius allows). From the table:

- :func:`reachable_region`: per number of disks and deflection, the smallest and
  largest feasible peak torque (the region of Fig. 8), with the best energy
  density and specific energy there;
- :func:`pareto_front`: the non-dominated points of two columns;
- :func:`mass_fronts`: lightest stack vs deflection at each stiffness of the grid;
- :func:`energy_front`: highest energy density vs deflection.

Pure functions on column dicts. Units in column names.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from springcad.config import HardwareSpec, ManufacturingSpec
from springcad.design import fatigue
from springcad.errors import ConfigError
from springcad.materials import material_table
from springcad.options import EXPLORE
from springcad.synthesis.candidates import CandidateSpace
from springcad.units import NMM_PER_NM


@dataclass(frozen=True)
class ExploreGrid:
    """The map's grid (N*m/rad, rad, mm).

    Attributes:
        stiffness_Nm_per_rad: (min, max, count), log-spaced stack stiffnesses.
        deflection_rad: (min, max, count), log-spaced stack deflections.
        max_disks: stacks of 1 ... max_disks identical disks.
        envelope_radius_mm: envelope radius, bushing included (mm).
        thickness_mm, contact_radius_mm: disk parameters tried at every target (mm).
        material: built-in material name.
        yield_margin, stress_concentration: as in the requirements: every disk keeps
            yield / predicted peak >= yield_margin, first designed to the beam stress
            yield / (margin x concentration) and lowered where the peak needs it.
    """

    stiffness_Nm_per_rad: tuple[float, float, int] = EXPLORE.stiffness_Nm_per_rad
    deflection_rad: tuple[float, float, int] = EXPLORE.deflection_rad
    max_disks: int = EXPLORE.max_disks
    envelope_radius_mm: float = EXPLORE.envelope_radius_mm
    thickness_mm: tuple[float, ...] = EXPLORE.thickness_mm
    contact_radius_mm: tuple[float, ...] = EXPLORE.contact_radius_mm
    material: str = EXPLORE.material
    yield_margin: float = 1.0
    stress_concentration: float = EXPLORE.stress_concentration

    @property
    def stiffnesses_Nm_per_rad(self) -> np.ndarray:
        lo, hi, n = self.stiffness_Nm_per_rad
        return np.geomspace(lo, hi, int(n))

    @property
    def deflections_rad(self) -> np.ndarray:
        lo, hi, n = self.deflection_rad
        return np.geomspace(lo, hi, int(n))

    def space(self, manufacturing: ManufacturingSpec | None = None,
              hardware: HardwareSpec | None = None) -> CandidateSpace:
        known = material_table()
        if self.material not in known:
            raise ConfigError("material", self.material,
                              f"is not a built-in material ({', '.join(known)})")

        mat = known[self.material]
        sigma = mat.yield_strength_MPa / (self.yield_margin * self.stress_concentration)
        endurance = fatigue.check(mat.name, 1.0)
        targets = tuple((float(k) * NMM_PER_NM, float(t)) for k in self.stiffnesses_Nm_per_rad
                        for t in self.deflections_rad)
        return CandidateSpace(
            targets=targets, materials=(mat,), design_stress_MPa=(sigma,),
            max_outer_radius_mm=self.envelope_radius_mm, max_axial_length_mm=float("inf"),
            max_disks=self.max_disks, mixed=False, thickness_mm=tuple(self.thickness_mm),
            contact_radius_mm=tuple(self.contact_radius_mm), outer_radius_fractions=(1.0,),
            n_flexures=(), fewer_flexures=(0,), inputs=("shaft",), compliance_splits=(0.5,),
            min_tip_radius_mm=0.3, yield_margin=self.yield_margin,
            stress_concentration=self.stress_concentration,
            allowed_peak_MPa=(mat.yield_strength_MPa / self.yield_margin,),
            endurance_limit_MPa=(endurance.endurance_limit_MPa if endurance else float("nan"),),
            manufacturing=manufacturing or ManufacturingSpec(),
            hardware=hardware or HardwareSpec())


def reachable_region(cols: dict) -> dict[str, np.ndarray]:
    """Per (number of disks, deflection): feasible peak-torque range and the best energies.

    Returns columns n_disks, deflection_rad, min/max_peak_torque_Nm,
    best_energy_density_J_per_cm3, best_specific_energy_J_per_kg, lightest_mass_kg.
    """
    f = cols["feasible"]
    n, th, T = cols["n_disks"][f], cols["deflection_rad"][f], cols["peak_torque_Nm"][f]
    ed, se, m = (cols["energy_density_J_per_cm3"][f], cols["specific_energy_J_per_kg"][f],
                 cols["mass_kg"][f])
    keys = np.unique(np.column_stack([n, th]), axis=0) if len(n) else np.zeros((0, 2))
    out = {k: [] for k in ("n_disks", "deflection_rad", "min_peak_torque_Nm",
                           "max_peak_torque_Nm", "best_energy_density_J_per_cm3",
                           "best_specific_energy_J_per_kg", "lightest_mass_kg")}
    for kn, kt in keys:
        sel = (n == kn) & (th == kt)
        out["n_disks"].append(int(kn))
        out["deflection_rad"].append(float(kt))
        out["min_peak_torque_Nm"].append(float(T[sel].min()))
        out["max_peak_torque_Nm"].append(float(T[sel].max()))
        out["best_energy_density_J_per_cm3"].append(float(ed[sel].max()))
        out["best_specific_energy_J_per_kg"].append(float(se[sel].max()))
        out["lightest_mass_kg"].append(float(m[sel].min()))
    return {k: np.array(v) for k, v in out.items()}


def pareto_front(x, y, maximise_x: bool = True, maximise_y: bool = True) -> np.ndarray:
    """Indices of the non-dominated points of (x, y), sorted by x.

    A point is dominated when another is at least as good in both and better in one.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    sx = x if maximise_x else -x
    sy = y if maximise_y else -y
    order = np.lexsort((-sy, -sx))  # best x first, then best y
    keep, best_y = [], -np.inf
    for i in order:
        if sy[i] > best_y:
            keep.append(i)
            best_y = sy[i]
    keep = np.array(keep, dtype=int)
    return keep[np.argsort(x[keep])]


def mass_fronts(cols: dict) -> dict[str, np.ndarray]:
    """At each stiffness of the grid: the lightest stacks vs deflection (Pareto: more
    deflection and less mass). Columns target_stiffness_Nm_per_rad, deflection_rad, mass_kg,
    n_disks, cid."""
    f = np.flatnonzero(cols["feasible"])
    out = {k: [] for k in ("target_stiffness_Nm_per_rad", "deflection_rad", "mass_kg", "n_disks",
                           "cid")}
    for k in np.unique(cols["target_stiffness_Nm_per_rad"][f]):
        sel = f[cols["target_stiffness_Nm_per_rad"][f] == k]
        front = sel[pareto_front(cols["deflection_rad"][sel], cols["mass_kg"][sel],
                                 maximise_x=True, maximise_y=False)]
        for i in front:
            out["target_stiffness_Nm_per_rad"].append(float(k))
            out["deflection_rad"].append(float(cols["deflection_rad"][i]))
            out["mass_kg"].append(float(cols["mass_kg"][i]))
            out["n_disks"].append(int(cols["n_disks"][i]))
            out["cid"].append(int(cols["cid"][i]))
    return {k: np.array(v) for k, v in out.items()}


def energy_front(cols: dict) -> dict[str, np.ndarray]:
    """Energy density vs deflection, Pareto (both higher is better), over every feasible stack."""
    f = np.flatnonzero(cols["feasible"])
    front = f[pareto_front(cols["deflection_rad"][f], cols["energy_density_J_per_cm3"][f])]
    return {k: cols[k][front] for k in ("cid", "n_disks", "deflection_rad", "peak_torque_Nm",
                                         "target_stiffness_Nm_per_rad", "energy_density_J_per_cm3",
                                         "specific_energy_J_per_kg", "mass_kg")}
