"""Typed part plans: what each part of a stack is, in numbers (mm).

A plan is the design's word on one part family (profile -> plan -> part, as
in bd_warehouse): frozen, typed, one class per part kind. The hardware layout
(:mod:`springcad.design.hardware`) makes them; the geometry layer builds each
family's solid from its plan (:mod:`springcad.geometry.families`), so a size
is decided once and never looked up by a string key.

Fields that say *where* a part goes (which joint, which spring) rather than
*what* it is are listed in ``PLACE_FIELDS`` and left out of
:meth:`PartPlan.shape_key`: two plans with the same shape key are the same
part number. Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import ClassVar

#: digits kept when plans are compared for identical parts (1 nm)
_KEY_DIGITS = 6


def _rounded(value):
    if isinstance(value, float):
        return round(value, _KEY_DIGITS)
    if isinstance(value, tuple):
        return tuple(_rounded(v) for v in value)
    return value


@dataclass(frozen=True, kw_only=True)
class PartPlan:
    """Base of every plan: its kind and how it is written to ``design.json``."""

    KIND: ClassVar[str] = ""
    PLACE_FIELDS: ClassVar[tuple[str, ...]] = ()

    def shape_key(self) -> tuple:
        """Hashable key of the part's shape (rounded to 1 nm), without its place in the stack."""
        return (self.KIND, *((f.name, _rounded(getattr(self, f.name))) for f in fields(self)
                            if f.name not in self.PLACE_FIELDS))

    def to_dict(self) -> dict:
        """The plan's numbers, units in the key names (the ``dims`` of a component)."""
        return asdict(self)


@dataclass(frozen=True, kw_only=True)
class FlexureRingPlan(PartPlan):
    """A spring's flexure ring, cut to the spring design's own profile.

    Attributes:
        spring_index: position of the spring in the stack (0 = input side).
        outer_radius_mm, root_radius_mm: rim size (mm), for the record.
    """

    KIND = "flexure_ring"
    #: the ring's shape is its spring's profile: the part family keys rings by spring name
    PLACE_FIELDS = ("spring_index",)
    spring_index: int
    outer_radius_mm: float
    root_radius_mm: float


@dataclass(frozen=True, kw_only=True)
class CamshaftPlan(PartPlan):
    """A camshaft engaging one spring or several springs joined shaft-to-shaft.

    Attributes:
        springs: stack positions of the springs it engages.
        profile_spring: the member whose tooth is cut (the smallest cam tip).
        toothed_start_mm, toothed_end_mm: axial extent of the teeth in the stack (mm).
        hub_length_mm: turned hub of an end camshaft, 0 for a floating one (mm).
        hub_radius_mm: hub radius, inside the cam root radius (mm).
        tip_radius_mm: tooth tip radius (mm).
        bore_diameter_mm: bore (mm).
        bore: "d_flat" (takes a D shaft) or "round" (runs on the alignment shaft).
        drive: "bore_flat", "hub_flat" or "" (floating).
        flat_ratio: position of a D flat as a fraction of its radius (-).
    """

    KIND = "camshaft"
    PLACE_FIELDS = ("springs", "toothed_start_mm", "toothed_end_mm")
    springs: tuple[int, ...]
    profile_spring: str
    toothed_start_mm: float
    toothed_end_mm: float
    hub_length_mm: float
    hub_radius_mm: float
    tip_radius_mm: float
    bore_diameter_mm: float
    bore: str
    drive: str
    flat_ratio: float

    @property
    def toothed_length_mm(self) -> float:
        return self.toothed_end_mm - self.toothed_start_mm

    @property
    def floating(self) -> bool:
        """No hub: the camshaft carries no external torque."""
        return not self.drive

    def shape_key(self) -> tuple:
        return (*super().shape_key(), ("toothed_length_mm", _rounded(self.toothed_length_mm)))

    def to_dict(self) -> dict:
        return {**super().to_dict(), "floating": self.floating}


@dataclass(frozen=True, kw_only=True)
class AnnulusPlan(PartPlan):
    """A ring (or disc, ``inner_radius_mm = 0``) of constant section along the axis.

    Attributes:
        inner_radius_mm, outer_radius_mm: radii (mm).
        hole_centres_mm: centres of axial holes (mm); hole_diameter_mm: their diameter.
    """

    inner_radius_mm: float
    outer_radius_mm: float
    hole_centres_mm: tuple[tuple[float, float], ...] = ()
    hole_diameter_mm: float = 0.0

    @property
    def holes(self) -> int:
        return len(self.hole_centres_mm)

    def to_dict(self) -> dict:
        return {**super().to_dict(), "holes": self.holes}


