"""Finalists: the full design goes down the screened ranking until a stack passes, and the
report says why each finalist failed."""

import pytest

from springcad.synthesis import pipeline, ranking
from springcad.synthesis.candidates import CandidateSpace
from springcad.synthesis.evaluate import evaluate_batch
from springcad.synthesis.finalists import failure_class
from springcad.synthesis.requirements import requirements_from_dict
from springcad.synthesis.runner import dask_client
from springcad.synthesis.store import ResultStore
from synth_fixtures import SMALL, small

#: maraging steel: 14 distinct feasible stacks in the small space
REQ = requirements_from_dict(small(materials={"names": ["maraging_300"]}))
SPACE = CandidateSpace.from_requirements(REQ)
MESSAGE = ("spring 'A': no beam stress keeps the yield margin 1 in this envelope (predicted "
           "peak 2197 MPa at the flexure flank)")


@pytest.fixture(scope="module")
def ranked():
    cols = evaluate_batch(SPACE, 0, SPACE.total)
    return ranking.distinct(cols, ranking.rank(cols, "mass_kg"), 6)


def _run(tmp_path, monkeypatch, doomed, finalists, max_finalists):
    real = pipeline.full_design_summary

    def full_design(req, cand):
        if int(cand["cid"]) in doomed:
            return {"cid": int(cand["cid"]), "ok": False, "error": MESSAGE,
                    "failure": failure_class(MESSAGE), "screened_mass_kg": cand["mass_kg"],
                    "screened_peak_stress_MPa": cand["peak_stress_MPa"]}
        return real(req, cand)

    monkeypatch.setattr(pipeline, "full_design_summary", full_design)
    store = ResultStore(tmp_path / "run", REQ.fingerprint(), SPACE.total, 300)
    with dask_client(n_workers=1, processes=False) as client:  # threads: the patch holds
        return pipeline.synthesize(REQ, SPACE, store, client, finalists=finalists,
                                   max_finalists=max_finalists, verify=False)


def test_finalists_go_down_the_ranking(tmp_path, monkeypatch, ranked):
    doomed = {int(r["cid"]) for r in ranked[:3]}
    result = _run(tmp_path, monkeypatch, doomed, finalists=2, max_finalists=6)
    # round 1: ranks 1-2 fail; round 2: rank 3 fails, rank 4 passes; no third round
    assert [f["cid"] for f in result.finalists] == [int(r["cid"]) for r in ranked[:4]]
    assert result.winner["cid"] == ranked[3]["cid"]
    report = result.to_dict()
    assert report["finalist_failures"] == {"yield_margin": 3}
    assert report["finalists_full_design"][3]["ok"]


def test_no_finalist_passes_says_why(tmp_path, monkeypatch, ranked):
    doomed = {int(r["cid"]) for r in ranked}
    result = _run(tmp_path, monkeypatch, doomed, finalists=2, max_finalists=4)
    assert result.winner is None and not result.ok
    assert len(result.finalists) == 4
    assert "none of the 4 best screened stacks passes the full design (4 on yield_margin)" \
        in result.winner_status
    assert "predicted peak 2197 MPa" in result.winner_status


@pytest.mark.parametrize("message, kind", [
    (MESSAGE, "yield_margin"),
    ("spring 'A': flexures 1.0100 x wider leave 0.300 mm to their neighbours", "neighbour_clearance"),
    ("spring 'A': root fillets of neighbouring flexures overlap at R_r = 31 mm", "fillet"),
    ("stack height 21.50 mm > 19.5 mm", "axial_length"),
    ("something else", "other"),
])
def test_failure_classes(message, kind):
    assert failure_class(message) == kind


