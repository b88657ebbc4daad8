"""``synthesize``: sweep -> rank -> full design of the finalists -> FEA and build checks -> winner.

Library code: it never prints (messages go to ``progress``) and writes nothing but
the sweep's part files through the store; the CLI writes the report and the
winner's job TOML.
"""

from __future__ import annotations

import math
import time
from collections import Counter
from dataclasses import dataclass, field

from springcad.config.specs import DEFAULT_DUTY_PRESET
from springcad.export.release import release_status
from springcad.options import SYNTHESIS
from springcad.synthesis import ranking
from springcad.synthesis.finalists import (build_checks, full_design_summary, job_document,
                                           toml_text, verify_candidate)
from springcad.synthesis.runner import run_sweep
from springcad.progress import Progress, no_progress
from springcad.units import G_PER_KG, NMM_PER_NM
from springcad.version import stamp

SCHEMA = "springcad.synthesis/1"


@dataclass
class SynthesisResult:
    """Everything ``springcad synthesize`` reports."""

    requirements: object
    stats: object
    n_candidates: int
    n_feasible: int
    top: list
    families: list
    finalists: list
    verifications: dict = field(default_factory=dict)
    winner: dict | None = None
    winner_job: dict | None = None
    winner_status: str = ""
    timings_s: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """A winner exists and, when FEA and build checks ran on it, they passed."""
        if self.winner is None:
            return False
        v = self.verifications.get(int(self.winner["cid"]))
        return v is None or v["ok"]

    @property
    def winner_file(self) -> str:
        """The file the winner's job is written to: ``winner.toml`` when it passed (or
        skipped) the FEA and build checks, else ``closest.toml`` (the best verified
        finalist, which fails)."""
        return "winner.toml" if self.ok else "closest.toml"

    def winner_toml(self) -> str:
        req = self.requirements
        status = self.winner_status.replace("; ", ";\n  ")
        head = (f"Synthesized by springcad from {req.source or req.name}:\n  {status}\n"
                f"Candidate {int(self.winner['cid'])} ({self.winner['family']}, input "
                f"{self.winner['input']}) of {self.n_candidates} enumerated, "
                f"{self.n_feasible} feasible after screening.\n"
                + ("Build it with: springcad build <this file>" if self.ok else
                   "NOT a winner: no verified finalist passed; this is the best of them, and "
                   "springcad build refuses it for the reason above until it is changed"))
        return toml_text(self.winner_job, head)

    def to_dict(self) -> dict:
        req = self.requirements
        return {
            **stamp(SCHEMA),
            "requirements": {
                "name": req.name, "source": req.source,
                "stiffness_Nm_per_rad": req.target_stiffness_Nmm_per_rad / NMM_PER_NM,
                "stiffness_tolerance_pct": 100 * req.stiffness_tolerance,
                "deflection_rad": req.deflection_rad,
                "deflection_deg": math.degrees(req.deflection_rad),
                "max_outer_radius_mm": req.max_outer_radius_mm,
                "max_axial_length_mm": req.max_axial_length_mm,
                "materials": [m.name for m in req.materials],
                "design_stress_MPa": {m.name: req.design_stress_MPa(m) for m in req.materials},
                "yield_margin": req.yield_margin, "fatigue_margin": req.fatigue_margin,
                "required_yield_margin": {m.name: req.required_yield_margin(m)
                                          for m in req.materials},
                "allowed_peak_stress_MPa": {m.name: req.allowed_peak_MPa(m)
                                            for m in req.materials},
                "stress_concentration": req.stress_concentration,
                "objective": req.objective, "minimise": req.minimise},
            "sweep": self.stats.to_dict(),
            "n_candidates": self.n_candidates, "n_feasible": self.n_feasible,
            "top_screened": self.top, "families": self.families,
            "finalists_full_design": self.finalists,
            "finalist_failures": dict(Counter(f["failure"] for f in self.finalists
                                              if not f["ok"])),
            "fea": self.verifications,
            "winner": self.winner, "winner_status": self.winner_status,
            "winner_job": self.winner_job, "ok": self.ok, "timings_s": self.timings_s,
        }


