"""The single-spring design record: :class:`SpringDesign`, what the design search makes.

The search (:mod:`springcad.design.search`) turns a :class:`~springcad.config.SpringSpec`
into this record; :mod:`springcad.design.resize` makes a record with other widths or
another root from it. The design follows the reference method
(``shared/notes/design-method.md``) with these deliberate deviations, each covered by a
test in ``tests/test_spring.py``:

1. The tip ball is sized for the *peak* load at the target deflection, not the
   load at the straight limit. When the spec exceeds the torque cap
   pi r_c^2 z sigma / (6 sqrt 3), the design stops and says so, unless the user
   fixed ``tip_radius_mm`` (as-built parts), in which case it warns.
2. N, r_c and R_r are found by exact enumeration and bracketing (no random search).
3. The serpentine optimiser is deterministic, with neighbour clearance and
   concave-edge radius as hard constraints (:func:`flexure.design_serpentine`).
4. Rim holes sit between flexures, fully inside the rim (``ring.py``).
5. The cam flank keeps the contact normal tangential and the gap is offset
   along the profile normal (``cam.py``).

Units: mm, N, MPa, N*mm, rad, kg.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from springcad.config import HardwareSpec, ManufacturingSpec, MaterialSpec, SpringSpec
from springcad.design import duty, fatigue
from springcad.design import flexure as fx
from springcad.design.curves import Profile
from springcad.design.shapes.base import FlexureRecord, FlexureShape
from springcad.design.shapes.registry import get as shape_named
from springcad.units import J_PER_NMM, MM3_PER_CM3, NMM_PER_NM

if TYPE_CHECKING:
    from springcad.design.stress import StressPrediction


@dataclass(frozen=True, repr=False)
class SpringDesign:
    """A complete single-spring design with its beam-theory predictions.

    Lengths mm, forces N, stresses MPa, torques N*mm, angles rad, mass kg.
    """

    name: str
    spec: SpringSpec
    material: MaterialSpec
    manufacturing: ManufacturingSpec
    hardware: HardwareSpec
    n_flexures: int
    contact_radius_mm: float
    root_radius_mm: float
    outer_radius_mm: float
    thickness_mm: float
    tip_radius_mm: float
    tip_radius_required_mm: float
    shape: FlexureRecord
    """The flexure shape's record: its name, width law, root width, centreline and area
    ratios (:mod:`springcad.design.shapes`)."""
    tip_load_N: float
    straight_limit_rad: float
    min_neighbour_clearance_mm: float | None
    rim_thickness_mm: float
    root_fillet_radius_mm: float
    neck_fillet_radius_mm: float
    torque_cap_Nmm: float
    stiffness_beam_Nmm_per_rad: float
    peak_stress_MPa: float
    ring: Profile | None = None
    cam: Profile | None = None
    hole_centres_mm: tuple[tuple[float, float], ...] = ()
    hole_diameter_mm: float = 0.0
    cam_tip_radius_mm: float = 0.0
    cam_root_radius_mm: float = 0.0
    cam_overtravel: float = 0.0
    cam_tip_clearance_mm: float = float("nan")
    """Estimated gap from the driving tooth tip to the ball at full deflection (mm)."""
    cam_min_tip_clearance_mm: float = 0.0
    """Tooth-tip-to-ball gap estimate the cam's flank length must reach at least (mm; 0: the
    design rule alone): set by the contact FEA's clearance correction
    (:func:`springcad.design.resize.with_cam_clearance`)."""
    warnings: tuple[str, ...] = field(default_factory=tuple)
    width_scale: float = 1.0
    """Factor on every flexure width (1.0 = the beam-theory widths; set by the FEA
    stiffness correction). ``root_width_mm`` and ``tip_load_N`` stay the beam-theory
    values; ``width_mm`` and the ring profile include the factor."""
    width_offset_mm: float = 0.0
    """Outward offset of every flexure edge and of the tip ball (a profile error, mm)."""
    root_flare: float = 0.0
    """Relative width added at the root (0.2 = 20 % wider), faded in over ``root_flare_length_mm``."""
    root_flare_length_mm: float = 0.0
    """Length of the root flare zone, from the root circle towards the tip (mm)."""
    stress_derating: float = 1.0
    """Beam stress used to size the flexures over the configured design stress (-): below 1
    when the predicted peak of the real geometry needed a lower beam stress to keep the
    required yield margin (:func:`design_spring`)."""
    stress: "StressPrediction | None" = None
    """Predicted peak stresses of the real geometry (:mod:`springcad.design.stress`)."""
    max_root_radius_mm: float = math.inf
    """Root radius cap from the stack (common rim-hole circle) the design was searched under (mm)."""
    design_choice: str = ""
    """Which layout the design search chose and why (the candidates it rejected first)."""
    duty_advice: str = ""
    """Sized for yield alone because the envelope cannot carry springcad's default duty:
    what would meet it (surface, material, one more disk), or ""."""
    thicker_plates_mm: tuple[float, ...] = ()
    """Stock plates thicker than this one that the spec allows, ascending (mm), when
    springcad chose the thickness (:mod:`springcad.design.stock`); else empty. The FEA
    stress correction may move the spring to one."""
    sized_for_default_duty: bool = False
    """The job declares no duty and the search sized the spring for springcad's default
    duty (its envelope carries it): the FEA corrections hold the design to that duty too."""

    # ------------------------------------------------------------- the shape
    @property
    def flexure_shape(self) -> FlexureShape:
        """The registered shape of the flexures (:func:`springcad.design.shapes.get`)."""
        return shape_named(self.shape.name)

    @property
    def flexure(self) -> str:
        """The shape's name ("straight", "serpentine", or another registered one)."""
        return self.shape.name

    @property
    def width_law(self) -> str:
        """"stress" (w sized for the design stress at peak load), "stiffness" (straight,
        w0 sized for K), or another shape's law."""
        return self.shape.width_law

    @property
    def root_width_mm(self) -> float:
        return self.shape.root_width_mm

    @property
    def centreline(self) -> fx.Centreline:
        return self.shape.centreline

    @property
    def serpentine_factor(self) -> float:
        """Area ratio the deflection needs over a straight flexure (eq. 4; 1 for straight) (-)."""
        return self.shape.required_area_ratio

    @property
    def area_ratio(self) -> float:
        return self.shape.area_ratio

    @property
    def serpentine_balance(self) -> str | None:
        """How the serpentine's lobes are balanced (:data:`flexure.BALANCES`): "uncoupled" (a
        tangential tip load moves the ball tangentially only), "root" (the reference tool's:
        root on the tip's radial line) or "swept"; None for other shapes."""
        return self.shape.balance

    # ------------------------------------------------------------- predictions
    @property
    def length_mm(self) -> float:
        return self.root_radius_mm - self.contact_radius_mm

    @property
    def root_station_mm(self) -> float:
        """y where the flexure centreline meets the root circle (mm): R_r for a flexure whose
        root sits on the tip's radial line, less when the root sits off it (an uncoupled
        serpentine, a swept arm). Beam integrals run from r_c to here; beyond it is rim."""
        return float(self.centreline.y_mm[-1])

    @property
    def max_deflection_rad(self) -> float:
        return self.spec.max_deflection_rad

    @property
    def target_stiffness_Nmm_per_rad(self) -> float:
        return self.spec.target_stiffness_Nmm_per_rad

    @property
    def peak_torque_Nmm(self) -> float:
        return self.stiffness_beam_Nmm_per_rad * self.max_deflection_rad

    @property
    def beam_stress_MPa(self) -> float:
        """Stress the constant-stress width law is sized to (MPa)."""
        return self.material.design_stress_MPa * self.stress_derating

    @property
    def predicted_peak_stress_MPa(self) -> float:
        """Peak von Mises of the real geometry at the max deflection, predicted (MPa)."""
        return self.stress.peak_MPa if self.stress is not None else self.peak_stress_MPa

    @property
    def yield_margin(self) -> float:
        """Yield strength over the *predicted* peak of the real geometry (-)."""
        return self.material.material.yield_strength_MPa / self.predicted_peak_stress_MPa

    @property
    def fatigue(self):
        """Fully reversed fatigue at +-theta_max from the predicted peak, with the duty's
        surface and reliability (:func:`springcad.design.fatigue.check`), or None without
        fatigue data."""
        d = self.material.duty
        return fatigue.check(self.material.material.name, self.predicted_peak_stress_MPa,
                             d.surface, d.reliability)

    @property
    def duty_check(self):
        """The duty at the predicted peak (:func:`springcad.design.duty.check`), or None
        without fatigue data."""
        return duty.check(self.material.duty, self.material.material.name,
                          self.predicted_peak_stress_MPa, self.max_deflection_rad,
                          where=f"predicted peak ({self.stress.region})"
                          if self.stress is not None else "beam peak")

    @property
    def required_yield_margin(self) -> float:
        """Yield / peak the design needs for yield and the duty (-)."""
        return duty.required_margin(self.material, self.max_deflection_rad)

    @property
    def sizing_margin(self) -> float:
        """Yield / peak the design was sized for (-): :attr:`required_yield_margin`, or with
        springcad's default duty when the spring was sized for it (the FEA stress
        correction holds the real geometry to the same margin)."""
        material = duty.sized_for(self.material) if self.sized_for_default_duty else self.material
        return duty.required_margin(material, self.max_deflection_rad)

    @property
    def yield_margin_beam(self) -> float:
        """Yield strength over the nominal beam stress (-): not a safety margin."""
        return self.material.material.yield_strength_MPa / self.peak_stress_MPa

    @property
    def energy_J(self) -> float:
        return 0.5 * self.stiffness_beam_Nmm_per_rad * self.max_deflection_rad ** 2 * J_PER_NMM

    def width_mm(self, y_mm):
        """Flexure width normal to the centreline at radius y (mm)."""
        y = np.asarray(y_mm, dtype=float)
        w = self.flexure_shape.width_mm(self, y)
        w = self.width_scale * w * fx.root_flare_factor(y, self.root_radius_mm, self.root_flare,
                                                         self.root_flare_length_mm)
        # near the tip the constant-stress law tends to zero: keep the web the wire can leave,
        # with a smooth maximum (blend 0.1 x web) so the edge has no kink for the spline,
        # the kernel or the stress field; 0.2 % above the web far from the blend. Applied
        # after the width scale: the FEA correction never thins the web below the rule
        web = 1.002 * self.manufacturing.min_web_mm
        eps = 0.1 * web
        w = 0.5 * (w + web + np.sqrt((w - web) ** 2 + eps ** 2))
        return w + 2.0 * self.width_offset_mm

    def beam_integral(self, youngs_modulus_MPa: float | None = None):
        """The beam integral's stations from r_c to the root station (mm), the width law
        there (mm), and ``compliance(width)``: one flexure's tip compliance (mm/N,
        :func:`~springcad.design.flexure.compliance_mm_per_N`) for any widths at those
        stations. ``youngs_modulus_MPa``: E instead of the material's (MPa)."""
        E = youngs_modulus_MPa or self.material.material.youngs_modulus_MPa
        rc, z = self.contact_radius_mm, self.thickness_mm
        y, _, slope, _ = fx.stations(self.centreline, rc, self.root_station_mm, 4001)

        def compliance(width):
            return fx.compliance_mm_per_N(self.centreline, y, width, z, E, rc, slope)

        return y, self.width_mm(y), compliance

    def beam_stiffness_Nmm_per_rad(self, width_offset_mm: float = 0.0,
                                   youngs_modulus_MPa: float | None = None) -> float:
        """Beam-theory stiffness of this geometry (N*mm/rad), optionally perturbed.

        K = N r_c^2 / (delta/F) with delta/F = integral 12 (y - r_c)^2 / (E z w^3) ds
        (Castigliano, Euler-Bernoulli bending only).

        Args:
            width_offset_mm: every flexure edge moved outward by this much (the flexure
                gets 2 x offset wider), as a wire-EDM profile error would (mm). The
                perturbation is applied to the real section, the width law or the tip
                ball's chord, whichever is wider, and scales the nominal prediction:
                K(offset) = K_law * C_real(0) / C_real(offset).
            youngs_modulus_MPa: E to use instead of the material's (MPa).
        """
        rc = self.contact_radius_mm
        y, w, compliance = self.beam_integral(youngs_modulus_MPa)
        k = self.n_flexures * rc ** 2 / compliance(w)
        if width_offset_mm:
            chord = 2 * np.sqrt(np.maximum(self.tip_radius_mm ** 2 - (y - rc) ** 2, 0.0))
            real = np.maximum(w, chord)
            k *= compliance(real) / compliance(np.maximum(real + 2 * width_offset_mm, 1e-3))
        return k

    @property
    def profile_area_mm2(self) -> float:
        return self._areas[0]

    @property
    def cam_area_mm2(self) -> float:
        return self._areas[1]

    @functools.cached_property
    def _areas(self) -> tuple[float, float]:
        nan = float("nan")
        return (self.ring.area_mm2() if self.ring is not None else nan,
                self.cam.area_mm2() if self.cam is not None else nan)

    @property
    def model_area_mm2(self) -> float:
        """Flexures (width law x area ratio) plus rim annulus: the reference tool's area (mm^2)."""
        y = np.linspace(self.contact_radius_mm, self.root_station_mm, 2001)
        flex = fx.area_mm2(self.centreline, y, self.width_mm(y))
        rim = math.pi * (self.outer_radius_mm ** 2 - self.root_radius_mm ** 2)
        return self.n_flexures * flex + rim

    @property
    def mass_kg(self) -> float:
        """Disk mass from the exact profile area (kg)."""
        area = self.profile_area_mm2 if self.ring is not None else self.model_area_mm2
        return area * self.thickness_mm * self.material.material.density_kg_per_mm3

    @property
    def envelope_volume_mm3(self) -> float:
        return math.pi * self.outer_radius_mm ** 2 * self.thickness_mm

    @property
    def energy_density_J_per_cm3(self) -> float:
        return self.energy_J / (self.envelope_volume_mm3 / MM3_PER_CM3)

    @property
    def specific_energy_J_per_kg(self) -> float:
        return self.energy_J / self.mass_kg

    def __repr__(self) -> str:
        # the profiles hold thousands of curve segments: print the key numbers only
        return (f"SpringDesign({self.name!r}, K_beam={self.stiffness_beam_Nmm_per_rad:.6g} "
                f"N*mm/rad, theta_max={self.max_deflection_rad:.4g} rad, N={self.n_flexures}, "
                f"r_c={self.contact_radius_mm:.4g} mm, R_o={self.outer_radius_mm:.4g} mm, "
                f"width_scale={self.width_scale:.4g})")

    def to_dict(self) -> dict:
        """The ``design.json`` entry of this spring (units in key names)."""
        return {
            "stiffness_Nm_per_rad": self.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "target_stiffness_Nm_per_rad": self.target_stiffness_Nmm_per_rad / NMM_PER_NM,
            "max_deflection_rad": self.max_deflection_rad,
            "straight_limit_rad": self.straight_limit_rad,
            "peak_torque_Nm": self.peak_torque_Nmm / NMM_PER_NM,
            "torque_cap_Nm": self.torque_cap_Nmm / NMM_PER_NM,
            "peak_stress_beam_MPa": self.peak_stress_MPa,
            "peak_stress_predicted_MPa": self.predicted_peak_stress_MPa,
            "peak_stress_region": self.stress.region if self.stress is not None else None,
            "stress_prediction_MPa": self.stress.to_dict() if self.stress is not None else None,
            "design_stress_MPa": self.material.design_stress_MPa,
            "beam_stress_MPa": self.beam_stress_MPa,
            "stress_derating": self.stress_derating,
            "required_yield_margin": self.material.safety_factor,
            "required_yield_margin_with_duty": self.required_yield_margin,
            "yield_margin": self.yield_margin,
            "yield_margin_beam": self.yield_margin_beam,
            "fatigue": self.fatigue.to_dict() if self.fatigue is not None else None,
            "duty": self.duty_check.to_dict() if self.duty_check is not None else None,
            "root_flare": self.root_flare,
            "root_flare_length_mm": self.root_flare_length_mm,
            "n_flexures": self.n_flexures,
            "contact_radius_mm": self.contact_radius_mm,
            "root_radius_mm": self.root_radius_mm,
            "outer_radius_mm": self.outer_radius_mm,
            "thickness_mm": self.thickness_mm,
            "tip_radius_mm": self.tip_radius_mm,
            "tip_radius_required_mm": self.tip_radius_required_mm,
            "root_width_mm": self.root_width_mm,
            "tip_load_N": self.tip_load_N,
            "flexure": self.flexure,
            "serpentine_balance": self.serpentine_balance,
            "width_law": self.width_law,
            "serpentine_factor": self.serpentine_factor,
            "area_ratio": self.area_ratio,
            "min_neighbour_clearance_mm": self.min_neighbour_clearance_mm,
            "centreline_mm": {"y": list(self.centreline.y_mm), "x": list(self.centreline.x_mm)},
            "rim_thickness_mm": self.rim_thickness_mm,
            "root_fillet_radius_mm": self.root_fillet_radius_mm,
            "neck_fillet_radius_mm": self.neck_fillet_radius_mm,
            "hole_diameter_mm": self.hole_diameter_mm,
            "hole_count": len(self.hole_centres_mm),
            "hole_circle_radius_mm": (math.hypot(*self.hole_centres_mm[0])
                                      if self.hole_centres_mm else None),
            "cam_tip_radius_mm": self.cam_tip_radius_mm,
            "cam_root_radius_mm": self.cam_root_radius_mm,
            "cam_overtravel": self.cam_overtravel,
            "cam_tip_clearance_at_max_deflection_mm": self.cam_tip_clearance_mm,
            "profile_area_mm2": self.profile_area_mm2,
            "mass_kg": self.mass_kg,
            "energy_J": self.energy_J,
            "envelope_volume_cm3": self.envelope_volume_mm3 / MM3_PER_CM3,
            "energy_density_J_per_cm3": self.energy_density_J_per_cm3,
            "specific_energy_J_per_kg": self.specific_energy_J_per_kg,
            "width_scale": self.width_scale,
            "width_offset_mm": self.width_offset_mm,
            "design_choice": self.design_choice,
            "duty_advice": self.duty_advice,
            "sized_for_default_duty": self.sized_for_default_duty,
            "warnings": list(self.warnings),
            **({"flexure_params": dict(self.shape.params)} if self.shape.params else {}),
        }
