"""Unit conversions at the boundary (config, reports).

Inside springcad: mm, N, MPa, N*mm, rad, kg.
"""

import math

NMM_PER_NM = 1000.0
"""N*mm in one N*m."""
MM3_PER_CM3 = 1000.0
KG_PER_MM3_PER_KG_PER_M3 = 1e-9
"""Multiply a density in kg/m^3 by this to get kg/mm^3."""
MPA_PER_GPA = 1000.0
J_PER_NMM = 1e-3
G_PER_KG = 1000.0
M_PER_MM = 1e-3
"""A length unit of 1 mm in metres (CAD files declare their unit in metres)."""
UM_PER_MM = 1000.0
"""Micrometres in one mm (tolerances, gaps and deviations are written in um)."""
BYTES_PER_KB = 1000
"""Bytes in one kB (file size limits in messages)."""
BYTES_PER_MB = 1_000_000
"""Bytes in one MB."""
RAD_PER_DEG = math.pi / 180.0
DEG_PER_RAD = 180.0 / math.pi


def deg_to_rad(deg):
    """Degrees to rad, a float or a numpy array (the same bits as ``math.radians``)."""
    return deg * RAD_PER_DEG


def rad_to_deg(rad):
    """Rad to degrees, a float or a numpy array (the same bits as ``math.degrees``)."""
    return rad * DEG_PER_RAD


def nmm_to_nm(torque_Nmm: float) -> float:
    return torque_Nmm / NMM_PER_NM


def fmt_mm(value: float) -> str:
    """A length as written on drawings and in notes: up to 3 decimals, no trailing zeros."""
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def fmt_interval(low: float, high: float, digits: int = 4) -> tuple[str, str]:
    """The two ends of an interval with enough significant digits that they differ.

    ``digits`` is the least number of significant digits; more are used (up to 10) when a
    narrow interval would otherwise print as ``[150, 150]``.
    """
    for d in range(digits, 11):
        lo, hi = f"{low:.{d}g}", f"{high:.{d}g}"
        if lo != hi or low == high:
            return lo, hi
    return lo, hi