def release_reasons(job_design, verification) -> list[str]:
    """Why ``springcad build``'s release gate would stamp a verified candidate NOT FOR
    MANUFACTURE, its geometry checks aside (:func:`build_checks` runs those): empty when
    it would be RELEASED (:func:`springcad.export.release.release_status`)."""
    return list(release_status(job_design, verification).reasons)


def verification_entry(req, cand: dict, fea_model: str, describe=None) -> dict:
    """What ``springcad build`` would decide about a candidate, as a report entry.

    The FEA (:func:`verify_candidate`, build's options) and then, if it passed, build's
    solids and checks on the FEA-corrected design (:func:`build_checks`). ``ok`` only when
    both pass and, with a duty in the requirements, build's release gate would stamp it
    RELEASED (the duty and the contact at full deflection hold). A failed solve or solid is a
    finding (``failures``), not a crash.

    Args:
        describe: ``describe(job_verification) -> str``, the entry's ``summary`` text
            (the API passes :func:`springcad.report.tables.verification_table`; rendering
            lives in the report layer); None: no text.
    """
    try:
        v, corrected = verify_candidate(req, cand, model=fea_model)
    except Exception as err:  # noqa: BLE001 - a failed solve is a finding, not a crash
        return {"ok": False, "failures": [f"FEA: {type(err).__name__}: {err}"], "notes": [],
                "summary": "", "springs": {}, "build_checks": None}
    entry = {"ok": v.ok, "failures": v.failures(), "notes": v.notes(),
             "summary": describe(v) if describe else "",
             "springs": {n: {"stiffness_fea_Nm_per_rad": sv.stiffness_fea_Nmm_per_rad / NMM_PER_NM,
                             "peak_von_mises_MPa": sv.peak_von_mises_MPa,
                             "peak_region": sv.run.peak_result.peak_region,
                             "yield_margin": sv.yield_margin,
                             "width_scale": sv.design.width_scale}
                         for n, sv in v.springs.items()},
             "mass_kg": corrected.stack.mass_kg, "build_checks": None}
    # build's release gate on the verified springs (the duty of the flexures and tip balls,
    # the contact at full deflection with the tolerances, the design's warnings such as cam
    # interfaces that can jam): with a duty in the requirements a finalist that would build
    # NOT FOR MANUFACTURE is not a winner; without one (the job gets springcad's default
    # duty at build) the first finalist build would release is preferred and else the gate's
    # reasons are named in the winner's status (:func:`synthesize`)
    stops = release_reasons(corrected, v) if v.ok else []
    entry["release_failures"] = stops
    if stops and req.duty is not None:
        entry["ok"] = False
        entry["failures"] = entry["failures"] + [f"release: {f}" for f in stops]
    if not entry["ok"]:
        return entry
    try:
        checks = build_checks(corrected)
    except Exception as err:  # noqa: BLE001 - a part that cannot be made is a finding
        checks = {"ok": False, "summary": "", "failures": [f"{type(err).__name__}: {err}"]}
    entry["build_checks"] = checks
    entry["ok"] = checks["ok"]
    entry["failures"] = entry["failures"] + [f"build checks: {f}" for f in checks["failures"]]
    return entry


