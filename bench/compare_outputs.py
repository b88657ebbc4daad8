"""Compare two output folders of springcad (a build, a verification or a design), file by file.

Usage: ``python bench/compare_outputs.py BEFORE AFTER [--rtol 1e-4] [--atol-mm 1e-3]
[--replace OLD=NEW ...]``

For a change meant to keep every output (issue 22: the same files with and without a speed-up,
or within the stated tolerances for floating output). Each file present in either folder is
reported as ``identical`` (same bytes), ``equal`` (the same content once the run's own clock is
left out), ``within`` (every number within the tolerance, the rest of the text the same) or
``DIFFERS``, with the largest absolute and relative change of its numbers and where it is:

* JSON: compared as documents, ``timings_s`` tables and ``timings_s``-like keys of the run left
  out; numbers inside strings (notes) compared as numbers;
* text (STEP, DXF, SVG, CSV, HTML): the numbers of each line within the tolerance, the text
  around them equal;
* binary STL: the triangle count equal, the vertices within ``atol_mm``;
* PNG: the share of pixels that differ and the largest channel change (a render of geometry
  moved by a micrometre may move a few pixels: reported, not judged);
* PDF: the text of each page (``pdftotext``, runs of blanks as one) as text; the bytes
  are reported too;
* ZIP: each member by the rules above; VTU (pyvista): nodes paired by position, then
  points and point data within the tolerance; a mesh whose nodes moved beyond ``atol_mm``
  (a geometry changed by a hair can mesh otherwise) is ``REMESHED`` and not compared;
* ``report.html`` holds the run's timings: compared, reported, not judged;
* part numbers (``RING-B2ED80A3``: a hash of the part's geometry) are compared as their
  family (``RING-#``), in file names too: a ring whose widths moved by 1e-6 is renamed.

A number passes when ``|a - b| <= atol + rtol * max(|a|, |b|)`` (``atol``: ``--atol-mm``,
for lengths in mm; 1e-9 elsewhere). Exit status 0 when nothing DIFFERS, 1 otherwise.
"""

from __future__ import annotations

import argparse
import io
import json
import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
#: a part number: family letters and a hash of the part's geometry (8 hex digits), which a
#: change of a micrometre's fraction renames; compared as its family (``RING-#``)
PART_NUMBER = re.compile(r"\b([A-Z][A-Z0-9]*(?:-[A-Z][A-Z0-9]*)*)-[0-9A-F]{8}\b")
#: keys of a JSON document that hold the run's own clock, not its results
RUN_KEYS = {"timings_s", "started", "start_time", "elapsed_s", "wall_s", "cpu_s"}
#: files that hold the run's own timings in their text: compared, not judged
RUN_FILES = {"report.html"}
TEXT_SUFFIXES = {".step", ".stp", ".dxf", ".svg", ".csv", ".html", ".txt", ".md", ".toml"}


class Diff:
    """The largest number change seen in one file (absolute, relative) and the first
    mismatch that is not a number."""

    def __init__(self, rtol: float, atol: float, replace: tuple = ()):
        self.rtol, self.atol, self.replace = rtol, atol, replace
        self.max_abs = self.max_rel = 0.0
        self.where = ""
        self.numbers = 0
        self.changed = 0
        self.failed = ""

    def number(self, a: float, b: float, where: str) -> None:
        self.numbers += 1
        d = abs(a - b)
        if d == 0.0:
            return
        self.changed += 1
        rel = d / max(abs(a), abs(b))
        if d > self.max_abs:
            self.max_abs, self.where = d, where
        self.max_rel = max(self.max_rel, rel)
        if d > self.atol + self.rtol * max(abs(a), abs(b)) and not self.failed:
            self.failed = f"{where}: {a!r} -> {b!r}"

    def text(self, a: str, b: str, where: str) -> None:
        """Two strings: the same words, numbers within the tolerance (part numbers as their
        family, the ``--replace`` pairs applied to ``a``)."""
        if a == b:
            return
        for old, new in self.replace:
            a = a.replace(old, new)
        a, b = PART_NUMBER.sub(r"\1-#", a), PART_NUMBER.sub(r"\1-#", b)
        if a == b:
            return
        na, nb = NUMBER.findall(a), NUMBER.findall(b)
        if NUMBER.sub("#", a) != NUMBER.sub("#", b) or len(na) != len(nb):
            if not self.failed:
                self.failed = f"{where}: {a[:120]!r} -> {b[:120]!r}"
            return
        for x, y in zip(na, nb):
            self.number(float(x), float(y), where)

    def verdict(self) -> str:
        if self.failed:
            return f"DIFFERS ({self.failed})"
        if not self.changed:
            return "equal"
        return (f"within ({self.changed}/{self.numbers} numbers changed, max abs "
                f"{self.max_abs:.3g} at {self.where}, max rel {self.max_rel:.3g})")


