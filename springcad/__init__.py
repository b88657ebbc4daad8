"""springcad: compact series torsion springs from spec to EDM drawings.

Internal units: lengths in mm, forces in N, stresses in MPa (N/mm^2),
torques in N*mm, angles in rad, masses in kg. Public result keys carry
their unit in the name (``stiffness_Nm_per_rad``).

Public API (:mod:`springcad.api`; results in N*m/rad, rad, MPa, kg)::

    import springcad as sc
    job = sc.load("templates/paper_S1.toml")     # or a dict
    d = sc.design_job(job)                        # Design: .springs, .stack
    v = sc.verify(d, model="2d")                  # Verification: FEA, corrected .design
    rec = sc.simulate(v, seed=1)                  # a simulated bench record
    f = sc.fit_record(rec, design=v.design)       # Fit: model, K, backlash, effects
    b = sc.build(v)                               # Build: solids and checks, in memory
    b = sc.export_build(b, "out/S1")              # CAD, drawings, BOM, out/S1/report.html
    ring = sc.FlexureRing(d.springs["S1"])        # build123d parts: the ring, a camshaft,
    cam = sc.Camshaft(d.springs["S1"])            # and b.compound(), the placed stack

``import springcad`` stays light: CAD, meshing and plotting libraries
are imported by the modules that use them.
"""

from springcad.api import (
    Build,
    Camshaft,
    Design,
    Fit,
    FlexureRing,
    Spring,
    Stack,
    Verification,
    bench_protocol,
    build,
    design_job,
    explore,
    export_build,
    export_verification,
    fit_record,
    load,
    simulate,
    synthesize,
    validate_paper,
    verify,
)
from springcad.design.shapes import registry as _shapes  # noqa: F401  the config's flexure names (light)
from springcad.errors import SpringcadError
from springcad.version import __version__

__all__ = ["Build", "Camshaft", "Design", "Fit", "FlexureRing", "Spring", "SpringcadError", "Stack", "Verification",
           "__version__", "bench_protocol", "build", "design_job", "explore", "export_build",
           "export_verification",
           "fit_record", "load", "simulate", "synthesize", "validate_paper", "verify"]
