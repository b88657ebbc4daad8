"""The duty's two pictures: a Haigh diagram with the operating points and an S-N plot with
the spectrum, drawn from the ``duty`` entry of ``design.json`` or ``fea.json``.

Haigh: stress amplitude over mean stress (MPa); the modified Goodman line of the part
(S_e at zero mean to S_ut at zero amplitude), the same line divided by the required
fatigue safety factor, the Goodman lines of the finite lives the blocks need, the
Langer (first-yield) line, and one point per block, labelled with its cycles.

S-N: the part's S-N line (log-log; the low-cycle line from S_ut at one cycle, Basquin
from f S_ut at 1e3 cycles to S_e at N_e, flat beyond for steels) and the spectrum as
a step line: the blocks' Goodman-equivalent amplitudes over their cumulative applied
cycles, largest first, with each block's life marked on the S-N line.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from springcad.report.mpl import pyplot


def sn_amplitude_MPa(d: dict, cycles: np.ndarray) -> np.ndarray:
    """The part's S-N amplitude at ``cycles`` from a duty entry (MPa)."""
    sut, f_sut = d["ultimate_strength_MPa"], d["low_cycle_strength_MPa"]
    se, ne, b = d["endurance_limit_MPa"], d["cycles_at_endurance"], d["sn_exponent"]
    n = np.asarray(cycles, dtype=float)
    low = sut * (f_sut / sut) ** (np.log10(np.maximum(n, 1.0)) / 3.0)
    basquin = f_sut * (n / 1e3) ** b
    out = np.where(n < 1e3, low, basquin)
    if d.get("has_endurance_limit", True):
        out = np.where(n >= ne, se, out)
    return out


