"""The result cache: stored results read back bit for bit, keys that change with every input,
a size bound, and a verification that reuses its springs' FEA when only the stack changed."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest

from springcad.cache import MISSING, Cache, open_cache, wanted


def _json(obj) -> str:
    return json.dumps(obj, sort_keys=True, default=repr)


def _without_timings(obj):
    """``obj`` (fea.json-like) without its wall-clock timings, which differ between runs."""
    if isinstance(obj, dict):
        return {k: _without_timings(v) for k, v in obj.items()
                if k not in ("timings_s", "timings")}
    if isinstance(obj, list):
        return [_without_timings(v) for v in obj]
    return obj


def test_store_and_load_are_bit_identical_and_keys_follow_the_inputs(tmp_path):
    c = Cache(tmp_path)
    value = {"x": [0.1, 1 / 3, float("inf")], "s": "Ø±°"}
    k = c.key("t", {"a": 1.0}, "b")
    assert c.load(k) is MISSING
    c.store(k, value)
    assert c.load(k) == value and c.hits == [k]
    assert c.key("t", {"a": 1.0}, "b") == k
    assert c.key("t", {"a": 1.0 + 1e-15}, "b") != k   # any change of an input is a new key
    assert c.key("u", {"a": 1.0}, "b") != k            # and of the kind of result
    assert c.key("t", "b", {"a": 1.0}) != k


def test_size_bound_removes_the_least_recently_used(tmp_path):
    c = Cache(tmp_path, max_mb=0.35)   # room for three entries of 0.1 MB, not four
    keys = [c.key("blob", i) for i in range(4)]
    for i, k in enumerate(keys[:3]):
        c.store(k, bytes(100_000))
        os.utime(c._path(k), (1000.0 + i, 1000.0 + i))   # stored in this order
    assert c.load(keys[0]) is not MISSING                # a read makes it the newest
    c.store(keys[3], bytes(100_000))
    assert c.size_bytes() <= c.max_bytes
    assert c.load(keys[1]) is MISSING                    # the oldest unused went
    assert c.load(keys[0]) is not MISSING and c.load(keys[3]) is not MISSING


def test_a_torn_entry_is_a_miss_and_an_unwritable_cache_is_skipped(tmp_path):
    c = Cache(tmp_path)
    k = c.key("t", 1)
    c.store(k, [1, 2, 3])
    c._path(k).write_bytes(b"\x80\x05 torn")
    assert c.load(k) is MISSING and not c._path(k).exists()
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    Cache(blocked).store(k, 1)                           # no error, nothing stored
    assert Cache(blocked).load(k) is MISSING


def test_switches(monkeypatch, tmp_path):
    monkeypatch.setenv("SPRINGCAD_CACHE", "off")
    assert not wanted(None) and wanted(True) and open_cache(None) is None
    monkeypatch.setenv("SPRINGCAD_CACHE", "1")
    assert wanted(None) and not wanted(False)
    monkeypatch.setenv("SPRINGCAD_CACHE_DIR", str(tmp_path))
    assert open_cache(None).folder == tmp_path


def _job(sequence):
    from springcad.config import read_toml

    cfg = read_toml(Path(__file__).resolve().parents[1] / "templates" / "paper_S1.toml")
    cfg["stack"] = {**cfg["stack"], "sequence": sequence}
    return cfg


def test_cached_fea_is_bit_identical_to_fresh_and_a_stack_change_reuses_it(monkeypatch,
                                                                           tmp_path):
    import springcad.api as sc

    monkeypatch.setenv("SPRINGCAD_CACHE_DIR", str(tmp_path))
    opts = dict(model="2d", contact=False, keep_fields=False)
    messages = []
    fresh = sc.verify(_job(["S1", "S1"]), cache=True, **opts)            # computed and stored
    t0 = time.perf_counter()
    cached = sc.verify(_job(["S1", "S1"]), cache=True,
                       progress=lambda m, f=None: messages.append(m), **opts)
    t_cached = time.perf_counter() - t0
    assert any("from the cache" in m for m in messages), messages
    assert _json(cached.raw.to_dict()["springs"]) == _json(fresh.raw.to_dict()["springs"])
    assert _json(cached.design.to_dict()) == _json(fresh.design.to_dict())
    # a fresh computation without the cache gives the same numbers (not its timings)
    again = sc.verify(_job(["S1", "S1"]), cache=False, **opts)
    assert (_json(_without_timings(again.raw.to_dict()["springs"]))
            == _json(_without_timings(fresh.raw.to_dict()["springs"])))
    # only the stack changed (two springs to three; one spring alone would give the rim
    # other room, a different design): the spring's FEA is reused, the stack is the new one
    messages.clear()
    three = sc.verify(_job(["S1", "S1", "S1"]), cache=True,
                    progress=lambda m, f=None: messages.append(m), **opts)
    assert any("FEA of this design and options from the cache" in m for m in messages)
    assert (_json(three.raw.to_dict()["springs"]["S1"])
            == _json(fresh.raw.to_dict()["springs"]["S1"]))
    assert three.stack_stiffness_Nm_per_rad == pytest.approx(
        fresh.stack_stiffness_Nm_per_rad * 2 / 3, rel=1e-12)
    assert t_cached < 5.0
