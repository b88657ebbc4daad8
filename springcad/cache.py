"""A content-addressed cache of what a build computes: designs, FEA results, checks, files.

A result is stored under the SHA-256 of everything it is a function of: the pickled inputs
(a job, a spring design and the verification options, a part and its drawing's title
block ...), the kind of result, and the code that computes it (:func:`code_digest`: the
springcad version, every source and data file of the ``springcad`` and ``fea`` packages,
and the versions of the libraries whose output is stored). Equal inputs give equal
pickles (the designs are built by deterministic code; measured across processes), so an
unchanged job hits; any change of an input or of the code is a new key, so a stale entry
is never read, it only ages out. Entries are pickles, read back bit for bit.

Where: ``$SPRINGCAD_CACHE_DIR``, else ``$XDG_CACHE_HOME/springcad``, else
``~/.cache/springcad``. Size: at most :attr:`~springcad.options.CacheDefaults.max_mb`
(``$SPRINGCAD_CACHE_MAX_MB``); past it the least recently used entries are removed
(a read refreshes an entry's time). On or off: the ``cache`` option of the API and
``--no-cache`` of the CLI; its default is :data:`springcad.options.CACHE` unless
``$SPRINGCAD_CACHE`` is ``0``/``off``/``no``/``false`` (the test suite's setting).
Writes are atomic (a temporary file renamed into place), so processes may share a cache.
A cache that cannot be written (read-only, full disk) is skipped, never an error.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import io
import os
import pickle
import tempfile
import weakref
from pathlib import Path

from springcad.options import CACHE
from springcad.version import __version__

ENV_DIR = "SPRINGCAD_CACHE_DIR"
ENV_SWITCH = "SPRINGCAD_CACHE"
ENV_MAX_MB = "SPRINGCAD_CACHE_MAX_MB"
#: values of ``$SPRINGCAD_CACHE`` that turn the default off
OFF = ("0", "off", "no", "false")
#: libraries whose output a cache entry holds (FEA numbers, CAD files, drawings, renders)
LIBRARIES = ("numpy", "scipy", "scikit-fem", "gmsh", "pypardiso", "build123d", "cadquery-ocp",
             "ezdxf", "matplotlib", "pyvista", "vtk")
#: eviction leaves the cache at this share of its bound
EVICT_TO = 0.8
_SUFFIX = ".pkl"
MISSING = object()


def cache_dir() -> Path:
    """The cache folder (not created here)."""
    env = os.environ.get(ENV_DIR, "").strip()
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", "").strip()
    return (Path(base) if base else Path.home() / ".cache") / "springcad"


def wanted(cache: bool | None) -> bool:
    """Whether to use the cache: ``cache`` when given, else the default (see module)."""
    if cache is not None:
        return bool(cache)
    return CACHE.enabled and os.environ.get(ENV_SWITCH, "").strip().lower() not in OFF


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 of the code a cached result depends on: the springcad version, every file of
    the ``springcad`` and ``fea`` packages but caches of bytecode, and the versions of
    :data:`LIBRARIES` (~10 ms)."""
    from importlib import metadata, util

    h = hashlib.sha256(f"springcad {__version__}\n".encode())
    for name in LIBRARIES:
        try:
            h.update(f"{name} {metadata.version(name)}\n".encode())
        except metadata.PackageNotFoundError:
            h.update(f"{name} -\n".encode())
    # the two packages' folders, found without importing them from below (fea sits
    # beside springcad on sys.path: find_spec locates it without running it)
    for root in (Path(__file__).parent, Path(util.find_spec("fea").origin).parent):
        for path in sorted(p for p in root.rglob("*") if p.is_file()
                           and "__pycache__" not in p.parts and p.suffix != ".pyc"):
            h.update(str(path.relative_to(root.parent)).encode() + b"\0")
            h.update(path.read_bytes())
    return h.hexdigest()


def canonical_bytes(obj) -> bytes:
    """``obj`` pickled without the memo (pickle's fast mode): every object is written out
    where it occurs, so equal values give equal bytes however their parts are shared (a
    design read back from the cache shares its strings differently from a computed one,
    and a plain pickle writes a shared object once and then refers to it).

    Raises:
        ValueError: ``obj`` refers to itself (no key; the caller computes).
    """
    buf = io.BytesIO()
    p = pickle.Pickler(buf, protocol=5)
    p.fast = True
    p.dump(obj)
    return buf.getvalue()


