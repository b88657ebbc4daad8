"""Build and export through the public API: solids and checks, then every file of a build.

``build`` makes the solids of a (verified) design and runs the geometry and
wire-EDM checks in memory; ``export_build`` writes the build folder: ``design.json``,
``fea/`` (when the design was FEA-verified), per-part STEP/STL/DXF/drawings,
the assembly, BOM, renders, ``build.json`` and ``report.html``. The folder
appears only when every file was written and read back (an atomic rename);
``springcad build`` is these two calls after ``design_job`` and ``verify``.
The name is ``export_build``, not ``export``, because ``springcad.export`` is a
subpackage: importing it rebinds that attribute of the package.

Units: lengths mm, stiffness N*m/rad, angles rad, masses kg.
"""

from __future__ import annotations

import contextlib
import copy
import datetime
import shutil
import time
import weakref
from pathlib import Path

from springcad.api import calls
from springcad.api.exports_beside import fea_and_render, part_drawings, render_inputs
from springcad.api.results import Design, Verification
from springcad.cache import MISSING, open_cache
from springcad.config import read_toml
from springcad.errors import ConfigError
from springcad.options import (DXF_VERSION, REVISION, api_door, check_dxf_version,
                               check_revision, written)
from springcad.parallel import ahead, enabled, single_threaded_blas
from springcad.progress import Tracker
from springcad.report import notebook
from springcad.report.fea_outputs import write_outputs
from springcad.report.html_build import write_build_report
from springcad.report.jsonio import write_json
from springcad.report.outdir import atomic_output_dir
from springcad.stages import stage
from springcad.version import __version__, stamp

#: schema of ``build.json``
SCHEMA = "springcad.build/1"

__all__ = ["Build", "build", "export_build", "export_verification", "load_title_block"]


