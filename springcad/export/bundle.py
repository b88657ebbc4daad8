"""Write every export of a built stack into a folder, and read the exports back.

Layout of the folder::

    parts/<PN>.step, .stl          every distinct part
    parts/<PN>.dxf                 cutting profile of planar / wire-EDM parts
    parts/<PN>.svg, .pdf           vendor drawing of every made part
    assembly.step                  the stack (parts once, placed per instance)
    bom.csv                        bill of materials
    assembly.png                   render for reports
    vendor.zip                     per-part STEP/DXF/PDF, BOM and README for the shop
                                   (:mod:`springcad.export.vendor`)

Units: mm.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from springcad.cache import files, memo
from springcad.export.bom import write_bom
from springcad.export.drawing import DrawingInfo, write_drawing
from springcad.export.dxf import (CHORD_TOL_MM, loops_area_mm2, loops_length_mm, read_dxf_loops,
                                  write_dxf)
from springcad.export.release import UNASSESSED
from springcad.export.render import render_png
from springcad.export.skeleton import built_part, with_solids
from springcad.export.step import read_step, write_assembly_step, write_part_step, write_part_stl
from springcad.export.vendor import write_vendor_bundle
from springcad.geometry.checks import Check
from springcad.geometry.profile import profile_face
from springcad.options import DXF_VERSION
from springcad.parallel import trim_heap
from springcad.progress import Progress, no_progress
from springcad.units import UM_PER_MM

#: read-back tolerances: volume and area (relative), bounding box (mm)
ROUNDTRIP_RTOL = 1e-3
BBOX_TOL_MM = 1e-3
#: DXF perimeter against the kernel face's (relative): catches a missing or extra
#: feature (a tip ball is ~1 mm of a 70-2100 mm wire path); measured 4e-7 (ring) to
#: 9e-6 (cam, 224 biarcs)
PERIMETER_RTOL = 1e-4


@dataclass(frozen=True)
class WrittenFile:
    """One exported file (path relative to the output folder)."""

    path: str
    kind: str
    part: str = ""
    bytes: int = 0
    info: str = ""

    def to_dict(self) -> dict:
        return asdict(self)


def _record(out_dir: Path, path: Path, kind: str, part: str = "", info: str = "") -> WrittenFile:
    return WrittenFile(str(Path(path).relative_to(out_dir)), kind, part,
                       Path(path).stat().st_size, info)


def part_fingerprint(part) -> tuple:
    """What a part's solid and files are a function of: its info (part number, profile,
    dimensions, fits ...), its slabs, colour and kind of solid (the cache key's input)."""
    return (part.info, part.slabs, part.colour, part.exact_prism)


def export_parts(assembly, out_dir: Path, drawing_info: dict, template: dict | None = None,
                 progress: Progress = no_progress, cache=None) -> list[WrittenFile]:
    """STEP, STL, DXF and drawings of every distinct part (:func:`export_part_sheets`, then
    :func:`export_part_cad`; in :func:`part_file_order`).

    Args:
        drawing_info: ``job``, ``revision``, ``date`` for the title blocks.
        progress: ``progress(message, fraction=None)``, called per part.
        cache: a :class:`springcad.cache.Cache` holding the files of parts (and their
            drawings' title blocks) exported before, or None.
    """
    sheets = export_part_sheets(assembly, out_dir, drawing_info, template, progress, cache)
    cad = export_part_cad(assembly, out_dir, drawing_info.get("date", ""), progress, cache)
    return part_file_order(assembly, cad + sheets)


#: the order of a part's files in a build's file list
PART_FILE_KINDS = ("step", "stl", "dxf", "svg", "pdf", "png")


def part_file_order(assembly, written: list[WrittenFile]) -> list[WrittenFile]:
    """The part files in the assembly's part order, each part's in :data:`PART_FILE_KINDS`
    order: the same list whichever process wrote which file first."""
    parts = list(assembly.parts)
    return sorted(written, key=lambda f: (parts.index(f.part), PART_FILE_KINDS.index(f.kind)))


def _each_part(assembly, out_dir: Path, kind: str, inputs, write, what: str,
               progress: Progress, cache, numbers=None) -> list[WrittenFile]:
    """Files of every distinct part (of those of ``numbers``, by part number, if given),
    through the cache: ``write(pn)`` returns (paths, [(kind, note)]) and ``inputs(pn)`` the
    cache key's inputs beside the part's fingerprint; ``what`` (e.g. "STEP, STL") names them
    in the progress lines."""
    out = []
    parts = [(pn, part) for pn, part in assembly.parts.items() if numbers is None or pn in numbers]
    for k, (pn, part) in enumerate(parts):
        progress(f"exporting {pn} ({what})", k / len(parts))
        paths, meta = files(cache, kind, (part_fingerprint(part), *inputs(pn)), out_dir,
                            lambda: write(pn),
                            lambda: progress(f"{pn}: {what} files from the cache", None))
        out += [_record(out_dir, path, kind_, pn, note) for path, (kind_, note) in zip(paths, meta)]
    return out


def export_part_cad(assembly, out_dir: Path, date: str = "", progress: Progress = no_progress,
                    cache=None) -> list[WrittenFile]:
    """STEP and STL of every distinct part (the CAD kernel's files), the STEP dated ``date``
    (YYYY-MM-DD); through ``cache`` (:class:`springcad.cache.Cache` or None)."""
    parts_dir = Path(out_dir) / "parts"
    parts_dir.mkdir(parents=True, exist_ok=True)

    def write(pn):
        part = built_part(assembly, pn)
        return ([write_part_step(part, parts_dir / f"{pn}.step", date),
                 write_part_stl(part, parts_dir / f"{pn}.stl")], [("step", ""), ("stl", "")])

    return _each_part(assembly, out_dir, "part-cad", lambda pn: (date,), write,
                      "STEP, STL", progress, cache)


def export_part_sheets(assembly, out_dir: Path, drawing_info: dict, template: dict | None = None,
                       progress: Progress = no_progress, cache=None,
                       dxf_version: str = DXF_VERSION) -> list[WrittenFile]:
    """DXF (profile-cut parts) and drawings (made parts) of every distinct part
    (:func:`export_part_dxfs`, then :func:`export_part_drawings`): no CAD kernel (the
    drawings' views and the DXF are drawn from the parts' profiles).

    Args:
        drawing_info: ``job``, ``revision``, ``date``, ``drawn_by``, ``release`` for the
            title blocks (the part's quantity is added).
        cache: a :class:`springcad.cache.Cache` or None.
        dxf_version: DXF file version (:data:`springcad.options.DXF_VERSIONS`): the
            default R2010 (AC1024) or R12 (AC1009) for CAM that reads nothing newer; both
            hold the same LINE/ARC/CIRCLE entities.
    """
    return (export_part_dxfs(assembly, out_dir, progress, cache, dxf_version)
            + export_part_drawings(assembly, out_dir, drawing_info, template, progress, cache))


def export_part_dxfs(assembly, out_dir: Path, progress: Progress = no_progress, cache=None,
                     dxf_version: str = DXF_VERSION) -> list[WrittenFile]:
    """The DXF of every profile-cut part (see :func:`export_part_sheets`)."""
    parts_dir = Path(out_dir) / "parts"
    parts_dir.mkdir(parents=True, exist_ok=True)
    cut = [pn for pn, part in assembly.parts.items() if part.info.cut_profile is not None]
    return _each_part(assembly, out_dir, "part-dxf", lambda pn: (dxf_version,),
                      lambda pn: _write_dxf(built_part(assembly, pn), parts_dir, dxf_version),
                      "DXF", progress, cache, cut)


def export_part_drawings(assembly, out_dir: Path, drawing_info: dict,
                         template: dict | None = None, progress: Progress = no_progress,
                         cache=None) -> list[WrittenFile]:
    """The drawings of every made part (see :func:`export_part_sheets`): written by a forked
    process beside the STEP/STL and DXF exports (the longest of the build's files)."""
    parts_dir = Path(out_dir) / "parts"
    parts_dir.mkdir(parents=True, exist_ok=True)
    qty = assembly.quantities()
    made = [pn for pn, part in assembly.parts.items() if part.info.process != "purchased"]

    def info(pn):
        return {**drawing_info, "quantity": qty[pn]}

    def write(pn):
        paths = write_drawing(built_part(assembly, pn), DrawingInfo(**info(pn)), parts_dir,
                              template)
        return paths, [(path.suffix[1:], "") for path in paths]

    return _each_part(assembly, out_dir, "part-drawings", lambda pn: (info(pn), template), write,
                      "drawings", progress, cache, made)


def _write_dxf(part, parts_dir: Path, dxf_version: str = DXF_VERSION) -> tuple[list[Path], list]:
    """Write a profile-cut part's DXF; returns its path and ("dxf", note)."""
    pn = part.part_number
    cut = sum(sl.length_mm for sl in part.slabs if sl.region is part.info.cut_profile)
    rep = write_dxf(part.info.cut_profile, parts_dir / f"{pn}.dxf", pn, part.info.thickness_mm,
                    version=dxf_version, profile_length_mm=cut or None)
    return [rep.path], [("dxf", f"{rep.n_loops} closed contours as {rep.n_entities} "
                                f"{rep.entities} entities, {rep.n_biarcs} biarcs, "
                                f"max deviation {UM_PER_MM * rep.max_deviation_mm:.3f} um")]


def export_stack(assembly, out_dir: Path, part_files: list[WrittenFile], render: bool = True,
                 progress: Progress = no_progress, release=None,
                 date: str = "", cache=None) -> list[WrittenFile]:
    """Assembly STEP, bill of materials, (optionally) the PNG render and the vendor bundle
    (:func:`export_assembly`, then :func:`export_bundle`; in that order in the list).

    Args:
        part_files: the parts' files (:func:`export_parts`), for the BOM and the bundle.
        progress: ``progress(message, fraction=None)``, called per file.
        release: the build's :class:`~springcad.export.release.ReleaseStatus` for the
            vendor bundle's README (not assessed if None).
        date: YYYY-MM-DD of the assembly STEP's header (the build's date).
        cache: a :class:`springcad.cache.Cache` holding the assembly STEP and render of
            designs exported before (the assembly is a function of its design), or None.
    """
    cad = export_assembly(assembly, out_dir, render, progress, date, cache)
    return stack_file_order(cad + export_bundle(assembly, out_dir, part_files, progress,
                                                release))


#: the order of the stack's files in a build's file list
STACK_FILE_KINDS = ("step_assembly", "bom", "png", "vendor_zip")


def stack_file_order(written: list[WrittenFile]) -> list[WrittenFile]:
    """The stack's files in :data:`STACK_FILE_KINDS` order."""
    return sorted(written, key=lambda f: STACK_FILE_KINDS.index(f.kind))


def export_assembly(assembly, out_dir: Path, render: bool = True,
                    progress: Progress = no_progress, date: str = "",
                    cache=None) -> list[WrittenFile]:
    """The assembly STEP (dated ``date``) and, with ``render``, the PNG render
    (:func:`export_render`): the files of the stack made from its solids (see
    :func:`export_stack` for the arguments)."""
    out_dir = Path(out_dir)
    progress("exporting assembly STEP", 0.0)

    def step():
        return [write_assembly_step(with_solids(assembly), out_dir / "assembly.step", date)], None

    hit = lambda: progress("assembly STEP from the cache", None)  # noqa: E731
    (path,), _ = files(cache, "assembly-step", (assembly.design, date), out_dir, step, hit)
    out = [_record(out_dir, path, "step_assembly")]
    if render:
        out += export_render(assembly, out_dir, progress, cache)
    return out


#: the cache kind of the assembly render (key inputs: the design)
_RENDER_KIND = "assembly-png"


def cached_render(assembly, out_dir: Path, cache) -> list[WrittenFile] | None:
    """``assembly.png`` written from the cache (the render of this design), or None."""
    if cache is None:
        return None
    hit = cache.load_files(cache.key(_RENDER_KIND, assembly.design), Path(out_dir))
    return None if hit is None else [_record(Path(out_dir), hit[0][0], "png")]


def export_render(assembly, out_dir: Path, progress: Progress = no_progress, cache=None,
                  triangles=None) -> list[WrittenFile]:
    """``assembly.png`` (:func:`springcad.export.render.render_png`), through the cache.

    Args:
        triangles: the parts' tessellation (:func:`springcad.export.render.part_triangles`)
            when it was made elsewhere (the render then needs no solid), else None.
    """
    out_dir = Path(out_dir)
    if triangles is None:
        trim_heap()  # the part exports' freed heap, before VTK's buffers (the build's peak)

    def png():
        return [render_png(assembly if triangles is not None else with_solids(assembly),
                           out_dir / "assembly.png", triangles=triangles)], None

    progress("rendering assembly.png", 0.5)
    hit = lambda: progress("assembly.png from the cache", None)  # noqa: E731
    (path,), _ = files(cache, _RENDER_KIND, (assembly.design,), out_dir, png, hit)
    return [_record(out_dir, path, "png")]


def export_bundle(assembly, out_dir: Path, part_files: list[WrittenFile],
                  progress: Progress = no_progress, release=None) -> list[WrittenFile]:
    """The bill of materials and the vendor bundle, from the parts' files (written)."""
    out_dir = Path(out_dir)
    by_part: dict[str, list[str]] = {}
    for f in part_files:
        by_part.setdefault(f.part, []).append(f.path)
    out = [_record(out_dir, write_bom(assembly, out_dir / "bom.csv", by_part), "bom")]
    progress("writing vendor.zip", 0.9)
    out.append(_record(out_dir, write_vendor_bundle(assembly, out_dir, release or UNASSESSED,
                                                    assembly.design.job.name), "vendor_zip"))
    return out


def dxf_reference(part) -> tuple[float, float]:
    """What the DXF read-back of a profile-cut part is held against: the kernel's area
    (mm^2) and perimeter (mm) of its profile face."""
    from springcad.geometry.base import face_area_mm2

    # the profile's loops were checked when the part's solid was made from them
    face = profile_face(part.info.cut_profile, part.part_number, check=False)
    return face_area_mm2(face), sum(e.length for e in face.edges())


def dxf_references(assembly) -> dict:
    """:func:`dxf_reference` of every profile-cut part, by part number: computed by the build's
    process while a second one writes the DXFs (:func:`roundtrip_checks`' ``references``)."""
    return {pn: dxf_reference(built_part(assembly, pn)) for pn, part in assembly.parts.items()
            if part.info.cut_profile is not None}


def roundtrip_checks(assembly, out_dir: Path, files: list[WrittenFile],
                     progress: Progress = no_progress, cache=None,
                     references: dict | None = None) -> list[Check]:
    """Read every part STEP and DXF back and hold it against the part.

    STEP: one valid solid, same volume (0.1 %) and bounding box (1 um).
    DXF: the CUT layer's lines, arcs and circles chain into one closed contour per
    loop of the profile, the file audits clean, the enclosed area equals the kernel's area
    of the profile face within the chordal tolerance x the perimeter, and the
    perimeter the kernel's within :data:`PERIMETER_RTOL` (``references``: those of
    :func:`dxf_references`, else computed here). With a
    :class:`springcad.cache.Cache`, the check of a file whose bytes were read back before
    against the same part is taken from it.
    """
    import hashlib

    out = []
    for k, f in enumerate(files):
        part = assembly.parts.get(f.part)
        if part is None or f.kind not in ("step", "dxf"):
            continue
        path = Path(out_dir) / f.path
        progress(f"reading back {f.path}", k / len(files))
        digest = hashlib.sha256(path.read_bytes()).hexdigest() if cache is not None else ""
        out.append(memo(cache, "roundtrip", (digest, f, part_fingerprint(part)),
                        lambda: _read_back(built_part(assembly, f.part), path, f,
                                           (references or {}).get(f.part))))
    return out


def _read_back(part, path: Path, f: WrittenFile, reference=None) -> Check:
    """The read-back check of one STEP or DXF file of ``part`` (see :func:`roundtrip_checks`;
    ``reference``: the DXF's :func:`dxf_reference`, or None to compute it)."""
    if f.kind == "step":
        rb = read_step(path)
        v = part.volume_mm3()
        bb = part.solid.bounding_box()
        ref_lo, ref_hi = (bb.min.X, bb.min.Y, bb.min.Z), (bb.max.X, bb.max.Y, bb.max.Z)
        box_err = max(abs(a - b) for a, b in zip(rb.bbox_min + rb.bbox_max, ref_lo + ref_hi))
        ok = (rb.n_solids == 1 and rb.valid and abs(rb.volume_mm3 - v) <= ROUNDTRIP_RTOL * v
              and box_err <= BBOX_TOL_MM and part.part_number in rb.names)
        return Check("step_roundtrip", f.path, ok, value=rb.volume_mm3, limit=v, unit="mm^3",
                     message=f"{rb.n_solids} solid(s), valid {rb.valid}, volume "
                             f"{100 * (rb.volume_mm3 / v - 1):+.5f} %, bbox off by "
                             f"{box_err:.2e} mm, names {list(rb.names)}")
    try:
        loops, auditor = read_dxf_loops(path)
    except ValueError as err:
        return Check("dxf_roundtrip", f.path, False, message=str(err))
    area, length = loops_area_mm2(loops), loops_length_mm(loops)
    ref, ref_len = reference if reference is not None else dxf_reference(part)
    n_loops = len(part.info.cut_profile.loops)
    ok = (len(loops) == n_loops and not auditor.has_errors
          and abs(area - ref) <= CHORD_TOL_MM * ref_len
          and abs(length - ref_len) <= PERIMETER_RTOL * ref_len)
    return Check("dxf_roundtrip", f.path, ok, value=area, limit=ref, unit="mm^2",
                 message=f"{len(loops)} closed line-and-arc contours (profile has "
                         f"{n_loops}), {len(auditor.errors)} audit errors, area "
                         f"{area - ref:+.2e} mm^2, perimeter {length - ref_len:+.2e} "
                         f"mm against the face; {f.info}")
