"""The public Python API: load, design, verify, build, export, simulate, fit; SI results.

The functions are ``load``, ``design_job``, ``verify``, ``build``, ``export_build``,
``simulate`` and ``fit_record`` (``springcad.design``, ``.export`` and ``.fit`` are
subpackages, whose import would rebind those names on the package).

The functions are what a notebook or script calls (:mod:`springcad.api.calls`,
:mod:`springcad.api.pipeline`); each returns a result object
(:mod:`springcad.api.results`) with the field's units in its names
(N*m/rad, rad, MPa, kg, mm), a one-line ``repr`` and a table with a drawing or
plot in Jupyter. ``springcad build`` and the other subcommands are thin layers
on the same calls; this package never imports the CLI.

Example:
    >>> import springcad as sc
    >>> d = sc.design_job(sc.load("templates/paper_S1.toml"))
    >>> v = sc.verify(d, model="2d", keep_fields=True)
    >>> b = sc.export_build(sc.build(v), "out/S1")     # out/S1/report.html
    >>> f = sc.fit_record(sc.simulate(v, seed=1), design=v.design)
"""

from springcad.api.calls import design_job, fit_record, load, simulate, verify
from springcad.api.pipeline import Build, build, export_build, load_title_block
from springcad.api.results import Design, Fit, Spring, Stack, Verification, profile_svg

__all__ = ["Build", "Design", "Fit", "Spring", "Stack", "Verification", "build", "design_job",
           "export_build", "fit_record", "load", "load_title_block", "profile_svg", "simulate",
           "verify"]