class Build:
    """A built stack: solids and check results, and after :func:`export_build` its files.

    Attributes:
        design: the :class:`Design` that was built (FEA-corrected when verified).
        verification: the :class:`Verification`, or None (beam-theory design).
        assembly: the :class:`springcad.geometry.stack.StackAssembly` (solids in mm).
        checks: the :class:`springcad.geometry.checks.CheckReport` of the solids.
        accept_violations: wire-EDM rule violations were accepted.
        out_dir: the build folder after :func:`export_build`, else None.
        files: the written files (:class:`springcad.export.bundle.WrittenFile`).
        roundtrip: the export read-back checks.
        release: the :class:`springcad.export.release.ReleaseStatus` after export.
        timings_s: seconds per stage.
    """

    def __init__(self, design: Design, verification: Verification | None, assembly, checks,
                 accept_violations: bool = False, timings_s: dict | None = None):
        self.design, self.verification = design, verification
        self.assembly, self.checks = assembly, checks
        self.accept_violations = accept_violations
        self.timings_s = dict(timings_s or {})
        self.started = datetime.datetime.now().isoformat(timespec="seconds")
        self.out_dir: Path | None = None
        self.files: list = []
        self.roundtrip: list = []
        self.release = None
        self.options: dict = {}
        #: the FEA outputs being written ahead (:class:`_OutputsAhead`), or None
        self._outputs_ahead = None

    @property
    def ok(self) -> bool:
        """No geometry error, and no rule violation unless accepted."""
        return self.checks.passed(self.accept_violations)

    @property
    def released(self) -> bool | None:
        """Released for manufacture (None before :func:`export_build` judged it)."""
        return None if self.release is None else self.release.released

    @property
    def stiffness_Nm_per_rad(self) -> float:
        """The stack stiffness: FEA when verified, else beam theory (N*m/rad)."""
        if self.verification is not None:
            return self.verification.stack_stiffness_Nm_per_rad
        return self.design.stack.stiffness_Nm_per_rad

    @property
    def max_deflection_rad(self) -> float:
        return self.design.stack.max_deflection_rad

    @property
    def mass_kg(self) -> float:
        """Mass of the springs of the stack (kg)."""
        return self.design.stack.mass_kg

    @property
    def report_html(self) -> Path | None:
        """``report.html`` of the build folder (after :func:`export_build`)."""
        return None if self.out_dir is None else self.out_dir / "report.html"

    def parts(self) -> list[dict]:
        """Per distinct part: part number, name, title, kind, quantity, process."""
        qty = self.assembly.quantities()
        return [{"part_number": pn, "name": p.info.name, "title": p.info.title,
                 "kind": p.info.kind, "quantity": qty[pn], "process": p.info.process}
                for pn, p in self.assembly.parts.items()]

    def compound(self):
        """The stack as one build123d ``Compound``: every placed part a child, named
        (``label``, e.g. ``spring_1_S1``) and coloured, in the stack frame (mm; z the axis,
        the input side at the lowest z), as the assembly STEP holds it."""
        return self.assembly.compound()

    def failures(self) -> list[str]:
        """The failed checks, one line each (geometry errors; violations unless accepted)."""
        bad = self.checks.errors + ([] if self.accept_violations else self.checks.violations)
        return [f"{c.subject}: {c.name}: {c.message}" for c in bad]

    def raise_for_failures(self) -> None:
        """Raises :class:`~springcad.geometry.checks.ChecksFailed` (a
        :class:`~springcad.errors.CheckFailed`) when a check failed."""
        self.checks.raise_if_failed(self.accept_violations)

    def to_dict(self) -> dict:
        """The ``build.json`` document (needs :func:`export_build` for files and release)."""
        asm, st = self.assembly, self.design.raw.stack
        checks = self.checks.checks + self.roundtrip
        ver = self.verification
        return {
            **stamp(SCHEMA),
            "job": {"name": self.design.job.name, "config": str(self.design.job.source)},
            "started": self.started,
            "verification": ({"ok": ver.ok, "fea_json": "fea/fea.json",
                              "springs": {r["spring"]: {
                                  "stiffness_fea_Nm_per_rad": r["stiffness_fea_Nm_per_rad"],
                                  "yield_margin": r["yield_margin"]} for r in ver.spring_table()}}
                             if ver is not None else f"skipped ({written('verify', False)})"),
            "options": {"accept_violations": self.accept_violations, "verify": ver is not None,
                        **self.options},
            "timings_s": self.timings_s,
            "release": self.release.to_dict() if self.release is not None else None,
            "stack": {"sequence": list(st.sequence), "input": st.input, "output": st.output,
                      "joints": list(st.joints), "input_parts": asm.input_names,
                      "output_parts": asm.output_names, "instances": len(asm.instances)},
            "parts": [{**{k: p[k] for k in ("part_number", "name", "title", "kind", "quantity",
                                            "process")},
                       "dimensions_mm": asm.parts[p["part_number"]].info.dimensions}
                      for p in self.parts()],
            "files": [f.to_dict() for f in self.files],
            "checks": {
                "passed": all(c.passed for c in checks if c.kind == "error"),
                "violations_accepted": bool(self.checks.violations) and self.accept_violations,
                "summary": self.checks.summary(),
                "n_checks": len(checks),
                "n_failed": sum(not c.passed for c in checks),
                "items": [c.to_dict() for c in checks]},
        }

    def __repr__(self) -> str:
        state = (f"exported to {self.out_dir} ({self.release.stamp})" if self.out_dir is not None
                 else "not exported")
        return (f"Build({self.design.job.name!r}: {len(self.assembly.parts)} parts, "
                f"{len(self.assembly.instances)} instances; {self.checks.summary()}"
                f"{' (accepted)' if self.checks.violations and self.accept_violations else ''}; "
                f"K={self.stiffness_Nm_per_rad:.4g} N*m/rad "
                f"({'FEA' if self.verification is not None else 'beam'}); {state})")

    def _repr_html_(self) -> str:
        return notebook.build_html(self)