#: types whose values may change after they were hashed: never remembered by identity
_MUTABLE = (dict, list, set, bytearray)
#: id -> (weak reference to the object, digest) of the key inputs hashed in this process
_DIGESTS: dict[int, tuple[weakref.ref, bytes]] = {}
_DIGESTS_MAX = 256


def input_digest(x) -> bytes:
    """SHA-256 of one key input: of its bytes, of its elements' digests for a tuple or
    list (a part's fingerprint is a new tuple of the same objects each time), else of
    :func:`canonical_bytes`. The digest of an object that cannot change (not a dict,
    list, set) is remembered by identity for the life of the object, so one design
    keying the design, checks, assembly and FEA outputs is written out once (a job
    design is ~3.5 MB canonical, ~0.18 s).

    Raises:
        ValueError etc.: as :func:`canonical_bytes`.
    """
    if isinstance(x, bytes):
        return hashlib.sha256(b"bytes\0" + x).digest()
    if type(x) in (tuple, list):
        h = hashlib.sha256(f"{type(x).__name__} {len(x)}\0".encode())
        for item in x:
            h.update(input_digest(item))
        return h.digest()
    if isinstance(x, _MUTABLE) or x is None or isinstance(x, (str, int, float, bool)):
        return hashlib.sha256(b"pickle\0" + canonical_bytes(x)).digest()
    hit = _DIGESTS.get(id(x))
    if hit is not None and hit[0]() is x:  # the same object (a dead one's id may be reused)
        return hit[1]
    digest = hashlib.sha256(b"pickle\0" + canonical_bytes(x)).digest()
    if len(_DIGESTS) >= _DIGESTS_MAX:
        _DIGESTS.clear()
    with contextlib.suppress(TypeError):  # not weakly referable: not remembered
        _DIGESTS[id(x)] = (weakref.ref(x), digest)  # weak: keeps no design alive
    return digest


