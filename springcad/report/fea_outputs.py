"""The files of an FEA verification: ``fea.json``, per-spring .vtu fields and PNG renders."""

from __future__ import annotations

import contextlib
import math
from pathlib import Path

from springcad.parallel import Pending, beside, enabled
from springcad.progress import Progress, no_progress
from springcad.report.jsonio import write_json


def write_outputs(result, folder: Path, render: bool = True,
                  progress: Progress = no_progress, cache=None,
                  beside_renders: bool = False) -> list[Path]:
    """``fea.json`` plus, per spring, .vtu files and PNG renders into ``folder``.

    Args:
        progress: ``progress(message, fraction=None)``, called per spring.
        cache: a :class:`springcad.cache.Cache` holding the files of spring verifications
            written before (keyed by the verification's own cache key), or None.
        beside_renders: the von Mises renders (VTK and matplotlib, about half the work) are
            drawn by a second process while this one writes the rest
            (:func:`springcad.parallel.beside`; here where steps do not run in a second
            process, or when the cache holds them all). The same files, listed in the same
            order.
    """
    written = []
    if render:
        springs = list(result.springs.items())
        beside_renders = (beside_renders and enabled()
                          and not all(_stored(cache, "fea-von-mises", name, v)
                                      for name, v in springs))
        if beside_renders:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot  # noqa: F401  (imported once, before the fork)
        run = beside if beside_renders else _here
        with run(_von_mises_all, springs, folder, cache, progress=progress) as renders:
            own = []
            for k, (name, v) in enumerate(springs):
                progress(f"writing {name} .vtu and PNG renders", k / len(springs))
                own.append(_cached(cache, "fea-files", name, v, folder,
                                   lambda: _spring_files(name, v, folder), progress))
            duty = []
            for name, v in springs:
                if v.duty_check is not None:
                    duty += _cached(cache, "fea-duty-files", name, v, folder,
                                    lambda: _duty_files(name, v, folder), progress)
            pictures = renders.result()
        for (name, _), files in zip(springs, own):
            # the order of one process writing them all: the 2D field, its renders, the rest
            vm = pictures[name]
            written += (files[:1] + vm + files[1:]) if vm else files
        written += duty
    write_json(folder / "fea.json", result.to_dict())
    written.append(folder / "fea.json")
    return written


@contextlib.contextmanager
def _here(func, *args, progress=no_progress):
    """``func``'s result, computed here before the block (:func:`beside`'s serial form)."""
    yield Pending(value=func(*args, progress=progress))


def _stored(cache, kind: str, name: str, v) -> bool:
    """Whether :func:`_cached` would take these files from the cache."""
    key = getattr(v, "cache_key", None)
    return cache is not None and key is not None and cache.has(cache.key(kind, key, name))


def _cached(cache, kind: str, name: str, v, folder: Path, write, progress) -> list[Path]:
    """The files ``write()`` writes for spring verification ``v``, from the cache when ``v``
    came through it (it carries ``cache_key``) and its files were written before."""
    key = getattr(v, "cache_key", None)
    if cache is None or key is None:
        return write()
    paths, _ = cache.files(kind, (key, name), folder, lambda: (write(), None),
                           lambda: progress(f"{name}: {kind} from the cache", None))
    return paths


def _von_mises_all(springs, folder: Path, cache, progress=no_progress) -> dict:
    """Per spring name, the von Mises PNGs of :func:`_von_mises_files`, through the cache."""
    return {name: _cached(cache, "fea-von-mises", name, v, folder,
                          lambda: _von_mises_files(name, v, folder), progress)
            for name, v in springs}


def _von_mises_files(name: str, v, folder: Path) -> list[Path]:
    """The von Mises PNGs of one spring (whole sector and zoomed on the peak), when its
    finest 2D mesh kept its fields."""
    r2 = v.run.study.finest
    if not r2.fields:
        return []
    from springcad.report.fea_png import render_von_mises

    title = f"{name} at {math.degrees(v.design.max_deflection_rad):.1f}° ({v.model})"
    return [render_von_mises(r2, folder / f"{name}_von_mises.png", title,
                             reported_peak_MPa=v.peak_von_mises_MPa),
            render_von_mises(r2, folder / f"{name}_von_mises_peak.png", f"{title}, zoomed",
                             zoom_mm=max(1.0, 1.5 * v.design.root_fillet_radius_mm),
                             reported_peak_MPa=v.peak_von_mises_MPa)]


def _spring_files(name: str, v, folder: Path) -> list[Path]:
    """The .vtu fields and the contact PNG of one spring (the 2D field first)."""
    from springcad.report.fea_vtu import write_vtu

    written = []
    r2 = v.run.study.finest
    r3 = v.run.check3d[-1] if v.run.check3d else None
    if r2.fields:
        tag = "3d" if v.model == "3d" else "2d"
        written.append(write_vtu(r2, folder / f"{name}_sector_{tag}.vtu"))
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
