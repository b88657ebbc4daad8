"""Release gate: may a build's drawings go to a shop, and if not, why not.

A build is *released* only when all of these hold:

* the FEA verification ran (no ``--no-verify``) and passed;
* at +-theta_max the tip ball's Hertz contact von Mises meets the yield margin and every
  clearance stays open with the profile tolerances (``fea.contact_tolerance``);
* every spring's verified stress field meets the job's duty with its fatigue safety
  factor (``fea.verdict``; a static/prototype duty is met by its 1e3 cycles and the
  drawing says "rated for 1e3 cycles at ...");
* the design carries no warning (spring warnings such as an undersized tip
  ball, stack warnings such as cam interfaces that can interfere in the Monte Carlo
  tolerance stack; a stress derating is a note where the FEA verified the stress);
* every geometry check and manufacturability rule passed (an accepted
  violation, ``--accept-violations``, is a reason too).

Anything else gives drawings stamped NOT FOR MANUFACTURE with every reason
written next to the title block, and the console summary lists the same
reasons. The gate only reads results; it never changes a design.
"""

from __future__ import annotations

from dataclasses import dataclass

from springcad.design.cam import OVERTRAVEL_REDUCED, TIP_CLEARANCE_SHORT
from springcad.design.sizing import STRESS_DERATED
from springcad.options import written

#: design-time estimates of the contact at +-theta_max that the contact FEA with the profile
#: tolerances checks on the real geometry: where it ran, they are notes, not reasons
CONTACT_ESTIMATES = (TIP_CLEARANCE_SHORT, OVERTRAVEL_REDUCED)
#: design-time facts the FEA verification judges on the real geometry (the beam stress
#: lowered so the predicted peak keeps the margin: the FEA's own margin is the check, and a
#: failure of it is a reason already): notes where the verification ran
VERIFIED_ESTIMATES = (STRESS_DERATED,)

RELEASED = "RELEASED"
NOT_FOR_MANUFACTURE = "NOT FOR MANUFACTURE"
#: reason of a drawing made outside ``springcad build`` (nobody assessed it)
NOT_ASSESSED = "release not assessed: drawing made outside `springcad build`"


@dataclass(frozen=True)
class ReleaseStatus:
    """The verdict of the release gate.

    Attributes:
        reasons: why the build is not released, one line each; empty when released.
        notes: facts worth reading that do not stop a release (e.g. a spring that
            would fail alone at its own limit but never reaches it in this stack).
    """

    reasons: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()
    ratings: tuple[str, ...] = ()
    """What each spring is rated for (its duty, Miner sum, safety factor, life at
    +-theta_max): written beside the stamp on the drawings, released or not."""

    @property
    def released(self) -> bool:
        return not self.reasons

    @property
    def stamp(self) -> str:
        """``"RELEASED"`` or ``"NOT FOR MANUFACTURE"``."""
        return RELEASED if self.released else NOT_FOR_MANUFACTURE

    def to_dict(self) -> dict:
        return {"status": self.stamp, "released": self.released,
                "reasons": list(self.reasons), "notes": list(self.notes),
                "ratings": list(self.ratings)}

    def summary_lines(self) -> list[str]:
        """The console summary: the verdict, then every reason and note."""
        head = (f"release: {self.stamp}" if self.released else
                f"release: {self.stamp} ({len(self.reasons)} reason"
                f"{'s' if len(self.reasons) != 1 else ''}; drawings are stamped)")
        return ([head] + [f"  - {r}" for r in self.reasons]
                + [f"  rating: {r}" for r in self.ratings]
                + [f"  note: {n}" for n in self.notes])


#: a drawing whose release nobody assessed is not for manufacture
UNASSESSED = ReleaseStatus((NOT_ASSESSED,))


def _check_reason(c) -> str:
    what = "manufacturability rule" if c.kind == "rule" else "check"
    return f"{what} {c.name} failed on {c.subject}: {c.message}".rstrip(": ")


def contact_notes(verification) -> list[str]:
    """The cam contact sweep's findings (ball leaving the flank, second contacts, stiffness
    departing from the linear FEA) of every spring of a verification, one line each.

    The FEA verification reports them without failing (``fea.verify``): they do not stop a
    release, but the console summary lists them with the release verdict.
    """
    out = []
    for name, spring in getattr(verification, "springs", {}).items():
        sweep = getattr(spring, "contact", None)
        for flag in getattr(sweep, "flags", None) or ():
            out.append(f"FEA contact sweep, spring {name}: {flag['message']}")
    return out


def _contact_assessed(verification) -> set[str]:
    """Springs whose contact at +-theta_max the FEA assessed with the profile tolerances
    (both ends with their clearances); its own failures are release reasons already."""
    out = set()
    for n, v in getattr(verification, "springs", {}).items():
        at_max = getattr(getattr(v, "contact", None), "at_max", None)
        ends = getattr(at_max, "ends", None) or {}
        if ends and all(getattr(e, "clearances", None) for e in ends.values()):
            out.add(n)
    return out


def release_status(job_design, verification=None, verify_skipped: bool = False,
                   checks=()) -> ReleaseStatus:
    """Judge a build.

    Args:
        job_design: the :class:`~springcad.design.job.JobDesign` that was built
            (after any FEA correction).
        verification: the FEA result (``.ok``, ``.failures()``, ``.notes()``), or None.
        verify_skipped: the user skipped the verification (``verify=False``).
        checks: every :class:`~springcad.geometry.checks.Check` of the build
            (geometry, manufacturability rules, export read-backs).

    Returns:
        the :class:`ReleaseStatus`; released only for a verified, warning-free
        build whose checks all passed.
    """
    reasons: list[str] = []
    notes: list[str] = []
    ratings: list[str] = []
    if verify_skipped:
        reasons.append(f"FEA verification skipped ({written('verify', False)}): beam-theory "
                       "design, stiffness and stress not verified")
    elif verification is None:
        reasons.append("no FEA verification result")
    else:
        if not verification.ok:
            reasons += [f"FEA verification failed: {f}" for f in verification.failures()] or [
                "FEA verification failed"]
        notes += list(verification.notes()) + contact_notes(verification)
        # the contact at full deflection (ball stress, clearances with the tolerances)
        reasons += [f"contact at full deflection: {r}"
                    for r in getattr(verification, "release_failures", list)()]
        # the duty at the verified stress field (a static/prototype duty releases as such)
        reasons += list(getattr(verification, "duty_failures", list)())
        ratings += list(getattr(verification, "ratings", list)())
        notes += [f"contact fatigue, {n}"
                  for n in getattr(verification, "contact_fatigue_notes", list)()]
    assessed = _contact_assessed(verification) if not verify_skipped else set()
    for w in job_design.release_warnings():
        name, _, text = w.partition(": ")
        if name.removeprefix("spring ") in assessed and text.startswith(CONTACT_ESTIMATES):
            notes.append(f"design estimate, checked by the contact FEA with the tolerances: {w}")
        elif verification is not None and not verify_skipped and text.startswith(
                VERIFIED_ESTIMATES):
            notes.append(f"design note, checked by the FEA verification: {w}")
        else:
            reasons.append(f"design warning: {w}")
    reasons += [_check_reason(c) for c in checks if not c.passed]
    return ReleaseStatus(tuple(dict.fromkeys(reasons)), tuple(dict.fromkeys(notes)),
                         tuple(ratings))
