"""Helpers shared by the CLI subcommands."""

from __future__ import annotations

from pathlib import Path


def default_out(config: Path) -> Path:
    """``outputs/<config stem>/`` under the current folder."""
    return Path("outputs") / Path(config).stem