def _design_of(design, cache: bool | None = None) -> tuple[Design, Verification | None]:
    if isinstance(design, Verification):
        return design.design, design
    return calls._design_of(design, cache), None


@api_door
def build(design, accept_violations: bool = False, progress=None,
          cache: bool | None = None) -> Build:
    """Make the solids of every part and run the geometry and wire-EDM checks.

    Args:
        design: a :class:`Verification` (its FEA-corrected design is built), a
            :class:`Design` (beam theory, not for manufacture), a Job, a TOML
            path or a config dict.
        accept_violations: a wire-EDM rule violation does not fail the build
            (it is recorded and stops the release).
        progress: optional ``callable(message, fraction=None)``.
        cache: reuse the checks of a design checked before (:mod:`springcad.cache`;
            None: :data:`springcad.options.CACHE`); the solids are always made.

    Returns:
        The :class:`Build` (``.ok`` says whether the checks passed; nothing is written).

    Raises:
        StageError: the CAD kernel failed on a part (names the part and what to change).
    """
    d, ver = _design_of(design, cache)
    store = open_cache(cache)
    outputs = _OutputsAhead.start(ver, store, progress)
    try:
        cached = _cached_build(d.raw, store, progress)
        if cached is not None:
            built = Build(d, ver, *cached[:2], accept_violations, cached[2])
        else:
            from springcad.export import skeleton
            from springcad.geometry.checks import build_and_check

            with single_threaded_blas():  # see export_build
                assembly, report, timings = build_and_check(d.raw, progress, store)
            skeleton.store(store, d.raw, assembly)
            built = Build(d, ver, assembly, report, accept_violations, timings)
    except BaseException:
        if outputs is not None:
            outputs.close()
        raise
    if outputs is not None:
        built._outputs_ahead = outputs
        weakref.finalize(built, outputs.close)
    return built


class _OutputsAhead:
    """The FEA outputs of a verification (``fea.json``, .vtu fields, PNG renders:
    :func:`~springcad.report.fea_outputs.write_outputs`) written by a second process while
    :func:`build` makes and checks the solids (they need only the verification; the CAD steps
    leave the second core idle), into a staging folder whose files :func:`export_build`
    moves into the build folder (:meth:`take`). The files are those ``export_build`` would
    write itself; it does when the outputs were not started (no second process, no
    verification), are not wanted (``render=False``, another cache choice) or were taken
    by an earlier export."""

    def __init__(self, ver, store):
        import tempfile

        self.folder = Path(tempfile.mkdtemp(prefix="springcad-fea-"))
        self.cached = store is not None
        self.used = False
        self._messages: list = []
        self._stack = contextlib.ExitStack()
        self.pending = ahead(self._stack, write_outputs, ver.raw, self.folder, render=True,
                             cache=store, progress=lambda m, f=None: self._messages.append((m, f)))

    @classmethod
    def start(cls, ver, store, progress) -> "_OutputsAhead | None":
        """Start writing the outputs of ``ver`` (a :class:`Verification` or None) in a second
        process; None when there is no verification or no second process."""
        if ver is None or not enabled():
            return None
        Tracker(progress)("writing the FEA outputs (.vtu, renders) in a second process")
        return cls(ver, store)

    def usable(self, render: bool, store) -> bool:
        """Whether an export with these options writes exactly these files."""
        return not self.used and render and self.cached == (store is not None)

    def take(self, folder: Path, progress) -> list[Path]:
        """Wait for the outputs (their progress replayed into ``progress``), move them into
        ``folder`` and return their paths there, in the order they were written."""
        self.used = True
        try:
            written = self.pending.result()
            for message, fraction in self._messages:
                progress(message, fraction)
            moved = []
            for path in written:
                target = Path(folder) / Path(path).relative_to(self.folder)
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.move(str(path), str(target))
                moved.append(target)
            return moved
        finally:
            self.close()

    def close(self) -> None:
        """Stop the second process if it still runs and remove the staging folder."""
        self.used = True
        self._stack.close()
        shutil.rmtree(self.folder, ignore_errors=True)


