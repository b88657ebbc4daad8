"""Atomic output folders: write into a temporary sibling, move into place when complete.

A failed run leaves nothing behind; an existing output folder is never
overwritten unless the caller passes ``overwrite=True``.
"""

from __future__ import annotations

import contextlib
import shutil
import tempfile
from pathlib import Path

from springcad.errors import OutputExistsError


@contextlib.contextmanager
def atomic_output_dir(out_dir: Path | str, overwrite: bool = False):
    """Yield a temporary folder that becomes ``out_dir`` when the block succeeds.

    Args:
        out_dir: final output folder.
        overwrite: replace an existing ``out_dir`` (otherwise it is an error).

    Raises:
        OutputExistsError: ``out_dir`` exists and is not empty and ``overwrite`` is false.
    """
    out_dir = Path(out_dir)
    if out_dir.exists() and any(out_dir.iterdir()) and not overwrite:
        raise OutputExistsError(
            f"output folder '{out_dir}' already exists and is not empty; "
            "choose another --out or pass --overwrite")
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.tmp-", dir=out_dir.parent))
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if out_dir.exists():
        backup = out_dir.with_name(f".{out_dir.name}.old")
        shutil.rmtree(backup, ignore_errors=True)
        out_dir.rename(backup)
        tmp.rename(out_dir)
        shutil.rmtree(backup, ignore_errors=True)
    else:
        tmp.rename(out_dir)
