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
from springcad.cache import memo, open_cache
from springcad.config import Job, job_from_dict, load_job
from springcad.errors import ConfigError, DataError
from springcad.options import BENCH, VERIFY, api_door, check_choice, check_number
from springcad.progress import Tracker
from springcad.stages import stage


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


@api_door
def design_job(job, cache: bool | None = None, progress=None) -> Design:
    """Design every spring of a job and the stack (beam theory and the stress model).

    Args:
        job: a :class:`~springcad.config.Job`, a TOML path or a config dict.
        cache: reuse the design of an equal job from the result cache
            (:mod:`springcad.cache`; None: the default, :data:`springcad.options.CACHE`).
        progress: ``progress(message, fraction)`` for the springs, the stock plate choice
            and a refusal's search (seconds to a minute or two; :mod:`springcad.progress`).

    Returns:
        The :class:`Design`.

    Raises:
        ConfigError: the config is not valid.
        StageError: the design math failed on this spec (names the job and what to change).
    """
    import springcad.design.job as _design

    job = _job(job)
    with stage("design", lambda: f"job {job.name}"):
        return Design(memo(open_cache(cache), "design", (job,),
                           lambda: _design.design_job(job, progress=progress)))


def _design_of(job_or_design, cache: bool | None = None) -> Design:
    """A :class:`Design` as given, or designed from a Job, a TOML path or a config dict."""
    return (job_or_design if isinstance(job_or_design, Design)
            else design_job(job_or_design, cache))


@api_door
def verify(job_or_design, model: str = VERIFY.model, levels: int = VERIFY.levels,
           tolerance_pct: float = VERIFY.tolerance_pct, correct: bool = VERIFY.correct,
           contact: bool = VERIFY.contact, keep_fields: bool = False,
           mesher: str = VERIFY.mesher, load: str = VERIFY.load,
           support_study: bool = VERIFY.support_study, progress=None,
           cache: bool | None = None) -> Verification:
    """FEA-verify (and correct the widths of) every spring.

    The defaults are :data:`springcad.options.VERIFY`, the same as ``springcad verify``'s
    and ``springcad build``'s.

    Args:
        job_or_design: a :class:`Design`, a Job, a TOML path or a config dict.
        model: ``"2d3d"`` (plane stress with a 3D factor, default), ``"2d"`` (plane
            stress, seconds) or ``"3d"`` (quadratic tets, slow).
        levels: mesh levels of the convergence study (3 to 5).
        tolerance_pct: accepted stiffness error against the target (%, 0 to 50 open).
        correct: scale the flexure widths until the FEA stiffness meets the target.
        contact: also run the cam contact sweep over +-theta_max.
        keep_fields: keep the stress fields of the finest meshes, so that
            :func:`export_build` can write the ``.vtu`` files and stress renders.
        mesher: ``"gmsh"`` (default) or ``"pytetwild"`` (fTetWild on the CAD solid;
            implies ``model="3d"``, ~1 min).
        load: cam load model, ``"traction"`` (smooth tangential patch, default) or
            ``"rigid_cam"``.
        support_study: also compare the rim held at its outer face with it held at
            its rim holes (full ring, ~10 s per spring).
        progress: optional ``callable(message, fraction)``.
        cache: reuse the FEA of a spring verified before with the same design and
            options (:mod:`springcad.cache`; None: :data:`springcad.options.CACHE`).

    Returns:
        The :class:`Verification`; ``.design`` is the corrected design.

    Raises:
        ConfigError: an option is not allowed (names the parameter).
        StageError: the mesher or solver failed (names the spring and what to change).
    """
    import fea.verify
    from fea.study import verify_options

    options = verify_options(model=model, levels=levels, mesher=mesher,
                             tolerance_pct=tolerance_pct, correct=correct, load=load,
                             support_study=support_study, contact=contact,
                             keep_fields=keep_fields)
    track = Tracker(progress)
    if not isinstance(job_or_design, Design):
        track("designing")
    d = _design_of(job_or_design, cache)
    with stage("verify", track.subject("verify")):
        return Verification(fea.verify.verify_job(d.raw, options, track, open_cache(cache)), d)


def _is_design_dict(value) -> bool:
    """A ``design.json`` document (``Design.to_dict()``), not a job config dict."""
    return isinstance(value, dict) and str(value.get("schema", "")).startswith("springcad.design")


@api_door
def bench_protocol(kind: str = "staircase", **options):
    """A bench test protocol: the paper's staircase of ramps or a stepped sine sweep.

    Args:
        kind: ``"staircase"`` (:class:`springcad.fit.protocols.Protocol`: ramps 0 ->
            +A -> 0 -> -A -> 0) or ``"sine"`` (:class:`~springcad.fit.protocols.SineSweep`).
        **options: the protocol's fields (rad, s, Hz), e.g. ``amplitudes_rad``,
            ``ramp_s``, ``rates_rad_per_s``, ``profile``, ``hold_s``, ``sample_rate_hz``,
            ``rest_s``; for sines ``frequencies_hz`` and ``cycles``. Options left out or
            None take the protocol's defaults.

    Raises:
        ConfigError: ``kind`` is not one of the two.
        DataError: the protocol cannot be run (names what is wrong).
    """
    from springcad.fit.protocols import Protocol, SineSweep

    check_choice("kind", kind, ("staircase", "sine"))
    given = {k: v for k, v in options.items() if v is not None}
    try:
        return (SineSweep if kind == "sine" else Protocol)(**given)
    except (TypeError, ValueError) as err:
        raise DataError(f"protocol: {err}") from None


