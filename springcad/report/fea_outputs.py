"""The files of an FEA verification: ``fea.json``, per-spring .vtu fields and PNG renders."""

from __future__ import annotations

import math
from pathlib import Path

from springcad.progress import Progress, no_progress
from springcad.report.jsonio import write_json


def write_outputs(result, folder: Path, render: bool = True,
                  progress: Progress = no_progress, cache=None) -> list[Path]:
    """``fea.json`` plus, per spring, .vtu files and PNG renders into ``folder``.

    Args:
        progress: ``progress(message, fraction=None)``, called per spring.
        cache: a :class:`springcad.cache.Cache` holding the files of spring verifications
            written before (keyed by the verification's own cache key), or None.
    """
    written = []
    if render:
        for k, (name, v) in enumerate(result.springs.items()):
            progress(f"writing {name} .vtu and PNG renders", k / len(result.springs))
            written += _cached(cache, "fea-files", name, v, folder,
                               lambda: _spring_files(name, v, folder), progress)
        for name, v in result.springs.items():
            if v.duty_check is not None:
                written += _cached(cache, "fea-duty-files", name, v, folder,
                                   lambda: _duty_files(name, v, folder), progress)
    write_json(folder / "fea.json", result.to_dict())
    written.append(folder / "fea.json")
    return written


def _cached(cache, kind: str, name: str, v, folder: Path, write, progress) -> list[Path]:
    """The files ``write()`` writes for spring verification ``v``, from the cache when ``v``
    came through it (it carries ``cache_key``) and its files were written before."""
    key = getattr(v, "cache_key", None)
    if cache is None or key is None:
        return write()
    paths, _ = cache.files(kind, (key, name), folder, lambda: (write(), None),
                           lambda: progress(f"{name}: {kind} from the cache", None))
    return paths


def _spring_files(name: str, v, folder: Path) -> list[Path]:
    """The .vtu fields and the von Mises and contact PNGs of one spring."""
    from springcad.report.fea_png import render_von_mises
    from springcad.report.fea_vtu import write_vtu

    written = []
    r2 = v.run.study.finest
    r3 = v.run.check3d[-1] if v.run.check3d else None
    if r2.fields:
        tag = "3d" if v.model == "3d" else "2d"
        written.append(write_vtu(r2, folder / f"{name}_sector_{tag}.vtu"))
        written.append(render_von_mises(
            r2, folder / f"{name}_von_mises.png",
            f"{name} at {math.degrees(v.design.max_deflection_rad):.1f}° ({v.model})",
            reported_peak_MPa=v.peak_von_mises_MPa))
        written.append(render_von_mises(
            r2, folder / f"{name}_von_mises_peak.png",
            f"{name} at {math.degrees(v.design.max_deflection_rad):.1f}° ({v.model}), zoomed",
            zoom_mm=max(1.0, 1.5 * v.design.root_fillet_radius_mm),
            reported_peak_MPa=v.peak_von_mises_MPa))
    if r3 is not None and r3.fields:
        written.append(write_vtu(r3, folder / f"{name}_sector_3d.vtu"))
    if getattr(v, "contact", None) is not None:
        from springcad.report.contact_png import render_contact

        written.append(render_contact(
            v.contact, folder / f"{name}_contact.png",
            f"{name}: rigid cam turned to +-{math.degrees(v.contact.max_deflection_rad):.1f}"
            " deg against the sector (2D plane stress, nonlinear kinematics)"))
    return written


def _duty_files(name: str, v, folder: Path) -> list[Path]:
    """The duty PNGs of one spring."""
    from springcad.report.duty_png import render_duty

    return list(render_duty(v.duty_check.to_dict(), folder, name, v.yield_strength_MPa))
