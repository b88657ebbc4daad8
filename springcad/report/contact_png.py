"""PNG of a cam contact sweep: torque and stiffness against cam angle, and the deformed
contact at +-theta_max (matplotlib, Agg backend, imported here only).

Renders a :class:`fea.contact_result.ContactSweep`; computes nothing. Units on the
axes: deg, N*m, N*m/rad, mm, MPa.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from springcad.units import NMM_PER_NM, rad_to_deg

_COLOURS = {"+": "tab:blue", "-": "tab:red"}


def _curve_axes(ax, sweep):
    deg = math.degrees
    for key, steps in sweep.steps.items():
        th = [deg(s.angle_rad) for s in steps]
        ax.plot(th, [s.torque_Nmm / NMM_PER_NM for s in steps], "o-", color=_COLOURS[key],
                label=f"{key} contact FEA")
        on = sweep.onset_rad.get(key, math.nan)
        if math.isfinite(on):
            end = steps[-1].angle_rad
            ref = np.linspace(on, end, 50)
            ax.plot(rad_to_deg(ref),
                    sweep.stiffness_linear_Nmm_per_rad * (ref - on) / NMM_PER_NM, "--",
                    color="0.4", lw=1)
            ax.axvspan(0, deg(on), color="0.85", lw=0)
    ax.plot([], [], "--", color="0.4", lw=1, label="linear FEA K (theta - onset)")
    ax.axhline(0, color="0.6", lw=0.5)
    ax.set_xlabel("cam angle (deg)")
    ax.set_ylabel("torque on the ring (N*m)")
    ax.set_title("torque - angle (grey: gap before contact)")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)


def _stiffness_axes(ax, sweep):
    deg = math.degrees
    k_lin = sweep.stiffness_linear_Nmm_per_rad / NMM_PER_NM
    tol = sweep.options.linearity_tolerance
    ax.axhspan(k_lin * (1 - tol), k_lin * (1 + tol), color="0.9", lw=0,
               label=f"linear FEA +-{100 * tol:g} %")
    ax.axhline(k_lin, color="0.3", lw=1)
    if sweep.stiffness_verified_Nmm_per_rad:
        ax.axhline(sweep.stiffness_verified_Nmm_per_rad / NMM_PER_NM, color="0.3", lw=1, ls=":",
                   label="verified K (3D factor)")
    for key, steps in sweep.steps.items():
        c = _COLOURS[key]
        for attr, marker, what in (("secant_Nmm_per_rad", "o", "secant T/theta"),
                                   ("engaged_secant_Nmm_per_rad", "s", "T/(theta - onset)"),
                                   ("tangent_Nmm_per_rad", "^", "tangent")):
            pts = [(deg(s.angle_rad), getattr(s, attr) / NMM_PER_NM) for s in steps
                   if getattr(s, attr) is not None]
            if pts:
                x, y = zip(*pts)
                ax.plot(x, y, marker + ("-" if attr != "secant_Nmm_per_rad" else ":"), color=c,
                        ms=5, lw=1, label=f"{key} {what}")
        small = sweep.small_angle_Nmm_per_rad.get(key)
        if small is not None:
            ax.plot([deg(sweep.onset_rad[key])], [small / NMM_PER_NM], "*", color=c, ms=12,
                    label=f"{key} small angle ({100 * sweep.small_angle_error(key):+.2f} %)")
    lo = min(0.55 * k_lin, *(0.95 * s.tangent_Nmm_per_rad / NMM_PER_NM
                             for v in sweep.steps.values()
                             for s in v if s.tangent_Nmm_per_rad is not None))
    hi = max(1.2 * k_lin, *(s.tangent_Nmm_per_rad / NMM_PER_NM for v in sweep.steps.values()
                             for s in v if s.tangent_Nmm_per_rad is not None))
    ax.set_ylim(max(0.0, lo), min(hi, 2.0 * k_lin))
    ax.set_xlabel("cam angle (deg)")
    ax.set_ylabel("stiffness (N*m/rad)")
    ax.set_title("secant and tangent stiffness")
    ax.legend(fontsize=7, ncol=3, loc="lower center", framealpha=0.9)
    ax.grid(alpha=0.3)


def _contact_axes(ax, fig, sweep, key):
    pic = sweep.pictures.get(key)
    if pic is None:
        ax.set_axis_off()
        return
    import matplotlib.tri as mtri

    step = sweep.steps[key][-1]
    rb = pic["ball_radius_mm"]
    centre = np.asarray(pic["ball_centre_deformed_mm"])
    half = 3.0 * rb
    pts = pic["points_mm"]
    tri = pic["triangles"]
    inside = np.all(np.abs(pts[:, tri] - centre[:, None, None]).max(axis=0) < 2 * half, axis=1)
    t = mtri.Triangulation(pts[0], pts[1], tri[inside])
    vmax = max(step.flexure_peak_MPa, 1.0)  # the contact itself is the Hertz value in the title
    pc = ax.tripcolor(t, pic["von_mises_MPa"], shading="gouraud", cmap="turbo", vmin=0.0,
                      vmax=vmax)
    cam = pic["cam_mm"]
    near = np.abs(cam - centre).max(axis=1) < 2 * half
    ax.plot(cam[near, 0], cam[near, 1], "k-", lw=1.2, label="cam (rigid, turned)")
    a = np.linspace(0, 2 * np.pi, 200)
    rest = pic["ball_centre_mm"]
    ax.plot(rest[0] + rb * np.cos(a), rest[1] + rb * np.sin(a), color="0.5", ls=":", lw=0.8,
            label="ball at rest")
    for p in pic["contacts_mm"]:
        ax.plot(*p, "m*", ms=12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal")
    desc = "; ".join(
        f"{c['feature']} {c['force_N']:.0f} N"
        + (f", flank {100 * c['flank_fraction']:.0f} %" if "flank_fraction" in c else "")
        + (f", Hertz p0 {c['hertz']['p0_MPa']:.0f} MPa" if "hertz" in c else "")
        for c in step.contacts) or "no contact"
    ax.set_title(f"{math.degrees(step.angle_rad):+.1f} deg: {desc}", fontsize=8)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=7, loc="lower left")
    fig.colorbar(pc, ax=ax, shrink=0.8, label="von Mises (MPa), clipped at the flexure peak")


def render_contact(sweep, path: Path | str, title: str = "") -> Path:
    """Torque-angle curve, stiffness and the deformed contact at +-theta_max into a PNG.

    Args:
        sweep: :class:`fea.contact_result.ContactSweep` (with its pictures).
        path: output PNG.
        title: figure title.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(14, 13))
    _curve_axes(axes[0, 0], sweep)
    _stiffness_axes(axes[0, 1], sweep)
    _contact_axes(axes[1, 0], fig, sweep, "+")
    _contact_axes(axes[1, 1], fig, sweep, "-")
    flags = [f["message"] for f in sweep.flags]
    import textwrap

    text = ("\n".join(textwrap.shorten(f, 230) for f in flags[:6]) if flags else
            "no flags: the ball stays on the driving flank, nothing else touches, stiffness "
            "linear")
    fig.suptitle(title or f"{sweep.name}: cam contact sweep", fontsize=12)
    fig.text(0.01, 0.005, text, fontsize=9, va="bottom", wrap=True,
             color="darkred" if flags else "darkgreen")
    fig.tight_layout(rect=(0, 0.07, 1, 0.97))
    # the colour bars of the lower panels keep tight_layout from seeing the upper x labels
    fig.subplots_adjust(hspace=0.28)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)
