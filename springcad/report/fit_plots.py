"""The PNG plots of ``springcad fit`` (matplotlib, Agg backend, imported only here).

* ``torque_deflection.png``: measured torque against deflection with the
  linear, deadband, logit and final loop models;
* ``crossover.png``: the same around zero torque (as the paper's Fig. 6);
* ``residual_step_<k>_<effect>.png``: the residual against deflection and
  against time before and after each step of the loop;
* ``energy_by_cycle.png``: energy loss of each loading–unloading cycle;
* ``unexplained.png``: where the structure left in the residual lives.

Units: N·m, rad, s.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from springcad.fit.analysis import FitResult, final_label
from springcad.fit.loop import State
from springcad.report.mpl import pyplot

#: at most this many points are drawn per scatter (evenly decimated)
_MAX_POINTS = 6000


def _every(n: int) -> slice:
    return slice(None, None, max(1, math.ceil(n / _MAX_POINTS)))


def plot_all(result: FitResult, out_dir: Path) -> dict[str, Path]:
    plt = pyplot()
    images = {}
    try:
        images["torque_deflection"] = _plot_models(plt, result, out_dir / "torque_deflection.png",
                                                   zoom=False)
        images["crossover"] = _plot_models(plt, result, out_dir / "crossover.png", zoom=True)
        images["energy"] = _plot_energy(plt, result, out_dir / "energy_by_cycle.png")
        steps = result.loop.steps
        if steps:
            for i, s in enumerate(steps):
                images[f"step{i}"] = _plot_residuals(
                    plt, result, s.before, s.after,
                    out_dir / f"residual_step_{i + 1}_{s.effect}.png",
                    f"step {i + 1}: {s.action} {s.effect}")
        else:
            images["step_none"] = _plot_residuals(plt, result, result.loop.baseline, None,
                                                  out_dir / "residual_linear.png",
                                                  "linear model (no effect added)")
        if result.loop.localisation is not None:
            images["unexplained"] = _plot_unexplained(plt, result, out_dir / "unexplained.png")
    finally:
        plt.close("all")
    return images


#: drawing order: model lines and points below, the measured data on top (a reader judges
#: the models against the data, so the data must never be hidden)
ZORDER_MODELS, ZORDER_FINAL, ZORDER_DATA = 2, 3, 4


def _plot_models(plt, result: FitResult, path: Path, zoom: bool) -> Path:
    fig = models_figure(plt, result, zoom)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def models_figure(plt, result: FitResult, zoom: bool):
    """Torque against deflection: the measured data above the paper models and the final model.

    Args:
        plt: ``matplotlib.pyplot`` (Agg).
        result: the fit.
        zoom: show the crossover region around zero torque only.

    Returns:
        The figure (the caller saves and closes it).
    """
    sig, rec = result.signals, result.record
    th, tq = rec.deflection_rad, rec.torque_Nm
    final = result.loop.final
    pred_final = final.model.predict(final.x, sig, np.arange(sig.n))
    fig, ax = plt.subplots(figsize=(7, 5))
    sel = _every(th.size)
    ax.plot(th[sel], tq[sel], ".", ms=1.6, color="0.15", alpha=0.35, label="measured",
            rasterized=True, zorder=ZORDER_DATA)
    grid = np.linspace(th.min(), th.max(), 2001)
    styles = {"linear": "C0", "deadband": "C1", "logit": "C2"}
    for name, m in result.paper_models.items():
        ax.plot(grid, m.predict(grid), color=styles[name], lw=1.4, zorder=ZORDER_MODELS,
                label=f"{name} (NRMSE {m.nrmse_pct:.2f} %)")
    if not result.loop.no_spring:
        ax.plot(th[sel], pred_final[sel], ".", ms=1.0, color="C3", alpha=0.5, zorder=ZORDER_FINAL,
                label=f"final: {final_label(result.loop)} (NRMSE {result.nrmse_pct(final):.2f} %)")
    if zoom:
        b = max(result.paper_models["deadband"].backlash_rad, 0.02 * sig.scales.theta_ref)
        half = 3.0 * b
        k = result.paper_models["deadband"].stiffness_Nm_per_rad
        ax.set_xlim(-half, half)
        ax.set_ylim(-k * half, k * half)
        ax.set_title("Crossover region (zoom)")
    else:
        ax.set_title("Torque against deflection")
    ax.set_xlabel("deflection (rad)")
    ax.set_ylabel("torque (N·m)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", markerscale=4)
    fig.tight_layout()
    return fig


def _plot_energy(plt, result: FitResult, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    amps = [c.sign * c.amplitude_rad for c in result.cycles]
    ax.plot(amps, [c.loss_pct for c in result.cycles], "o", color="0.5",
            label="apparent (measured loop area)")
    en = result.energy
    if en.pct is not None:
        a = max(abs(x) for x in amps)
        for side in (-1, 1):
            ax.errorbar([side * a], [en.pct], yerr=[[en.pct - en.ci_low], [en.ci_high - en.pct]],
                        fmt="s", color="C3", capsize=3,
                        label="hysteresis model, largest cycles (95 % CI)" if side > 0 else None)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.legend(fontsize=7)
    ax.set_xlabel("cycle amplitude (rad)")
    ax.set_ylabel("energy loss (%)")
    ax.set_title("Energy loss per loading–unloading cycle")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_residuals(plt, result: FitResult, before: State, after: State | None, path: Path,
                    title: str) -> Path:
    sig = result.signals
    idx = np.arange(sig.n)
    states = [("before", before)] + ([("after", after)] if after is not None else [])
    fig, axes = plt.subplots(len(states), 2, figsize=(10, 3.2 * len(states)), squeeze=False)
    sel = _every(sig.n)
    for row, (label, st) in enumerate(states):
        r = st.model.residual(st.x, sig, idx)
        keep = np.ones(sig.n, bool) if st.mask is None else ~st.mask
        for col, (x, xlabel) in enumerate(((sig.theta, "deflection (rad)"), (sig.t, "time (s)"))):
            ax = axes[row, col]
            ax.plot(x[sel][keep[sel]], r[sel][keep[sel]], ".", ms=1.0, rasterized=True)
            if st.mask is not None and st.mask.any():
                ax.plot(x[st.mask], r[st.mask], "x", ms=3, color="C3", label="glitches")
                ax.legend(fontsize=7)
            ax.axhline(0.0, color="k", lw=0.5)
            ax.set_xlabel(xlabel)
            ax.set_ylabel("residual (N·m)")
            ax.set_title(f"{label}: {st.label} (NRMSE {result.nrmse_pct(st):.2f} %)", fontsize=8)
            ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _plot_unexplained(plt, result: FitResult, path: Path) -> Path:
    """Residual of the final model in time, in deflection (per direction) and as spectra,
    with the localised patterns marked."""
    loc = result.loop.localisation
    data, findings = loc["data"], loc["findings"]
    sig, final = result.signals, result.loop.final
    idx = final.inliers(np.arange(sig.n))
    r = final.model.residual(final.x, sig, idx)
    ang = data.get("angle_spectrum")
    fig, axes = plt.subplots(2, 2, figsize=(11, 7))
    sel = _every(idx.size)
    ax = axes[0, 0]
    ax.plot(sig.t[idx][sel], r[sel], ".", ms=1.0, color="0.6", rasterized=True, label="residual")
    tc = data["time_component"]
    if any(tc["torque_Nm"]):
        ax.plot(tc["t_s"], tc["torque_Nm"], "-", color="C3", lw=1.0, label="time pattern found")
    for f in findings:
        if "at_s" in f:
            ax.axvline(f["at_s"], color="C3", ls="--", lw=1.0)
            ax.annotate(f"change at {f['at_s']:.3g} s", (f["at_s"], ax.get_ylim()[1]),
                        fontsize=7, color="C3", va="top")
    ax.set_xlabel("time (s)")
    ax.set_title("in time", fontsize=9)
    ax.legend(fontsize=7, markerscale=4)
    ax = axes[0, 1]
    d = data["deflection"]
    centre = np.asarray(d["centre_rad"])
    for key, label, colour in (("up", "deflection increasing", "C0"),
                               ("down", "deflection decreasing", "C1")):
        ax.plot(centre, np.asarray(d[f"mean_{key}_Nm"], float), "-o", ms=2, lw=1, color=colour,
                label=label)
    for f in findings:
        if "beyond_rad" in f:
            for side in (-1, 1):
                ax.axvspan(side * f["beyond_rad"], side * abs(centre).max(), color="C3",
                           alpha=0.12)
        if "within_rad" in f:
            ax.axvspan(-f["within_rad"], f["within_rad"], color="C3", alpha=0.12)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("deflection (rad)")
    ax.set_title("in deflection: mean residual per bin and direction", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    ts = data["time_spectrum"]
    f_hz = np.asarray(ts["frequency_hz"])
    ax.semilogy(f_hz[1:], np.asarray(ts["amplitude_Nm"])[1:], lw=0.6, label="residual")
    ax.semilogy(f_hz[1:], np.asarray(ts["level_Nm"])[1:], lw=1.0, color="k",
                label="local noise level")
    for f in findings:
        if f["kind"] == "periodic_time":
            ax.axvline(f["frequency_hz"], color="C3", ls="--", lw=1.0)
    ax.set_xlabel("frequency (Hz)")
    ax.set_title("periodic in time? (amplitude spectrum)", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    if ang:
        ax.plot(ang["cycles_per_rad"][1:], ang["amplitude_Nm"][1:], lw=0.8)
        for f in findings:
            if f["kind"] == "periodic_angle":
                ax.axvline(1.0 / f["period_rad"], color="C3", ls="--", lw=1.0)
        ax.set_xlabel("cycles per rad")
        ax.set_title("periodic in deflection? (spectrum of the deflection pattern)", fontsize=9)
    else:
        runs = data["runs"]
        ax.plot(runs["t_s"], runs["mean_Nm"], "o", ms=3, label="mean per run (N·m)")
        ax2 = ax.twinx()
        ax2.plot(runs["t_s"], runs["slope_Nm_per_rad"], "s", ms=3, color="C1",
                 label="slope per run (N·m/rad)")
        ax2.set_ylabel("slope (N·m/rad)", fontsize=8)
        ax.set_xlabel("time (s)")
        ax.set_title("per run between reversals", fontsize=9)
        ax.legend(fontsize=7, loc="lower left", framealpha=0.6)
        ax2.legend(fontsize=7, loc="lower right", framealpha=0.6)
    for a in axes.flat:
        a.grid(alpha=0.3)
        a.set_ylabel(a.get_ylabel() or "residual (N·m)", fontsize=8)
    fig.suptitle("Unexplained structure: " + _wrap(loc["summary"], 110), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _wrap(text: str, width: int) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))
