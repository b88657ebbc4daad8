"""Fixtures for the geometry tests (defined in cad_fixtures.py, shared with tests/export)."""

from cad_fixtures import (  # noqa: F401
    cam_s1, ring_s1, s1_design, s1_stack, stack_4xs1,
)