def _json(a, b, diff: Diff, path: str = "") -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in RUN_KEYS:
                continue
            if k not in a or k not in b:
                if not diff.failed:
                    diff.failed = f"{path}/{k} only in {'after' if k in b else 'before'}"
                continue
            _json(a[k], b[k], diff, f"{path}/{k}")
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            if not diff.failed:
                diff.failed = f"{path}: {len(a)} -> {len(b)} items"
            return
        for i, (x, y) in enumerate(zip(a, b)):
            _json(x, y, diff, f"{path}[{i}]")
    elif isinstance(a, bool) or isinstance(b, bool) or a is None or b is None:
        if a != b and not diff.failed:
            diff.failed = f"{path}: {a!r} -> {b!r}"
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if a != a and b != b:  # both nan
            return
        diff.number(float(a), float(b), path)
    elif isinstance(a, str) and isinstance(b, str):
        diff.text(a, b, path)
    elif a != b and not diff.failed:
        diff.failed = f"{path}: {a!r} -> {b!r}"


def _lines(a: str, b: str, diff: Diff) -> None:
    la, lb = a.splitlines(), b.splitlines()
    if len(la) != len(lb):
        diff.failed = f"{len(la)} -> {len(lb)} lines"
        return
    for k, (x, y) in enumerate(zip(la, lb)):
        diff.text(x, y, f"line {k + 1}")


def _stl(a: bytes, b: bytes, diff: Diff) -> None:
    import numpy as np

    if a[:5] == b"solid" and b[:5] == b"solid":
        _lines(a.decode(errors="replace"), b.decode(errors="replace"), diff)
        return
    na, nb = (int(np.frombuffer(x[80:84], "<u4")[0]) for x in (a, b))
    if na != nb:
        diff.failed = f"{na} -> {nb} triangles"
        return
    rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    va = np.frombuffer(a[84:], rec, count=na)["v"].astype(float)
    vb = np.frombuffer(b[84:], rec, count=nb)["v"].astype(float)
    d = np.abs(va - vb).ravel()
    diff.numbers += d.size
    if d.size and d.max() > 0:
        k = int(np.argmax(d))
        diff.numbers -= 1  # counted again by number()
        diff.number(float(va.ravel()[k]), float(vb.ravel()[k]), f"vertex coordinate {k}")
        diff.changed += int(np.count_nonzero(d)) - 1


def _png(a: bytes, b: bytes) -> str:
    import numpy as np
    from matplotlib import image

    ia, ib = image.imread(io.BytesIO(a)), image.imread(io.BytesIO(b))
    if ia.shape != ib.shape:
        return f"DIFFERS (image {ia.shape} -> {ib.shape})"
    d = np.abs(ia.astype(float) - ib.astype(float))
    changed = np.any(d > 0, axis=-1) if d.ndim == 3 else d > 0
    return (f"pixels differ: {100 * changed.mean():.3f} % of {changed.size}, largest channel "
            f"change {d.max():.3f} (not judged)")


def _pdf_text(data: bytes) -> str | None:
    with tempfile.NamedTemporaryFile(suffix=".pdf") as f:
        f.write(data)
        f.flush()
        try:
            text = subprocess.run(["pdftotext", "-layout", f.name, "-"], capture_output=True,
                                  text=True, check=True).stdout
        except (OSError, subprocess.CalledProcessError):
            return None
    # the layout's spacing follows the glyph widths of the words beside it (a renamed part
    # number): runs of blanks compared as one
    return "\n".join(re.sub(r"[ \t]+", " ", line).strip() for line in text.splitlines())


def _vtu(a: bytes, b: bytes, diff: Diff) -> None:
    import numpy as np
    import pyvista
    from scipy.spatial import cKDTree

    def read(data):
        with tempfile.NamedTemporaryFile(suffix=".vtu") as f:
            f.write(data)
            f.flush()
            return pyvista.read(f.name)

    ma, mb = read(a), read(b)
    if ma.points.shape != mb.points.shape:
        diff.failed = f"points {ma.points.shape} -> {mb.points.shape}"
        return
    # nodes paired by position (a mesher may number the same nodes otherwise)
    pa, pb = np.asarray(ma.points, float), np.asarray(mb.points, float)
    dist, near = cKDTree(pa).query(pb)
    if dist.max() > diff.atol:
        diff.failed = (f"REMESHED: a node {dist.max():.3g} mm from the nearest before; fields "
                       "not compared node by node")
        return
    diff.number(float(pa[near].ravel()[np.argmax(np.abs(pa[near] - pb))]),
                float(pb.ravel()[np.argmax(np.abs(pa[near] - pb))]), "points")
    for name in ma.point_data.keys():
        x, y = np.asarray(ma.point_data[name], float), mb.point_data.get(name)
        if y is None or np.shape(x) != np.shape(y):
            diff.failed = f"{name}: missing or reshaped"
            return
        x, y = x[near], np.asarray(y, float)
        d = np.abs(x - y)
        if d.size:
            k = int(np.argmax(d))
            diff.number(float(np.ravel(x)[k]), float(np.ravel(y)[k]), f"{name}[{k}]")