def _verified_run(tmp_path, monkeypatch, failing_checks, verify_top, release=()):
    """synthesize with verify=True, the full design and FEA passing and build's checks
    failing for the stacks in ``failing_checks`` (full design, FEA and solids replaced: what
    is tested is the choice); ``release``: the FEA's release findings (contact at full
    deflection) of every candidate."""
    from types import SimpleNamespace

    def full_design(req, cand):
        return {"cid": int(cand["cid"]), "ok": True, "error": "", "failure": "",
                "mass_kg": float(cand["mass_kg"])}

    def fea(req, cand, model):
        v = SimpleNamespace(ok=True, failures=lambda: [], notes=lambda: [],
                            summary=lambda: f"FEA of {int(cand['cid'])} passed", springs={},
                            release_failures=lambda: list(release), duty_failures=list)
        return v, SimpleNamespace(cid=int(cand["cid"]), stack=SimpleNamespace(mass_kg=0.3))

    def checks(corrected):
        bad = corrected.cid in failing_checks
        return {"ok": not bad, "summary": "",
                "failures": ["RING-1: edm.min_web: 0.31 mm < 0.35 mm"] if bad else []}

    monkeypatch.setattr(pipeline, "full_design_summary", full_design)
    monkeypatch.setattr(pipeline, "verify_candidate", fea)
    monkeypatch.setattr(pipeline, "build_checks", checks)
    store = ResultStore(tmp_path / "run", REQ.fingerprint(), SPACE.total, 300)
    with dask_client(n_workers=1, processes=False) as client:
        return pipeline.synthesize(REQ, SPACE, store, client, finalists=6, max_finalists=6,
                                   verify=True, verify_top=verify_top)


def test_winner_is_the_best_finalist_that_passes_build_checks(tmp_path, monkeypatch):
    result = _verified_run(tmp_path, monkeypatch, set(), verify_top=3)
    first_pick = int(result.winner["cid"])
    assert result.ok and list(result.verifications) == [first_pick]  # first passed: stop
    again = _verified_run(tmp_path / "b", monkeypatch, {first_pick}, verify_top=3)
    cids = list(again.verifications)
    assert cids[0] == first_pick and len(cids) == 2
    assert not again.verifications[first_pick]["ok"]
    assert again.verifications[first_pick]["failures"] == [
        "build checks: RING-1: edm.min_web: 0.31 mm < 0.35 mm"]
    assert again.ok and int(again.winner["cid"]) == cids[1] != first_pick
    assert again.winner_status == "FEA (2d3d) and build checks passed"
    assert again.winner_job["job"]["description"].endswith(
        f"candidate {cids[1]}, 37.5 N*m/rad over +-{SMALL['requirement']['deflection_deg']:g} deg")


def test_no_finalist_passes_build_checks_is_not_ok(tmp_path, monkeypatch):
    everyone = {int(r["cid"]) for r in _ranked_all()}
    result = _verified_run(tmp_path, monkeypatch, everyone, verify_top=2)
    assert not result.ok and len(result.verifications) == 2
    assert result.winner_status.startswith("FEA or build checks FAILED for every verified "
                                           "finalist; best shown. build checks: RING-1")


def _ranked_all():
    cols = evaluate_batch(SPACE, 0, SPACE.total)
    return ranking.distinct(cols, ranking.rank(cols, "mass_kg"), 1000)


def test_winner_that_build_will_not_release_says_so(tmp_path, monkeypatch):
    """Requirements without a [duty] (issue 26 review 7): the winner is still the first to
    pass the FEA and build's checks, but its status (winner.toml's header, the CLI's last
    line) says build will stamp it NOT FOR MANUFACTURE, with the count and the first
    finding; with no findings the status is the plain one."""
    assert REQ.duty is None
    finding = "spring A at +10.7 deg: clearance driving flank to neck -33.5 um worst case"
    result = _verified_run(tmp_path, monkeypatch, set(), verify_top=3, release=(finding, "x"))
    assert result.ok
    assert result.winner_status == (
        "FEA (2d3d) and build checks passed; but build will stamp it NOT FOR MANUFACTURE: 2 "
        "release findings (springcad's default duty and the contact at full deflection; the "
        f"requirements declare no [duty]), the first: {finding}")
    assert "NOT FOR MANUFACTURE" in result.winner_toml()
