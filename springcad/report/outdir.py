"""Atomic outputs: check the target before any work, write into a hidden sibling, move into place.

The rules every command follows:

* :func:`check_output_dir` / :func:`check_output_file` run before any work and
  refuse (exit 2) an output that is a file where a folder is meant (or the
  reverse), lies under a file, cannot be written, is a symbolic link, contains
  an input file or the current folder, or exists and is not empty without
  ``overwrite``.
* Everything is written into a fresh hidden folder beside the target
  (``.<name>.springcad-tmp-XXXXXXXX``, created with ``mkdtemp``, so no existing
  folder is ever reused). A failed or interrupted run removes it, and any parent
  folders the run created, and leaves an existing output untouched.
* With ``overwrite`` the old output is moved into another fresh hidden folder
  (``.<name>.springcad-old-XXXXXXXX``) only once the new output is complete, the
  new one is moved into place, and only then is the old one deleted; if the move
  fails the old output is put back. Nothing outside the target is deleted.
  SIGINT and SIGTERM are held off during these few renames.
* Permissions follow the umask, as for any file the user creates.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import tempfile
from pathlib import Path

from springcad.errors import OutputExistsError, OutputPathError

TMP_TAG = "springcad-tmp-"
OLD_TAG = "springcad-old-"


def umask() -> int:
    """The process umask (read without changing it for longer than a call)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def signals_held():
    """Hold off SIGINT and SIGTERM for a few file-system operations (delivered after)."""
    sigs = {signal.SIGINT, signal.SIGTERM}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    except (AttributeError, ValueError, OSError):  # not on this platform / thread
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _abs(path: Path) -> Path:
    return Path(os.path.abspath(path))


def _check_common(out: Path, what: str, inputs) -> Path:
    """Checks shared by folders and files; returns the nearest existing ancestor folder."""
    if str(out) in ("", "."):
        raise OutputPathError(f"output {what} '{out}' is the current folder; give a new "
                              f"{what} name with --out")
    target = _abs(out)
    cwd = _abs(Path.cwd())
    if target == cwd or target in cwd.parents:
        raise OutputPathError(f"output {what} '{out}' is or contains the current folder; give a "
                              f"new {what} with --out")
    for inp in inputs:
        if inp is None:
            continue
        inp = _abs(Path(inp))
        if target == inp or target in inp.parents:
            raise OutputPathError(f"output {what} '{out}' is or contains the input '{inp}'; "
                                  f"write the output elsewhere")
    base = None
    for parent in reversed(target.parents):
        if not (parent.exists() or parent.is_symlink()):
            break
        if not parent.is_dir():
            raise OutputPathError(f"output {what} '{out}' lies under '{parent}', which is a "
                                  "file, not a folder")
        base = parent
    return base


def _probe(base: Path, out: Path, what: str) -> None:
    """Can we create (and rename) entries in ``base``? Root passes chmod, so really try."""
    try:
        with signals_held():
            probe = tempfile.mkdtemp(prefix=f".{TMP_TAG}probe-", dir=base)
            os.rmdir(probe)
    except OSError as err:
        raise OutputPathError(f"cannot write the output {what} '{out}': '{base}' is not "
                              f"writable ({err.strerror or err})") from None


def check_output_dir(out_dir: Path | str, overwrite: bool = False, inputs=()) -> Path:
    """Refuse an output folder that cannot (or may not) be written; before any work.

    Args:
        out_dir: the output folder.
        overwrite: an existing non-empty folder may be replaced.
        inputs: input files of the run; the output must not contain them.

    Raises:
        OutputExistsError: it exists, is not empty and ``overwrite`` is false.
        OutputPathError: it is a file, lies under a file, is a symbolic link, contains an
            input or the current folder, or its parent is not writable.
    """
    out = Path(out_dir)
    base = _check_common(out, "folder", inputs)
    if out.is_symlink():
        raise OutputPathError(f"output folder '{out}' is a symbolic link; give the folder itself")
    if out.exists():
        if not out.is_dir():
            raise OutputPathError(f"output folder '{out}' is a file; --out names a folder")
        if any(out.iterdir()) and not overwrite:
            raise OutputExistsError(f"output folder '{out}' already exists and is not empty; "
                                    "choose another --out or pass --overwrite")
    _probe(base, out, "folder")
    return out


