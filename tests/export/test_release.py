"""Release gate: only a verified, warning-free build with every check passed is released."""

import pytest

from cad_fixtures import TEMPLATES
from pdftext import pdf_text
from springcad.export.drawing import DrawingInfo, write_drawing
from springcad.export.release import (NOT_FOR_MANUFACTURE, RELEASED, ReleaseStatus,
                                      release_status)
from springcad.geometry.checks import Check


class FakeVerification:
    """Stands in for fea.verdict.JobVerification (only what the gate reads)."""

    def __init__(self, failures=(), notes=(), contact_flags=None):
        from types import SimpleNamespace

        self._failures, self._notes = list(failures), list(notes)
        self.springs = {n: SimpleNamespace(contact=None if flags is None else SimpleNamespace(
            flags=[{"message": m} for m in flags])) for n, flags in (contact_flags or {}).items()}

    @property
    def ok(self):
        return not self._failures

    def failures(self):
        return self._failures

    def notes(self):
        return self._notes


@pytest.fixture(scope="module")
def designs():
    from springcad.config import load_job
    from springcad.design.job import design_job

    return {n: design_job(load_job(TEMPLATES / f"{n}.toml")) for n in ("default", "paper_4xS1")}


def test_clean_verified_build_is_released(designs):
    ok = [Check("solid_valid", "X", True)]
    status = release_status(designs["default"], FakeVerification(), False, ok)
    assert status.released and status.stamp == RELEASED and status.reasons == ()


def test_every_reason_stops_the_release(designs):
    clean = designs["default"]
    skipped = release_status(clean, None, verify_skipped=True)
    assert not skipped.released and "--no-verify" in skipped.reasons[0]
    failed = release_status(clean, FakeVerification(["S1: yield margin 1.05 < 1.2"]))
    assert failed.stamp == NOT_FOR_MANUFACTURE
    assert failed.reasons == ("FEA verification failed: S1: yield margin 1.05 < 1.2",)
    violated = release_status(clean, FakeVerification(), checks=[
        Check("edm.hole_edge", "RING-1", False, kind="rule", message="0.505 mm < 0.6 mm")])
    assert violated.reasons == ("manufacturability rule edm.hole_edge failed on RING-1: "
                                "0.505 mm < 0.6 mm",)
    # a note of the verification is shown but does not stop the release
    noted = release_status(clean, FakeVerification(notes=["spring S1 alone ..."]))
    assert noted.released and noted.notes == ("spring S1 alone ...",)


def test_design_warnings_stop_the_release(designs):
    """The paper's 4xS1 spring has an undersized tip ball and MC interference (design.json)."""
    d = designs["paper_4xS1"]
    assert d.stack.backlash.mc_interference_fraction > 0
    status = release_status(d, FakeVerification())
    assert not status.released
    text = "\n".join(status.reasons)
    assert "tip ball 0.300 mm is below" in text or "no tip ball carries the peak load" in text
    frac = 100 * d.stack.backlash.mc_interference_fraction
    assert f"{frac:.1f} % of Monte Carlo stacks" in text
    lines = status.summary_lines()
    assert lines[0].startswith(f"release: {NOT_FOR_MANUFACTURE} ({len(status.reasons)} reasons")
    assert all(f"  - {r}" in lines for r in status.reasons)


def test_drawing_carries_the_stamp_and_reasons(ring_s1, tmp_path):
    reasons = ("FEA verification skipped (--no-verify): beam-theory design",
               "design warning: spring S1: tip ball 0.300 mm is below the 0.344 mm")
    info = DrawingInfo(job="j", quantity=1, release=ReleaseStatus(reasons))
    _, pdf = write_drawing(ring_s1, info, tmp_path)
    text = pdf_text(pdf)
    # the stamp, how many reasons and the first (every reason: report.html, build.json)
    assert NOT_FOR_MANUFACTURE in text and "2 reasons" in text and "--no-verify" in text
    released = DrawingInfo(job="j", quantity=1, release=ReleaseStatus())
    (tmp_path / "ok").mkdir()
    _, pdf = write_drawing(ring_s1, released, tmp_path / "ok")
    text = pdf_text(pdf)
    assert RELEASED in text and NOT_FOR_MANUFACTURE not in text