def _cached_build(job_design, store, progress):
    """``(assembly, checks, timings_s)`` of a design built and checked before: its
    :class:`~springcad.export.skeleton.LazyAssembly` (solids built only if asked for) and
    its stored checks; None when either is not cached (or no cache)."""
    if store is None:
        return None
    from springcad.export import skeleton

    t0 = time.perf_counter()
    assembly = skeleton.load(store, job_design)
    if assembly is None:
        return None
    t1 = time.perf_counter()
    report = store.load(store.key("checks", job_design))
    if report is MISSING:
        return None
    track = Tracker(progress)
    with stage("solids", track.subject("solids")):
        track("parts of this design from the cache (solids built only if an export needs them)")
    track.last = ""
    with stage("checks", track.subject("checks")):
        track("checks of this design from the cache")
    return assembly, report, {"solids": round(t1 - t0, 3),
                              "checks": round(time.perf_counter() - t1, 3)}


@api_door
def export_verification(verification: Verification, out, overwrite: bool = False,
                        render: bool = True, progress=None,
                        cache: bool | None = None) -> list[Path]:
    """Write a verification folder: ``fea.json`` and, per spring, the ``.vtu`` fields and
    PNG renders (von Mises, cam contact, duty), what ``springcad verify`` writes (the von
    Mises renders by a second process beside the rest:
    :func:`~springcad.report.fea_outputs.write_outputs`).

    Args:
        verification: the :class:`Verification` (``keep_fields=True`` for the fields).
        out: the output folder; it appears only when everything was written.
        overwrite: replace an existing folder.
        render: write the ``.vtu`` fields and PNG renders (else ``fea.json`` only).
        progress: optional ``callable(message, fraction=None)``.
        cache: reuse the files of springs written before (:mod:`springcad.cache`; None:
            :data:`springcad.options.CACHE`).

    Returns:
        The files written, under ``out``.

    Raises:
        OutputExistsError, OutputPathError: the folder cannot be written.
    """
    if not isinstance(verification, Verification):
        raise ConfigError("export_verification", type(verification).__name__,
                          "takes the Verification that sc.verify returned")
    out = Path(out)
    inputs = [x for x in (verification.job.source,)
              if isinstance(x, (str, Path)) and x and Path(x).is_file()]
    with atomic_output_dir(out, overwrite=overwrite, inputs=inputs) as tmp:
        written = write_outputs(verification.raw, Path(tmp), render=render,
                                progress=Tracker(progress), cache=open_cache(cache),
                                beside_renders=True)
    return [out / Path(f).relative_to(tmp) for f in written]


@api_door
def load_title_block(source=None) -> dict:
    """The drawing title block: a TOML path, a dict, or None for the default template.

    Raises:
        ConfigError: a table the drawings need is missing.
    """
    from springcad.export.drawing import load_title_block as _default

    if isinstance(source, dict):
        template = source
    else:
        template = read_toml(source) if source else _default(None)
    for key in ("block", "rows"):
        if key not in template:
            raise ConfigError(f"{source}: {key}", None, "is required in a title block template "
                                                        "(see templates/drawing_title_block.toml)")
    return template


def build_date() -> str:
    """The build's date (YYYY-MM-DD) for title blocks and STEP headers: today, or the UTC
    day of ``SOURCE_DATE_EPOCH`` (seconds since 1970, the reproducible-builds convention)
    when it is set, so two builds of one job give byte-identical files.

    Raises:
        ConfigError: ``SOURCE_DATE_EPOCH`` is not a whole number of seconds.
    """
    import os

    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if not epoch:
        return datetime.date.today().isoformat()
    try:
        stamp = datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc)
    except (ValueError, OverflowError, OSError) as err:
        raise ConfigError("SOURCE_DATE_EPOCH (environment)", epoch,
                          "must be whole seconds since 1970-01-01 UTC",
                          "unset it to date the build today") from err
    return stamp.date().isoformat()


