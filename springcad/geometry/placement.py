"""Where a part sits in a stack: :class:`Placement` and the placed :class:`Instance`.

Units: mm, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from springcad.design.hardware import Component

if TYPE_CHECKING:  # a placed part needs no CAD kernel to be read (export/skeleton.py)
    from springcad.geometry.base import SpringcadPart


@dataclass(frozen=True)
class Placement:
    """Where a part sits in the stack: optional turn-over, rotation about z, translation.

    A point p of the part frame goes to T + Rz(angle) F p, where F = diag(-1, 1, -1)
    (half a turn about y) when ``flipped`` and T = (x, y, z).
    """

    z_mm: float
    x_mm: float = 0.0
    y_mm: float = 0.0
    flipped: bool = False
    angle_rad: float = 0.0

    def location(self):
        from build123d import Location, Rot

        loc = Location((self.x_mm, self.y_mm, self.z_mm)) * Rot(0, 0, math.degrees(self.angle_rad))
        return loc * Rot(0, 180, 0) if self.flipped else loc

    def map_xy(self, pts: np.ndarray) -> np.ndarray:
        """Part-frame (n, 2) points to stack coordinates (mm)."""
        p = np.asarray(pts, dtype=float)
        if self.flipped:
            p = p * np.array([-1.0, 1.0])
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        return p @ np.array([[c, s], [-s, c]]) + np.array([self.x_mm, self.y_mm])

    def map_z(self, z0: float, z1: float) -> tuple[float, float]:
        """Part-frame axial interval to stack coordinates (mm)."""
        if self.flipped:
            return self.z_mm - z1, self.z_mm - z0
        return self.z_mm + z0, self.z_mm + z1


@dataclass
class Instance:
    """One placed part of the stack.

    Attributes:
        name: unique instance name (the Component name, with ``_k`` for sets).
        part: the part.
        placement: where it sits.
        component: the Component it was built from.
        role: "input", "output" or "".
        colour: RGB (0-1) for renders and the assembly STEP.
    """

    name: str
    part: SpringcadPart
    placement: Placement
    component: Component
    role: str = ""
    colour: tuple = ()
    _shape: object = field(default=None, repr=False)
    _face_boxes: object = field(default=None, repr=False)

    @property
    def shape(self):
        """The part's solid moved into place (cached)."""
        if self._shape is None:
            self._shape = self.part.solid.moved(self.placement.location())
        return self._shape

    @property
    def z_range_mm(self) -> tuple[float, float]:
        z0, z1 = self.part.z_range_mm
        return self.placement.map_z(z0, z1)
