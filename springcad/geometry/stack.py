"""Assemble a designed stack into placed, named, coloured parts.

Every solid is built from the stack's :class:`~springcad.design.hardware.Component`
list (the single source of sizes and axial places), each by its part family
(:mod:`springcad.geometry.families`). Identical parts are built once and placed
several times (four S1 rings are one part, quantity 4). An end camshaft or
torque shaft on the output side is the input part turned over.
Units: mm, rad.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from springcad.geometry.placement import Instance, Placement
from springcad.progress import Progress, no_progress

if TYPE_CHECKING:  # an assembly is read (export/skeleton.py) without the CAD kernel
    from springcad.geometry.base import SpringcadPart

__all__ = ["Instance", "Placement", "StackAssembly", "build_stack"]


@dataclass
class StackAssembly:
    """The placed parts of a stack, which of them carry the input and the output.

    Attributes:
        design: the :class:`~springcad.design.job.JobDesign` it was built from.
        instances: placed parts, input side first.
        parts: distinct parts by part number.
    """

    design: object
    instances: list[Instance]
    parts: dict[str, SpringcadPart]

    @property
    def input_names(self) -> list[str]:
        return [i.name for i in self.instances if i.role == "input"]

    @property
    def output_names(self) -> list[str]:
        return [i.name for i in self.instances if i.role == "output"]

    def quantities(self) -> dict[str, int]:
        """Number of placed instances of each part number."""
        out: dict[str, int] = {}
        for inst in self.instances:
            out[inst.part.part_number] = out.get(inst.part.part_number, 0) + 1
        return out

    def part_named(self, name: str) -> SpringcadPart:
        """The part whose job-local label is ``name`` (e.g. ``"S1-RING"``)."""
        for part in self.parts.values():
            if part.name == name:
                return part
        raise KeyError(f"no part named {name!r}; names: {sorted(p.name for p in self.parts.values())}")

    def instance(self, name: str) -> Instance:
        for inst in self.instances:
            if inst.name == name:
                return inst
        raise KeyError(name)

    def compound(self):
        """A build123d Compound whose children are the named, coloured instances."""
        from build123d import Color, Compound

        children = []
        for inst in self.instances:
            shape = inst.shape
            shape.label = inst.name
            shape.color = Color(*inst.colour)
            children.append(shape)
        return Compound(children=children, label=self.design.job.name)


def build_stack(job_design, progress: Progress = no_progress) -> StackAssembly:
    """Build and place every part of a designed job's stack.

    Each component is built by its part family (:mod:`springcad.geometry.families`)
    from its typed plan.

    Args:
        job_design: a :class:`~springcad.design.job.JobDesign`.
        progress: ``progress(message, fraction=None)``, called per distinct part built.

    Raises:
        GeometryError: a part cannot be made (the message names it and the cause).
    """
    from springcad.geometry.families import BuildContext, PartCache, build_component

    stack = job_design.stack
    comps = stack.components
    ctx = BuildContext(stack.springs, PartCache(progress))
    for k, comp in enumerate(comps):
        ctx.cache.fraction = k / len(comps)
        build_component(ctx, comp)
    return StackAssembly(job_design, ctx.instances, dict(ctx.cache.by_number))
