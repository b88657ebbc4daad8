"""What a flexure shape is: the protocol every registered shape meets, and its record.

A flexure shape decides, for one layout (N, r_c, tip ball, R_r from
:mod:`springcad.design.layout`), how the flexure between the tip ball and the rim
is drawn: its centreline and width law (the outline that :mod:`springcad.design.ring`
turns into the ring profile, and so geometry/ and fea/ see), the sizing that gives
the target stiffness at the design stress, and the stress-concentration calibration
the design's peak prediction (:mod:`springcad.design.stress`) uses. The design
search (:func:`springcad.design.sizing._design_at`) knows no shape by name: it asks
the registry (:mod:`springcad.design.shapes.registry`).

Local flexure frame as in :mod:`springcad.design.flexure`: the flexure axis is +y,
the tip-ball centre at ``(0, r_c)``. Units: mm, N, MPa, N*mm, rad.
"""

from __future__ import annotations

from dataclasses import dataclass

from springcad.config import ManufacturingSpec, SpringSpec
from springcad.design import stress
from springcad.design.flexure import Centreline
from springcad.design.layout import Layout
from springcad.design.shapes.screen import ScreenCentreline, ScreenRows, ScreenSizing


@dataclass(frozen=True)
class FlexureRecord:
    """What a shape chose for one spring: the shape's part of a ``SpringDesign``.

    Attributes:
        name: the registered shape name (``design.json``'s ``flexure``).
        width_law: the width law's name, as ``design.json`` reports it.
        root_width_mm: the width law's root width w0 before the width factor (mm).
        centreline: the flexure centreline from r_c to the root.
        required_area_ratio: flexure area over a straight flexure's that the deflection
            needs (``design.json``'s ``serpentine_factor``; 1 for straight shapes) (-).
        area_ratio: the area ratio the centreline reaches (-).
        balance: how a serpentine's lobes are balanced
            (:data:`springcad.design.flexure.BALANCES`), None for other shapes.
        params: further numbers of the shape's own width law, (name, value) pairs with
            units in the names; reported in ``design.json`` when not empty.
    """

    name: str
    width_law: str
    root_width_mm: float
    centreline: Centreline
    required_area_ratio: float = 1.0
    area_ratio: float = 1.0
    balance: str | None = None
    params: tuple[tuple[str, float], ...] = ()

    def param(self, key: str) -> float:
        """One of :attr:`params` by name."""
        return dict(self.params)[key]


@dataclass(frozen=True)
class SizingContext:
    """Everything a shape's sizing may use: the spec, its layout and the rules.

    Attributes:
        spec: the spring spec (target stiffness, deflection, envelope, name).
        layout: the candidate layout (N, r_c, ball, R_r, straight limit, tip load).
        stress_MPa: the beam stress the flexures are sized to (design stress x derating).
        youngs_modulus_MPa: E of the material (MPa).
        manufacturing: the wire-EDM rules (slot width, inside radius, web).
        max_root_radius_mm: the largest root radius the rim (and the stack) allows (mm).
        balances: the serpentine balances the search tries.
    """

    spec: SpringSpec
    layout: Layout
    stress_MPa: float
    youngs_modulus_MPa: float
    manufacturing: ManufacturingSpec
    max_root_radius_mm: float
    balances: tuple[str, ...] = ()

    @property
    def target_stiffness_Nmm_per_rad(self) -> float:
        return self.spec.target_stiffness_Nmm_per_rad

    @property
    def deflection_rad(self) -> float:
        return self.spec.max_deflection_rad


@dataclass(frozen=True)
class Sizing:
    """A shape's answer for one layout.

    Attributes:
        layout: the layout as the shape uses it (a shape may move the root radius and
            with it the straight limit, as the straight shape's own rim rule does).
        record: the shape's record.
        clearance_mm: the smallest gap to the neighbouring flexure the sizing measured
            (mm), or None when it measured none.
    """

    layout: Layout
    record: FlexureRecord
    clearance_mm: float | None = None


class FlexureShape:
    """A flexure shape: subclass it, set the class attributes, implement :meth:`size`
    and :meth:`width_mm`, and register an instance
    (:func:`springcad.design.shapes.registry.register`).

    Class attributes:
        name: the name a config asks for (``springs.<name>.flexure``).
        auto: whether ``flexure = "auto"`` tries this shape (in registration order).
        defers_to: shapes tried before this one when it is asked for by name (the
            serpentine defers to the straight flexure where that already reaches).
        summary: one line for messages and docs.
    """

    name: str = ""
    auto: bool = True
    defers_to: tuple[str, ...] = ()
    summary: str = ""

    def __repr__(self) -> str:
        return f"<flexure shape {self.name!r}>"

    def size(self, ctx: SizingContext) -> Sizing | None:
        """The flexure of this shape that gives the target stiffness in ``ctx.layout``
        at ``ctx.stress_MPa``, or None when this shape does not reach the deflection
        there (the search then tries the next shape).

        Raises:
            DesignError: the shape reaches but breaks a rule (the message says which).
        """
        raise NotImplementedError

    def refusal(self, ctx: SizingContext) -> str:
        """Why this shape, asked for by name, cannot serve ``ctx`` ("" when it might):
        checked before any shape is tried, so the user's request is refused early."""
        return ""

    def width_mm(self, design, y_mm):
        """The width law at radius y of ``design`` (a
        :class:`~springcad.design.spring.SpringDesign`, which holds this shape's record)
        before the width factor, the root flare, the web floor and the profile offset
        that ``SpringDesign.width_mm`` applies (mm)."""
        raise NotImplementedError

    # ------------------------------------------------------------- the synthesis screen
    @property
    def screens(self) -> bool:
        """Whether the synthesis screen can size this shape (:meth:`screen_size`)."""
        return type(self).screen_size is not FlexureShape.screen_size

    def screen_size(self, rows: ScreenRows) -> ScreenSizing:
        """:meth:`size` on arrays, for many disks at once (:mod:`.screen`).

        Raises:
            NotImplementedError: the shape has no screen; the synthesis does not offer it.
        """
        raise NotImplementedError(f"flexure shape '{self.name}' has no synthesis screen")

    def screen_centreline(self, rows: ScreenRows, sizing: ScreenSizing) -> ScreenCentreline | None:
        """The centreline of the taken rows on the screen's stations, or None for the
        radial straight line the screen assumes by default."""
        return None

    def calibration(self) -> stress.StressCalibration:
        """The stress-concentration coefficients of this shape's peak prediction: the
        shipped FEA fit (``springcad/data/stress_calibration.json``) with the flank factor
        of this shape's rows when it has some, unless a shape brings its own."""
        return stress.calibration(self.name)
