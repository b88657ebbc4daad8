"""Result store of a sweep: one Parquet part file per finished batch, and a manifest.

A run folder holds ``manifest.json`` (what was enumerated: the space fingerprint,
batch size, candidate count) and ``parts/part-NNNNNN.parquet``, batch ``b``
covering candidate ids ``[b * batch_size, (b + 1) * batch_size)``. A part is
written to a temporary name and renamed, so a killed run leaves only whole
parts; a resumed run evaluates only the batches without a part. This is the one
module of :mod:`springcad.synthesis` that writes files (the resumable run folder
is its state). Parquet via pyarrow: columnar, typed, compressed, readable by
pandas/polars/duckdb without springcad.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from springcad.errors import OutputExistsError

MANIFEST = "manifest.json"
SCHEMA = "springcad.sweep/1"


def to_table(columns: dict):
    """Columns (numpy arrays, object arrays of str) -> a pyarrow Table."""
    import pyarrow as pa

    return pa.table({k: pa.array(v.tolist() if v.dtype == object else v)
                     for k, v in columns.items()})


class ResultStore:
    """A resumable sweep folder.

    Args:
        root: the folder (created if missing).
        fingerprint: identifies the candidate space; a folder made for another
            space is refused unless ``overwrite``.
        total: number of candidates; batch_size: candidates per part.
        overwrite: delete the parts of a different (or the same) earlier run.
        resume: keep the parts of the same space (default); False starts afresh.
    """

    def __init__(self, root: Path | str, fingerprint: str, total: int, batch_size: int,
                 overwrite: bool = False, resume: bool = True):
        self.root = Path(root)
        self.parts = self.root / "parts"
        self.total, self.batch_size = int(total), int(batch_size)
        self.manifest = {"schema": SCHEMA, "fingerprint": fingerprint, "total": self.total,
                         "batch_size": self.batch_size}
        old = self._read_manifest()
        if old is not None and (old != self.manifest or not resume):
            if not overwrite:
                raise OutputExistsError(
                    f"{self.root} holds a sweep of another candidate space or batch size "
                    f"(fingerprint {old.get('fingerprint')}, batch size {old.get('batch_size')})"
                    if old != self.manifest else f"{self.root} holds an earlier sweep")
            for p in self.parts.glob("part-*.parquet"):
                p.unlink()
        self.parts.mkdir(parents=True, exist_ok=True)
        tmp = self.root / (MANIFEST + ".tmp")
        tmp.write_text(json.dumps(self.manifest, indent=1))
        os.replace(tmp, self.root / MANIFEST)

    def _read_manifest(self) -> dict | None:
        path = self.root / MANIFEST
        if not path.exists():
            return None
        try:
            return json.loads(path.read_text())
        except (OSError, json.JSONDecodeError):
            return {}

    @property
    def n_batches(self) -> int:
        return -(-self.total // self.batch_size)

    def batch_range(self, b: int) -> tuple[int, int]:
        return b * self.batch_size, min((b + 1) * self.batch_size, self.total)

    def part_path(self, b: int) -> Path:
        return self.parts / f"part-{b:06d}.parquet"

    def done_batches(self) -> set[int]:
        return {int(p.stem.split("-")[1]) for p in self.parts.glob("part-*.parquet")}

    def pending_batches(self) -> list[int]:
        done = self.done_batches()
        return [b for b in range(self.n_batches) if b not in done]

    def write_part(self, b: int, columns: dict) -> Path:
        """Write batch ``b`` atomically (temporary name, then rename)."""
        import pyarrow.parquet as pq

        path = self.part_path(b)
        tmp = path.with_suffix(".tmp")
        pq.write_table(to_table(columns), tmp)
        os.replace(tmp, path)
        return path

    def read(self, columns: list[str] | None = None, feasible_only: bool = False) -> dict:
        """Every written part as numpy columns (object arrays for strings)."""
        import pyarrow.parquet as pq

        tables = []
        for p in sorted(self.parts.glob("part-*.parquet")):
            t = pq.read_table(p, columns=columns)
            if feasible_only:
                t = t.filter(t.column("feasible"))
            tables.append(t)
        if not tables:
            return {}
        import pyarrow as pa

        t = pa.concat_tables(tables)
        return {name: _numpy(t.column(name)) for name in t.column_names}


def _numpy(col) -> np.ndarray:
    import pyarrow as pa

    if pa.types.is_string(col.type) or pa.types.is_large_string(col.type):
        return np.array(col.to_pylist(), dtype=object)
    return col.to_numpy()
