"""The files of an FEA verification: ``fea.json``, per-spring .vtu fields and PNG renders."""

from __future__ import annotations

import math
from pathlib import Path

from springcad.progress import Progress, no_progress
from springcad.report.jsonio import write_json


def write_outputs(result, folder: Path, render: bool = True,
                  progress: Progress = no_progress) -> list[Path]:
    """``fea.json`` plus, per spring, .vtu files and PNG renders into ``folder``.

    Args:
        progress: ``progress(message, fraction=None)``, called per spring.
    """
    written = []
    if render:
        from springcad.report.fea_png import render_von_mises
        from springcad.report.fea_vtu import write_vtu

        for k, (name, v) in enumerate(result.springs.items()):
            progress(f"writing {name} .vtu and PNG renders", k / len(result.springs))
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
        from springcad.report.duty_png import render_duty

        for name, v in result.springs.items():
            check = v.duty_check
            if check is not None:
                written += render_duty(check.to_dict(), folder, name, v.yield_strength_MPa)
    write_json(folder / "fea.json", result.to_dict())
    written.append(folder / "fea.json")
    return written
