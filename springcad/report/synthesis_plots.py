"""Design-space map outputs: Parquet tables and PNG plots (matplotlib, Agg backend).

Renders what :mod:`springcad.synthesis.explore` computed; computes no physics.

- ``region.png``: peak torque vs deflection reachable by one disk and by stacks of
  2 ... N disks (cf. paper Fig. 8: the series stack widens the single-disk region
  toward large deflections at the same peak torque);
- ``pareto_mass.png``: lightest stack vs deflection at several stiffnesses;
- ``pareto_energy.png``: energy density vs deflection, every feasible stack and the front.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from springcad.report.mpl import pyplot
from springcad.synthesis.store import to_table
from springcad.units import G_PER_KG


def write_parquet(path: Path | str, columns: dict) -> Path:
    """Write numpy columns as one Parquet file."""
    import pyarrow.parquet as pq

    pq.write_table(to_table(columns), Path(path))
    return Path(path)


def plot_region(region: dict, path: Path | str, title: str = "") -> Path:
    """Reachable peak torque vs deflection: one disk, and stacks of up to n disks."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    n_all = np.unique(region["n_disks"]) if len(region["n_disks"]) else np.array([], dtype=int)
    cmap = plt.get_cmap("viridis", max(len(n_all), 2))

    def band(sel):
        th = np.unique(region["deflection_rad"][sel])
        lo = np.array([region["min_peak_torque_Nm"][sel][region["deflection_rad"][sel] == t].min()
                       for t in th])
        hi = np.array([region["max_peak_torque_Nm"][sel][region["deflection_rad"][sel] == t].max()
                       for t in th])
        return th, lo, hi

    if len(n_all):
        th, lo, hi = band(np.ones(len(region["n_disks"]), dtype=bool))
        ax.fill_between(th, lo, hi, color="#7fc97f", alpha=0.35, step="mid",
                        label=f"stacks of 1-{int(n_all.max())} disks")
        one = region["n_disks"] == 1
        if one.any():
            th, lo, hi = band(one)
            ax.fill_between(th, lo, hi, color="#f0027f", alpha=0.35, step="mid",
                            label="one disk")
        for j, n in enumerate(n_all):
            th, _, hi = band(region["n_disks"] == n)
            ax.step(th, hi, where="mid", color=cmap(j), lw=1.2, label=f"max torque, {n} disk(s)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("deflection in each direction (rad)")
    ax.set_ylabel("peak torque (N·m)")
    ax.set_title(title or "Reachable peak torque vs deflection")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def plot_mass_fronts(fronts: dict, path: Path | str, max_curves: int = 7) -> Path:
    """Lightest stack vs deflection, one curve per stiffness (a spread of the grid's values)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    ks = np.unique(fronts["target_stiffness_Nm_per_rad"])
    if len(ks) > max_curves:
        ks = ks[np.unique(np.round(np.linspace(0, len(ks) - 1, max_curves)).astype(int))]
    cmap = plt.get_cmap("plasma", max(len(ks), 2))
    for j, k in enumerate(ks):
        sel = fronts["target_stiffness_Nm_per_rad"] == k
        th, m, n = (fronts["deflection_rad"][sel], fronts["mass_kg"][sel],
                    fronts["n_disks"][sel])
        ax.plot(th, G_PER_KG * m, "-o", color=cmap(j), ms=3, lw=1.2, label=f"K = {k:.3g} N·m/rad")
        for t, mm, nn in zip(th, m, n):
            ax.annotate(str(nn), (t, G_PER_KG * mm), fontsize=6, xytext=(2, 2),
                        textcoords="offset points", color=cmap(j))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("deflection in each direction (rad)")
    ax.set_ylabel("lightest stack mass (g)  [labels: number of disks]")
    ax.set_title("Pareto front: mass vs deflection at given stiffness")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def plot_energy_front(cols: dict, front: dict, path: Path | str) -> Path:
    """Energy density vs deflection: every feasible stack (by number of disks) and the front."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    f = cols["feasible"]
    n = cols["n_disks"][f]
    sc = ax.scatter(cols["deflection_rad"][f], cols["energy_density_J_per_cm3"][f], c=n, s=4,
                    cmap="viridis", alpha=0.4, rasterized=True)
    if len(n):
        fig.colorbar(sc, ax=ax, label="number of disks")
    ax.plot(front["deflection_rad"], front["energy_density_J_per_cm3"], "-", color="crimson",
            lw=1.8, label="Pareto front")
    ax.set_xscale("log")
    ax.set_xlabel("deflection in each direction (rad)")
    ax.set_ylabel("energy density over the stack envelope (J/cm³)")
    ax.set_title("Pareto front: energy density vs deflection")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)