@dataclass(frozen=True, kw_only=True)
class RimSpacerPlan(AnnulusPlan):
    """Aluminium ring between two bolted rims; ``joint`` is the joint it sits in;
    ``process``: the manufacturing process its webs were sized for
    (:func:`springcad.design.rim_spacer.rim_spacer_fit`)."""

    KIND = "rim_spacer"
    PLACE_FIELDS = ("joint",)
    joint: int
    process: str = "laser"


@dataclass(frozen=True, kw_only=True)
class RimWasherPlan(AnnulusPlan):
    """Plastic ring between the rims of two springs sharing a camshaft."""

    KIND = "rim_washer"
    PLACE_FIELDS = ("joint",)
    joint: int


@dataclass(frozen=True, kw_only=True)
class CentreSpacerPlan(AnnulusPlan):
    """Plastic disc between rim-joined springs, larger than the cam teeth."""

    KIND = "centre_spacer"
    PLACE_FIELDS = ("joint",)
    joint: int


@dataclass(frozen=True, kw_only=True)
class BushingPlan(AnnulusPlan):
    """Plastic sleeve around the rims of a stack of three or more springs."""

    KIND = "bushing"


@dataclass(frozen=True, kw_only=True)
class RimFlangePlan(AnnulusPlan):
    """Input/output adapter bolted to an end spring's rim (``spring_index``)."""

    KIND = "rim_flange"
    PLACE_FIELDS = ("spring_index",)
    spring_index: int


@dataclass(frozen=True, kw_only=True)
class AlignmentShaftPlan(PartPlan):
    """Ground pin on which the floating camshafts run."""

    KIND = "alignment_shaft"
    diameter_mm: float


@dataclass(frozen=True, kw_only=True)
class FastenerPlan(PartPlan):
    """The pins or screws of one rim-to-rim joint (one per hole).

    Attributes:
        type: "dowel" or "bolt" (``hardware.fastener``).
        diameter_mm, length_mm: pin / shank size (mm); the length is the grip.
        hole_centres_mm: where they go (mm).
        joint: the joint they pin.
    """

    KIND = "fastener"
    PLACE_FIELDS = ("hole_centres_mm", "joint")
    type: str
    diameter_mm: float
    length_mm: float
    hole_centres_mm: tuple[tuple[float, float], ...]
    joint: int

    @property
    def hole_circle_radius_mm(self) -> float:
        return math.hypot(*self.hole_centres_mm[0]) if self.hole_centres_mm else 0.0

    def to_dict(self) -> dict:
        return {**super().to_dict(), "hole_circle_radius_mm": self.hole_circle_radius_mm}


@dataclass(frozen=True, kw_only=True)
class TorqueShaftPlan(PartPlan):
    """Input/output torque shaft on an end camshaft (a D shaft or a D socket)."""

    KIND = "torque_shaft"
    STYLE: ClassVar[str] = ""
    flat_ratio: float
    stickout_mm: float
    corner_radius_mm: float

    def to_dict(self) -> dict:
        return {"style": self.STYLE, **super().to_dict()}


@dataclass(frozen=True, kw_only=True)
class DShaftPlan(TorqueShaftPlan):
    """A D shaft through the camshaft's D bore, sticking out beyond the hub.

    Attributes:
        diameter_mm: shaft diameter (mm) = the bore.
        engaged_length_mm: length inside the camshaft (mm).
        stickout_mm: length outside (mm).
        flat_ratio: D flat position (-); corner_radius_mm: its corner rounding (mm).
    """

    STYLE = "d_shaft"
    diameter_mm: float
    engaged_length_mm: float


@dataclass(frozen=True, kw_only=True)
class HubSocketPlan(TorqueShaftPlan):
    """A shaft whose D socket fits over the camshaft's D hub.

    Attributes:
        outer_radius_mm: shaft radius (mm).
        socket_depth_mm: depth of the socket (mm).
        hub_radius_mm: radius of the hub it takes (mm).
    """

    STYLE = "hub_socket"
    outer_radius_mm: float
    socket_depth_mm: float
    hub_radius_mm: float