def synthesize(req, space, store, client, *, finalists: int = SYNTHESIS.finalists,
               max_finalists: int = SYNTHESIS.max_finalists,
               verify_top: int = SYNTHESIS.verify_top, verify: bool = True,
               fea_model: str = SYNTHESIS.fea_model,
               progress: Progress = no_progress, describe=None) -> SynthesisResult:
    """Run the whole synthesis for requirements ``req``.

    Args:
        space: :class:`~springcad.synthesis.candidates.CandidateSpace` of ``req``.
        store: the run's :class:`~springcad.synthesis.store.ResultStore`.
        client: a :class:`distributed.Client` (sweep and full designs run on it).
        finalists: screened stacks given the full design per round (Dask tasks), best
            first; while no finalist passes, the next round goes further down the ranking.
        max_finalists: most stacks given the full design in all.
        verify_top: how many of the full-design-feasible finalists get build's FEA and
            checks (best first); the winner is the first that passes both.
        verify: run the FEA and build checks at all.
        fea_model: :class:`fea.study.VerifyOptions` model for the finalists ("2d3d":
            ``springcad build``'s; "2d": faster, without the 3D factor).
        progress: ``progress(message, fraction=None)``: the sweep's counts
            (:func:`run_sweep`) and one-line status messages.
        describe: ``describe(job_verification) -> str``, the text kept (and shown) for
            each verified finalist (:func:`verification_entry`); None: none.
    """
    t = {}
    t0 = time.perf_counter()
    stats = run_sweep(space, store, client, progress)
    t["sweep"] = time.perf_counter() - t0
    cols = store.read()
    col, minimise = req.objective_column, req.minimise
    order = ranking.rank(cols, col, minimise)
    families = ranking.family_report(cols, col, minimise)
    top = ranking.distinct(cols, order, max(20, max_finalists))
    result = SynthesisResult(req, stats, len(cols["cid"]), int(cols["feasible"].sum()), top,
                             families, [])  # top: distinct stacks, best first
    progress(f"{result.n_feasible} of {result.n_candidates} candidates feasible after screening")
    if not top:
        result.winner_status = "no feasible stack"
        result.timings_s = t
        return result
    # full design of the finalists, on the cluster, down the ranking until one passes
    t0 = time.perf_counter()
    rows, summaries = [], []
    limit = min(len(top), max(max_finalists, 1))
    while len(rows) < limit and not any(s["ok"] for s in summaries):
        batch = top[len(rows):min(len(rows) + max(finalists, 1), limit)]
        progress(f"full design of screened stacks {len(rows) + 1}-{len(rows) + len(batch)} "
            f"of {len(top)}")
        futures = client.map(full_design_summary, [req] * len(batch), batch, pure=False)
        summaries += client.gather(futures)
        rows += batch
    t["full_design"] = time.perf_counter() - t0
    result.finalists = summaries
    result.top = top[:max(20, len(rows))]
    good = [(r, s) for r, s in zip(rows, summaries) if s["ok"]]
    key = "mass_kg" if col == "mass_kg" else col
    if good:
        good.sort(key=lambda rs: (rs[1].get(key, rs[0][col]) if minimise
                                  else -rs[1].get(key, rs[0][col]), rs[1]["mass_kg"]))
    else:
        counts = Counter(s["failure"] for s in summaries)
        result.winner_status = (
            f"none of the {len(summaries)} best screened stacks passes the full design ("
            + ", ".join(f"{n} on {c}" for c, n in counts.most_common()) + "); first: "
            + summaries[0]["error"])
        result.timings_s = t
        return result
    winner, status = good[0][0], "full design passed; FEA and build checks not run"
    if verify:
        t0 = time.perf_counter()
        status, unreleased = None, None
        for r, s in good[:verify_top]:
            progress(f"FEA ({fea_model}) and build checks of candidate {int(r['cid'])} "
                f"({r['family']}, {G_PER_KG * s['mass_kg']:.1f} g)")
            entry = verification_entry(req, r, fea_model, describe)
            result.verifications[int(r["cid"])] = entry
            progress(entry["summary"] or "; ".join(entry["failures"]))
            if entry["ok"] and not entry.get("release_failures"):
                winner, status = r, f"FEA ({fea_model}) and build checks passed"
                break
            if entry["ok"] and unreleased is None:
                unreleased = (r, entry)
        if status is None and unreleased is not None:
            winner, entry = unreleased
            status = (f"FEA ({fea_model}) and build checks passed, but `springcad build` will "
                      f"stamp it NOT FOR MANUFACTURE (no verified finalist passes build's release"
                      f" gate; the requirements declare no duty, so the job gets springcad's "
                      f"default duty, preset '{DEFAULT_DUTY_PRESET}'): "
                      + "; ".join(entry["release_failures"]) + "; declare a [duty] in the "
                      "requirements to rank the stacks for it (preset = \"static\" for a "
                      "prototype)")
        if status is None:
            winner = good[0][0]
            first = result.verifications[int(winner["cid"])]
            status = ("FEA or build checks FAILED for every verified finalist; best shown. "
                      + "; ".join(first["failures"]))
        t["fea"] = time.perf_counter() - t0
    result.winner = winner
    result.winner_status = status
    result.winner_job = job_document(req, winner)
    result.timings_s = t
    return result
