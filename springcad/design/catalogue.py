"""Purchased parts from standard catalogues (data files in ``springcad/data``).

* ISO 8734 hardened dowel pins, m6: ``iso8734_dowels.csv`` (diameter, nominal length).
* ISO 4762 socket-head screws and ISO 4032 nuts: bd_warehouse's tables (:func:`bolt_set`),
  the ones the solids are built from.
* ISO 286-2 limit deviations of the dowels (m6) and of their slip-fit holes (E7), and of
  the g6 shafts springcad turns (a D shaft's size across its flat, :func:`g6_deviation_mm`).

Rim dowels locate neighbouring rims and carry the torque between them. They are a slip
fit in every rim they pass (E7 holes, never pressed): the smallest clearance E7/m6
exceeds the mismatch of two rims' hole patterns (:func:`rim_pin_fit`), so no set of
pins can jam however many there are, and every pin is bonded at assembly with a
retaining compound (it cures after the stack is closed).

A rim dowel is the longest catalogue pin that stays inside the two rims it joins
(flush or recessed: nothing beside the rims may be touched by a pin end), centred in
them, and only if it still engages each rim by :data:`MIN_ENGAGEMENT_PER_DIAMETER` x
its diameter. Units: mm.
"""

from __future__ import annotations

import csv
import functools
import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path

from springcad.config.schema import BOLT_DIAMETERS_MM
from springcad.data import DOWEL_FILE, dowel_lengths
from springcad.errors import DesignError, RemedyError, change_text
from springcad.units import UM_PER_MM

#: a dowel engages each part it locates by at least this x its diameter
MIN_ENGAGEMENT_PER_DIAMETER = 1.0
#: upper length tolerance of a dowel pin (mm) by nominal length (up to, mm): a pin is
#: ordered to length within +tol/0; DIN 7's table (+0.3 to 10 mm, +0.5 to 50, +0.8 above),
#: taken for ISO 8734 pins too. A pin is chosen so that at its longest it still fits the
#: room between the outer faces of the two parts it joins (never proud of either face,
#: where a washer or a spring that turns against it may sit)
DOWEL_LENGTH_TOLERANCE_MM = ((10.0, 0.3), (50.0, 0.5), (math.inf, 0.8))


def dowel_length_tolerance_mm(length_mm: float) -> float:
    """Upper length tolerance of a dowel of this nominal length (mm)."""
    return next(tol for upto, tol in DOWEL_LENGTH_TOLERANCE_MM if length_mm <= upto + 1e-9)


#: ISO 286-2 limit deviations (um) by nominal size range (upper bound of the range, mm):
#: shaft m6 (lower, upper) and hole E7 (lower, upper)
_M6_UM = ((3.0, 2, 8), (6.0, 4, 12), (10.0, 6, 15), (18.0, 7, 18))
_E7_UM = ((3.0, 14, 24), (6.0, 20, 32), (10.0, 25, 40), (18.0, 32, 50))
#: shaft g6 (lower, upper): fundamental deviation g (-2, -4, -5, -6, -7, -9, -10, -12, -14,
#: -15, -17, -18, -20 um) minus IT6 (6, 8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40 um) below
#: it, up to 500 mm (a stack's torque shaft grows with its torque: Ø51 for 470 N*m)
_G6_UM = ((3.0, -8, -2), (6.0, -12, -4), (10.0, -14, -5), (18.0, -17, -6), (30.0, -20, -7),
          (50.0, -25, -9), (80.0, -29, -10), (120.0, -34, -12), (180.0, -39, -14),
          (250.0, -44, -15), (315.0, -49, -17), (400.0, -54, -18), (500.0, -60, -20))
#: the ISO fit of a rim dowel's hole in every rim it passes (slip fit over an m6 pin)
RIM_PIN_HOLE_FIT = "E7"


def _deviation_mm(table, diameter_mm: float, what: str) -> tuple[float, float]:
    for upper_mm, lo_um, hi_um in table:
        if diameter_mm <= upper_mm + 1e-9:
            return lo_um / UM_PER_MM, hi_um / UM_PER_MM
    raise DesignError(f"{what} Ø{diameter_mm:g}: above the {table[-1][0]:g} mm of springcad's "
                      "ISO 286 table")


def m6_deviation_mm(diameter_mm: float) -> tuple[float, float]:
    """(lower, upper) deviation of an m6 pin (mm, ISO 286-2)."""
    return _deviation_mm(_M6_UM, diameter_mm, "m6 pin")


