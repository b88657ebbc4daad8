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
from synth_fixtures import small

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
