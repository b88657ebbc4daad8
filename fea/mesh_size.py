"""Element size rules for the ring face: how many elements go where, before gmsh meshes it.

:class:`MeshSize` holds the level-0 rules (elements across a flexure, per fillet
radius, across the contact patch; rim size, gradation); :class:`SizeField` turns
them into a target size at any point of the face for gmsh's size callback
(:func:`fea.mesh.mesh_face_levels`). Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class MeshSize:
    """Element size rules (level 0, before refinement).

    Attributes:
        across_width: quadratic elements across the local flexure width.
        per_fillet_radius: elements per fillet / ball radius (size = radius / this).
        patch_elements: elements across the contact-patch half-width.
        rim_size_fraction: element size in the rim as a fraction of the rim thickness.
        gradation: size growth per mm of distance from a feature (-).
        factor: global multiplier on every size.
        layers: quadratic element layers through the thickness (3D extrusion).
    """

    across_width: float = 1.5
    per_fillet_radius: float = 1.5
    patch_elements: float = 1.5
    rim_size_fraction: float = 0.5
    gradation: float = 0.4
    factor: float = 1.0
    layers: int = 2


#: the verification's level-0 mesh rules (2D study levels 1..n refine them; levels 1-3
#: have ~3k, 12k, 48k DOFs for the paper springs)
DEFAULT_SIZE = MeshSize(across_width=1.0, per_fillet_radius=2.0, patch_elements=1.0,
                        gradation=0.3, rim_size_fraction=0.8, layers=1)


class SizeField:
    """Local target element size (mm) over the ring face, built from its geometry.

    Size is the smallest of: the rim size; in and near each flexure its width
    divided by ``across_width`` (so every station has the same number of
    elements across, the tip included); near each fillet and the tip ball
    their radius divided by ``per_fillet_radius``; near each contact point the
    patch half-width divided by ``patch_elements``; each grown linearly with
    distance by ``gradation``.
    """

    def __init__(self, geometry, rules: MeshSize, patch_half_width_mm: float):
        from scipy.spatial import cKDTree

        g = geometry
        self.rules = rules
        self.g = g
        self.h_max = rules.rim_size_fraction * g.rim_thickness_mm
        self.tree = cKDTree(g.centreline_mm)
        # the centreline's points for :meth:`_nearest` (a few hundred)
        cl = np.asarray(g.centreline_mm, dtype=float)
        self._cl_x, self._cl_y = np.ascontiguousarray(cl[:, 0]), np.ascontiguousarray(cl[:, 1])
        self.width = [float(w) for w in g.width_mm]
        h_tip = min(g.tip_radius_mm, g.neck_fillet_radius_mm) / rules.per_fillet_radius
        self.h_flex = [max(w / rules.across_width, h_tip) for w in self.width]
        self.n = g.n_flexures
        self.pitch = 2 * math.pi / g.n_flexures
        # modelled flexures by index around the ring (flexure 0 along +y)
        self.modelled = {int(round((a - math.pi / 2) / self.pitch)) % self.n
                         for a in g.flexure_angles_rad}
        # polar angle of the flexure-0 centreline as a function of radius: a point's
        # nearest flexures are found from its angle in O(1), however many flexures
        cl = np.asarray(g.centreline_mm)
        r = np.hypot(cl[:, 0], cl[:, 1])
        phi = np.arctan2(cl[:, 1], cl[:, 0])
        order = np.argsort(r)
        self.r_tab, self.phi_tab = r[order], phi[order]
        self.feat = [(x, y, r_, r_ / rules.per_fillet_radius) for x, y, r_, _k in g.fillets_mm]
        # contact point of flexure 0 (frame of flexure 0)
        self.patch = ((g.tip_radius_mm, g.contact_radius_mm),
                      patch_half_width_mm / rules.patch_elements)
        self.holes = [(c[0], c[1]) for c in g.hole_centres_mm]
        self.h_hole = (g.hole_radius_mm * 2 * math.pi / 16) if self.holes else 0.0

    def _candidates(self, x: float, y: float):
        r = math.hypot(x, y)
        phi_c = float(np.interp(r, self.r_tab, self.phi_tab))
        j = int(round((math.atan2(y, x) - phi_c) / self.pitch))
        return [(j + d) % self.n for d in (-1, 0, 1) if (j + d) % self.n in self.modelled]

    def _nearest(self, x: float, y: float) -> tuple[float, int]:
        """Distance (mm) to the nearest centreline point and its index: ``self.tree.query``'s
        answer (the same squared sum dx^2 + dy^2, its square root), without the k-d tree's
        per-query overhead (~50 us, a third of the size callback gmsh calls thousands of times
        per mesh)."""
        dx = self._cl_x - x
        dy = self._cl_y - y
        d2 = dx * dx + dy * dy
        i = int(d2.argmin())
        return math.sqrt(d2[i]), i

    def __call__(self, x: float, y: float) -> float:
        grad = self.rules.gradation
        h = self.h_max
        for j in self._candidates(x, y):
            a = -j * self.pitch
            c, s = math.cos(a), math.sin(a)
            xl, yl = c * x - s * y, s * x + c * y  # point in flexure 0's frame
            d, i = self._nearest(xl, yl)
            h = min(h, self.h_flex[i] + grad * max(d - 0.5 * self.width[i], 0.0))
            for fx_, fy_, fr, fh in self.feat:
                h = min(h, fh + grad * max(math.hypot(xl - fx_, yl - fy_) - fr, 0.0))
            (px, py), hp = self.patch
            h = min(h, hp + grad * math.hypot(xl - px, yl - py))
        for hx, hy in self.holes:
            dist = math.hypot(x - hx, y - hy) - self.g.hole_radius_mm
            h = min(h, self.h_hole + grad * max(dist, 0.0))
        return float(h * self.rules.factor)

