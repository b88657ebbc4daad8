"""The studies of the public API: the paper validation, synthesis and the design-space map.

``validate_paper`` predicts the paper's Table I configurations and traces the
residual; ``synthesize`` searches every stack of a requirement for the best one and
writes the winner's job config; ``explore`` maps the reachable peak torque against
deflection (paper Fig. 8) with its Pareto fronts. ``springcad paper``, ``synthesize``
and ``explore`` are these calls and a printout.

Units: stiffness N*m/rad, angles rad, lengths mm, masses kg.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from springcad.options import EXPLORE, SYNTHESIS, api_door, check_choice, check_number, refuse
from springcad.progress import Tracker, no_progress
from springcad.report.jsonio import write_json
from springcad.report.tables import verification_table
from springcad.stages import stage
from springcad.version import stamp

__all__ = ["explore", "synthesize", "validate_paper"]

#: schema of ``explore.json``
EXPLORE_SCHEMA = "springcad.explore/1"


@api_door
def validate_paper(data_dir=None, templates_dir=None, use_fea: bool = True, progress=None):
    """Predict every Table I configuration of the paper and explain the stiffness residual.

    Args:
        data_dir: folder with the paper's CSV tables (default: the shipped copy).
        templates_dir: folder with the ``paper_*.toml`` templates (default: the shipped ones).
        use_fea: quantify geometry, contact and width effects with the FEA (~30 s);
            otherwise beam theory only.
        progress: optional ``callable(message, fraction=None)``.

    Returns:
        The :class:`springcad.validation.paper.Validation` (``to_dict()`` is
        ``validation.json``; :func:`springcad.report.paper_report.write_paper_report`
        writes the report).

    Raises:
        ConfigError: a table or template is missing.
        StageError: the design math or the FEA failed (names the step).
    """
    from springcad.validation.paper import validate_paper as _validate

    track = Tracker(progress)
    with stage("verify" if use_fea else "design", lambda: track.last):
        return _validate(data_dir, templates_dir, use_fea=use_fea, progress=track)


def _announce(progress, space, store) -> None:
    progress(f"{space.total} candidate stacks in {store.n_batches} batches "
             f"({len(store.pending_batches())} to evaluate)")


def _check_cluster(workers, batch_size) -> None:
    check_number("batch_size", batch_size, 1, float("inf"), integer=True)
    if workers is not None:
        check_number("workers", workers, 1, float("inf"), integer=True)


@api_door
def synthesize(requirements, out=None, *, scheduler: str | None = None,
               workers: int | None = None, batch_size: int = SYNTHESIS.batch_size,
               restart: bool = False, finalists: int = SYNTHESIS.finalists,
               max_finalists: int = SYNTHESIS.max_finalists,
               verify_top: int = SYNTHESIS.verify_top, verify: bool = True,
               fea_model: str = SYNTHESIS.fea_model, progress=None):
    """The best stack meeting a requirement: sweep, rank, full design, FEA and checks.

    Writes ``out/parts/*.parquet`` (every candidate; a rerun resumes), ``out/synthesis.json``
    and, when a finalist passed, ``out/winner.toml`` (a job config ``build`` accepts); when
    every verified finalist failed, the best of them as ``out/closest.toml`` (its header
    says why it fails).

    Args:
        requirements: a requirements TOML path (see ``templates/requirements_*.toml``).
        out: the run folder (default ``outputs/<requirements name>/``).
        scheduler: address of an existing Dask cluster; default a local one.
        workers: local cluster workers (default: every core).
        batch_size: candidates per Dask task and per Parquet part.
        restart: discard an earlier run's parts in ``out`` instead of resuming.
        finalists: screened stacks given the full design per round, best first.
        max_finalists: most stacks given the full design in all.
        verify_top: full-design-feasible finalists given build's FEA and checks.
        verify: run the FEA and checks at all.
        fea_model: FEA model of the finalists, ``"2d3d"`` (build's) or ``"2d"``.
        progress: optional ``callable(message, fraction=None)``: one-line status
            messages and the sweep's counts (a :class:`springcad.progress.Count` message
            with its fraction).

    Returns:
        The :class:`springcad.synthesis.pipeline.SynthesisResult` (``.ok``, ``.winner``).
    """
    from springcad.synthesis.candidates import CandidateSpace
    from springcad.synthesis.pipeline import synthesize as _synthesize
    from springcad.synthesis.requirements import load_requirements
    from springcad.synthesis.runner import dask_client
    from springcad.synthesis.store import ResultStore

    _check_cluster(workers, batch_size)
    for name, value in (("finalists", finalists), ("max_finalists", max_finalists),
                        ("verify_top", verify_top)):
        check_number(name, value, 1 if name != "verify_top" else 0, float("inf"), integer=True)
    check_choice("fea_model", fea_model, ("2d3d", "2d"))
    req = load_requirements(requirements)
    space = CandidateSpace.from_requirements(req)
    out = Path(out) if out is not None else Path("outputs") / Path(requirements).stem
    store = ResultStore(out, req.fingerprint(), space.total, batch_size, overwrite=restart,
                        resume=not restart)
    progress = progress or no_progress
    _announce(progress, space, store)
    with dask_client(scheduler, workers) as client:
        result = _synthesize(req, space, store, client, finalists=finalists,
                             max_finalists=max_finalists, verify_top=verify_top, verify=verify,
                             fea_model=fea_model, progress=progress,
                             describe=verification_table)
    write_json(out / "synthesis.json", result.to_dict())
    if result.winner is not None:
        (out / result.winner_file).write_text(result.winner_toml())
    return result


@api_door
def explore(out=Path("outputs") / "explore", *,
            stiffness_Nm_per_rad=EXPLORE.stiffness_Nm_per_rad,
            deflection_rad=EXPLORE.deflection_rad, max_disks: int = EXPLORE.max_disks,
            envelope_radius_mm: float = EXPLORE.envelope_radius_mm,
            thickness_mm=EXPLORE.thickness_mm, contact_radius_mm=EXPLORE.contact_radius_mm,
            material: str = EXPLORE.material,
            stress_concentration: float = EXPLORE.stress_concentration,
            scheduler: str | None = None,
            workers: int | None = None, batch_size: int = SYNTHESIS.batch_size,
            restart: bool = False, progress=None) -> dict:
    """Map the reachable peak torque against deflection for stacks of 1 ... N disks.

    Writes ``out/parts/*.parquet`` (every candidate; resumable), ``region.parquet``,
    ``pareto_mass.parquet``, ``pareto_energy.parquet``, their PNG plots and
    ``explore.json`` (the returned summary).

    Args:
        out: the run folder.
        stiffness_Nm_per_rad, deflection_rad: ``(min, max, count)`` log-spaced grids.
        max_disks: stacks of 1 ... ``max_disks`` identical disks (1 to 20).
        envelope_radius_mm: envelope radius, bushing included (mm).
        thickness_mm, contact_radius_mm: disk parameters tried at every target (mm).
        material: built-in material name.
        stress_concentration: first beam stress = yield / this (>= 1).
        scheduler, workers, batch_size, restart: the Dask run, as in :func:`synthesize`.
        progress: status messages and the sweep's counts, as in :func:`synthesize`.

    The defaults are :data:`springcad.options.EXPLORE` (``springcad explore``'s); an option
    given as None takes its default.

    Returns:
        The ``explore.json`` summary (grid, sweep statistics, per number of disks).
    """
    from springcad.report.synthesis_plots import (plot_energy_front, plot_mass_fronts,
                                                  plot_region, write_parquet)
    from springcad.synthesis.explore import (ExploreGrid, energy_front, mass_fronts,
                                             reachable_region)
    from springcad.synthesis.runner import dask_client, run_sweep
    from springcad.synthesis.store import ResultStore

    _check_cluster(workers, batch_size)
    given = {k: v for k, v in dict(
        stiffness_Nm_per_rad=stiffness_Nm_per_rad, deflection_rad=deflection_rad,
        max_disks=max_disks, envelope_radius_mm=envelope_radius_mm, thickness_mm=thickness_mm,
        contact_radius_mm=contact_radius_mm, material=material,
        stress_concentration=stress_concentration).items() if v is not None}
    for name in ("stiffness_Nm_per_rad", "deflection_rad"):
        if name in given:
            given[name] = _grid_range(name, given[name])
    for name in ("thickness_mm", "contact_radius_mm"):
        if name in given:
            given[name] = tuple(given[name])
    grid = ExploreGrid(**given)
    check_number("max_disks", grid.max_disks, 1, 20, integer=True)
    check_number("stress_concentration", grid.stress_concentration, 1.0, float("inf"))
    for name in ("thickness_mm", "contact_radius_mm"):
        for value in getattr(grid, name):
            check_number(name, value, 0.0, float("inf"), low_open=True, unit=" mm")
    check_number("envelope_radius_mm", grid.envelope_radius_mm, 0.0, float("inf"),
                 low_open=True, unit=" mm")
    space = grid.space()
    fingerprint = hashlib.sha256(json.dumps(grid.__dict__, sort_keys=True,
                                            default=str).encode()).hexdigest()[:16]
    out = Path(out)
    store = ResultStore(out, fingerprint, space.total, batch_size, overwrite=restart,
                        resume=not restart)
    progress = progress or no_progress
    _announce(progress, space, store)
    with dask_client(scheduler, workers) as client:
        stats = run_sweep(space, store, client, progress)
    cols = store.read()
    region = reachable_region(cols)
    fronts = mass_fronts(cols)
    efront = energy_front(cols)
    write_parquet(out / "region.parquet", region)
    write_parquet(out / "pareto_mass.parquet", fronts)
    write_parquet(out / "pareto_energy.parquet", efront)
    plot_region(region, out / "region.png",
                f"Reachable region, {grid.material}, R {grid.envelope_radius_mm:g} mm envelope")
    plot_mass_fronts(fronts, out / "pareto_mass.png")
    plot_energy_front(cols, efront, out / "pareto_energy.png")

    def per_disks(n: int) -> dict:
        here = region["n_disks"] == n
        return {"n_disks": n, "feasible": int((cols["feasible"] & (cols["n_disks"] == n)).sum()),
                "max_deflection_rad": float(region["deflection_rad"][here].max())
                if here.any() else None,
                "max_peak_torque_Nm": float(region["max_peak_torque_Nm"][here].max())
                if here.any() else None}

    summary = {**stamp(EXPLORE_SCHEMA), "grid": grid.__dict__, "sweep": stats.to_dict(),
               "n_candidates": len(cols["cid"]), "n_feasible": int(cols["feasible"].sum()),
               "per_n_disks": [per_disks(n) for n in range(1, grid.max_disks + 1)]}
    write_json(out / "explore.json", summary)
    return summary


def _grid_range(name: str, value) -> tuple[float, float, int]:
    """``(min, max, count)`` from a tuple or a ``"MIN:MAX:COUNT"`` string.

    Raises:
        OptionError: a ConfigError naming the parameter, unless 0 < MIN < MAX and COUNT >= 2.
    """
    try:
        lo, hi, n = value.split(":") if isinstance(value, str) else value
        lo, hi, n = float(lo), float(hi), int(n)
    except (TypeError, ValueError):
        raise refuse(name, value, "is MIN:MAX:COUNT, e.g. 5:500:24") from None
    if not (0 < lo < hi and n >= 2):
        raise refuse(name, value, "needs 0 < MIN < MAX and COUNT >= 2")
    return lo, hi, n
