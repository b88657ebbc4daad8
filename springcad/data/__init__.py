"""Data shipped with springcad: the material table, the drawing title block and the
paper's measured tables and job templates (copies of ``templates/`` and
``../shared/data``, kept identical by tests).

Found through :mod:`importlib.resources` only, so an installed wheel finds them
wherever it runs.
"""

from __future__ import annotations

import csv
import functools
from importlib import resources
from pathlib import Path

#: the ISO 8734 dowel catalogue (diameter, nominal length), mm
DOWEL_FILE = "iso8734_dowels.csv"


def data_path(*parts: str) -> Path:
    """Filesystem path of a file or folder shipped in ``springcad/data``."""
    return Path(str(resources.files(__name__).joinpath(*parts)))


@functools.cache
def dowel_lengths() -> dict[float, tuple[float, ...]]:
    """Nominal lengths (mm) of every ISO 8734 diameter (mm) in :data:`DOWEL_FILE` (read
    here, below the config, so its checks and the design's catalogue read one table)."""
    text = data_path(DOWEL_FILE).read_text()
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    out: dict[float, list[float]] = {}
    for r in rows:
        out.setdefault(float(r["diameter_mm"]), []).append(float(r["length_mm"]))
    return {d: tuple(sorted(ls)) for d, ls in out.items()}
