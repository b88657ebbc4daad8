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
* The hidden names carry the writing process's id (``.<name>.springcad-tmp-<pid>-XXXXXXXX``).
  A run killed with SIGKILL cannot clean up; the next run into the same place removes
  the hidden entries of processes that are no longer running and names those it
  cannot judge (a holder of an old output that is not in place any more, a name
  without a pid from an older springcad) on stderr.
* A full disk is a clean error (exit 2) naming the free space needed: large writers
  (the .vtu fields, whose VTK writer crashes on a full disk) check the free space
  first (:func:`require_free_space`), and any ENOSPC while writing becomes a
  :class:`~springcad.errors.NoSpaceError` after the partial output is removed.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
import signal
import sys
import tempfile
from pathlib import Path

from springcad.errors import NoSpaceError, OutputExistsError, OutputPathError
from springcad.options import spell

TMP_TAG = "springcad-tmp-"
OLD_TAG = "springcad-old-"
#: free space kept beyond a writer's estimate (bytes)
SPACE_RESERVE_BYTES = 8 * 2 ** 20


def _mb(n_bytes: float) -> str:
    return f"{n_bytes / 2 ** 20:.1f} MB"


def _free_bytes(folder: Path) -> int | None:
    try:
        return shutil.disk_usage(folder).free
    except OSError:
        return None


def require_free_space(folder: Path | str, needed_bytes: int, what: str) -> None:
    """Refuse to start a write of about ``needed_bytes`` that the disk cannot hold.

    Raises:
        NoSpaceError: fewer than ``needed_bytes`` + :data:`SPACE_RESERVE_BYTES` are free;
            the message names both.
    """
    folder = Path(folder)
    free = _free_bytes(folder)
    need = int(needed_bytes) + SPACE_RESERVE_BYTES
    if free is not None and free < need:
        raise NoSpaceError(f"not enough free space to write {what}: it needs about "
                           f"{_mb(need)} (with a {_mb(SPACE_RESERVE_BYTES)} reserve) and the "
                           f"disk holding '{folder}' has {_mb(free)} free; free at least "
                           f"{_mb(need - free)} or write the output elsewhere with {spell('out')}")


def _no_space(err: BaseException) -> OSError | None:
    """The ENOSPC (or EDQUOT) OSError behind ``err``, if any (causes and contexts)."""
    seen = set()
    while err is not None and id(err) not in seen:
        seen.add(id(err))
        if isinstance(err, OSError) and err.errno in (errno.ENOSPC, errno.EDQUOT):
            return err
        err = err.__cause__ or err.__context__
    return None


def _tmp_prefix(name: str, tag: str) -> str:
    """Hidden sibling prefix carrying this process's id (see the module docstring)."""
    return f".{name}.{tag}{os.getpid()}-"


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # exists (another user's) or cannot tell: leave it
    return True


def clean_stale(out: Path) -> tuple[list[Path], list[str]]:
    """Remove the hidden temporary entries of dead runs beside ``out``.

    Returns:
        (removed paths, messages about entries left in place); each is also printed on
        stderr, so a user sees what happened to the disk space.
    """
    out = _abs(out)
    parent = out.parent
    pattern = re.compile(rf"^\.{re.escape(out.name)}\.springcad-(tmp|old)-(?:(\d+)-)?")
    removed, kept = [], []
    try:
        entries = list(parent.iterdir())
    except OSError:
        return removed, kept
    for entry in entries:
        m = pattern.match(entry.name)
        if not m:
            continue
        kind, pid = m.group(1), m.group(2)
        if pid is None:
            kept.append(f"'{entry}' is a temporary {'folder' if entry.is_dir() else 'file'} of "
                        "an earlier springcad run (no process id recorded); delete it if no "
                        "springcad run is writing there")
            continue
        if _alive(int(pid)):
            continue
        if kind == "old" and not (out.exists() or out.is_symlink()):
            kept.append(f"'{entry}' holds the previous output of a run (pid {pid}) killed "
                        f"while replacing '{out}'; move it back or delete it")
            continue
        with contextlib.suppress(OSError):
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry)
            else:
                entry.unlink()
            removed.append(entry)
    for p in removed:
        print(f"springcad: removed '{p}', the temporary output of a run that is no longer "
              "running (killed?)", file=sys.stderr)
    for k in kept:
        print(f"springcad: note: {k}", file=sys.stderr)
    return removed, kept