def render_haigh(d: dict, path: Path, title: str, yield_MPa: float | None = None) -> Path:
    """The Haigh diagram of one spring's duty entry, written to ``path`` (PNG)."""
    plt = pyplot()
    sut, se = d["ultimate_strength_MPa"], d["endurance_limit_MPa"]
    n_req = d["required_safety_factor"]
    fig, ax = plt.subplots(figsize=(7.5, 5.2), dpi=110)
    m = np.array([0.0, sut])
    ax.plot(m, se * (1 - m / sut), color="k", lw=1.8,
            label=f"Goodman, infinite life: S_e = {se:.0f} MPa")
    ax.plot(m / n_req, se / n_req * (1 - m / sut), color="k", lw=1.2, ls="--",
            label=f"Goodman / {n_req:g} (required safety factor)")
    blocks = d["blocks"]
    lives = sorted({b["cycles"] for b in blocks if b["cycles"] < d["cycles_at_endurance"]})
    for n in lives:
        s_n = float(sn_amplitude_MPa(d, np.array([n]))[0])
        ax.plot(m, s_n * (1 - m / sut), color="tab:gray", lw=0.9, ls=":")
        ax.annotate(f"life {n:.0e}", (0, s_n), xytext=(4, 2), textcoords="offset points",
                    fontsize=8, color="tab:gray")
    if yield_MPa:
        ax.plot([0, yield_MPa], [yield_MPa, 0], color="tab:red", lw=1.0, ls="-.",
                label=f"Langer (first yield): S_y = {yield_MPa:.0f} MPa")
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, max(len(blocks), 1)))
    for b, c in zip(blocks, colours):
        ax.plot(b["mean_MPa"], b["amplitude_MPa"], "o", ms=8, color=c, mec="k",
                label=f"{b['label']}: {b['cycles']:.2g} cycles, damage {b['damage']:.3g}")
    top = max([se, yield_MPa or 0.0] + [b["amplitude_MPa"] for b in blocks]) * 1.15
    ax.set_xlim(0, sut * 1.02)
    ax.set_ylim(0, top)
    ax.set_xlabel("mean stress σm (MPa)")
    ax.set_ylabel("stress amplitude σa (MPa)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="upper right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def render_sn(d: dict, path: Path, title: str) -> Path:
    """The S-N plot with the duty's spectrum, written to ``path`` (PNG)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.2), dpi=110)
    n = np.logspace(0, 9, 400)
    ax.loglog(n, sn_amplitude_MPa(d, n), color="k", lw=1.8,
              label=f"S-N of the part ({d['surface']}, reliability {d['reliability']:g})")
    ax.loglog(n, sn_amplitude_MPa(d, n) / d["required_safety_factor"], color="k", lw=1.0,
              ls="--", label=f"S-N / {d['required_safety_factor']:g} (required safety factor)")
    blocks = sorted(d["blocks"], key=lambda b: -b["equivalent_amplitude_MPa"])
    x, y = [1.0], []
    total = 0.0
    for b in blocks:
        y.append(b["equivalent_amplitude_MPa"])
        total += b["cycles"]
        x.append(total)
    if blocks:
        ax.stairs(y, x, color="tab:blue", lw=2.0, baseline=None,
                  label=f"duty spectrum (Goodman-equivalent amplitude), Miner sum "
                        f"{d['miner_sum']:.3g}")
    for b in blocks:
        life = b.get("life_cycles")
        if life:
            ax.plot(life, b["equivalent_amplitude_MPa"], "x", color="tab:red", ms=8)
    ax.plot([], [], "x", color="tab:red", label="life of each block's amplitude")
    life_max = d.get("life_at_max_deflection_cycles")
    ax.axhline(d["peak_at_max_deflection_MPa"], color="tab:orange", lw=0.9, ls=":",
               label=f"peak at ±θmax {d['peak_at_max_deflection_MPa']:.0f} MPa: "
                     + (f"life {life_max:.3g} cycles" if life_max else
                        "no failure (below the endurance limit)"))
    lo = 0.5 * min([d["endurance_limit_MPa"] / d["required_safety_factor"]]
                   + [b["equivalent_amplitude_MPa"] for b in blocks if b["equivalent_amplitude_MPa"] > 0])
    ax.set_ylim(lo, d["ultimate_strength_MPa"] * 1.2)
    ax.set_xlim(1, 1e9)
    ax.set_xlabel("cycles")
    ax.set_ylabel("fully reversed stress amplitude (MPa)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7.5, loc="lower left")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def render_duty(d: dict, folder: Path, name: str, yield_MPa: float | None = None
                ) -> list[Path]:
    """Both pictures of one spring's duty entry into ``folder``: ``<name>_haigh.png`` and
    ``<name>_sn.png``."""
    where = d.get("where", "")
    head = (f"{name}: {d['duty'].split(';')[0]} at the {where}, "
            f"±{d['max_deflection_deg']:.1f}° max")
    safety = (f"safety factor {d['safety_factor']:.2f} (required "
              f"{d['required_safety_factor']:g})")
    return [render_haigh(d, folder / f"{name}_haigh.png",
                         f"{head}\nHaigh diagram, {safety}", yield_MPa),
            render_sn(d, folder / f"{name}_sn.png", f"{head}\nS-N of the part and the duty, "
                      f"{safety}")]


def duty_rows(d: dict) -> list[tuple[str, str]]:
    """The duty's numbers as (label, text) rows for reports."""
    def n(v):
        return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.3g}"

    def life(v):  # JSON holds an infinite life as null
        return "no failure (below the endurance limit)" if v is None else f"{v:.3g} cycles"
    rows = [("duty", d["duty"]), ("source", d["duty_source"]), ("critical point", d["where"]),
            ("peak at ±θmax (MPa)", n(d["peak_at_max_deflection_MPa"])),
            ("S_e of the part (MPa): S_e' x surface x size x reliability",
             f"{d['polished_endurance_limit_MPa']:.0f} x {d['surface_factor']:g} x "
             f"{d['size_factor']:g} x {d['reliability_factor']:.3f} = "
             f"{d['endurance_limit_MPa']:.0f}")]
    for b in d["blocks"]:
        rows.append((f"block '{b['label']}'",
                     f"{b['cycles']:.3g} cycles of {b['mean_deg']:+.1f} ± {b['amplitude_deg']:.1f}°"
                     f": σa {b['amplitude_MPa']:.0f}, σm {b['mean_MPa']:.0f}, Goodman "
                     f"{b['equivalent_amplitude_MPa']:.0f} MPa; "
                     + ("" if b["life_cycles"] is None else "life ") + f"{life(b['life_cycles'])}; "
                     f"damage {b['damage']:.3g}"))
    rows += [("Miner sum", n(d["miner_sum"])),
             ("fatigue safety factor (required)",
              f"{d['safety_factor']:.2f} ({d['required_safety_factor']:g})"),
             ("life at ±θmax", life(d["life_at_max_deflection_cycles"])),
             ("fatigue-rated deflection (°), static θmax (°)",
              f"{d['fatigue_rated_deflection_deg']:.1f}, {d['max_deflection_deg']:.1f}"),
             ("verdict", "met" if d["met"] else "NOT met")]
    return rows
