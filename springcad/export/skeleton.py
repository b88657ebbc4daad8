"""A built stack without its solids, for rebuilding an unchanged job from the result cache.

A warm build of an unchanged job reads every file, check and read-back from the cache
(:mod:`springcad.cache`); the solids would only serve to compute nothing. So the first
build stores the assembly's *skeleton*: per part its info, slabs, colour, kind of solid
and exact volume (the bill of materials' mass), per instance its name, part, placement,
component, role and colour. A later build of the same design (the key: the design and
the code, as for every cache entry) gets a :class:`LazyAssembly` from it: the same
parts, quantities, names and masses, and the solids built from the design only when
something asks for one (an export that is not cached, ``part.solid`` from the API).
The solids are a function of the design (built by deterministic code), so the lazily
built ones are those a fresh build makes, and so are the files written from them
(``tests/export/test_skeleton.py``).

Units: mm, mm^3.
"""

from __future__ import annotations

from springcad.cache import MISSING
from springcad.geometry.part_info import NamedByInfo
from springcad.geometry.stack import Instance, StackAssembly, build_stack

#: the cache kind of a skeleton (key inputs: the job design)
KIND = "assembly-skeleton"


class PartRecord(NamedByInfo):
    """A part of a :class:`LazyAssembly`: what the exports read without the solid.

    Attributes:
        info: the :class:`~springcad.geometry.base.PartInfo` (part number, profile ...).
        slabs, colour, exact_prism: as on the built part.
        volume_mm3: the solid's exact volume (mm^3).

    Any other attribute (``solid``, ``describe`` ...) is the built part's: asking for one
    builds the assembly's solids (once).
    """

    def __init__(self, info, slabs, colour, exact_prism: bool, volume_mm3: float):
        self.info, self.slabs, self.colour = info, slabs, colour
        self.exact_prism, self.volume_mm3 = exact_prism, volume_mm3
        self._owner = None

    def built(self):
        """The part with its solid (builds the assembly's solids the first time)."""
        return self._owner.solid_assembly().parts[self.part_number]

    def __getattr__(self, name):
        if name.startswith("__") or name == "_owner":
            raise AttributeError(name)
        return getattr(self.built(), name)

    def __repr__(self) -> str:
        return f"PartRecord({self.part_number!r}, {self.name!r})"


class LazyAssembly(StackAssembly):
    """A :class:`~springcad.geometry.stack.StackAssembly` of :class:`PartRecord` parts
    whose solids are built from ``design`` on first use (:meth:`solid_assembly`)."""

    def __init__(self, design, instances, parts):
        super().__init__(design, instances, parts)
        self._solids = None
        for part in parts.values():
            part._owner = self

    def solid_assembly(self) -> StackAssembly:
        """The assembly with its solids, built from the design the first time."""
        if self._solids is None:
            self._solids = build_stack(self.design)
        return self._solids

    def compound(self):
        return self.solid_assembly().compound()


def with_solids(assembly) -> StackAssembly:
    """``assembly`` itself, or for a :class:`LazyAssembly` its built twin."""
    return assembly.solid_assembly() if isinstance(assembly, LazyAssembly) else assembly


def built_part(assembly, part_number: str):
    """The part ``part_number`` of ``assembly`` with its solid."""
    return with_solids(assembly).parts[part_number]


def part_volume_mm3(part) -> float:
    """The exact volume of a part's solid (mm^3): stored for a :class:`PartRecord`."""
    if isinstance(part, PartRecord):
        return part.volume_mm3
    return part.volume_mm3()


def skeleton_of(assembly) -> dict:
    """The picklable skeleton of a built assembly (parts as plain records, no solids)."""
    parts = {pn: (p.info, p.slabs, p.colour, p.exact_prism, part_volume_mm3(p))
             for pn, p in assembly.parts.items()}
    instances = [(i.name, i.part.part_number, i.placement, i.component, i.role, i.colour)
                 for i in assembly.instances]
    return {"parts": parts, "instances": instances}


def from_skeleton(design, skeleton: dict) -> LazyAssembly:
    """The :class:`LazyAssembly` of ``design`` from its stored skeleton."""
    parts = {pn: PartRecord(*rec) for pn, rec in skeleton["parts"].items()}
    instances = [Instance(name, parts[pn], placement, component, role, colour)
                 for name, pn, placement, component, role, colour in skeleton["instances"]]
    return LazyAssembly(design, instances, parts)


def load(cache, design) -> LazyAssembly | None:
    """The lazy assembly of ``design`` when its skeleton is cached, else None."""
    if cache is None:
        return None
    skeleton = cache.load(cache.key(KIND, design))
    return None if skeleton is MISSING else from_skeleton(design, skeleton)


def store(cache, design, assembly) -> None:
    """Store the skeleton of ``assembly`` (built from ``design``) in ``cache`` (or not, None)."""
    if cache is not None and not isinstance(assembly, LazyAssembly):
        cache.store(cache.key(KIND, design), skeleton_of(assembly))
