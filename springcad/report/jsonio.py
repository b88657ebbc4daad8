"""JSON writer shared by every output: NaN/inf as null, numpy scalars as numbers."""

from __future__ import annotations

import json
import math
from pathlib import Path


def _clean(obj):
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "item") and callable(obj.item):  # numpy scalars
        return _clean(obj.item())
    return obj


def write_json(path: Path, data: dict) -> None:
    """Write JSON with NaN/inf as null and numpy scalars as numbers."""
    Path(path).write_text(json.dumps(_clean(data), indent=2) + "\n")