def _raise_if_no_space(err: BaseException, out: Path, written_bytes: int) -> None:
    """A write that filled the disk: one clean message (the partial output is removed)."""
    full = _no_space(err)
    if full is None:
        return
    base = next((p for p in _abs(out).parents if p.exists()), Path("/"))
    free = _free_bytes(base)
    now = f"{_mb(free)} is free" if free is not None else "the free space is unknown"
    raise NoSpaceError(
        f"the disk holding '{base}' is full: the output stopped after {_mb(written_bytes)} "
        f"({full.strerror or full}) and was removed, {now}; free more than "
        f"{_mb(written_bytes + SPACE_RESERVE_BYTES)} (the whole output is larger than what "
        f"was written) or write it elsewhere with {spell('out')}") from err


def _size(path: Path) -> int:
    if path.is_file():
        return path.stat().st_size
    total = 0
    for p in path.rglob("*"):
        with contextlib.suppress(OSError):
            if p.is_file():
                total += p.stat().st_size
    return total


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
                              f"{what} name with {spell('out')}")
    target = _abs(out)
    cwd = _abs(Path.cwd())
    if target == cwd or target in cwd.parents:
        raise OutputPathError(f"output {what} '{out}' is or contains the current folder; give a "
                              f"new {what} with {spell('out')}")
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
            raise OutputPathError(f"output folder '{out}' is a file; {spell('out')} names a folder")
        if any(out.iterdir()) and not overwrite:
            raise OutputExistsError(f"output folder '{out}' already exists and is not empty; "
                                    f"choose another {spell('out')} or pass "
                                    f"{spell('overwrite', True)}")
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
                              f"(e.g. record.csv) with {spell('out')}")
    if out.exists() or out.is_symlink():
        if not overwrite:
            raise OutputExistsError(f"'{out}' already exists; choose another {spell('out')} or "
                                    f"pass {spell('overwrite', True)}")
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
    clean_stale(out)
    with signals_held():
        created = _make_parents(out.parent)
        tmp = Path(tempfile.mkdtemp(prefix=_tmp_prefix(out.name, TMP_TAG), dir=out.parent))
    try:
        yield tmp
        _commit_dir(tmp, out, overwrite)
    except BaseException as err:
        written = _size(tmp) if _no_space(err) is not None else 0
        with signals_held():
            shutil.rmtree(tmp, ignore_errors=True)
            _remove_created(created)
        _raise_if_no_space(err, out, written)
        raise


def _commit_dir(tmp: Path, out: Path, overwrite: bool) -> None:
    with signals_held():
        os.chmod(tmp, 0o777 & ~umask())
        if out.exists() and any(out.iterdir()):
            if not overwrite:
                raise OutputExistsError(f"output folder '{out}' appeared while running; "
                                        "nothing was replaced")
            holder = Path(tempfile.mkdtemp(prefix=_tmp_prefix(out.name, OLD_TAG),
                                           dir=out.parent))
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
    clean_stale(out)
    with signals_held():
        created = _make_parents(out.parent)
        fd, name = tempfile.mkstemp(prefix=_tmp_prefix(out.name, TMP_TAG), dir=out.parent)
        os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        with signals_held():
            os.chmod(tmp, 0o666 & ~umask())
            os.replace(tmp, out)
    except BaseException as err:
        written = _size(tmp) if _no_space(err) is not None and tmp.exists() else 0
        with signals_held():
            with contextlib.suppress(OSError):
                tmp.unlink()
            _remove_created(created)
        _raise_if_no_space(err, out, written)
        raise
