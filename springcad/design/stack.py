"""Series stacks: series stiffness, eq. 10, backlash and the hardware layout.

The connection sequence (the paper's alternation rule) is
:mod:`springcad.connections`; the parts and their places are
:mod:`springcad.design.hardware`. Units: mm, N*mm, rad, kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from springcad.connections import connection_sequence
from springcad.design.connections import camshaft_indices
from springcad.design.hardware import (Component, StackLayout, bolt_circle_limit_mm, d_joints,
                                      stack_layout)
from springcad.design.joint_strength import stack_pin_strengths
from springcad.design.ring import pinned_hole_patterns
from springcad.design.spring import SpringDesign
from springcad.design.tolerance import Interface, StackBacklash, stack_backlash
from springcad.units import J_PER_NMM, MM3_PER_CM3, NMM_PER_NM

__all__ = ["StackDesign", "camshaft_indices", "connection_sequence", "design_stack",
           "eq10_limit", "series_stiffness"]


def series_stiffness(stiffnesses) -> float:
    """1/K = sum 1/K_i (same units as the inputs)."""
    return 1.0 / sum(1.0 / k for k in stiffnesses)


def eq10_limit(limits_rad, stiffnesses) -> tuple[float, float, tuple[float, ...]]:
    """Stack deflection limit, paper eq. 10.

    Returns:
        (limit_rad, torque at the limit, each spring's deflection at the limit).
    """
    torque = min(t * k for t, k in zip(limits_rad, stiffnesses))
    shares = tuple(torque / k for k in stiffnesses)
    return sum(shares), torque, shares


@dataclass(frozen=True, repr=False)
class StackDesign:
    """A stack of designed springs with its predictions."""

    springs: tuple[SpringDesign, ...]
    input: str
    output: str
    joints: tuple[str, ...]
    backlash: StackBacklash
    layout: StackLayout

    @property
    def components(self) -> tuple[Component, ...]:
        """Every part of the stack (:mod:`springcad.design.hardware`)."""
        return self.layout.components

    @property
    def sequence(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.springs)

    @property
    def stiffness_Nmm_per_rad(self) -> float:
        return series_stiffness([s.stiffness_beam_Nmm_per_rad for s in self.springs])

    @property
    def target_stiffness_Nmm_per_rad(self) -> float:
        return series_stiffness([s.target_stiffness_Nmm_per_rad for s in self.springs])

    @property
    def limit(self):
        return eq10_limit([s.max_deflection_rad for s in self.springs],
                          [s.stiffness_beam_Nmm_per_rad for s in self.springs])

    @property
    def max_deflection_rad(self) -> float:
        return self.limit[0]

    @property
    def sum_of_limits_rad(self) -> float:
        """Sum of the springs' own limits: what eq. 10 gives only when all springs share one peak torque."""
        return sum(s.max_deflection_rad for s in self.springs)

    @property
    def limiting_spring(self) -> str:
        t = [s.max_deflection_rad * s.stiffness_beam_Nmm_per_rad for s in self.springs]
        return self.springs[t.index(min(t))].name

    @property
    def energy_J(self) -> float:
        return 0.5 * self.stiffness_Nmm_per_rad * self.max_deflection_rad ** 2 * J_PER_NMM

    @property
    def mass_kg(self) -> float:
        return sum(c.mass_kg for c in self.components if c.in_mass)

    @property
    def height_mm(self) -> float:
        return self.layout.height_mm

    @property
    def envelope_radius_mm(self) -> float:
        return self.layout.envelope_radius_mm

    @property
    def has_bushing(self) -> bool:
        return self.layout.floating_camshafts

    @property
    def envelope_volume_mm3(self) -> float:
        return math.pi * self.envelope_radius_mm ** 2 * self.height_mm

    def notes(self) -> list[str]:
        out = []
        limit, torque, _ = self.limit
        if abs(self.sum_of_limits_rad - limit) > 1e-9:
            out.append(
                f"eq. 10: the stack limit is {limit:.3f} rad, not the sum of the springs' limits "
                f"{self.sum_of_limits_rad:.3f} rad: spring {self.limiting_spring} reaches its limit "
                f"first at {torque / NMM_PER_NM:.2f} N*m and the other springs stay below theirs")
        return out + self.warnings()

    def warnings(self) -> list[str]:
        """What makes this stack unfit to release as designed (cam interfaces that can jam)."""
        b = self.backlash
        if not (b.interference_possible or b.mc_interference_fraction > 0):
            return []
        worst = (f"worst-case gap d_min < 0 (worst_min backlash {b.worst_min:.4f} rad)"
                 if b.interference_possible else
                 f"worst-case gap d_min >= 0 (worst_min backlash {b.worst_min:.4f} rad)")
        return [f"interference warning: {worst}; {100 * b.mc_interference_fraction:.1f} % of "
                "Monte Carlo stacks have at least one cam interface in interference: tighten "
                "tolerances or raise w_gap_mm"]

    def __repr__(self) -> str:
        return (f"StackDesign({' + '.join(self.sequence)}, K={self.stiffness_Nmm_per_rad:.6g} "
                f"N*mm/rad, input {self.input}, output {self.output})")

    def to_dict(self) -> dict:
        limit, torque, shares = self.limit
        return {
            "sequence": list(self.sequence),
            "input": self.input,
            "output": self.output,
            "connections": [f"{j}-to-{j}" for j in self.joints],
            "stiffness_Nm_per_rad": self.stiffness_Nmm_per_rad / NMM_PER_NM,
            "target_stiffness_Nm_per_rad": self.target_stiffness_Nmm_per_rad / NMM_PER_NM,
            "max_deflection_rad": limit,
            "sum_of_spring_limits_rad": self.sum_of_limits_rad,
            "limiting_spring": self.limiting_spring,
            "torque_at_limit_Nm": torque / NMM_PER_NM,
            "shares_at_limit": [
                {"spring": s.name, "deflection_rad": th, "torque_Nm": torque / NMM_PER_NM,
                 "fraction_of_own_limit": th / s.max_deflection_rad}
                for s, th in zip(self.springs, shares)],
            "backlash_rad": self.backlash.to_dict(),
            "rim_pins": [p.to_dict() for p in stack_pin_strengths(self)],
            "height_mm": self.height_mm,
            "envelope_radius_mm": self.envelope_radius_mm,
            "envelope_volume_cm3": self.envelope_volume_mm3 / MM3_PER_CM3,
            "mass_kg": self.mass_kg,
            "energy_J": self.energy_J,
            "energy_density_J_per_cm3": self.energy_J / (self.envelope_volume_mm3 / MM3_PER_CM3),
            "specific_energy_J_per_kg": self.energy_J / self.mass_kg,
            "components": [c.to_dict() for c in self.components],
            "notes": self.notes(),
        }


def design_stack(springs: list[SpringDesign], input_connection: str, mc_samples: int = 20000,
                 seed: int = 1) -> StackDesign:
    """Assemble designed springs (input to output) into a :class:`StackDesign`."""
    # rims joined rim to rim are pinned through the same holes: one circle, one set of angles
    limit = bolt_circle_limit_mm(springs[0].hardware, len(springs),
                                 min(s.outer_radius_mm for s in springs))
    holed = pinned_hole_patterns({s.name: s for s in springs}, [s.name for s in springs],
                                 input_connection, limit)
    springs = [holed[s.name] for s in springs]
    joints, output = connection_sequence(len(springs), input_connection)
    mfg = springs[0].manufacturing
    interfaces = [Interface(s.contact_radius_mm, s.manufacturing.w_gap_mm,
                            s.manufacturing.t_spring_mm, s.manufacturing.t_shaft_mm, cam)
                  for s, cam in zip(springs, camshaft_indices(joints))]
    layout = stack_layout(springs, joints, input_connection, output)
    backlash = stack_backlash(interfaces, mc_samples, seed, mfg.tolerance_distribution,
                              d_joints(layout, mfg.t_shaft_mm))
    return StackDesign(tuple(springs), input_connection, output, joints, backlash, layout)