def _drawn_by() -> str:
    return f"springcad {__version__}"


@api_door
def export_build(built: Build, out, overwrite: bool = False, render: bool = True,
                 revision: str = REVISION,
           title_block=None, progress=None, timings_s: dict | None = None,
           cache: bool | None = None, dxf_version: str = DXF_VERSION) -> Build:
    """Write a build folder: design, FEA results, CAD, drawings, BOM, build.json, report.html.

    Args:
        built: a :class:`Build` whose checks passed.
        out: the output folder; it appears only when everything was written.
        overwrite: replace an existing folder.
        render: draw the PNG renders (assembly, FEA stress).
        revision: drawing revision (1 to 8 ASCII letters or digits).
        title_block: title block template (path or dict; default the packaged one).
        progress: optional ``callable(message, fraction=None)``.
        timings_s: times of earlier stages (s) to record in ``build.json``.
        cache: reuse the files (and read-back checks) of parts, assembly and FEA exported
            before with the same inputs (:mod:`springcad.cache`; None:
            :data:`springcad.options.CACHE`); the files are the same bytes.
        dxf_version: "R2010" (default, AC1024) or "R12" (AC1009, for CAM that reads
            nothing newer); either holds LINE, ARC and CIRCLE entities only.

    Returns:
        A new :class:`Build`, the given one with ``out_dir``, ``files``, ``release`` and
        ``report_html`` (the given one is left as it was, like build123d's ``export_step``
        leaves its shape).

    Raises:
        CheckFailed: the build's checks, or an export read-back, failed (nothing written).
        OutputExistsError, OutputPathError: the folder cannot be written.
    """
    if not isinstance(built, Build):
        raise ConfigError("export_build", type(built).__name__, "takes the Build that sc.build returned")
    check_revision(revision)
    check_dxf_version(dxf_version)
    built.raise_for_failures()
    built = copy.copy(built)  # the exported build; the argument stays as it was
    template = load_title_block(title_block)
    out = Path(out)
    track = Tracker(progress)
    t0 = time.perf_counter()
    built.options = {"revision": revision, "render": render, "dxf_version": dxf_version}
    store = open_cache(cache)
    inputs = [x for x in (built.design.job.source, title_block)
              if isinstance(x, (str, Path)) and x and Path(x).is_file()]
    outputs, built._outputs_ahead = built._outputs_ahead, None
    if outputs is not None and not outputs.usable(render, store):
        outputs.close()
        outputs = None
    with contextlib.ExitStack() as leaving:
        if outputs is not None:  # not taken (an error, an interrupt): stopped and removed
            leaving.callback(outputs.close)
        _export_into(built, out, overwrite, inputs, render, template, revision, dxf_version,
                     store, track, outputs, timings_s, t0)
    built.out_dir = out
    return built


