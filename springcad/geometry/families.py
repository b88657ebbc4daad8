"""Part families: one builder per plan kind, found in a registry by kind.

A builder turns a stack component (its typed plan, see
:mod:`springcad.design.plans`) into parts and places them; identical parts are
built once (the part cache keys them by the plan's shape). A new part family
is a plan class in the design layer and one ``@family`` function here.
Units: mm, rad.
"""

from __future__ import annotations

from typing import Callable

from springcad.design import plans as pl
from springcad.design.hardware import RIM_SPACER_MATERIAL, Component
from springcad.design.processes import process
from springcad.design.ring import hole_fits
from springcad.errors import GeometryError
from springcad.geometry.adapters import AlignmentShaft, RimFlange, TorqueShaft
from springcad.geometry.base import COLOURS, SpringcadPart
from springcad.geometry.disk import Camshaft, FlexureRing
from springcad.geometry.fasteners import DowelPin, RimNut, RimScrew, nut_height_mm
from springcad.geometry.placement import Instance, Placement
from springcad.geometry.spacers import Bushing, CentreSpacer, RimSpacer, RimWasher
from springcad.materials import material_table
from springcad.progress import Progress, no_progress

#: builder(context, component) by component kind
FAMILIES: dict[str, Callable[["BuildContext", Component], None]] = {}


def family(kind: str):
    """Register the decorated function as the builder of components of ``kind``."""
    def register(builder):
        if kind in FAMILIES:
            raise ValueError(f"two builders for part kind '{kind}'")
        FAMILIES[kind] = builder
        return builder
    return register


#: when a turned steel part is heat treated (drawing notes, part identity)
TURNED_HEAT_TREATMENT_SEQUENCE = "after rough turning, before grinding the fits"


def _r(x: float) -> float:
    return round(float(x), 6)


class PartCache:
    """Builds each distinct part once; names parts of one kind PREFIX, PREFIX-2, ...

    The name is the job-local label; the part number comes from the geometry
    (:func:`springcad.geometry.base.part_number_of`), so two cache keys that
    make the same geometry give one part.

    Attributes:
        fraction: share of the stack built so far (0-1), passed on to ``progress``.
    """

    def __init__(self, progress: Progress = no_progress):
        self.parts: dict[tuple, SpringcadPart] = {}
        self.by_number: dict[str, SpringcadPart] = {}
        self.count: dict[str, int] = {}
        self.progress = progress
        self.fraction: float | None = None

    def get(self, key: tuple, make, prefix: str | None = None):
        if key not in self.parts:
            number = None
            if prefix is not None:
                k = self.count.get(prefix, 0) + 1
                self.count[prefix] = k
                number = prefix if k == 1 else f"{prefix}-{k}"
            part = make(number)
            part = self.by_number.setdefault(part.part_number, part)
            self.progress(f"built {part.name} ({part.part_number})", self.fraction)
            self.parts[key] = part
        return self.parts[key]


class BuildContext:
    """What every builder needs: the stack's springs, the steel, the cache and the placed list.

    Args:
        springs: the stack's spring designs, input side first.
        cache: the :class:`PartCache` of this build.
    """

    def __init__(self, springs, cache: PartCache):
        self.springs = springs
        mat = springs[0].material.material
        self.steel = (mat.description or mat.name, mat.density_kg_per_m3)
        self.heat_treatment = mat.heat_treatment
        #: hardness and heat-treatment sequence of the steel parts (drawings, part identity)
        self.steel_spec = {"hardness": mat.hardness,
                           "heat_treatment_sequence": mat.heat_treatment_sequence}
        #: turned steel parts: hardened after rough turning, fits ground afterwards
        self.turned_spec = {"hardness": mat.hardness,
                            "heat_treatment_sequence": TURNED_HEAT_TREATMENT_SEQUENCE}
        #: callout of the rim holes, the same on every part they pass
        self.hole_fits = hole_fits(springs[0].hardware)
        self.cache = cache
        self.instances: list[Instance] = []

    def place(self, name: str, part: SpringcadPart, comp: Component, placement: Placement,
              role: str = "", colour=None) -> None:
        self.instances.append(Instance(name, part, placement, comp, role, colour or part.colour))

    def shaped(self, comp: Component, make, prefix: str):
        """The part of this component's shape and length, built once."""
        return self.cache.get((comp.plan.shape_key(), _r(comp.length_mm)), make, prefix)


def build_component(ctx: BuildContext, comp: Component) -> None:
    """Build and place one component with its family's builder.

    Raises:
        GeometryError: no family builds this kind of part.
    """
    try:
        builder = FAMILIES[comp.kind]
    except KeyError:
        raise GeometryError(f"{comp.name}: no part family for component kind '{comp.kind}' "
                            f"(known: {', '.join(sorted(FAMILIES))})") from None
    builder(ctx, comp)


@family(pl.FlexureRingPlan.KIND)
def _flexure_ring(ctx: BuildContext, comp: Component) -> None:
    s = ctx.springs[comp.plan.spring_index]
    part = ctx.cache.get((comp.kind, s.name), lambda pn: FlexureRing(s))
    ctx.place(comp.name, part, comp, Placement(comp.z_mm), comp.role)


