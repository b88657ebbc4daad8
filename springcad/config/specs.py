"""The validated job: frozen dataclasses in internal units (mm, N*mm, MPa, rad).

Defaults come from :data:`springcad.config.schema.SECTIONS` (declared once there).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from springcad.config.schema import default
from springcad.materials import Material


def _d(section: str, name: str):
    return field(default=default(section, name))


#: the duty a job gets without a [duty] table (README; springcad.design.duty.PRESETS)
DEFAULT_DUTY_PRESET = "robot_joint"


@dataclass(frozen=True)
class DutyBlock:
    """One block of a duty: ``cycles`` cycles of deflection ``mean`` +- ``amplitude``.

    Attributes:
        cycles: number of cycles (-).
        amplitude: half the deflection range, in ``unit``.
        mean: mean deflection (signed), in ``unit``.
        unit: ``"fraction"`` (of the spring's theta_max) or ``"rad"``.
        label: a name for reports.
    """

    cycles: float
    amplitude: float
    mean: float = 0.0
    unit: str = "fraction"
    label: str = ""


@dataclass(frozen=True)
class DutySpec:
    """What the springs will see in service, and how it is judged.

    The duty is one of: a named ``preset`` (:data:`springcad.design.duty.PRESETS`),
    ``blocks``, or a deflection time ``series`` counted by rainflow (ASTM E1049),
    repeated ``series_repeats`` times over the life.

    Attributes:
        preset: preset name, or None.
        blocks: explicit blocks.
        series: deflection samples in ``series_unit`` (a time series, turning points
            are found by the counting).
        series_unit: ``"fraction"`` (of theta_max) or ``"rad"``.
        series_repeats: how many times the series is repeated over the life (-).
        series_file: the file the series came from (reports).
        safety_factor: required fatigue safety factor on stress (-): the stresses of
            every block times this factor still give a Miner sum <= 1.
        reliability: survival probability of the endurance limit (-).
        surface: surface condition of the cut faces (``springcad/data/surface.csv``,
            from ``manufacturing.surface``); sets the Marin factor and the drawing note.
        declared: the job declared a ``[duty]`` table (False: springcad's default duty).
    """

    preset: str | None = DEFAULT_DUTY_PRESET
    blocks: tuple[DutyBlock, ...] = ()
    series: tuple[float, ...] = ()
    series_unit: str = "fraction"
    series_repeats: float = 1.0
    series_file: str = ""
    safety_factor: float = _d("duty", "safety_factor")
    reliability: float = _d("duty", "reliability")
    surface: str = _d("manufacturing", "surface")
    declared: bool = False


@dataclass(frozen=True)
class MaterialSpec:
    """Material with the stress the flexures are designed to (MPa), and the duty."""

    material: Material
    design_stress_MPa: float
    safety_factor: float
    """Required ratio yield strength / peak stress (checked by FEA)."""
    duty: DutySpec = field(default_factory=DutySpec)
    """The fatigue duty the flexures are sized for too (:mod:`springcad.design.duty`)."""


@dataclass(frozen=True)
class SpringSpec:
    """What the user asks of one spring disk.

    Attributes:
        name: spring name used in the stack sequence.
        target_stiffness_Nmm_per_rad: target stiffness (N*mm/rad).
        max_deflection_rad: deflection the spring must reach at design stress (rad).
        outer_radius_mm: disk outer radius R_o (mm).
        thickness_mm: disk thickness z (mm), or None to choose it from stock plate.
        contact_radius_mm: r_c, or None to choose it.
        min_tip_radius_mm: smallest tip-ball radius allowed (mm).
        tip_radius_mm: exact tip-ball radius (as built), or None to size it for the peak load.
        n_flexures: N, or None to choose it.
        root_radius_mm: R_r, or None for the rim rule.
        flexure: "auto", "straight" or "serpentine".
        max_thickness_mm: the thickest disk the chosen thickness may be (mm; None: no
            bound but the stock list's), when ``thickness_mm`` is None.
        cam_min_tip_clearance_mm: the tooth-tip-to-ball gap estimate every layout's cam
            must reach (mm; 0: the design rule alone). Not a config key: the contact FEA's
            cam correction sets it when no longer flank fits the tooth, so the search
            passes over layouts without room for one (:mod:`springcad.design.redesign`).
        shared_camshaft: the layout keys (of n_flexures, contact_radius_mm, tip_radius_mm)
            springcad fixed so that springs sharing a camshaft share one tooth profile
            (:func:`springcad.design.camshaft_share.camshaft_groups`). Not a config key: a refusal
            never asks the user to remove them.
    """

    name: str
    target_stiffness_Nmm_per_rad: float
    max_deflection_rad: float
    outer_radius_mm: float
    thickness_mm: float | None
    contact_radius_mm: float | None = None
    min_tip_radius_mm: float = _d("springs.<name>", "min_tip_radius_mm")
    tip_radius_mm: float | None = None
    n_flexures: int | None = None
    root_radius_mm: float | None = None
    flexure: str = _d("springs.<name>", "flexure")
    max_thickness_mm: float | None = None
    cam_min_tip_clearance_mm: float = 0.0
    shared_camshaft: tuple[str, ...] = ()


@dataclass(frozen=True)
class StackSpec:
    """Series stack: springs from input to output."""

    sequence: tuple[str, ...]
    input: str = _d("stack", "input")


#: worst-case tip-to-cam gap per side the chosen ``w_gap_mm`` keeps over the two profile
#: tolerances (mm): the default template's 0.04 mm gap over +-0.01 mm profiles
W_GAP_CLEARANCE_MM = 0.02


@dataclass(frozen=True)
class ManufacturingSpec:
    """Process limits and tolerances (mm)."""

    process: str = _d("manufacturing", "process")
    t_spring_mm: float = _d("manufacturing", "t_spring_mm")
    t_shaft_mm: float = _d("manufacturing", "t_shaft_mm")
    w_gap_mm: float = _d("manufacturing", "w_gap_mm")
    wire_diameter_mm: float = _d("manufacturing", "wire_diameter_mm")
    spark_gap_mm: float = _d("manufacturing", "spark_gap_mm")
    min_slot_width_mm: float = _d("manufacturing", "min_slot_width_mm")
    min_web_mm: float = _d("manufacturing", "min_web_mm")
    min_hole_edge_mm: float = _d("manufacturing", "min_hole_edge_mm")
    tolerance_distribution: str = _d("manufacturing", "tolerance_distribution")

    def __post_init__(self):
        if self.w_gap_mm is None:  # chosen: the worst-case tip-to-cam gap stays positive
            object.__setattr__(self, "w_gap_mm",
                               self.t_spring_mm + self.t_shaft_mm + W_GAP_CLEARANCE_MM)

    @property
    def min_inside_radius_mm(self) -> float:
        """Smallest inside corner radius the wire can cut (mm)."""
        return 0.5 * self.wire_diameter_mm + self.spark_gap_mm

    @property
    def kerf_mm(self) -> float:
        """Width of the slot the wire cuts: wire + 2 spark gaps (mm)."""
        return self.wire_diameter_mm + 2.0 * self.spark_gap_mm


@dataclass(frozen=True)
class HardwareSpec:
    """Fasteners, spacers and shafts (mm), densities of the non-steel parts (kg/m^3)."""

    fastener: str = _d("hardware", "fastener")
    fastener_diameter_mm: float = _d("hardware", "fastener_diameter_mm")
    fastener_count: int = _d("hardware", "fastener_count")
    shaft_diameter_mm: float = _d("hardware", "shaft_diameter_mm")
    rim_spacer_thickness_mm: float = _d("hardware", "rim_spacer_thickness_mm")
    bushing_wall_mm: float = _d("hardware", "bushing_wall_mm")
    camshaft_hub_length_mm: float = _d("hardware", "camshaft_hub_length_mm")
    rim_spacer_density_kg_per_m3: float = _d("hardware", "rim_spacer_density_kg_per_m3")
    plastic_density_kg_per_m3: float = _d("hardware", "plastic_density_kg_per_m3")
    given: tuple[str, ...] = ()
    """The keys the config's ``[hardware]`` table gives; springcad may choose the others
    (:func:`springcad.design.job.design_job`: fewer or other rim fasteners than the
    defaults when those cannot be made, and says so)."""

    @property
    def hole_diameter_mm(self) -> float:
        """Rim hole: dowel press fit at nominal, bolt clearance per ISO 273 medium (mm)."""
        d = self.fastener_diameter_mm
        if self.fastener == "dowel":
            return d
        return d + (0.4 if d <= 3.0 else 0.5)


@dataclass(frozen=True)
class AnalysisSpec:
    """Monte Carlo settings of the backlash statistics."""

    monte_carlo_samples: int = _d("analysis", "monte_carlo_samples")
    seed: int = _d("analysis", "seed")


@dataclass(frozen=True)
class Job:
    """A validated job: everything the pipeline needs, in internal units.

    ``warnings`` are plausibility warnings about legal but suspicious values;
    the CLI prints them.
    """

    name: str
    description: str
    material: MaterialSpec
    springs: dict[str, SpringSpec]
    stack: StackSpec
    manufacturing: ManufacturingSpec
    hardware: HardwareSpec
    analysis: AnalysisSpec = field(default_factory=AnalysisSpec)
    source: str = ""
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)