def e7_deviation_mm(diameter_mm: float) -> tuple[float, float]:
    """(lower, upper) deviation of an E7 hole (mm, ISO 286-2)."""
    return _deviation_mm(_E7_UM, diameter_mm, "E7 hole")


def g6_deviation_mm(diameter_mm: float) -> tuple[float, float]:
    """(lower, upper) deviation of a g6 shaft (mm, ISO 286-2)."""
    return _deviation_mm(_G6_UM, diameter_mm, "g6 shaft")


@dataclass(frozen=True)
class RimPinFit:
    """How a rim dowel sits in the E7 holes of the rims it joins (mm).

    Attributes:
        clearance_min_mm, clearance_max_mm: diametral clearance of one pin in one hole.
        mismatch_mm: largest offset of one pin's two holes when two rims' patterns are
            laid over each other: each hole within a pattern zone of diameter
            ``pattern_zone_mm`` around its place in its own rim's pattern.
        pattern_zone_mm: the hole-to-hole position zone (diameter) within a rim.
    """

    clearance_min_mm: float
    clearance_max_mm: float
    mismatch_mm: float
    pattern_zone_mm: float

    @property
    def cannot_jam(self) -> bool:
        """Every pin finds room in both holes for any pattern within tolerance: the two
        holes' half clearances together cover the offset of their centres."""
        return self.clearance_min_mm >= self.mismatch_mm - 1e-12


def rim_pin_fit(diameter_mm: float, pattern_zone_mm: float) -> RimPinFit:
    """The slip fit of an m6 rim dowel in E7 holes of two rims whose hole patterns each
    hold a position zone Ø``pattern_zone_mm`` hole to hole (mm)."""
    p_lo, p_hi = m6_deviation_mm(diameter_mm)
    h_lo, h_hi = e7_deviation_mm(diameter_mm)
    return RimPinFit(clearance_min_mm=h_lo - p_hi, clearance_max_mm=h_hi - p_lo,
                     mismatch_mm=pattern_zone_mm, pattern_zone_mm=pattern_zone_mm)


def dowel_designation(diameter_mm: float, length_mm: float, stainless: bool = False) -> str:
    """The order designation (ISO 8734:1997: diameter x length, then type A = through
    hardened steel "A - St", or martensitic stainless steel "C1" for a stainless stack; the
    diameter tolerance is always m6), e.g. ``ISO 8734 - 1.5 x 8 - A - St``."""
    return f"ISO 8734 - {diameter_mm:g} x {length_mm:g} - {'C1' if stainless else 'A - St'}"


def rim_dowel_length(diameter_mm: float, first_mm: float, gap_mm: float,
                     second_mm: float) -> float:
    """Catalogue length (mm) of a dowel through two rims ``first_mm`` and ``second_mm``
    thick with ``gap_mm`` between them, centred in the three: the longest whose largest
    length (nominal + :func:`dowel_length_tolerance_mm`) fits the room and whose nominal
    length engages each rim by the minimum.

    Raises:
        RemedyError: no catalogue pin of this diameter, or none that fits inside the rims
            and engages each by the minimum (naming the nearest catalogue diameters that
            do).
    """
    lengths = dowel_lengths().get(float(diameter_mm))
    others = _other_diameters(diameter_mm, lambda d, ls: _rim_dowel_fit(
        d, ls, first_mm, gap_mm, second_mm))
    if not lengths:
        raise RemedyError(f"dowel Ø{diameter_mm:g}: not an ISO 8734 diameter in {DOWEL_FILE} "
                          f"({', '.join(f'{d:g}' for d in sorted(dowel_lengths()))})", others)
    length = _rim_dowel_fit(diameter_mm, lengths, first_mm, gap_mm, second_mm)
    if length is not None:
        return length
    room = first_mm + gap_mm + second_mm
    listed = ", ".join(f"{v:g}" for v in lengths)
    raise RemedyError(f"dowel Ø{diameter_mm:g}: no ISO 8734 length ({listed}) fits the "
                      f"{room:g} mm of two rims at its longest (nominal + its length "
                      f"tolerance, +{dowel_length_tolerance_mm(lengths[0]):g} mm) and engages "
                      f"each by {MIN_ENGAGEMENT_PER_DIAMETER * diameter_mm:g} mm", others)


#: a pin refusal names at most this many other catalogue diameters (each is checked with
#: the whole job's design search, seconds each)
DIAMETER_REMEDIES = 2


