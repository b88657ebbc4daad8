"""The functions of the public API: load, design, verify, build, export, simulate, fit.

The functions here are what a notebook or script calls; the result objects
wrap the internal design/analysis types (which work in N*mm and mm) and
expose the field's units in their names: stiffness in N*m/rad, angles in
rad, stresses in MPa, masses in kg, lengths in mm. Every result prints as one
short line (``repr``) and shows a small table (and a drawing or plot) in
Jupyter (``_repr_html_``).

Example:
    >>> import springcad as sc
    >>> job = sc.load("templates/paper_S1.toml")
    >>> d = sc.design_job(job)
    >>> d.stack.stiffness_Nm_per_rad
    >>> v = sc.verify(d, model="2d")
    >>> rec = sc.simulate(d, seed=1)
    >>> f = sc.fit_record(rec, design=d)

The functions are named ``design_job`` and ``fit_record`` (not ``design``,
``fit``) because ``springcad.design`` and ``springcad.fit`` are subpackages:
importing them rebinds those attribute names on the package.

Heavy libraries (scikit-fem, matplotlib) are imported inside the functions
that need them, so ``import springcad`` stays light.
"""

from __future__ import annotations

import math
from pathlib import Path

from springcad.api.results import Design, Fit, Verification
from springcad.errors import ConfigError, DataError


def load(source):
    """Load and validate a job config.

    Args:
        source: a TOML file path (``str`` or ``Path``), or a dict with the
            same tables as the TOML file.

    Returns:
        The validated :class:`springcad.config.Job`.

    Raises:
        ConfigError: unreadable file or a disallowed value (names the key).
    """
    from springcad.config import job_from_dict, load_job

    if isinstance(source, dict):
        return job_from_dict(source, name=str(source.get("name", "job")), source="<dict>")
    if isinstance(source, (str, Path)):
        return load_job(source)
    raise ConfigError("job", type(source).__name__, "give a TOML path or a dict")


def _job(job_or_design):
    if isinstance(job_or_design, Design):
        return job_or_design.job
    if isinstance(job_or_design, (str, Path, dict)):
        return load(job_or_design)
    return job_or_design


def design_job(job) -> Design:
    """Design every spring of a job and the stack (beam theory and the stress model).

    Args:
        job: a :class:`~springcad.config.Job`, a TOML path or a config dict.

    Returns:
        The :class:`Design`.
    """
    from springcad.design.job import design_job as _design_job

    return Design(_design_job(_job(job)))


def verify(job_or_design, model: str = "2d", levels: int = 3, tolerance_pct: float = 1.0,
           correct: bool = True, contact: bool = False, keep_fields: bool = False,
           progress=None) -> Verification:
    """FEA-verify (and correct the widths of) every spring.

    Args:
        job_or_design: a :class:`Design`, a Job, a TOML path or a config dict.
        model: ``"2d"`` (plane stress, seconds), ``"2d3d"`` (adds a 3D factor)
            or ``"3d"`` (quadratic tets, slow).
        levels: mesh levels of the convergence study (3 to 5).
        tolerance_pct: accepted stiffness error against the target (%).
        correct: scale the flexure widths until the FEA stiffness meets the target.
        contact: also run the cam contact sweep over +-theta_max.
        keep_fields: keep the stress fields of the finest meshes, so that
            :func:`export` can write the ``.vtu`` files and stress renders.
        progress: optional ``callable(message, fraction)``.

    Returns:
        The :class:`Verification`; ``.design`` is the corrected design.
    """
    from fea.verify import VerifyOptions, verify_job

    if model not in ("2d", "2d3d", "3d"):
        raise ConfigError("model", model, "is one of '2d', '2d3d', '3d'")
    if not (isinstance(levels, int) and 3 <= levels <= 5):
        raise ConfigError("levels", levels, "is an integer from 3 to 5")
    if not 0 < tolerance_pct <= 50:
        raise ConfigError("tolerance_pct", tolerance_pct, "lies in (0, 50] %")
    d = job_or_design if isinstance(job_or_design, Design) else design_job(job_or_design)
    options = VerifyOptions(model=model, levels=levels, tolerance=tolerance_pct / 100.0,
                            correct=correct, keep_fields=keep_fields, contact=contact)
    args = (d.raw, options) + ((progress,) if progress is not None else ())
    return Verification(verify_job(*args), d)


def simulate(spring, protocol=None, noise=None, seed: int = 0, backlash_rad: float | None = None,
             **effects):
    """Simulate a bench record of a spring under a test protocol.

    Args:
        spring: a :class:`Design` (its stack's beam stiffness and nominal
            backlash), a :class:`Verification` (its FEA stack stiffness), or a
            stiffness in N*m/rad.
        protocol: a :class:`springcad.fit.protocols.Protocol` or ``SineSweep``
            (default: the paper's staircase).
        noise: a :class:`springcad.fit.bench.BenchNoise` (default: the paper's levels).
        seed: random seed.
        backlash_rad: backlash (rad); default the design's nominal, or 0.
        **effects: further :class:`springcad.fit.bench.BenchSpring` fields
            (``friction_torque_Nm``, ``lag_s``, ``drift_Nm_per_s``, ...).

    Returns:
        A :class:`springcad.fit.bench.SimulatedRecord` (``.record`` is what ``fit`` reads).
    """
    from springcad.fit.bench import BenchNoise, BenchSpring
    from springcad.fit.bench import simulate as _simulate
    from springcad.fit.protocols import Protocol

    if isinstance(spring, Verification):  # the FEA stiffness, the corrected design's backlash
        k = spring.stack_stiffness_Nm_per_rad
        b = spring.design.stack.backlash_nominal_rad if backlash_rad is None else backlash_rad
    elif isinstance(spring, Design):
        k = spring.stack.stiffness_Nm_per_rad
        b = spring.stack.backlash_nominal_rad if backlash_rad is None else backlash_rad
    elif isinstance(spring, (int, float)) and math.isfinite(spring) and spring > 0:
        k, b = float(spring), backlash_rad or 0.0
    else:
        raise DataError(f"simulate: give a Design or a positive stiffness in N*m/rad, not {spring!r}")
    try:
        bench = BenchSpring(k, backlash_rad=b, **effects)
    except TypeError as err:
        raise DataError(f"simulate: {err}") from None
    return _simulate(bench, protocol=protocol or Protocol(), noise=noise or BenchNoise(),
                     seed=seed)


def fit_record(record, target_stiffness_Nm_per_rad: float | None = None, design=None) -> Fit:
    """Fit the paper's models to a bench record and explain the residual.

    Args:
        record: a :class:`~springcad.fit.bench.SimulatedRecord`, a
            :class:`~springcad.fit.data.BenchRecord`, or a CSV path (columns
            ``time_s, torque_Nm, deflection_rad``).
        target_stiffness_Nm_per_rad: target for the stiffness error (default: the design's).
        design: a :class:`Design` to compare the fit with.

    Returns:
        The :class:`Fit`.
    """
    from springcad.fit.analysis import fit_record as _fit_record
    from springcad.fit.data import parse_bench_csv

    if hasattr(record, "record") and hasattr(record, "spring"):  # SimulatedRecord
        record = record.record
    if isinstance(record, (str, Path)):
        path = Path(record)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as err:
            raise DataError(f"bench data file '{path}' cannot be read: {err}") from None
        record = parse_bench_csv(text, source=str(path))
    design_dict = design.to_dict() if isinstance(design, Design) else design
    return Fit(_fit_record(record, target_stiffness_Nm_per_rad, design_dict))