def _export_into(built: Build, out: Path, overwrite: bool, inputs: list, render: bool, template,
                 revision: str, dxf_version: str, store, track, outputs, timings_s, t0) -> None:
    """The files of :func:`export_build` (its arguments, checked), written into a temporary
    folder that becomes ``out``; sets ``built``'s files, checks and timings."""
    from springcad.export.bundle import (WrittenFile, dxf_references, export_assembly,
                                         export_bundle, export_part_cad, export_part_dxfs,
                                         part_file_order, roundtrip_checks, stack_file_order)
    from springcad.export.skeleton import LazyAssembly
    from springcad.export.release import release_status
    from springcad.geometry.checks import CheckReport

    d, ver, asm = built.design, built.verification, built.assembly
    # one BLAS thread, as in the second processes: the CAD steps' BLAS work is tall, thin
    # products (placing 10^6 profile points), which OpenBLAS's second thread made 3-7x
    # slower on a busy machine (measured: 1e6 x 2 points placed, 0.63 s wall with two
    # threads, 0.09 s with one, the same numbers)
    with atomic_output_dir(out, overwrite=overwrite, inputs=inputs) as tmp, \
            single_threaded_blas():
        tmp = Path(tmp)
        with stage("exports", track.subject("exports")):
            write_json(tmp / "design.json", d.to_dict())
            built.release = release_status(d.raw, ver.raw if ver is not None else None,
                                           ver is None, built.checks.checks)
            info = {"job": d.job.name, "revision": revision,
                    "date": build_date(), "drawn_by": _drawn_by(),
                    "release": built.release}
            with part_drawings(asm, tmp, info, template, store, track) as drawings, \
                    contextlib.ExitStack() as later:
                # the drawings' process first, the longest of the exports; the render's
                # tessellation (this process) runs beside it
                png, triangles = render_inputs(asm, tmp, render, store, track)
                # FEA files to write (not written ahead): their process starts now; the
                # assembly render alone starts once the drawings' process has ended (VTK's
                # frame buffers and matplotlib's sheets in two processes beside this one
                # were the build's memory peak: default job 0.99 GB)
                fea = ver if outputs is None else None
                second = [None if fea is None else later.enter_context(
                    fea_and_render(fea, asm, tmp, png, triangles, store, track))]

                def render_when_drawn(wait: bool = False) -> None:
                    if second[0] is None and (wait or drawings.ready()):
                        drawings.result()  # its progress, in order
                        second[0] = later.enter_context(
                            fea_and_render(None, asm, tmp, png, triangles, store, track))

                def step(message, fraction=None):  # this process's progress, per file
                    track(message, fraction)
                    render_when_drawn()

                cad = export_part_cad(asm, tmp, info["date"], progress=step, cache=store)
                # the DXFs here, the drawings there: the drawings' process, then the render's,
                # take about as long as this one's share
                dxfs = export_part_dxfs(asm, tmp, progress=step, cache=store,
                                        dxf_version=dxf_version)
                stack = export_assembly(asm, tmp, render=False, progress=step,
                                        date=info["date"], cache=store)
                checks = roundtrip_checks(asm, tmp, cad, progress=step, cache=store)
                references = None if isinstance(asm, LazyAssembly) else dxf_references(asm)
                checks += roundtrip_checks(asm, tmp, dxfs, progress=step, cache=store,
                                           references=references)
                render_when_drawn(wait=True)
                parts = part_file_order(asm, cad + dxfs + drawings.result())
                stack += export_bundle(asm, tmp, parts, progress=track,
                                       release=built.release)
                if outputs is not None:  # before the render's result: progress in that order
                    fea_files = outputs.take(tmp / "fea", track)
                fea_files, png = second[0].result() if outputs is None else (
                    fea_files, second[0].result()[1])
            files = parts + stack_file_order(stack + png)
            order = {f.path: k for k, f in enumerate(files)}
            built.roundtrip = sorted(checks, key=lambda c: order[c.subject])
        CheckReport(built.roundtrip).raise_if_failed()
        files.append(WrittenFile("design.json", "design", "", (tmp / "design.json").stat().st_size))
        files += [WrittenFile(str(f.relative_to(tmp)), "fea", "", f.stat().st_size)
                  for f in fea_files]
        built.files = files
        built.timings_s = {**(timings_s or {}), **built.timings_s,
                           "exports": round(time.perf_counter() - t0, 3)}
        built.timings_s["total"] = round(sum(v for k, v in built.timings_s.items()
                                             if k != "total"), 3)
        write_json(tmp / "build.json", built.to_dict())
        report = write_build_report(tmp)  # last: it reads the files written above
        built.files.append(WrittenFile("report.html", "report", "", report.stat().st_size))
        write_json(tmp / "build.json", built.to_dict())  # now listing the report too