@family(pl.CamshaftPlan.KIND)
def _camshaft(ctx: BuildContext, comp: Component) -> None:
    plan: pl.CamshaftPlan = comp.plan
    members = [ctx.springs[i] for i in plan.springs]
    prof = next(m for m in members if m.name == plan.profile_spring)
    part = ctx.cache.get(plan.shape_key(), lambda pn: Camshaft.from_plan(plan, prof))
    part.check_members(members)
    # an output end camshaft is the input part turned over
    flipped = comp.role == "output" and plan.hub_length_mm > 0
    z = plan.toothed_start_mm + (plan.toothed_length_mm if flipped else 0.0)
    ctx.place(comp.name, part, comp, Placement(z, flipped=flipped), comp.role)


def _annular_family(cls, prefix: str, heat: str = "", **spec):
    """Register the builder of a ring-shaped part class placed on the axis.

    The part's material and density are the component's (the hardware config's densities);
    ``spec``: hardness and heat-treatment sequence of its stock (drawing notes).
    """
    @family(cls.KIND)
    def build(ctx: BuildContext, comp: Component) -> None:
        material = (comp.material, comp.density_kg_per_m3)
        fits = ctx.hole_fits if comp.plan.hole_centres_mm else {}
        if cls is RimSpacer and fits:  # clearance holes for the rim pins, toleranced by process
            tol = process(comp.plan.process).hole_tolerance_mm
            fits = {"holes": f"±{tol:g}", "hole_purpose": "clearance for the rim pins"}
        part = ctx.shaped(comp, lambda pn: cls.from_plan(pn, comp.plan, comp.length_mm,
                                                         material, heat, fits=fits, **spec),
                          prefix)
        ctx.place(comp.name, part, comp, Placement(comp.z_mm))
    return build


_SHIM = material_table()[RIM_SPACER_MATERIAL]
_annular_family(RimSpacer, "RIM-SPACER", _SHIM.heat_treatment, hardness=_SHIM.hardness,
                heat_treatment_sequence=_SHIM.heat_treatment_sequence)
_annular_family(RimWasher, "RIM-WASHER")
_annular_family(CentreSpacer, "CENTRE-SPACER")
_annular_family(Bushing, "BUSHING")


@family(pl.RimFlangePlan.KIND)
def _rim_flange(ctx: BuildContext, comp: Component) -> None:
    fits = ctx.hole_fits if comp.plan.hole_centres_mm else {}
    part = ctx.shaped(comp, lambda pn: RimFlange.from_plan(
        pn, comp.plan, comp.length_mm, ctx.steel, ctx.heat_treatment, fits=fits,
        **ctx.steel_spec), "RIM-FLANGE")
    ctx.place(comp.name, part, comp, Placement(comp.z_mm), comp.role, COLOURS[comp.role])


@family(pl.AlignmentShaftPlan.KIND)
def _alignment_shaft(ctx: BuildContext, comp: Component) -> None:
    r = 0.5 * comp.plan.diameter_mm
    part = ctx.shaped(comp, lambda pn: AlignmentShaft(
        pn, 0.0, r, comp.length_mm, ctx.steel, heat_treatment=ctx.heat_treatment,
        **ctx.turned_spec),
        "ALIGNMENT-SHAFT")
    ctx.place(comp.name, part, comp, Placement(comp.z_mm))


@family(pl.TorqueShaftPlan.KIND)
def _torque_shaft(ctx: BuildContext, comp: Component) -> None:
    part = ctx.shaped(comp, lambda pn: TorqueShaft(pn, comp.plan, comp.length_mm, ctx.steel,
                                                   ctx.heat_treatment, **ctx.turned_spec),
                      "TORQUE-SHAFT")
    # the output shaft is the input part turned over
    flipped = comp.role == "output"
    z = comp.z_mm + (comp.length_mm if flipped else 0.0)
    ctx.place(comp.name, part, comp, Placement(z, flipped=flipped), comp.role, COLOURS[comp.role])


@family(pl.FastenerPlan.KIND)
def _fasteners(ctx: BuildContext, comp: Component) -> None:
    plan: pl.FastenerPlan = comp.plan
    dia, length = plan.diameter_mm, plan.length_mm
    if plan.type == "dowel":
        stainless = "stainless" in ctx.steel[0].lower()  # C1 pins in stainless rings
        parts = [(ctx.cache.get(("dowel", _r(dia), _r(length), stainless),
                                lambda pn: DowelPin(pn, dia, length, stainless), "DOWEL"),
                  comp.z_mm, "")]
    else:
        nut_h = nut_height_mm(dia)
        screw = ctx.cache.get(("screw", _r(dia), _r(length)),
                              lambda pn: RimScrew(pn, dia, length, nut_h), "SCREW")
        nut = ctx.cache.get(("nut", _r(dia)), lambda pn: RimNut(pn, dia), "NUT")
        parts = [(screw, comp.z_mm, ""), (nut, comp.z_mm + length, "_nut")]
    for k, (x, y) in enumerate(plan.hole_centres_mm):
        for part, z, suffix in parts:
            ctx.place(f"{comp.name}_{k + 1}{suffix}", part, comp, Placement(z, x, y))
