"""Bench records: read, validate and describe measured torque–deflection data.

Units inside ``springcad.fit``: torque in N·m, angles in rad, time in s (the
bench CSV is in N·m, and the paper quotes stiffness in N·m/rad). This module is
the one place where bench units are converted (degrees → rad, N·mm → N·m).

The input file is only ever opened for reading.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from springcad import units
from springcad.errors import DataError
from springcad.options import ANGLE_UNITS, BENCH, TORQUE_UNITS, check_choice, spell
from springcad.textio import decode_utf8

#: Fewer samples than this cannot be segmented into cycles and cross-validated.
MIN_SAMPLES = 200

#: Encoder column names picked up without being named on the command line.
AUTO_ENCODER_COLUMNS = {
    "rad": ("encoder_in_rad", "encoder_out_rad"),
    "deg": ("encoder_in_deg", "encoder_out_deg"),
}



@dataclass(frozen=True)
class ColumnMap:
    """Names of the CSV columns to read.

    Attributes:
        time: time column (s).
        torque: measured torque column (``torque_unit``).
        deflection: optically measured spring deflection column (``angle_unit``).
        encoder: one or two encoder angle columns (``angle_unit``). With two,
            the encoder deflection is ``first - second`` (input minus output
            motor); with one, that column is the encoder deflection. ``None``
            picks up ``encoder_in_rad``/``encoder_out_rad`` (or ``_deg``) when
            present.
    """

    time: str = BENCH.time_col
    torque: str = BENCH.torque_col
    deflection: str = BENCH.deflection_col
    encoder: tuple[str, ...] | None = None


@dataclass(frozen=True)
class BenchRecord:
    """One validated bench record in internal units.

    Attributes:
        time_s: sample times, strictly increasing (s).
        torque_Nm: measured torque (N·m).
        deflection_rad: measured spring deflection (rad).
        encoder_deflection_rad: motor-encoder deflection (rad) or ``None``.
        source: where the record came from (file path or ``"simulated"``).
        warnings: plausibility warnings (suspicious magnitudes); never fatal.
    """

    time_s: np.ndarray
    torque_Nm: np.ndarray
    deflection_rad: np.ndarray
    encoder_deflection_rad: np.ndarray | None = None
    source: str = ""
    warnings: tuple[str, ...] = field(default=())

    @property
    def n_samples(self) -> int:
        return int(self.time_s.size)

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0])

    @property
    def sample_rate_hz(self) -> float:
        """Median sample rate (Hz)."""
        return float(1.0 / np.median(np.diff(self.time_s)))

    def to_csv(self) -> str:
        """The record as bench CSV text (see :func:`to_csv_text`)."""
        return to_csv_text(self)


#: a bench record is a few MB (20 000 samples at 500 Hz); refuse absurd files before reading
MAX_CSV_BYTES = 200_000_000
#: physical bounds of a torsion-spring bench record (N*m, rad): outside them the units or the
#: file are wrong, and the fit's numerics would be meaningless
TORQUE_RANGE_NM = (1e-6, 1e6)
DEFLECTION_RANGE_RAD = (1e-6, 1e4)
#: correlation of torque with deflection below minus this reads as a flipped channel
FLIPPED_CORRELATION = 0.3


def read_bench_csv(path: Path | str, columns: ColumnMap = ColumnMap(),
                   angle_unit: str = BENCH.angle_unit, torque_unit: str = BENCH.torque_unit,
                   trust_units: bool = False) -> BenchRecord:
    """Read and validate a bench CSV: the one reader of every door.

    The file may be at most :data:`MAX_CSV_BYTES`, UTF-8 (a leading byte-order mark is
    dropped). Lines starting with ``#`` and blank lines are skipped; the first other line
    is the header. Columns not named in ``columns`` are ignored. The record must look
    like a torsion-spring bench record (:func:`check_record`).

    Args:
        path: CSV file (read only).
        columns: which columns hold time, torque, deflection and encoders.
        angle_unit: ``"rad"`` or ``"deg"`` for every angle column.
        torque_unit: ``"Nm"`` or ``"Nmm"`` for the torque column.
        trust_units: keep units the data contradicts (a warning instead of
            the refusal; see :func:`make_record`).

    Returns:
        The record in s, N·m and rad.

    Raises:
        DataError: missing, unreadable, too large or not UTF-8 file; missing columns,
            non-numeric or non-finite values, time not strictly increasing, too few
            samples, constant channels, units the data contradicts, magnitudes out of
            range or a flipped sign.
        ConfigError: an angle or torque unit that is not one of the allowed.
    """
    path = Path(path)
    try:
        if not path.is_file():
            raise DataError(f"bench data file '{path}' does not exist or is not a file")
        if path.stat().st_size > MAX_CSV_BYTES:
            raise DataError(f"bench data file '{path}' is larger than "
                            f"{MAX_CSV_BYTES // units.BYTES_PER_MB} MB; split the record")
        raw = path.read_bytes()
    except OSError as err:
        raise DataError(f"bench data file '{path}' cannot be read: {err.strerror or err}") from None
    text, problem = decode_utf8(raw)
    if text is None:
        raise DataError(f"bench data file '{path}' {problem}")
    record = parse_bench_csv(text, columns, angle_unit, torque_unit, source=str(path),
                             trust_units=trust_units)
    check_record(record)
    return record


def check_record(record: BenchRecord) -> None:
    """Refuse records no torsion spring produces: magnitudes out of range, torque falling
    as the deflection rises (a flipped sign).

    Raises:
        DataError: naming the channel, the value and what to check.
    """
    src = record.source
    for name, values, (lo, hi), unit in (
            ("torque", record.torque_Nm, TORQUE_RANGE_NM, "N*m"),
            ("deflection", record.deflection_rad, DEFLECTION_RANGE_RAD, "rad")):
        peak = float(np.max(np.abs(values)))
        if not lo <= peak <= hi:
            raise DataError(f"{src}: the {name} peaks at {peak:.3g} {unit}; a torsion-spring bench "
                            f"record lies between {lo:g} and {hi:g} {unit}: check the column's "
                            f"unit ({spell('torque_unit')}, {spell('angle_unit')}) and scale")
    x = record.deflection_rad - record.deflection_rad.mean()
    y = record.torque_Nm - record.torque_Nm.mean()
    slope = float(x @ y) / float(x @ x)
    # a record with no spring (torque noise only) has a slope of either sign: it is refused
    # only when the torque clearly follows the deflection downwards, and otherwise the fit
    # reports whether any stiffness stands above the noise
    correlation = float(x @ y) / math.sqrt(float(x @ x) * float(y @ y))
    if correlation < -FLIPPED_CORRELATION:
        raise DataError(f"{src}: the torque falls as the deflection rises (least-squares slope "
                        f"{slope:.3g} N*m/rad): the sign of the torque or the deflection column "
                        "is flipped; negate one of them")


def parse_bench_csv(text: str, columns: ColumnMap = ColumnMap(), angle_unit: str = "rad",
                    torque_unit: str = "Nm", source: str = "<text>",
                    trust_units: bool = False) -> BenchRecord:
    """Parse and validate bench CSV text (see :func:`read_bench_csv`; no range checks)."""
    check_choice("angle_unit", angle_unit, ANGLE_UNITS)
    check_choice("torque_unit", torque_unit, TORQUE_UNITS)
    header, line_numbers, rows = _split_rows(text, source)
    encoder = columns.encoder
    if encoder is None:
        auto = AUTO_ENCODER_COLUMNS[angle_unit]
        encoder = tuple(c for c in auto if c in header)
    if len(encoder) > 2:
        raise DataError(f"at most two encoder columns (input, output) can be given, got {list(encoder)}")
    wanted = {"time": columns.time, "torque": columns.torque, "deflection": columns.deflection}
    missing = [f"'{name}' ({role}; choose another with {spell(role + '_col')})"
               for role, name in wanted.items() if name not in header]
    missing += [f"'{name}' (encoder; see {spell('encoder_cols')})" for name in encoder
                if name not in header]
    if missing:
        raise DataError(f"{source}: missing column(s) {', '.join(missing)}; "
                        f"the header has: {', '.join(header)}")
    contradictions = _named_unit_contradictions(
        [columns.deflection, *encoder], columns.torque, angle_unit, torque_unit)
    if contradictions:
        raise DataError(f"{source}: " + "; ".join(contradictions))
    data = {name: _numeric_column(name, header.index(name), rows, line_numbers, source)
            for name in (*wanted.values(), *encoder)}
    angle_scale = units.deg_to_rad(1.0) if angle_unit == "deg" else 1.0
    time_s = data[columns.time]
    torque_Nm = units.nmm_to_nm(data[columns.torque]) if torque_unit == "Nmm" else data[columns.torque]
    deflection_rad = data[columns.deflection] * angle_scale
    encoder_rad = None
    if encoder:
        encoder_rad = data[encoder[0]] * angle_scale
        if len(encoder) == 2:
            encoder_rad = encoder_rad - data[encoder[1]] * angle_scale
    names = {"time": columns.time, "torque": columns.torque, "deflection": columns.deflection}
    return make_record(time_s, torque_Nm, deflection_rad, encoder_rad, source=source,
                       line_numbers=line_numbers, names=names, angle_unit=angle_unit,
                       torque_unit=torque_unit, trust_units=trust_units)


def make_record(time_s, torque_Nm, deflection_rad, encoder_deflection_rad=None, *,
                source: str = "", line_numbers: np.ndarray | None = None,
                names: dict | None = None, angle_unit: str = "rad",
                torque_unit: str = "Nm", trust_units: bool = False) -> BenchRecord:
    """Validate arrays in internal units and wrap them in a :class:`BenchRecord`.

    Args:
        time_s: sample times (s).
        torque_Nm: torque (N·m).
        deflection_rad: spring deflection (rad).
        encoder_deflection_rad: optional encoder deflection (rad).
        source: description for messages.
        line_numbers: file line of each sample, for messages (default: index + 2).
        names: column names for messages (keys ``time``, ``torque``, ``deflection``).
        angle_unit: unit the angles were given in, for unit warnings.
        torque_unit: unit the torque was given in, for unit warnings.
        trust_units: the user vouches for the units (``trust_units``): a unit
            the magnitudes contradict is a warning, not a refusal.

    Raises:
        DataError: see :func:`read_bench_csv` and ``_unit_warnings``.
    """
    names = names or {"time": "time_s", "torque": "torque_Nm", "deflection": "deflection_rad"}
    arrays = {"time": np.asarray(time_s, float), "torque": np.asarray(torque_Nm, float),
              "deflection": np.asarray(deflection_rad, float)}
    sizes = {k: v.shape for k, v in arrays.items()}
    if len({s for s in sizes.values()}) != 1 or arrays["time"].ndim != 1:
        raise DataError(f"channels must be 1-D and of equal length, got shapes {sizes}")
    n = arrays["time"].size
    if line_numbers is None:
        line_numbers = np.arange(n) + 2
    for role, values in arrays.items():
        bad = ~np.isfinite(values)
        if bad.any():
            first = int(np.argmax(bad))
            raise DataError(f"{source}: column '{names[role]}' has {int(bad.sum())} non-finite "
                            f"value(s) (NaN or inf), first at line {line_numbers[first]}")
    if n < MIN_SAMPLES:
        raise DataError(f"{source}: too few samples: {n}; need at least {MIN_SAMPLES} "
                        "(several loading-unloading cycles)")
    dt = np.diff(arrays["time"])
    if (dt <= 0).any():
        i = int(np.argmax(dt <= 0))
        raise DataError(
            f"{source}: time column '{names['time']}' must increase strictly, but line "
            f"{line_numbers[i + 1]} has t = {arrays['time'][i + 1]:g} after "
            f"t = {arrays['time'][i]:g} on line {line_numbers[i]}")
    for role in ("torque", "deflection"):
        if np.ptp(arrays[role]) == 0.0:
            raise DataError(f"{source}: {role} channel '{names[role]}' never changes "
                            f"(constant {arrays[role][0]:g}); is the sensor connected and logged?")
    encoder = None
    if encoder_deflection_rad is not None:
        encoder = np.asarray(encoder_deflection_rad, float)
        if encoder.shape != arrays["time"].shape:
            raise DataError(f"encoder channel has shape {encoder.shape}, expected ({n},)")
        bad = ~np.isfinite(encoder)
        if bad.any():
            raise DataError(f"{source}: encoder column(s) have {int(bad.sum())} non-finite value(s), "
                            f"first at line {line_numbers[int(np.argmax(bad))]}")
    warnings = _unit_warnings(arrays, names, angle_unit, source, torque_unit, trust_units)
    return BenchRecord(arrays["time"], arrays["torque"], arrays["deflection"], encoder,
                       source=source, warnings=tuple(warnings))


def to_csv_text(record: BenchRecord) -> str:
    """Format a record as bench CSV text (s, N·m, rad; encoder as one column).

    The inverse of :func:`parse_bench_csv` with the default column names.
    """
    cols = [record.time_s, record.torque_Nm, record.deflection_rad]
    header = ["time_s", "torque_Nm", "deflection_rad"]
    if record.encoder_deflection_rad is not None:
        cols.append(record.encoder_deflection_rad)
        header.append("encoder_in_rad")
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    np.savetxt(buf, np.column_stack(cols), delimiter=",", fmt="%.9g")
    return buf.getvalue()


#: field separators a bench CSV may use, in the order they are looked for in its header:
#: a comma, a semicolon (spreadsheets in locales with a decimal comma), a tab
SEPARATORS = (",", ";", "\t")


def separator(text: str) -> str:
    """The field separator of a bench CSV: the first of :data:`SEPARATORS` its header line
    (the first line neither blank nor a ``#`` comment) holds, else a comma (one column)."""
    for line in io.StringIO(text):  # lazily: the header is near the top of a large file
        if line.strip() and not line.lstrip().startswith("#"):
            return next((sep for sep in SEPARATORS if sep in line), ",")
    return ","


def _split_rows(text: str, source: str) -> tuple[list[str], np.ndarray, list[list[str]]]:
    """Header, line numbers and fields of a bench CSV's data rows. A semicolon-separated
    file may write its numbers with a decimal comma (``1,25``): they are read as ``1.25``."""
    header = None
    rows, line_numbers = [], []
    sep = separator(text)
    reader = csv.reader(io.StringIO(text), delimiter=sep)
    for fields in reader:
        if sep == ";" and header is not None:
            fields = [f.replace(",", ".") for f in fields]
        line = reader.line_num
        if not fields or all(not f.strip() for f in fields) or fields[0].lstrip().startswith("#"):
            continue
        if header is None:
            header = [f.strip() for f in fields]
            dup = sorted({h for h in header if header.count(h) > 1})
            if dup:
                raise DataError(f"{source}: duplicate column name(s) in header: {', '.join(dup)}")
            continue
        if len(fields) != len(header):
            raise DataError(f"{source}: line {line} has {len(fields)} field(s) but the header "
                            f"has {len(header)}")
        rows.append(fields)
        line_numbers.append(line)
    if header is None:
        raise DataError(f"{source}: no header line found (the file is empty or only comments)")
    if not rows:
        raise DataError(f"{source}: the file has a header but no data rows")
    return header, np.asarray(line_numbers), rows


def _numeric_column(name: str, col: int, rows: list[list[str]], line_numbers: np.ndarray,
                    source: str) -> np.ndarray:
    out = np.empty(len(rows))
    for i, fields in enumerate(rows):
        cell = fields[col].strip()
        try:
            out[i] = float(cell)
        except ValueError:
            shown = repr(cell) if cell else "an empty cell"
            raise DataError(f"{source}: column '{name}', line {line_numbers[i]}: {shown} is not "
                            "a number") from None
    return out


#: a flexure torsion spring of this kind deflects far less than a full turn
MAX_DEFLECTION_RAD = 2.0 * np.pi
#: angles read as degrees that never reach one degree are angles in rad (rad)
MIN_DEFLECTION_DEG_RAD = units.deg_to_rad(1.0)
#: torque range over deflection range of compact torsion springs (N·m/rad)
IMPLIED_STIFFNESS_RANGE_NM_PER_RAD = (0.05, 1e5)
#: read as N·mm, a spring softer than this (N·m/rad) is worth a question: the springs
#: springcad designs and benches are tens to hundreds of N·m/rad (templates: 37.5 to 150)
SOFT_IN_NMM_NM_PER_RAD = 1.0


def unit_contradiction(message: str, source: str, trust_units: bool) -> str:
    """A unit the data contradicts: raise it, or return it as a warning when the user
    vouches for the units (``trust_units``).

    Raises:
        DataError: unless ``trust_units``.
    """
    if trust_units:
        return f"{message} (kept: {spell('trust_units', True)})"
    raise DataError(f"{source}: {message}; if the units are right after all, pass "
                    f"{spell('trust_units', True)}")


def _named_unit_contradictions(angle_columns: list[str], torque_column: str, angle_unit: str,
                               torque_unit: str) -> list[str]:
    """Columns whose name states a unit other than the one they are read in."""
    out = []
    for name in angle_columns:
        stated = "deg" if name.endswith("_deg") else "rad" if name.endswith("_rad") else None
        if stated is not None and stated != angle_unit:
            out.append(f"column '{name}' is named in {stated} but {spell('angle_unit', angle_unit)}"
                       f" was given, which would scale every angle by "
                       f"{'pi/180' if angle_unit == 'deg' else '180/pi'}; pass "
                       f"{spell('angle_unit', stated)} (or rename the column if its name is wrong)")
    stated = ("Nmm" if torque_column.endswith("_Nmm") else
              "Nm" if torque_column.endswith("_Nm") else None)
    if stated is not None and stated != torque_unit:
        out.append(f"column '{torque_column}' is named in {stated} but "
                   f"{spell('torque_unit', torque_unit)} was given (a factor 1000); pass "
                   f"{spell('torque_unit', stated)} (or rename the column if its name is wrong)")
    return out


def _unit_warnings(arrays: dict, names: dict, angle_unit: str, source: str,
                   torque_unit: str = "Nm", trust_units: bool = False) -> list[str]:
    """Warnings where magnitudes suggest a wrong unit.

    Raises:
        DataError: the data contradicts the units it is read in: the
            deflection exceeds a full turn (no spring of this kind does), angles
            read as degrees never reach one degree (angles in rad), or a torque
            read as N·mm gives a spring softer than any bench measures while
            N·m gives an ordinary one. The last two are warnings with
            ``trust_units`` (a full turn never is).
    """
    out = []
    theta_max = float(np.max(np.abs(arrays["deflection"])))
    torque_max = float(np.max(np.abs(arrays["torque"])))
    rate_hz = 1.0 / float(np.median(np.diff(arrays["time"])))
    if theta_max > MAX_DEFLECTION_RAD:
        hint = (f"if the column is in degrees, pass {spell('angle_unit', 'deg')}"
                if angle_unit == "rad"
                else "check the angle unit")
        raise DataError(f"{source}: deflection reaches {theta_max:.4g} rad ({theta_max / (2 * np.pi):.3g} "
                        f"turns), more than a full turn, which no flexure torsion spring deflects: "
                        f"{hint}")
    if theta_max > 2.0:
        hint = (f"pass {spell('angle_unit', 'deg')} if the column is in degrees"
                if angle_unit == "rad"
                else "check the angle unit")
        out.append(f"deflection reaches {theta_max:.3g} rad ({units.rad_to_deg(theta_max):.0f} deg), "
                   f"more than any compact torsion spring deflects: {hint}")
    elif theta_max < 2e-3:
        out.append(f"deflection never exceeds {theta_max:.3g} rad: is the column in rad "
                   "(not revolutions or a scaled unit)?")
    elif theta_max < MIN_DEFLECTION_DEG_RAD and angle_unit == "deg":
        # the file's angles never reach one degree: what angles in rad look like, and 180/pi
        # times less than the ramps (several degrees) a torsion-spring bench runs
        out.append(unit_contradiction(
            f"read with {spell('angle_unit', 'deg')}, the deflection never exceeds "
            f"{units.rad_to_deg(theta_max):.3g} deg, less than the degree or more a bench ramp "
            "reaches; values this small are angles in rad (a factor 57.3 = 180/pi): drop "
            f"{spell('angle_unit', 'deg')}", source, trust_units))
    if torque_max > 2000.0:
        out.append(f"torque reaches {torque_max:.4g} N·m: if the column is in N·mm, "
                   f"pass {spell('torque_unit', 'Nmm')}")
    elif torque_max < 1e-2:
        out.append(f"torque never exceeds {torque_max:.3g} N·m: is the column in N·m?")
    if rate_hz < 5.0:
        out.append(f"sample rate is {rate_hz:.3g} Hz: is the time column '{names['time']}' in "
                   "seconds (not milliseconds or sample indices)?")
    elif rate_hz > 1e5:
        out.append(f"sample rate is {rate_hz:.3g} Hz: is the time column '{names['time']}' in "
                   "seconds (not hours or minutes)?")
    ptp_theta = float(np.ptp(arrays["deflection"]))
    implied = float(np.ptp(arrays["torque"])) / ptp_theta
    low, high = IMPLIED_STIFFNESS_RANGE_NM_PER_RAD
    if torque_unit == "Nmm" and implied < low <= units.NMM_PER_NM * implied <= high:
        # read as N*mm the spring is implausibly soft, read as N*m it is an ordinary one
        out.append(unit_contradiction(
            f"read with {spell('torque_unit', 'Nmm')}, torque range over deflection range is "
            f"{implied:.3g} N·m/rad, softer than any torsion spring bench measures, and "
            f"{units.NMM_PER_NM * implied:.3g} N·m/rad read as N·m (a factor 1000): the torque column is "
            f"in N·m; drop {spell('torque_unit', 'Nmm')}", source, trust_units))
    elif torque_unit == "Nmm" and low <= implied < SOFT_IN_NMM_NM_PER_RAD <= units.NMM_PER_NM * implied <= high:
        out.append(f"read with {spell('torque_unit', 'Nmm')}, torque range over deflection "
                   f"range is {implied:.3g} N·m/rad, a very soft spring, and "
                   f"{units.NMM_PER_NM * implied:.3g} N·m/rad read as N·m: is the column in N·m? If so, "
                   f"drop {spell('torque_unit', 'Nmm')} "
                   "(with a target stiffness, the fit checks this against it)")
    elif implied < low or implied > high:
        out.append(f"torque range over deflection range is {implied:.3g} N·m/rad, far from any "
                   "compact torsion spring: check the units of both columns")
    return out
