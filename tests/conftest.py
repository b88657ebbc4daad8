"""Shared fixtures: template paths and designs built once per session."""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
from pathlib import Path

import pytest

# the suite computes every result (tests patch the stages they break, which a cached result
# would skip); tests of the cache turn it on explicitly (cache=True) in their own folders.
# Subprocesses (the CLI tests) inherit both settings; nothing is written to ~/.cache.
os.environ.setdefault("SPRINGCAD_CACHE", "off")
if "SPRINGCAD_CACHE_DIR" not in os.environ:
    _CACHE = tempfile.mkdtemp(prefix="springcad-test-cache-")
    os.environ["SPRINGCAD_CACHE_DIR"] = _CACHE
    atexit.register(shutil.rmtree, _CACHE, True)

ROOT = Path(__file__).resolve().parents[1]
TEMPLATES = ROOT / "templates"
SHARED = ROOT.parent / "shared"
#: the paper's measured tables: ../shared/data beside the repository, else the shipped copy
PAPER_DATA = SHARED / "data" if (SHARED / "data").exists() else ROOT / "springcad" / "data" / "paper"


def pytest_collection_modifyitems(config, items):
    """Modules holding heavy cases (marked slow) run first, each module kept together (its
    module fixtures built once). pytest-xdist's load scheduling sends a worker more tests
    as it runs dry, in smaller batches towards the end: with the long tests early, the
    run ends on short ones and the workers finish together, instead of one worker
    starting a two-minute refusal test while the other has nothing left."""
    heavy = {item.module.__name__ for item in items
             if item.get_closest_marker("slow") is not None and hasattr(item, "module")}
    order = {id(item): k for k, item in enumerate(items)}
    items.sort(key=lambda item: (getattr(getattr(item, "module", None), "__name__", "")
                                 not in heavy, order[id(item)]))


#: test modules that share an expensive fixture or result (seconds to half a minute each),
#: keyed to a group name: pytest-xdist runs a group's tests on one worker, so the shared
#: work is done once instead of on each worker that receives one of its tests
SHARED_WORK = {
    # conftest.s1_cli_build: one CLI build of paper S1 (20-27 s setup)
    "tests/export/test_cli_build.py": "s1_cli_build",
    "tests/report/test_html_build_report.py": "s1_cli_build",
    # s1_verified and s2_verified: the FEA verification of each paper spring (19-28 s each)
    "tests/fea/test_verify.py": "fea_verify",
    # the full design of each screened case, made once for both tests (_DESIGNED)
    "tests/synthesis/test_synth_screening.py": "synth_screening",
    # the spring B that designs, made once for both error types (_MADE)
    "tests/test_job_refusals.py": "job_refusals",
    # module fixtures: builds, verifications and validations read by several tests
    "tests/test_front_door.py": "front_door",
    "tests/fea/test_cli.py": "fea_cli",
    "tests/export/test_drawing_layout.py": "drawing_layout",
    "tests/export/test_outputs_ahead.py": "outputs_ahead",
    "tests/synthesis/test_synth_cli.py": "synth_cli",
    "tests/test_paper_validation.py": "paper_validation",
    # the held-out g04 spring designed once for both tests (20-30 s)
    "tests/test_ball_window.py": "ball_window",
}


@pytest.hookimpl(optionalhook=True, tryfirst=True)
def pytest_xdist_make_scheduler(config, log):
    """``-n N`` (xdist's load scheduling): tests go out one at a time in collection order
    (heavy modules first, above), as load scheduling does, but the modules of SHARED_WORK
    go out as one unit per group. Load scheduling deals consecutive chunks of tests, so a
    module fixture was built twice whenever a module straddled two chunks, and a session
    fixture once on each worker that ran one of its tests."""
    if config.getvalue("dist") != "load":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class SharedWorkScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return SHARED_WORK.get(nodeid.split("::", 1)[0], nodeid)

    config.option.loadscopereorder = False  # keep the order above, not the largest unit first
    return SharedWorkScheduling(config, log)


def template(name: str) -> Path:
    return TEMPLATES / f"{name}.toml"


@pytest.fixture(scope="session")
def paper_designs():
    """JobDesign of every paper template, keyed by template name (explain=False: the same
    designs without the default duty's advice search, which no user of the fixture reads)."""
    from springcad.config import load_job
    from springcad.design.job import design_job

    names = ["paper_S1", "paper_S2", "paper_2xS1", "paper_2xS2", "paper_4xS1", "paper_S1_2xS2",
             "paper_S2_3xS1", "paper_4xS1_mfr1", "paper_4xS1_mfr2"]
    return {n: design_job(load_job(template(n)), explain=False) for n in names}


#: the umask of the shared S1 build below: an unusual one, which every output must follow
S1_BUILD_UMASK = 0o027


@pytest.fixture(scope="session")
def s1_cli_build(tmp_path_factory):
    """One accepted ``springcad build`` of paper S1 without FEA (revision B, under
    S1_BUILD_UMASK), made once per worker: (exit status, output folder), its console
    output in ``out/../stdout``. For the tests that only read a build's files
    (export/test_cli_build.py, report/test_html_build_report.py); tests that patch a stage,
    interrupt a build or test the cache build their own."""
    import contextlib
    import io

    from springcad.cli import main

    out = tmp_path_factory.mktemp("s1_build") / "s1"
    console = io.StringIO()
    old_mask = os.umask(S1_BUILD_UMASK)
    try:
        with contextlib.redirect_stdout(console):
            code = main(["build", str(template("paper_S1")), "--out", str(out),
                         "--accept-violations", "--revision", "B", "--no-verify"])
    finally:
        os.umask(old_mask)
    (out.parent / "stdout").write_text(console.getvalue())
    return code, out
