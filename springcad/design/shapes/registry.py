"""The flexure-shape registry: shapes by name, and the rule that picks one for a layout.

A new shape is one module with a :class:`~springcad.design.shapes.base.FlexureShape`
subclass and a ``register(...)`` call (plus its calibration data when it does not use
the shipped one); a built-in one is also named in :data:`BUILT_IN`. The config schema's
allowed ``flexure`` values follow the registry
(:data:`springcad.config.schema.FLEXURE_SHAPES`).

This module is light (no numpy): ``import springcad`` imports it so that the config
knows every built-in name before any design module loads; a built-in shape's module
is imported the first time the shape is asked for.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from springcad.config.schema import FLEXURE_SHAPES
from springcad.errors import DesignError

if TYPE_CHECKING:
    from springcad.design.shapes.base import FlexureShape, Sizing, SizingContext

#: the built-in shapes, in the order "auto" tries them: name -> the module that defines
#: and registers it
BUILT_IN = {"straight": "springcad.design.shapes.straight",
            "serpentine": "springcad.design.shapes.serpentine"}
#: the shapes registered so far by name (a built-in one once its module is imported)
SHAPES: dict[str, "FlexureShape"] = {}
#: the request that tries every shape whose ``auto`` is set
AUTO = "auto"

for _name in BUILT_IN:
    FLEXURE_SHAPES.add(_name)


def register(shape: "FlexureShape") -> "FlexureShape":
    """Add ``shape`` under its name; the config then accepts the name.

    Raises:
        ValueError: the name is empty, "auto", or taken by another shape.
    """
    if not shape.name or shape.name == AUTO:
        raise ValueError(f"a flexure shape needs a name other than '{AUTO}', got {shape.name!r}")
    if shape.name in SHAPES and SHAPES[shape.name] is not shape:
        raise ValueError(f"two flexure shapes named '{shape.name}'")
    SHAPES[shape.name] = shape
    FLEXURE_SHAPES.add(shape.name)
    return shape


def unregister(name: str) -> None:
    """Remove a shape (a test's toy shape); the config no longer accepts the name."""
    SHAPES.pop(name, None)
    FLEXURE_SHAPES.discard(name)


def get(name: str) -> "FlexureShape":
    """The shape registered as ``name`` (a built-in one's module imported on first use).

    Raises:
        DesignError: no such shape (names the registered ones).
    """
    if name not in SHAPES and name in BUILT_IN:
        importlib.import_module(BUILT_IN[name])
    try:
        return SHAPES[name]
    except KeyError:
        raise DesignError(f"no flexure shape '{name}'; registered: "
                          f"{', '.join(names())}") from None


def names() -> tuple[str, ...]:
    """The registered shape names: the built-in ones first, then in registration order."""
    return tuple(n for n in FLEXURE_SHAPES if n != AUTO)


def tried(requested: str) -> list["FlexureShape"]:
    """The shapes a request tries, in order: every ``auto`` shape for "auto"; else the
    shapes the requested one defers to, then itself."""
    if requested == AUTO:
        return [s for s in map(get, names()) if s.auto]
    shape = get(requested)
    return [get(n) for n in shape.defers_to] + [shape]


def size_flexure(requested: str, ctx: "SizingContext") -> tuple["Sizing", list[str]]:
    """The first shape of the request that sizes a flexure in ``ctx``, with the warnings.

    Args:
        requested: the spec's ``flexure``: "auto" or a registered name.
        ctx: the layout and rules (:class:`~springcad.design.shapes.base.SizingContext`).

    Returns:
        (sizing, warnings): a warning when a shape the requested one defers to is used.

    Raises:
        DesignError: the requested shape refuses the layout, or no shape tried reaches
            the deflection (each shape's own error propagates).
    """
    name = ctx.spec.name
    if requested != AUTO and (why := get(requested).refusal(ctx)):
        raise DesignError(f"spring '{name}': {why}")
    for shape in tried(requested):
        sizing = shape.size(ctx)
        if sizing is None:
            continue
        warnings = []
        if requested not in (AUTO, shape.name):
            warnings.append(f"{requested} requested but {shape.name} flexures already reach the "
                            f"target deflection; {shape.name} flexures used")
        return sizing, warnings
    raise DesignError(
        f"spring '{name}': no {'flexure shape' if requested == AUTO else requested + ' flexure'}"
        f" reaches {ctx.deflection_rad:.4f} rad with {ctx.layout.n} flexures between "
        f"r_c = {ctx.layout.rc:.3g} mm and R_r = {ctx.layout.rr:.3g} mm; registered shapes: "
        f"{', '.join(names())}")