def _other_diameters(diameter_mm: float, fit) -> list[tuple[dict, str]]:
    """The catalogue diameters nearest ``diameter_mm`` (by ratio) that ``fit(d, lengths)``
    gives a length for, as :class:`~springcad.errors.RemedyError` remedies naming the pin
    (at most :data:`DIAMETER_REMEDIES`)."""
    key = "hardware.fastener_diameter_mm"
    found = [(d, v) for d, ls in sorted(dowel_lengths().items()) if d != diameter_mm
             for v in [fit(d, ls)] if v is not None]
    found.sort(key=lambda dv: abs(math.log(dv[0] / diameter_mm)))
    return [({key: d}, change_text(key, d, diameter_mm, f"ISO 8734 {d:g} x {v:g}"))
            for d, v in found[:DIAMETER_REMEDIES]]


def _rim_dowel_fit(diameter_mm: float, lengths, first_mm: float, gap_mm: float,
                   second_mm: float) -> float | None:
    """The longest of ``lengths`` (mm) that :func:`rim_dowel_length` accepts, or None."""
    room = first_mm + gap_mm + second_mm
    need = MIN_ENGAGEMENT_PER_DIAMETER * diameter_mm
    for length in reversed(lengths):
        recess = 0.5 * (room - length)
        if (room - length - dowel_length_tolerance_mm(length) >= -1e-9
                and min(first_mm, second_mm) - recess >= need - 1e-9):
            return length
    return None


def drive_pin_length(diameter_mm: float, ring_mm: float, flange_mm: float) -> tuple[float, float]:
    """(catalogue length, length in the ring) of a drive pin (mm) through a rim flange into
    a ring ``ring_mm`` thick, engaging the ring and standing proud of the flange's outer
    face each by at least the minimum engagement, its ring end at least its length
    tolerance short of the ring's far face (never proud there): the shortest length that
    reaches that far into the ring; when none does (a ring thicker than the catalogue's
    longest pin needs), the longest, as deep in the ring as standing proud by the minimum
    allows (bonded in its hole, the rest of the hole empty).

    Raises:
        RemedyError: the ring is too thin for this diameter (names the nearest catalogue
            diameters that engage it).
    """
    lengths = dowel_lengths().get(float(diameter_mm), ())
    fit = _drive_pin_fit(diameter_mm, lengths, ring_mm, flange_mm)
    if fit is not None:
        return fit
    need = MIN_ENGAGEMENT_PER_DIAMETER * diameter_mm
    raise RemedyError(f"drive pin Ø{diameter_mm:g}: no ISO 8734 length "
                      f"({', '.join(f'{v:g}' for v in lengths) or 'none'}) engages a "
                      f"{ring_mm:g} mm ring by {need:g} mm with its end its length tolerance "
                      f"short of the ring's far face and stands {need:g} mm proud of a "
                      f"{flange_mm:g} mm rim flange",
                      _other_diameters(diameter_mm, lambda d, ls: (
                          _drive_pin_fit(d, ls, ring_mm, flange_mm) or (None,))[0]))


def _drive_pin_fit(diameter_mm: float, lengths, ring_mm: float,
                   flange_mm: float) -> tuple[float, float] | None:
    """(length, length in the ring) that :func:`drive_pin_length` chooses from ``lengths``
    (mm), or None."""
    need = MIN_ENGAGEMENT_PER_DIAMETER * diameter_mm
    for length in lengths:  # through the ring to its length tolerance short of the far face
        in_ring = ring_mm - dowel_length_tolerance_mm(length)
        if in_ring >= need - 1e-9 and length - in_ring - flange_mm >= need - 1e-9:
            return length, in_ring
    if not lengths:
        return None
    longest = lengths[-1]  # in part: standing proud by the minimum
    in_ring = min(ring_mm - dowel_length_tolerance_mm(longest), longest - flange_mm - need)
    return (longest, in_ring) if in_ring >= need - 1e-9 else None


# ------------------------------------------------------------- screws and nuts
#: the ISO standards of the rim screws and nuts (bd_warehouse's names)
SCREW_STANDARD, NUT_STANDARD = "iso4762", "iso4032"


