"""A rebuild of a design built before takes its parts from the cached skeleton
(springcad/export/skeleton.py): no solid is made unless an export needs one, and the files
written from the lazily built solids are those of a fresh build, byte for byte (a zero's
sign in STEP/STL aside, which OCCT writes either way from one export to the next)."""

from pathlib import Path

import springcad as sc
from springcad.api.pipeline import load_title_block
from springcad.export.bom import bom_rows
from springcad.export.bundle import export_parts
from springcad.export.skeleton import LazyAssembly, PartRecord

ROOT = Path(__file__).resolve().parents[2]
INFO = {"job": "skeleton", "revision": "A", "date": "2023-11-14", "drawn_by": "test"}


def _files(root: Path) -> dict:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def test_rebuild_from_the_skeleton_builds_no_solid_and_writes_the_fresh_files(
        tmp_path, monkeypatch):
    monkeypatch.setenv("SPRINGCAD_CACHE_DIR", str(tmp_path / "cache"))
    design = sc.design_job(ROOT / "templates" / "paper_S1.toml", cache=False)
    fresh = sc.build(design, accept_violations=True, cache=True)  # stores the skeleton
    assert not isinstance(fresh.assembly, LazyAssembly)
    again = sc.build(design, accept_violations=True, cache=True)
    lazy = again.assembly
    assert isinstance(lazy, LazyAssembly) and lazy._solids is None
    # what the build, the BOM and the vendor README read, without a solid
    assert again.parts() == fresh.parts()
    assert again.checks.to_dict() == fresh.checks.to_dict()
    assert lazy.quantities() == fresh.assembly.quantities()
    assert [(i.name, i.role, i.part.part_number, i.placement, i.colour) for i in lazy.instances] \
        == [(i.name, i.role, i.part.part_number, i.placement, i.colour)
            for i in fresh.assembly.instances]
    assert bom_rows(lazy) == bom_rows(fresh.assembly)  # masses from the stored volumes
    assert lazy._solids is None
    # an export that is not cached builds the solids once, and writes the fresh files
    template = load_title_block()
    export_parts(fresh.assembly, tmp_path / "fresh", INFO, template)
    export_parts(lazy, tmp_path / "lazy", INFO, template)
    assert lazy._solids is not None
    a, b = _files(tmp_path / "fresh"), _files(tmp_path / "lazy")
    assert set(a) == set(b) and len(a) > 10
    for name in a:  # zeros are written unsigned (export/step.py): the same bytes
        assert a[name] == b[name], name
    # the API's part.solid works on a record too (the built part's)
    part = next(iter(lazy.parts.values()))
    assert isinstance(part, PartRecord)
    assert abs(part.solid.volume - part.volume_mm3) <= 1e-9 * part.volume_mm3