def compare_bytes(name: str, a: bytes, b: bytes, rtol: float, atol_mm: float,
                  replace: tuple = ()) -> str:
    """The verdict for one file's two versions (see the module docstring)."""
    if a == b:
        return "identical"
    suffix = Path(name).suffix.lower()
    diff = Diff(rtol, atol_mm if suffix in {".step", ".stp", ".dxf", ".stl", ".svg", ".vtu"}
                else 1e-9, replace)
    if suffix == ".json":
        _json(json.loads(a), json.loads(b), diff)
    elif suffix in TEXT_SUFFIXES:
        _lines(a.decode(errors="replace"), b.decode(errors="replace"), diff)
    elif suffix == ".stl":
        _stl(a, b, diff)
    elif suffix == ".png":
        return _png(a, b)
    elif suffix == ".pdf":
        ta, tb = _pdf_text(a), _pdf_text(b)
        if ta is None or tb is None:
            return "DIFFERS (bytes; pdftotext not available)"
        _lines(ta, tb, diff)
        return "bytes differ; text " + diff.verdict()
    elif suffix == ".vtu":
        _vtu(a, b, diff)
    elif suffix == ".zip":
        za, zb = zipfile.ZipFile(io.BytesIO(a)), zipfile.ZipFile(io.BytesIO(b))
        if sorted(map(_family, za.namelist())) != sorted(map(_family, zb.namelist())):
            return "DIFFERS (members differ)"
        names = {_family(m): m for m in zb.namelist()}
        out = [f"{m}: {compare_bytes(m, za.read(m), zb.read(names[_family(m)]), rtol, atol_mm, replace)}"
               for m in sorted(za.namelist())]
        bad = [o for o in out if "DIFFERS" in o]
        return ("DIFFERS (" + "; ".join(bad[:3]) + ")") if bad else (
            "members: " + "; ".join(o for o in out if not o.endswith(": identical"))
            if any(not o.endswith(": identical") for o in out) else "members identical")
    else:
        return "DIFFERS (bytes)"
    return diff.verdict()


def _family(name: str) -> str:
    return PART_NUMBER.sub(r"\1-#", name)


def compare_folders(a: Path, b: Path, rtol: float = 1e-4, atol_mm: float = 1e-3,
                    replace: tuple = ()) -> list:
    """(relative path, verdict) of every file of either folder, sorted; files are paired by
    their path with part numbers as their family (a renamed part is the same file)."""
    fa = {_family(str(p.relative_to(a))): p for p in a.rglob("*") if p.is_file()}
    fb = {_family(str(p.relative_to(b))): p for p in b.rglob("*") if p.is_file()}
    out = []
    for name in sorted(fa.keys() | fb.keys()):
        if name not in fa or name not in fb:
            out.append((name, f"DIFFERS (only {'after' if name in fb else 'before'})"))
            continue
        verdict = compare_bytes(name, fa[name].read_bytes(), fb[name].read_bytes(),
                                rtol, atol_mm, replace)
        if fa[name].name != fb[name].name:
            verdict = f"[{fa[name].name} -> {fb[name].name}] {verdict}"
        if Path(name).name in RUN_FILES and verdict != "identical":
            verdict = "run file (its own timings), not judged: " + verdict.replace("DIFFERS",
                                                                                   "differs")
        out.append((name, verdict))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--rtol", type=float, default=1e-4, help="relative tolerance (default 1e-4)")
    ap.add_argument("--atol-mm", type=float, default=1e-3,
                    help="absolute tolerance of lengths in STEP, DXF, STL, SVG, VTU (mm; "
                         "default 1e-3)")
    ap.add_argument("--replace", action="append", default=[], metavar="OLD=NEW",
                    help="replace OLD by NEW in the before folder's text (e.g. the checkout "
                         "folder the job was read from); may be repeated")
    args = ap.parse_args(argv)
    replace = tuple(tuple(r.split("=", 1)) for r in args.replace)
    rows = compare_folders(args.before, args.after, args.rtol, args.atol_mm, replace)
    for name, verdict in rows:
        print(f"{name}: {verdict}")
    bad = [n for n, v in rows if "DIFFERS" in v and "REMESHED" not in v]
    remeshed = [n for n, v in rows if "REMESHED" in v]
    if remeshed:
        print(f"remeshed (not compared node by node): {remeshed}")
    print(f"{len(rows)} files: {sum(v == 'identical' for _, v in rows)} identical, "
          f"{len(bad)} differ beyond the tolerance" + (f": {bad}" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