@dataclass(frozen=True)
class BoltSet:
    """Sizes of a rim screw and its nut (mm), from bd_warehouse's catalogue tables, the
    ones the solids are built from (:mod:`springcad.geometry.fasteners`).

    Attributes:
        size: thread size, e.g. ``"M2.5-0.45"``.
        head_diameter_mm, head_height_mm: ISO 4762 socket head dk and k.
        nut_across_corners_mm, nut_height_mm: ISO 4032 hex nut e (= s / cos 30 deg) and m.
        lengths_mm: the ISO 4762 nominal lengths of this size.
    """

    size: str
    head_diameter_mm: float
    head_height_mm: float
    nut_across_corners_mm: float
    nut_height_mm: float
    lengths_mm: tuple[float, ...]

    def screw_length_mm(self, grip_mm: float) -> float:
        """Shortest nominal length that passes the grip and the nut (mm), as the solids
        choose it (:class:`springcad.geometry.fasteners.RimScrew`).

        Raises:
            RemedyError: no length is long enough (names dowels and the smallest larger
                screw that is).
        """
        need = grip_mm + self.nut_height_mm
        for v in self.lengths_mm:
            if v >= need - 1e-9:
                return v
        fastener, diameter = "hardware.fastener", "hardware.fastener_diameter_mm"
        d_now = float(self.size[1:].split("-")[0])
        larger = [(d, b) for d in BOLT_DIAMETERS_MM if d > d_now
                  for b in [bolt_set(d)] if b.lengths_mm[-1] >= grip_mm + b.nut_height_mm - 1e-9]
        raise RemedyError(
            f"rim screws: no {self.size} ISO 4762 screw (lengths up to {self.lengths_mm[-1]:g} "
            f"mm) is long enough for a {grip_mm:g} mm grip and a {self.nut_height_mm:g} mm nut",
            [({fastener: "dowel"}, change_text(fastener, "dowel", "bolt",
                                               "flush or drive pins, no grip"))]
            + [({diameter: d}, change_text(diameter, d, d_now,
                                           f"{b.size} x {b.screw_length_mm(grip_mm):g}"))
               for d, b in larger[:1]])


def _bd_warehouse_table(name: str) -> list[dict]:
    """Rows of one of bd_warehouse's catalogue CSV files, read without importing it (the
    design layer stays free of the CAD kernel)."""
    spec = importlib.util.find_spec("bd_warehouse")
    if spec is None or not spec.submodule_search_locations:
        raise DesignError("rim screws need the bd_warehouse package (its ISO 4762 / ISO 4032 "
                          "tables); install it or use hardware.fastener = \"dowel\"")
    path = Path(spec.submodule_search_locations[0]) / "data" / name
    with path.open(encoding="utf-8", newline="") as fh:
        return [{k.strip(): (v or "").strip() for k, v in row.items()}
                for row in csv.DictReader(fh)]


@functools.cache
def bolt_set(diameter_mm: float) -> BoltSet:
    """ISO 4762 screw and ISO 4032 nut of thread diameter ``diameter_mm`` (mm).

    Raises:
        DesignError: not a catalogue size of both.
    """
    def row(table, key):
        for r in table:
            if r["Size"].startswith(f"M{diameter_mm:g}-") and r.get(key):
                return r
        return None

    screws = _bd_warehouse_table("socket_head_cap_parameters.csv")
    nuts = _bd_warehouse_table("hex_nut_parameters.csv")
    s, n = row(screws, f"{SCREW_STANDARD}:dk"), row(nuts, f"{NUT_STANDARD}:s")
    if s is None or n is None:
        raise DesignError(f"rim screws: hardware.fastener_diameter_mm = {diameter_mm:g} is not "
                          f"an ISO 4762 screw with an ISO 4032 nut; pick a metric size (M1.6, "
                          "M2, M2.5, M3, ...) or use fastener = \"dowel\"")
    lengths = next(r for r in _bd_warehouse_table("nominal_screw_lengths.csv")
                   if r["Screw_Type"] == SCREW_STANDARD)["Nominal_Sizes"]
    lo, hi = float(s[f"{SCREW_STANDARD}:short"]), float(s[f"{SCREW_STANDARD}:long"])
    return BoltSet(size=s["Size"], head_diameter_mm=float(s[f"{SCREW_STANDARD}:dk"]),
                   head_height_mm=float(s[f"{SCREW_STANDARD}:k"]),
                   nut_across_corners_mm=float(n[f"{NUT_STANDARD}:s"]) / math.cos(math.pi / 6),
                   nut_height_mm=float(n[f"{NUT_STANDARD}:m"]),
                   lengths_mm=tuple(v for v in (float(x) for x in lengths.split(","))
                                    if lo <= v <= hi))
