"""Manufacturing processes: what each can make and hold (``springcad/data/processes.toml``).

Pure data and formulas, no geometry kernel: the design step sizes parts with them
(e.g. the rim spacer's inner edge and hole size), the geometry step checks the cut
profiles against them (:mod:`springcad.geometry.sheet`), the drawings and the BOM
print the same process text. Units: mm.
"""

from __future__ import annotations

import functools
import math
import tomllib
from dataclasses import dataclass

from springcad.data import data_path
from springcad.errors import ConfigError

PROCESS_FILE = "processes.toml"
#: a part this thin or thinner is cut from sheet stock, whatever cuts it (mm): a shim
SHEET_STOCK_MAX_MM = 1.0
#: thickness tolerance drawn on such a part, the sheet as supplied (+-mm): ISO 2768-1 has
#: no general tolerance below 0.5 mm, and the gap it sets between two springs needs no
#: finer one
SHEET_THICKNESS_TOLERANCE_MM = 0.05


@dataclass(frozen=True)
class Process:
    """One process's capabilities (see the data file's header for every field)."""

    key: str
    text: str
    materials: tuple[str, ...]
    min_web_mm: float
    min_web_per_thickness: float
    min_hole_per_thickness: float
    hole_tolerance_mm: float
    position_tolerance_mm: float
    fits: tuple[str, ...]
    pattern_zone_mm: float = 0.0
    internal_profiles: tuple[str, ...] = ()
    min_internal_radius_mm: float = 0.0
    before_hardening: bool = False
    contour_tolerance_mm: float = 0.0

    @property
    def pattern_zone(self) -> float:
        """Diameter of the position zone of one pattern's holes to each other (mm): the
        data file's ``pattern_zone_mm``, else the position zone (2 x its radius)."""
        return self.pattern_zone_mm or 2.0 * self.position_tolerance_mm

    def min_web(self, thickness_mm: float) -> float:
        """Smallest web between a hole and another contour, or two facing contours (mm)."""
        return max(self.min_web_mm, self.min_web_per_thickness * thickness_mm)

    def hole_web_loss_mm(self) -> float:
        """How much a web from a cut hole to another contour may lose against its nominal
        size on a sheet part this process cuts (mm): the hole at its largest (half the
        hole tolerance), off its true position by the position zone's radius, the other
        contour off the drawing by the contour tolerance."""
        return 0.5 * self.hole_tolerance_mm + self.position_tolerance_mm + self.contour_tolerance_mm

    def contour_web_loss_mm(self) -> float:
        """How much a web between two cut contours of a sheet part may lose against its
        nominal size (mm): each contour off the drawing by the contour tolerance."""
        return 2.0 * self.contour_tolerance_mm

    def clearance_hole(self, pin_max_mm: float, mate_position_mm: float) -> float:
        """Nominal diameter (rounded up to 0.01 mm) of a hole that clears a pin of largest
        diameter ``pin_max_mm`` located by holes of another part whose true position is
        within ``mate_position_mm`` (radius): at its smallest size and worst position
        the hole still clears the pin at its worst position (mm)."""
        need = (pin_max_mm + 2.0 * (mate_position_mm + self.position_tolerance_mm)
                + self.hole_tolerance_mm)
        return math.ceil(round(need * 100.0, 6)) / 100.0

    def makes_internal(self, kind: str) -> bool:
        """The process makes a non-round hole or pocket of this kind ("through", "blind")."""
        return kind in self.internal_profiles

    def can_finish(self, fit: str) -> bool:
        """The process holds this ISO fit on a hole or bore without a second operation."""
        return not fit or fit in self.fits


@functools.cache
def processes() -> dict[str, Process]:
    """Every process of the data file, by key."""
    with open(data_path(PROCESS_FILE), "rb") as fh:
        data = tomllib.load(fh)
    return {k: Process(key=k, text=v["text"], materials=tuple(v["materials"]),
                       min_web_mm=float(v["min_web_mm"]),
                       min_web_per_thickness=float(v["min_web_per_thickness"]),
                       min_hole_per_thickness=float(v["min_hole_per_thickness"]),
                       hole_tolerance_mm=float(v["hole_tolerance_mm"]),
                       position_tolerance_mm=float(v["position_tolerance_mm"]),
                       fits=tuple(v["fits"]),
                       pattern_zone_mm=float(v.get("pattern_zone_mm", 0.0)),
                       internal_profiles=tuple(v.get("internal_profiles", ())),
                       min_internal_radius_mm=float(v.get("min_internal_radius_mm", 0.0)),
                       before_hardening=bool(v.get("before_hardening", False)),
                       contour_tolerance_mm=float(v.get("contour_tolerance_mm", 0.0)))
            for k, v in data.items()}


def process(key: str) -> Process:
    """The process named ``key``.

    Raises:
        ConfigError: no such process in the data file.
    """
    try:
        return processes()[key]
    except KeyError:
        raise ConfigError(f"manufacturing process '{key}': not in {PROCESS_FILE} "
                          f"(known: {', '.join(sorted(processes()))})") from None


def sheet_web_mm(key: str, thickness_mm: float, process_min_mm: float = 0.0) -> float:
    """Thinnest web (mm) a part ``thickness_mm`` thick may have between a hole and another
    contour, or between two facing contours, when ``key`` cuts it: the process's own rule
    (:meth:`Process.min_web`) and ``process_min_mm`` (wire EDM: the job's
    ``[manufacturing]`` web or hole-edge limit), and on sheet stock
    (:data:`SHEET_STOCK_MAX_MM` or thinner) at least the sheet thickness, whatever the
    process (issue 26): a web narrower than the sheet is thick twists and tears when the
    part is deburred, handled and slipped over its pins."""
    sheet = thickness_mm if thickness_mm <= SHEET_STOCK_MAX_MM else 0.0
    return max(process(key).min_web(thickness_mm), process_min_mm, sheet)


def process_text(key: str) -> str:
    """What the drawing, BOM and README call the process (the key if unknown)."""
    p = processes().get(key)
    return p.text if p else key


def process_chain_text(key: str, secondary: tuple[str, ...] = ()) -> str:
    """The main process and those that finish features after it, as the drawing's title
    block and the BOM print them (``"turned, sinker EDM"``)."""
    return ", ".join(process_text(k) for k in (key, *secondary))
