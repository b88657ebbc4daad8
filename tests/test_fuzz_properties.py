"""Property-based tests (hypothesis) over configs, bench CSVs and output paths.

For any mutated input of the issue-11 families (``tests/fuzz_cases.py``) and any
output path layout: no exception escapes ``main`` (no traceback), the exit status
is 0, 1 or 2, a refusal is exactly one ``error:`` line, the inputs are
byte-identical afterwards, and no temporary or partial folder is left. The runs
are derandomized (a fixed seed) with a fixed number of examples, so CI time is
bounded and every run sees the same cases; ``bench/fuzz_cli.py`` runs the same
families at scale in subprocesses.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

from springcad.cli import main
from tests.conftest import template
from tests.fuzz_cases import mutate_config, mutate_csv

FUZZ = settings(derandomize=True, deadline=None, database=None, print_blob=False,
                suppress_health_check=[HealthCheck.too_slow])
#: templates that design in well under a second (the mutations are what matters)
FAST_TEMPLATES = [template(n) for n in ("paper_S1", "paper_2xS1", "paper_S1_2xS2", "paper_2xS2")]


@contextlib.contextmanager
def workdir():
    path = Path(tempfile.mkdtemp(prefix="springcad-fuzz-"))
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


def run(argv) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(argv)
    return status, err.getvalue()


def assert_clean_outcome(status: int, err: str) -> None:
    assert status in (0, 1, 2), err
    assert "Traceback" not in err and "internal error" not in err, err
    if status == 2:
        errors = [line for line in err.splitlines() if ": error:" in line]
        assert len(errors) == 1, err
        assert err.rstrip().splitlines()[-1] == errors[0], err


def leftovers(folder: Path, expected: set[str]) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name not in expected)


@pytest.mark.slow
@seed(6)
@settings(FUZZ, max_examples=60)
@given(rng=st.randoms(use_true_random=False))
def test_mutated_configs_design_or_refuse_cleanly(rng):
    """Every mutated config designs or is refused cleanly.

    The examples are pinned by ``@seed`` (derandomize alone seeds from the test's source, so
    an edited docstring drew another set). Seed 6's 60 examples reach all 13 families of
    ``mutate_config`` (6 designs, 54 refusals, 3 of them the design search's; ~30-60 s).
    The source-seeded 60 used before reached 11 (no ``bounds``, no ``multi``) and spent
    137 of ~140 s in four design-search refusals, one (paper S1 at safety_factor = 3) ~95 s
    in the refusal's search. Measured (2026-11-27): a config reader that lets a non-UTF-8
    file's decode error escape (exit 3) fails this test with seed 6, as it did before."""
    family, data = mutate_config(rng, FAST_TEMPLATES)
    with workdir() as w:
        cfg = w / "job.toml"
        cfg.write_bytes(data)
        status, err = run(["design", str(cfg), "--out", str(w / "out")])
        assert_clean_outcome(status, err)
        assert cfg.read_bytes() == data
        assert leftovers(w, {"job.toml"} | ({"out"} if status == 0 else set())) == [], family
        if status == 0:
            d = json.loads((w / "out" / "design.json").read_text())
            masses = [s["mass_kg"] for s in d["springs"].values()] + [d["stack"]["mass_kg"]]
            assert all(m is not None and 0 < m < 100 for m in masses), (family, masses)


@functools.cache
def clean_record() -> str:
    with workdir() as w:
        rec = w / "rec.csv"
        assert run(["simulate", str(template("paper_2xS1")), "--out", str(rec), "--seed", "5"])[0] == 0
        return rec.read_text()


@pytest.mark.slow
@settings(FUZZ, max_examples=20)
@given(rng=st.randoms(use_true_random=False))
def test_mutated_bench_csvs_fit_or_refuse_cleanly(rng):
    family, data = mutate_csv(rng, clean_record())
    with workdir() as w:
        csv = w / "rec.csv"
        csv.write_bytes(data)
        status, err = run(["fit", str(csv), "--out", str(w / "out"), "--no-plots"])
        assert_clean_outcome(status, err)
        assert csv.read_bytes() == data
        assert leftovers(w, {"rec.csv"} | ({"out"} if status == 0 else set())) == [], family


#: the layout of the working folder before the run: name -> file content or None (folder)
LAYOUT = st.dictionaries(
    st.sampled_from(["a", "a/b", "a/keep.txt", "out", "out/keep.txt", ".out.old",
                     ".out.old/precious.txt", "f"]),
    st.one_of(st.none(), st.binary(min_size=0, max_size=8)), max_size=4)
OUT = st.lists(st.sampled_from(["a", "b", "out", "f", "keep.txt", "new"]), min_size=1, max_size=3)


def make_layout(root: Path, layout: dict) -> None:
    for name in sorted(layout):  # parents first
        path = root / name
        if any(p.exists() and not p.is_dir() for p in path.parents):
            continue
        if path.exists():
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        if layout[name] is None:
            path.mkdir()
        else:
            path.write_bytes(layout[name])


def snapshot(root: Path) -> dict:
    return {p.relative_to(root).as_posix(): (None if p.is_dir() else p.read_bytes())
            for p in root.rglob("*")}


@pytest.mark.slow
@settings(FUZZ, max_examples=30)
@given(layout=LAYOUT, parts=OUT, overwrite=st.booleans(),
       command=st.sampled_from(["design", "simulate"]))
def test_output_paths_never_lose_data(layout, parts, overwrite, command):
    """Whatever exists where the output goes, the run writes its output or refuses; nothing
    outside the output path changes, and the output changes only on success."""
    with workdir() as w:
        root = w / "root"
        root.mkdir()
        make_layout(root, layout)
        cfg = w / "job.toml"
        cfg.write_bytes(template("paper_S1").read_bytes())
        out = root.joinpath(*parts)
        before = snapshot(root)
        argv = [command, str(cfg), "--out", str(out)] + (["--overwrite"] if overwrite else [])
        status, err = run(argv)
        assert_clean_outcome(status, err)
        assert status in (0, 2)
        after = snapshot(root)
        rel = out.relative_to(root).as_posix()

        def outside(snap):
            return {k: v for k, v in snap.items() if k != rel and not k.startswith(rel + "/")}

        created_parents = {p.relative_to(root).as_posix() for p in out.parents
                           if root in p.parents and p.relative_to(root).as_posix() not in before}
        assert {k: v for k, v in outside(after).items() if k not in created_parents} == \
            outside(before), err
        if status != 0:
            assert after == before, err
        else:
            assert out.exists()
            assert (out / "design.json").exists() if command == "design" else out.is_file()
        assert not [k for k in after if "springcad-tmp" in k or "springcad-old" in k]
