"""Serpentine flexures: constant-stress beams curved to the length the deflection needs.

Beyond the straight limit the flexure keeps the constant-stress width law (eq. 2) at
the design stress and is lengthened by curving its centreline between its neighbours
until its area is the serpentine factor s = (theta_d / theta_s)^(3/2) (eq. 4) times a
straight one's (:func:`springcad.design.flexure.design_serpentine`: the deterministic
search over tilt shapes, neighbour clearance and concave edge radius as hard rules).
Its vectorised twin, which the synthesis screen runs on many disks at once, is
:mod:`springcad.design.shapes.serpentine_screen`. Units: mm, N, MPa, rad.
"""

from __future__ import annotations

import math

import numpy as np

from springcad.design import flexure as fx
from springcad.design.shapes.base import FlexureRecord, FlexureShape, Sizing, SizingContext
from springcad.design.shapes.screen import ScreenCentreline, ScreenRows, ScreenSizing
from springcad.design.shapes.serpentine_screen import serpentine_centrelines, serpentine_reach
from springcad.design.shapes.registry import register
from springcad.errors import DesignError


class Serpentine(FlexureShape):
    """Curved constant-stress flexures; defers to straight flexures where they reach."""

    name = "serpentine"
    defers_to = ("straight",)
    summary = "constant-stress flexures curved between their neighbours"

    def size(self, ctx: SizingContext) -> Sizing:
        lay, spec, mfg, sigma = ctx.layout, ctx.spec, ctx.manufacturing, ctx.stress_MPa
        rc, rr, z = lay.rc, lay.rr, spec.thickness_mm
        s_req = fx.serpentine_factor(ctx.deflection_rad, lay.theta_s)

        def width_fn(y):
            return fx.constant_stress_width_mm(y, lay.load, rc, z, sigma)

        # the tilt fades out over two rim thicknesses before the root: both root fillets then
        # sit on the rim on a nearly radial edge. Shorter, the last bend wedges the fillet on
        # its inside far along the rim (measured 2026-11-28 with the zone x0.5: paper S1 and
        # S2's fillets overlap their neighbours', and the predicted root peak rises, S1
        # 1374 -> 1427 MPa at x0.75, S2 1230 -> 1263 at x0.75 and 1310 MPa at x0.5)
        try:
            res = fx.design_serpentine(
                target_area_ratio=s_req, contact_radius_mm=rc, root_radius_mm=rr,
                n_flexures=lay.n, width_fn=width_fn, tip_radius_mm=lay.rb,
                min_clearance_mm=max(mfg.min_slot_width_mm, 2 * mfg.min_inside_radius_mm),
                min_inside_radius_mm=mfg.min_inside_radius_mm,
                root_zone_mm=2.0 * (spec.outer_radius_mm - rr), balances=ctx.balances)
        except DesignError as err:  # the flexure module does not know the spring's name
            raise DesignError(f"spring '{spec.name}': {err}") from None
        record = FlexureRecord(self.name, "stress", math.sqrt(6 * lay.load * (rr - rc) / (z * sigma)),
                               res.centreline, required_area_ratio=s_req,
                               area_ratio=res.area_ratio, balance=res.balance)
        return Sizing(lay, record, res.min_clearance_mm)

    def screen_size(self, rows: ScreenRows) -> ScreenSizing:
        """Every row, the serpentine factor and the search's first test, exact: some trial
        shape reaches the area ratio at full tilt (else ``serpentine_budget``)."""
        L = rows.rr - rows.rc
        s = (rows.theta / rows.theta_s) ** 1.5
        reach = serpentine_reach(s, rows.rc, rows.rr, rows.n, rows.load, rows.z, rows.sigma,
                                 rows.clearance_mm, 2.0 * (rows.ro - rows.rr))
        return ScreenSizing(
            np.ones(len(s), dtype=bool), rows.rr, rows.theta_s,
            np.sqrt(6 * rows.load * L / (rows.z * rows.sigma)), s,
            6 * rows.load / (rows.z * rows.sigma), rows.sigma,
            failures=[("serpentine_budget", reach < s, s, reach)])

    def screen_centreline(self, rows: ScreenRows, sizing: ScreenSizing) -> ScreenCentreline:
        """The serpentine the design would choose (``serpentine_shape`` when none keeps the
        wire's concave edge radius)."""
        shape = serpentine_centrelines(sizing.s, rows.rc, sizing.rr, rows.n, rows.load, rows.z,
                                       rows.sigma, rows.clearance_mm,
                                       2.0 * (rows.ro - sizing.rr), rows.min_inside_radius_mm)
        return ScreenCentreline(
            shape["x"], shape["y"], shape["slope"], shape["kappa"],
            failures=[("serpentine_shape", ~shape["ok"], shape["edge_radius_mm"],
                       np.full(len(rows.rc), rows.min_inside_radius_mm))])

    def width_mm(self, design, y_mm):
        """sqrt(6 F (y - r_c) / (z sigma)) at the design's beam stress (mm)."""
        return fx.constant_stress_width_mm(y_mm, design.tip_load_N, design.contact_radius_mm,
                                           design.thickness_mm, design.beam_stress_MPa)


SERPENTINE = register(Serpentine())
