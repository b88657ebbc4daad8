"""Candidate enumeration: every stack of the design space has one integer id.

A stack is ``n_a`` disks of design A followed (input to output) by ``n_b`` disks
of design B (``n_b = 0``: identical disks). Every disk is designed for the same
peak torque T = K theta (the stack reaches its deflection with every disk at its
own limit, eq. 10 with no disk under-used). The A group takes the share ``split``
of the stack compliance:

    K_A = n_a K / split,  theta_A = split theta / n_a,
    K_B = n_b K / (1 - split),  theta_B = (1 - split) theta / n_b.

A *family* is one (n_a, n_b); inside a family the candidates are the cartesian
product of the dimensions (target, material, outer-radius fraction, input, z_A,
z_B, r_c, split, N), so a candidate id decodes with :func:`numpy.unravel_index`
and a batch of ids never needs the whole table in memory. Ids are stable for a
given space, which is what lets an interrupted run resume.
Units: N*mm, mm, rad, MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from springcad.config import HardwareSpec, ManufacturingSpec
from springcad.design.hardware import BUSHING_CLEARANCE_MM
from springcad.materials import Material

#: version of what a candidate row holds: part of the fingerprint of a run folder, so a
#: folder swept by an earlier screening model is not resumed (2: predicted peak stress)
SCREENING_MODEL = 2
#: dimension names, in product order
DIMS = ("target", "material", "fraction", "input", "z_a", "z_b", "rc", "split", "n_flex")


@dataclass(frozen=True)
class Family:
    """Stacks of ``n_a`` disks of design A then ``n_b`` of design B (0: identical)."""

    n_a: int
    n_b: int

    @property
    def n_disks(self) -> int:
        return self.n_a + self.n_b

    @property
    def label(self) -> str:
        if self.n_b == 0:
            return f"{self.n_a} identical" if self.n_a > 1 else "1 disk"
        return f"{self.n_a}A+{self.n_b}B mixed"


@dataclass(frozen=True)
class CandidateSpace:
    """The enumerated design space and everything a worker needs to evaluate it.

    Attributes:
        targets: (stack stiffness N*mm/rad, stack deflection rad) pairs.
        materials: candidate materials; ``design_stress_MPa`` the flexure stress of each.
        max_outer_radius_mm: envelope radius, bushing included (mm; inf = none).
        max_axial_length_mm: stack height limit (mm; inf = none).
        max_disks, mixed: which families.
        thickness_mm, contact_radius_mm, outer_radius_fractions, n_flexures, inputs,
            compliance_splits: the dimensions.
        fewer_flexures: with ``n_flexures`` empty, N = (largest that fits) - k for each k.
        min_tip_radius_mm: smallest tip-ball radius (mm).
        tip_radius_mm: fixed tip-ball radius (mm; None: sized for the peak load), see
            :class:`~springcad.synthesis.requirements.SearchSpace`.
        yield_margin, stress_concentration: required yield strength / predicted peak
            stress, and the factor that set ``design_stress_MPa`` (reported only).
        allowed_peak_MPa: per material, the largest predicted peak stress of a disk
            (yield / the required margin, the fatigue margin included) (MPa).
        fatigue_limited: per material, whether the fatigue margin sets that limit.
        endurance_limit_MPa: per material, the part's endurance limit S_e (MPa; NaN
            without fatigue data), for the fatigue margin column.
    """

    targets: tuple[tuple[float, float], ...]
    materials: tuple[Material, ...]
    design_stress_MPa: tuple[float, ...]
    max_outer_radius_mm: float
    max_axial_length_mm: float
    max_disks: int
    mixed: bool
    thickness_mm: tuple[float, ...]
    contact_radius_mm: tuple[float, ...]
    outer_radius_fractions: tuple[float, ...]
    n_flexures: tuple[int, ...]
    fewer_flexures: tuple[int, ...]
    inputs: tuple[str, ...]
    compliance_splits: tuple[float, ...]
    min_tip_radius_mm: float
    yield_margin: float
    stress_concentration: float
    manufacturing: ManufacturingSpec
    hardware: HardwareSpec
    flexure: str = "auto"
    """"auto" or "straight" (serpentine disks rejected)."""
    stiffness_tolerance: float = float("inf")
    """Accepted |K_stack / K_target - 1| of the beam stiffness the built widths give (-)."""
    allowed_peak_MPa: tuple[float, ...] = ()
    fatigue_limited: tuple[bool, ...] = ()
    endurance_limit_MPa: tuple[float, ...] = ()
    fatigue_margin: float | None = None
    tip_radius_mm: float | None = None
    contact_allowed_MPa: tuple[float, ...] = ()
    """Per material: allowed tip-ball contact von Mises (MPa; default yield / margin)."""

    @classmethod
    def from_requirements(cls, req) -> "CandidateSpace":
        """The space of a :class:`~springcad.synthesis.requirements.Requirements`."""
        s = req.search
        return cls(
            targets=((req.target_stiffness_Nmm_per_rad, req.deflection_rad),),
            materials=req.materials,
            design_stress_MPa=tuple(req.design_stress_MPa(m) for m in req.materials),
            max_outer_radius_mm=req.max_outer_radius_mm,
            max_axial_length_mm=req.max_axial_length_mm, max_disks=s.max_disks, mixed=s.mixed,
            thickness_mm=s.thickness_mm, contact_radius_mm=s.contact_radius_mm,
            outer_radius_fractions=s.outer_radius_fractions, n_flexures=s.n_flexures,
            fewer_flexures=s.fewer_flexures, inputs=s.inputs, compliance_splits=s.compliance_splits,
            min_tip_radius_mm=s.min_tip_radius_mm, yield_margin=req.yield_margin,
            stress_concentration=req.stress_concentration, manufacturing=req.manufacturing,
            hardware=req.hardware, flexure=s.flexure,
            stiffness_tolerance=req.stiffness_tolerance,
            allowed_peak_MPa=tuple(req.allowed_peak_MPa(m) for m in req.materials),
            fatigue_limited=tuple(req.fatigue_limited(m) for m in req.materials),
            endurance_limit_MPa=tuple(req.endurance_limit_MPa(m) for m in req.materials),
            fatigue_margin=req.fatigue_margin, tip_radius_mm=s.tip_radius_mm,
            contact_allowed_MPa=tuple(req.contact_allowed_MPa(m) for m in req.materials))

    def stress_limits(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per material: allowed predicted peak (MPa), fatigue-limited, S_e (MPa; NaN)."""
        k = len(self.materials)
        allowed = (self.allowed_peak_MPa
                   or tuple(m.yield_strength_MPa / self.yield_margin for m in self.materials))
        return (np.array(allowed, dtype=float),
                np.array(self.fatigue_limited or (False,) * k, dtype=bool),
                np.array(self.endurance_limit_MPa or (float("nan"),) * k, dtype=float))

    def contact_limits(self, material_index) -> tuple[np.ndarray, np.ndarray]:
        """(Poisson's ratio, allowed tip-ball contact von Mises MPa) of each row's material:
        yield / the required yield margin, and the duty's contact fatigue, as the design
        sizes its balls."""
        idx = np.asarray(material_index, dtype=int)
        nu = np.array([m.poisson_ratio for m in self.materials], dtype=float)
        allowed = np.array(self.contact_allowed_MPa or
                           [m.yield_strength_MPa / self.yield_margin for m in self.materials])
        return nu[idx], allowed[idx]

    # ------------------------------------------------------------- families
    @property
    def families(self) -> tuple[Family, ...]:
        out = []
        for n in range(1, self.max_disks + 1):
            out.append(Family(n, 0))
            if self.mixed:
                out.extend(Family(a, n - a) for a in range(1, n))
        return tuple(out)

    def shape(self, family: Family) -> tuple[int, ...]:
        mixed = family.n_b > 0
        return (len(self.targets), len(self.materials), len(self.outer_radius_fractions),
                len(self.inputs), len(self.thickness_mm), len(self.thickness_mm) if mixed else 1,
                len(self.contact_radius_mm), len(self.compliance_splits) if mixed else 1,
                len(self.n_flexures) or len(self.fewer_flexures))

    @property
    def sizes(self) -> np.ndarray:
        return np.array([math.prod(self.shape(f)) for f in self.families], dtype=np.int64)

    @property
    def total(self) -> int:
        return int(self.sizes.sum())

    def disk_outer_radius_mm(self, n_disks, fraction):
        """R_o of a disk: the envelope radius less the bushing of a 3+ stack, times the fraction."""
        hw = self.hardware
        bushing = np.where(np.asarray(n_disks) >= 3, BUSHING_CLEARANCE_MM + hw.bushing_wall_mm, 0.0)
        return (self.max_outer_radius_mm - bushing) * np.asarray(fraction)

    # ------------------------------------------------------------- decoding
    def decode(self, start: int, stop: int) -> dict[str, np.ndarray]:
        """Candidates ``start <= id < stop`` as columns of numbers (internal units)."""
        sizes = self.sizes
        offsets = np.concatenate([[0], np.cumsum(sizes)])
        stop = min(stop, self.total)
        parts = []
        for f_idx, fam in enumerate(self.families):
            lo, hi = max(start, offsets[f_idx]), min(stop, offsets[f_idx + 1])
            if lo >= hi:
                continue
            local = np.arange(lo - offsets[f_idx], hi - offsets[f_idx])
            idx = dict(zip(DIMS, np.unravel_index(local, self.shape(fam))))
            idx["cid"] = np.arange(lo, hi, dtype=np.int64)
            idx["family"] = np.full(hi - lo, f_idx)
            parts.append(idx)
        if not parts:
            return {}
        cols = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
        fams = self.families
        n_a = np.array([fams[i].n_a for i in cols["family"]])
        n_b = np.array([fams[i].n_b for i in cols["family"]])
        tg = np.array(self.targets)[cols["target"]]
        z = np.array(self.thickness_mm)
        mixed = n_b > 0
        split = np.where(mixed, np.array(self.compliance_splits)[cols["split"]], 1.0)
        # N > 0: exactly N flexures; N <= 0: -N fewer than the largest count that fits
        nflex = (np.array(self.n_flexures)[cols["n_flex"]] if self.n_flexures
                 else -np.array(self.fewer_flexures)[cols["n_flex"]])
        fraction = np.array(self.outer_radius_fractions)[cols["fraction"]]
        return {
            "cid": cols["cid"], "family": cols["family"], "n_a": n_a, "n_b": n_b,
            "target_stiffness_Nmm_per_rad": tg[:, 0], "deflection_rad": tg[:, 1],
            "material": cols["material"], "input": cols["input"],
            "outer_radius_mm": self.disk_outer_radius_mm(n_a + n_b, fraction),
            "z_a": z[cols["z_a"]], "z_b": np.where(mixed, z[cols["z_b"]], 0.0),
            "rc": np.array(self.contact_radius_mm)[cols["rc"]], "split": split,
            "n_flexures": nflex,
        }