class Cache:
    """A cache folder: pickled results by key, least recently used removed past the bound.

    Args:
        folder: where (default :func:`cache_dir`).
        max_mb: size bound (MB; default ``$SPRINGCAD_CACHE_MAX_MB`` or
            :attr:`~springcad.options.CacheDefaults.max_mb`).
    """

    def __init__(self, folder: Path | str | None = None, max_mb: float | None = None):
        self.folder = Path(folder) if folder is not None else cache_dir()
        if max_mb is None:
            env = os.environ.get(ENV_MAX_MB, "").strip()
            max_mb = float(env) if env else CACHE.max_mb
        self.max_bytes = int(max_mb * 2 ** 20)
        self.hits: list[str] = []
        self.stored: list[str] = []

    def key(self, kind: str, *inputs) -> str | None:
        """The key of result ``kind`` of ``inputs`` (picklable objects or bytes) under this
        code (:func:`code_digest`); None when an input cannot be written canonically (then
        the result is computed and not stored)."""
        h = hashlib.sha256(f"{code_digest()}\n{kind}\n".encode())
        for x in inputs:
            try:
                h.update(input_digest(x))
            except (ValueError, RecursionError, pickle.PicklingError, TypeError, AttributeError):
                return None
        return f"{kind}-{h.hexdigest()}"

    def _path(self, key: str) -> Path:
        return self.folder / key[-2:] / (key + _SUFFIX)

    def has(self, key: str | None) -> bool:
        """Whether ``key`` has an entry (it may still turn out torn when loaded)."""
        return key is not None and self._path(key).is_file()

    def load(self, key: str | None):
        """The stored value of ``key``, or :data:`MISSING`. An unreadable entry is removed."""
        if key is None:
            return MISSING
        path = self._path(key)
        try:
            with open(path, "rb") as fh:
                value = pickle.load(fh)
        except FileNotFoundError:
            return MISSING
        except Exception:  # a torn or foreign file: drop it, compute again
            with _quiet():
                path.unlink()
            return MISSING
        with _quiet():
            os.utime(path)  # least recently used: a read refreshes the entry
        self.hits.append(key)
        return value

    def store(self, key: str, value) -> None:
        """Store ``value`` under ``key`` (atomic), then keep the folder within its bound.
        A value that cannot be pickled or written is not stored (the cache is optional)."""
        if key is None:
            return
        path = self._path(key)
        tmp = None
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=_SUFFIX)
            with os.fdopen(fd, "wb") as fh:
                pickle.dump(value, fh, protocol=5)
            os.replace(tmp, path)
            tmp = None
        except (OSError, pickle.PicklingError, TypeError, AttributeError):
            return
        finally:
            if tmp is not None:
                with _quiet():
                    os.unlink(tmp)
        self.stored.append(key)
        self.evict()

    def fetch(self, key: str | None, compute, on_hit=None):
        """The value stored under ``key`` (then ``on_hit()`` is called), else ``compute()``,
        stored."""
        value = self.load(key)
        if value is MISSING:
            value = compute()
            self.store(key, value)
        elif on_hit is not None:
            on_hit()
        return value

    def entries(self) -> list[tuple[float, int, Path]]:
        """(last use, bytes, path) of every entry."""
        out = []
        if not self.folder.is_dir():
            return out
        for sub in os.scandir(self.folder):
            if not sub.is_dir():
                continue
            for e in os.scandir(sub.path):
                if e.name.endswith(_SUFFIX) and not e.name.startswith(".tmp-"):
                    with _quiet():
                        st = e.stat()
                        out.append((st.st_mtime, st.st_size, Path(e.path)))
        return out

    def size_bytes(self) -> int:
        return sum(n for _, n, _ in self.entries())

    def evict(self) -> None:
        """Remove the least recently used entries while the folder exceeds its bound."""
        entries = self.entries()
        total = sum(n for _, n, _ in entries)
        if total <= self.max_bytes:
            return
        for _, n, path in sorted(entries, key=lambda e: e[0]):
            if total <= EVICT_TO * self.max_bytes:
                break
            with _quiet():
                path.unlink()
                total -= n

    # ------------------------------------------------------------------ files
    def store_files(self, key: str | None, root: Path, paths, meta=None) -> None:
        """Store the bytes of files (``paths`` under ``root``), and ``meta``, under ``key``."""
        root = Path(root)
        self.store(key, {"files": {str(Path(p).relative_to(root)): Path(p).read_bytes()
                                   for p in paths}, "meta": meta})

    def load_files(self, key: str | None, root: Path):
        """Write the files stored under ``key`` into ``root``: (their paths in the stored
        order, the stored ``meta``), or None."""
        entry = self.load(key)
        if entry is MISSING:
            return None
        out = []
        for rel, data in entry["files"].items():
            path = Path(root) / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
            out.append(path)
        return out, entry["meta"]

    def files(self, kind: str, inputs: tuple, root: Path, write, on_hit=None):
        """Files ``write()`` writes under ``root``, from the cache when the same ``kind`` and
        ``inputs`` wrote them before. ``write()`` returns (paths, meta); so does this."""
        key = self.key(kind, *inputs)
        hit = self.load_files(key, root)
        if hit is not None:
            if on_hit is not None:
                on_hit()
            return hit
        paths, meta = write()
        self.store_files(key, root, paths, meta)
        return paths, meta


class _quiet:
    """Ignore OSError (a cache that cannot be written or read is skipped)."""

    def __enter__(self):
        return self

    def __exit__(self, kind, value, tb):
        return kind is not None and issubclass(kind, OSError)


def open_cache(cache: bool | None = None) -> Cache | None:
    """The cache when it is wanted (:func:`wanted`), else None."""
    return Cache() if wanted(cache) else None


def files(cache: Cache | None, kind: str, inputs: tuple, root: Path, write, on_hit=None):
    """:meth:`Cache.files`, or ``write()`` when ``cache`` is None."""
    if cache is None:
        return write()
    return cache.files(kind, inputs, root, write, on_hit)


def memo(cache: Cache | None, kind: str, inputs: tuple, compute, on_hit=None):
    """``compute()`` through the cache: its stored value for the same ``kind`` and
    ``inputs`` (then ``on_hit()`` is called), else computed and stored; with ``cache``
    None, simply ``compute()``."""
    if cache is None:
        return compute()
    return cache.fetch(cache.key(kind, *inputs), compute, on_hit)
