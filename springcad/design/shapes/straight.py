"""Straight flexures: radial parabolic beams sized for the target stiffness.

Where the straight limit theta_s (eq. 3) reaches the deflection, a radial flexure with
the parabolic width law w(y) = w0 sqrt((y - r_c) / L) and its root width w0 sized for
K (K = N r_c^2 E z w0^3 / (8 L^3)) stays below the design stress at the deflection;
its root radius then follows the rim rule with that w0. Units: mm, N, MPa, rad.
"""

from __future__ import annotations

import math

import numpy as np

from springcad.design import flexure as fx
from springcad.design.layout import Layout, rim_root_radius
from springcad.design.shapes.base import FlexureRecord, FlexureShape, Sizing, SizingContext
from springcad.design.shapes.screen import ScreenRows, ScreenSizing, rim_root_radius_rows
from springcad.design.shapes.registry import register


class Straight(FlexureShape):
    """Radial flexures with the stiffness width law."""

    name = "straight"
    summary = "radial flexures, width sized for the stiffness"

    def refusal(self, ctx: SizingContext) -> str:
        lay, theta_d = ctx.layout, ctx.deflection_rad
        if lay.theta_s >= theta_d:
            return ""
        return (f"straight flexures reach only {lay.theta_s:.4f} rad "
                f"({math.degrees(lay.theta_s):.2f} deg) < max deflection {theta_d:.4f} rad; "
                "allow flexure = \"serpentine\" or \"auto\"")

    def size(self, ctx: SizingContext) -> Sizing | None:
        lay, spec, E = ctx.layout, ctx.spec, ctx.youngs_modulus_MPa
        K, z, n, rc = ctx.target_stiffness_Nmm_per_rad, spec.thickness_mm, lay.n, lay.rc
        if lay.theta_s < ctx.deflection_rad:
            return None

        def w0_stiff(length):
            return fx.straight_root_width_for_stiffness_mm(K, n, rc, length, E, z)

        rr = spec.root_radius_mm or min(ctx.max_root_radius_mm,
                                        rim_root_radius(spec.outer_radius_mm, n, rc, w0_stiff))
        theta_s = fx.straight_limit_rad(n, z, ctx.stress_MPa, rr - rc, E, K, rc)
        if theta_s < ctx.deflection_rad:
            return None
        record = FlexureRecord(self.name, "stiffness", w0_stiff(rr - rc),
                               fx.Centreline.straight(rc, rr))
        return Sizing(Layout(n, rc, lay.rb, lay.rb_req, rr, theta_s, lay.load), record)

    def screen_size(self, rows: ScreenRows) -> ScreenSizing:
        """The rows whose straight limit reaches the deflection, as :meth:`size` (a rim
        rule without a root fails ``rim_rule``; a limit that falls short at the new root
        radius leaves the row to the next shape)."""
        m = len(rows.K)
        nan = np.full(m, np.nan)
        taken, rim_bad = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
        rr, theta_s, w0 = nan.copy(), nan.copy(), nan.copy()
        i = np.flatnonzero(rows.theta_s >= rows.theta)
        if i.size:
            r = rows.take(i)
            coef = 8.0 * r.K / (r.n * r.rc ** 2 * r.E * r.z)
            rr_s = np.minimum(rim_root_radius_rows(r.ro, r.n, r.rc,
                                                   lambda Ls, c=coef: np.cbrt(c * Ls ** 3)),
                              r.rim_max)
            rim_bad[i[np.isnan(rr_s)]] = True
            th2 = fx.straight_limit_rad(r.n, r.z, r.sigma, rr_s - r.rc, r.E, r.K, r.rc)
            keep = ~np.isnan(rr_s) & (th2 >= r.theta)
            j = i[keep]
            taken[j], rr[j], theta_s[j] = True, rr_s[keep], th2[keep]
            w0[j] = np.cbrt(coef[keep] * (rr[j] - rows.rc[j]) ** 3)
        L = rr - rows.rc
        return ScreenSizing(
            taken, rr, theta_s, w0, np.ones(m), w0 ** 2 / L,
            6 * rows.load * L / (rows.z * w0 ** 2),
            failures=[("rim_rule", rim_bad, rows.n.astype(float), rows.ro)])

    def width_mm(self, design, y_mm):
        """w0 sqrt((y - r_c) / L) (mm)."""
        y = np.asarray(y_mm, dtype=float)
        return design.root_width_mm * np.sqrt(np.maximum(y - design.contact_radius_mm, 0.0)
                                              / design.length_mm)


STRAIGHT = register(Straight())
