"""Data shipped with springcad: the material table, the drawing title block and the
paper's measured tables and job templates (copies of ``templates/`` and
``../shared/data``, kept identical by tests).

Found through :mod:`importlib.resources` only, so an installed wheel finds them
wherever it runs.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def data_path(*parts: str) -> Path:
    """Filesystem path of a file or folder shipped in ``springcad/data``."""
    return Path(str(resources.files(__name__).joinpath(*parts)))
