"""Purchased parts from standard catalogues (data files in ``springcad/data``).

* ISO 8734 hardened dowel pins, m6: ``iso8734_dowels.csv`` (diameter, nominal length).

A rim dowel is the longest catalogue pin that stays inside the two rims it joins
(flush or recessed: nothing beside the rims may be touched by a pin end), centred in
them, and only if it still engages each rim by :data:`MIN_ENGAGEMENT_PER_DIAMETER` x
its diameter. Units: mm.
"""

from __future__ import annotations

import csv
import functools

from springcad.data import data_path
from springcad.errors import DesignError

DOWEL_FILE = "iso8734_dowels.csv"
#: a pressed dowel engages each part it locates by at least this x its diameter
MIN_ENGAGEMENT_PER_DIAMETER = 1.0


@functools.cache
def dowel_lengths() -> dict[float, tuple[float, ...]]:
    """Nominal lengths (mm) of every ISO 8734 diameter (mm) in the catalogue."""
    text = data_path(DOWEL_FILE).read_text()
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    out: dict[float, list[float]] = {}
    for r in rows:
        out.setdefault(float(r["diameter_mm"]), []).append(float(r["length_mm"]))
    return {d: tuple(sorted(ls)) for d, ls in out.items()}


def dowel_designation(diameter_mm: float, length_mm: float) -> str:
    """The order designation, e.g. ``ISO 8734 - 1.5 m6 x 8``."""
    return f"ISO 8734 - {diameter_mm:g} m6 x {length_mm:g}"


def rim_dowel_length(diameter_mm: float, first_mm: float, gap_mm: float,
                     second_mm: float) -> float:
    """Catalogue length (mm) of a dowel through two rims ``first_mm`` and ``second_mm``
    thick with ``gap_mm`` between them, centred in the three.

    Raises:
        DesignError: no catalogue pin of this diameter, or none that fits inside the
            rims and engages each by the minimum.
    """
    lengths = dowel_lengths().get(float(diameter_mm))
    if not lengths:
        raise DesignError(f"dowel Ø{diameter_mm:g}: not an ISO 8734 diameter in {DOWEL_FILE} "
                          f"({', '.join(f'{d:g}' for d in sorted(dowel_lengths()))})")
    room = first_mm + gap_mm + second_mm
    need = MIN_ENGAGEMENT_PER_DIAMETER * diameter_mm
    for length in reversed(lengths):
        recess = 0.5 * (room - length)
        if recess >= -1e-9 and min(first_mm, second_mm) - recess >= need - 1e-9:
            return length
    raise DesignError(f"dowel Ø{diameter_mm:g}: no ISO 8734 length ({', '.join(f'{v:g}' for v in lengths)}) "
                      f"fits the {room:g} mm of two rims and engages each by {need:g} mm")
