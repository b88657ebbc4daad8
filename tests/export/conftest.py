"""Fixtures for the export tests: the geometry tests' built stacks (one cache per session)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "geometry"))

from cad_fixtures import (  # noqa: E402, F401
    cam_s1, ring_s1, s1_design, s1_stack, stack_4xs1,
)