@api_door
def simulate(spring, protocol=None, noise=None, seed: int = 0, backlash_rad: float | None = None,
             stiffness_Nm_per_rad: float | None = None, **effects):
    """Simulate a bench record of a spring under a test protocol.

    Args:
        spring: a :class:`Design` (its stack's beam stiffness and nominal
            backlash), a :class:`Verification` (its FEA stack stiffness), a Job, a TOML
            path or a config dict (designed first), or a stiffness in N*m/rad.
        protocol: a :class:`springcad.fit.protocols.Protocol` or ``SineSweep``
            (see :func:`bench_protocol`; default: the paper's staircase).
        noise: a :class:`springcad.fit.bench.BenchNoise` or a dict of its fields
            (default: the paper's levels).
        seed: random seed.
        backlash_rad: backlash (rad); default the design's nominal, or 0.
        stiffness_Nm_per_rad: stiffness (N*m/rad) in place of the design's.
        **effects: further :class:`springcad.fit.bench.BenchSpring` fields
            (``friction_torque_Nm``, ``lag_s``, ``drift_Nm_per_s``, ...).

    Returns:
        A :class:`springcad.fit.bench.SimulatedRecord` (``.record`` is what ``fit`` reads).
    """
    from springcad.fit.bench import BenchNoise, BenchSpring
    from springcad.fit.bench import simulate as _simulate
    from springcad.fit.protocols import Protocol

    if isinstance(spring, (str, Path, dict, Job)):
        spring = design_job(spring)
    if isinstance(spring, Verification):  # the FEA stiffness, the corrected design's backlash
        k = spring.stack_stiffness_Nm_per_rad
        b = spring.design.stack.backlash_nominal_rad
    elif isinstance(spring, Design):
        k = spring.stack.stiffness_Nm_per_rad
        b = spring.stack.backlash_nominal_rad
    elif (isinstance(spring, (int, float)) and not isinstance(spring, bool)
          and math.isfinite(spring) and spring > 0):
        k, b = float(spring), 0.0
    else:
        raise DataError(f"simulate: give a Design or a positive stiffness in N*m/rad, "
                        f"not {spring!r}")
    k = k if stiffness_Nm_per_rad is None else stiffness_Nm_per_rad
    b = b if backlash_rad is None else backlash_rad
    with stage("simulate"):
        try:
            noise = BenchNoise(**noise) if isinstance(noise, dict) else noise
            bench = BenchSpring(k, backlash_rad=b, **effects)
        except TypeError as err:
            raise DataError(f"simulate: {err}") from None
        return _simulate(bench, protocol=protocol or Protocol(), noise=noise or BenchNoise(),
                         seed=seed)


@api_door
def fit_record(record, target_stiffness_Nm_per_rad: float | None = None, design=None, *,
               time_col: str = BENCH.time_col, torque_col: str = BENCH.torque_col,
               deflection_col: str = BENCH.deflection_col, encoder_cols=None,
               angle_unit: str = BENCH.angle_unit, torque_unit: str = BENCH.torque_unit,
               trust_units: bool = False) -> Fit:
    """Fit the paper's models to a bench record and explain the residual.

    Args:
        record: a :class:`~springcad.fit.bench.SimulatedRecord`, a
            :class:`~springcad.fit.data.BenchRecord`, or a CSV path (read by
            :func:`springcad.fit.data.read_bench_csv`: at most 200 MB, UTF-8 with or
            without a byte-order mark, checked for physical ranges).
        target_stiffness_Nm_per_rad: target for the stiffness error (default: the design's).
        design: a :class:`Design`, a job TOML path or a config dict to compare the fit with.
        time_col: time column (s) of a CSV.
        torque_col: torque column of a CSV (in ``torque_unit``).
        deflection_col: optical deflection column of a CSV (in ``angle_unit``).
        encoder_cols: one or two encoder angle columns (input, output); default
            ``encoder_in_rad``/``encoder_out_rad`` (or ``_deg``) when present.
        angle_unit: ``"rad"`` or ``"deg"``, every angle column of a CSV.
        torque_unit: ``"Nm"`` or ``"Nmm"``, the torque column of a CSV.
        trust_units: fit even when the data contradicts the units (a warning instead
            of the refusal).

    Returns:
        The :class:`Fit` (``.warnings`` lists the record's and the design's warnings).

    Raises:
        DataError: the file or the record cannot be used (names what and why).
        ConfigError: an option is not allowed (names the parameter).
    """
    from springcad.fit.analysis import fit_record as _fit_record
    from springcad.fit.compare import design_from_config
    from springcad.fit.data import ColumnMap, read_bench_csv

    if target_stiffness_Nm_per_rad is not None:
        check_number("target_stiffness_Nm_per_rad", target_stiffness_Nm_per_rad, 0.0, 1e6,
                     low_open=True, unit=" N*m/rad")
    if hasattr(record, "record") and hasattr(record, "spring"):  # SimulatedRecord
        record = record.record
    if isinstance(record, (str, Path)):
        columns = ColumnMap(time_col, torque_col, deflection_col,
                            tuple(encoder_cols) if encoder_cols else None)
        record = read_bench_csv(record, columns, angle_unit, torque_unit, trust_units)
    if isinstance(design, (str, Path)):  # fitting works without the design core
        config = design
        with stage("design", lambda: f"config {config}"):
            design = design_from_config(config)
    elif design is not None and not _is_design_dict(design):
        design = _design_of(design).to_dict()
    warnings = tuple(design.get("warnings", ())) if design is not None else ()
    with stage("fit", lambda: f"record {record.source}"):
        return Fit(_fit_record(record, target_stiffness_Nm_per_rad, design,
                               trust_units=trust_units), design_warnings=warnings)
