"""The public Python API: every stage a user can run, with every option; SI results.

The stages are ``load``, ``design_job``, ``verify``, ``build``, ``export_build``,
``export_verification``, ``simulate`` (with ``bench_protocol``), ``fit_record``, ``validate_paper``,
``synthesize`` and ``explore``; each ``springcad`` subcommand is one of them and a
printout. For build123d users, ``FlexureRing`` and ``Camshaft`` make a designed spring's
parts, and ``Build.compound()`` the placed stack (:mod:`springcad.api.parts`). The
defaults are declared once, in :mod:`springcad.options` (``design_job``
and ``fit_record``, not ``design`` and ``fit``: ``springcad.design``, ``.export`` and ``.fit`` are
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

from springcad.api.calls import bench_protocol, design_job, fit_record, load, simulate, verify
from springcad.api.parts import Camshaft, FlexureRing
from springcad.api.pipeline import (Build, build, export_build, export_verification,
                                    load_title_block)
from springcad.api.results import Design, Fit, Spring, Stack, Verification
from springcad.api.studies import explore, synthesize, validate_paper
from springcad.report.notebook import profile_svg

__all__ = ["Build", "Camshaft", "Design", "FlexureRing", "Fit", "Spring", "Stack", "Verification", "bench_protocol", "build",
           "design_job", "explore", "export_build", "export_verification", "fit_record", "load", "load_title_block",
           "profile_svg", "simulate", "synthesize", "validate_paper", "verify"]