def check_output_file(out_file: Path | str, overwrite: bool = False, inputs=()) -> Path:
    """Refuse an output file that cannot (or may not) be written; before any work.

    Raises:
        OutputExistsError: it exists and ``overwrite`` is false.
        OutputPathError: it is a folder, lies under a file, is an input, or its folder is
            not writable.
    """
    out = Path(out_file)
    base = _check_common(out, "file", inputs)
    if out.is_dir():
        raise OutputPathError(f"output file '{out}' is a folder; give a file name "
                              "(e.g. record.csv) with --out")
    if out.exists() or out.is_symlink():
        if not overwrite:
            raise OutputExistsError(f"'{out}' already exists; choose another --out or pass "
                                    "--overwrite")
    _probe(base, out, "file")
    return out


def _make_parents(folder: Path) -> list[Path]:
    """mkdir -p, returning the folders created (deepest last)."""
    missing = []
    p = _abs(folder)
    while not p.exists():
        missing.append(p)
        p = p.parent
    for p in reversed(missing):
        p.mkdir()
    return list(reversed(missing))


def _remove_created(created: list[Path]) -> None:
    for p in reversed(created):
        with contextlib.suppress(OSError):
            p.rmdir()  # only if still empty


@contextlib.contextmanager
def atomic_output_dir(out_dir: Path | str, overwrite: bool = False, inputs=()):
    """Yield a temporary folder that becomes ``out_dir`` when the block succeeds.

    Args:
        out_dir: final output folder.
        overwrite: replace an existing ``out_dir`` (otherwise it is an error).
        inputs: input files, which ``out_dir`` must not contain.

    Raises:
        OutputExistsError, OutputPathError: see :func:`check_output_dir`.
    """
    out = check_output_dir(out_dir, overwrite, inputs)
    with signals_held():
        created = _make_parents(out.parent)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.{TMP_TAG}", dir=out.parent))
    try:
        yield tmp
        _commit_dir(tmp, out, overwrite)
    except BaseException:
        with signals_held():
            shutil.rmtree(tmp, ignore_errors=True)
            _remove_created(created)
        raise


def _commit_dir(tmp: Path, out: Path, overwrite: bool) -> None:
    with signals_held():
        os.chmod(tmp, 0o777 & ~umask())
        if out.exists() and any(out.iterdir()):
            if not overwrite:
                raise OutputExistsError(f"output folder '{out}' appeared while running; "
                                        "nothing was replaced")
            holder = Path(tempfile.mkdtemp(prefix=f".{out.name}.{OLD_TAG}", dir=out.parent))
            old = holder / out.name
            os.rename(out, old)
            try:
                os.rename(tmp, out)
            except BaseException:
                os.rename(old, out)
                os.rmdir(holder)
                raise
            shutil.rmtree(holder, ignore_errors=True)
        else:
            os.replace(tmp, out)  # out absent or an empty folder


@contextlib.contextmanager
def atomic_output_file(out_file: Path | str, overwrite: bool = False, inputs=()):
    """Yield a temporary file path that replaces ``out_file`` when the block succeeds.

    Raises:
        OutputExistsError, OutputPathError: see :func:`check_output_file`.
    """
    out = check_output_file(out_file, overwrite, inputs)
    with signals_held():
        created = _make_parents(out.parent)
        fd, name = tempfile.mkstemp(prefix=f".{out.name}.{TMP_TAG}", dir=out.parent)
        os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        with signals_held():
            os.chmod(tmp, 0o666 & ~umask())
            os.replace(tmp, out)
    except BaseException:
        with signals_held():
            with contextlib.suppress(OSError):
                tmp.unlink()
            _remove_created(created)
        raise