def test_a_rating_is_not_written_as_a_reason(ring_s1, tmp_path):
    """The duty's rating ("duty met ...") is a fact of the design: in a NOT FOR MANUFACTURE
    box it stands under a heading of its own after the reasons, never as a reason's bullet
    (shop review 9 read it as the second reason). Read back with poppler."""
    reason = "contact at full deflection: spring S1 at +16.0 deg: tip ball Hertz contact"
    rating = ("spring S1: duty met: Miner sum 0.0883, fatigue safety factor 1.11 "
              "(required 1)")
    info = DrawingInfo(job="j", quantity=1, release=ReleaseStatus((reason,), (), (rating,)))
    _, pdf = write_drawing(ring_s1, info, tmp_path)
    lines = [ln.strip() for ln in pdf_text(pdf).splitlines()]
    first = next(i for i, ln in enumerate(lines) if "1 reason" in ln)
    head = next(i for i, ln in enumerate(lines) if ln.startswith("RATING"))
    rated = next(i for i, ln in enumerate(lines) if "duty met" in ln)
    assert first < head < rated
    assert "not a reason" in lines[head]
    # only the reason carries the reasons' bullet
    assert [ln for ln in lines[first:rated + 1] if ln.startswith("- ")] == [
        next(ln for ln in lines if ln.startswith("- contact"))]
    assert not lines[rated].startswith("-")


def test_a_drawing_nobody_assessed_is_not_for_manufacture(ring_s1, tmp_path):
    _, pdf = write_drawing(ring_s1, DrawingInfo(job="j", quantity=1), tmp_path)
    assert NOT_FOR_MANUFACTURE in pdf_text(pdf)


def test_contact_sweep_findings_are_listed_not_blocking(designs):
    """The FEA contact sweep flags (no verification failure) are notes of the verdict: in
    the console summary beside RELEASED, never a reason."""
    ver = FakeVerification(contact_flags={"S1": ["+: the ball leaves the driving flank",
                                                 "-: second contact: ball:0 touches pocket:0"],
                                          "S2": None})
    status = release_status(designs["default"], ver)
    assert status.released
    assert status.notes == ("FEA contact sweep, spring S1: +: the ball leaves the driving flank",
                            "FEA contact sweep, spring S1: -: second contact: ball:0 touches "
                            "pocket:0")
    assert [f"  note: {n}" for n in status.notes] == status.summary_lines()[1:]


def test_tooth_tip_estimates_give_way_to_the_contact_fea(designs):
    """A design-time estimate of the tooth tip near the ball stops the release unless the
    contact FEA assessed the clearances at +-theta_max with the tolerances (its failures are
    reasons of their own): then it is a note."""
    from dataclasses import replace
    from types import SimpleNamespace

    from springcad.design.cam import OVERTRAVEL_REDUCED, TIP_CLEARANCE_SHORT

    d = designs["default"]
    s1 = replace(d.springs["S1"], warnings=(f"{TIP_CLEARANCE_SHORT}: 21 um (estimate)",
                                            f"{OVERTRAVEL_REDUCED} to 1.2 x max deflection"))
    warned = replace(d, springs={"S1": s1})
    ver = FakeVerification()
    assert not release_status(warned, ver).released  # no contact assessment
    end = SimpleNamespace(clearances=["driving_tooth_tip/ball"])
    ver.springs = {"S1": SimpleNamespace(contact=SimpleNamespace(
        flags=[], at_max=SimpleNamespace(ends={"+": end, "-": end})))}
    status = release_status(warned, ver)
    assert status.released
    assert sum("checked by the contact FEA" in n for n in status.notes) == 2


def test_a_stress_derating_is_a_note_where_the_fea_verified_the_stress(designs):
    """The design lowered its beam stress so the predicted peak keeps the margin: the FEA
    verification judges the real geometry's margin (its failure is a reason of its own), so
    with a verification the derating is a note; without one (--no-verify) it stays a reason
    (held-out wrist spring: NOT FOR MANUFACTURE for this line alone before)."""
    from dataclasses import replace

    from springcad.design.sizing import STRESS_DERATED

    d = designs["default"]
    s1 = replace(d.springs["S1"], warnings=(f"{STRESS_DERATED} from 890 to 872 MPa so the "
                                            "predicted peak keeps the yield margin 1.2",))
    derated = replace(d, springs={"S1": s1})
    status = release_status(derated, FakeVerification())
    assert status.released
    assert status.notes == (f"design note, checked by the FEA verification: spring S1: "
                            f"{s1.warnings[0]}",)
    skipped = release_status(derated, None, verify_skipped=True)
    assert any(r.startswith("design warning: spring S1: beam stress lowered")
               for r in skipped.reasons)
    failed = release_status(derated, FakeVerification(["S1: yield margin 1.05 < 1.2"]))
    assert not failed.released
