"""The config schema: one declaration per key, ranges enforced at load, README in step.

Regression tests for the config classes of issue 11 (sections of the wrong type,
names that break exports, non-UTF-8 files, 400-digit integers, deep nesting,
1e300 sizes, unbounded Monte Carlo samples, the keys that were silently ignored).
"""

import dataclasses
import math
import re
import subprocess
import sys
import tomllib

import pytest

from springcad.config import job_from_dict, load_job
from springcad.config.schema import SECTIONS, keys, markdown_table, readme_with_table
from springcad.config.specs import AnalysisSpec, HardwareSpec, ManufacturingSpec
from springcad.errors import ConfigError
from tests.conftest import ROOT, template


def paper_s1():
    return tomllib.loads(template("paper_S1").read_text())


def set_key(data, section, name, value):
    if section == "springs.<name>":
        table = data["springs"]["S1"]
        if name.startswith("max_deflection"):
            table.pop("max_deflection_deg", None)
    elif section == "duty.blocks":
        table = {"cycles": 10.0}
        table["amplitude_deg" if name.endswith("_deg") else "amplitude_fraction"] = 0.1
        data["duty"] = {"blocks": [table]}
    else:
        table = data.setdefault(section, {})
    table[name] = value
    return data


def test_readme_table_is_generated_from_the_schema():
    readme = (ROOT / "README.md").read_text()
    assert readme_with_table(readme) == readme, "run: python -m springcad.config --readme README.md"
    for section, ks in SECTIONS.items():
        for k in ks:
            assert f"`{section}.{k.name}`" in markdown_table()


@pytest.mark.parametrize("cls,section", [(ManufacturingSpec, "manufacturing"),
                                         (HardwareSpec, "hardware"), (AnalysisSpec, "analysis")])
def test_spec_fields_are_the_schema_keys_with_its_defaults(cls, section):
    fields = {f.name: f.default for f in dataclasses.fields(cls)}
    # which [hardware] keys the config gives (springcad chooses the others): not a key
    assert fields.pop("given", ()) == ()
    declared = keys(section)
    if section == "manufacturing":
        # the surface of the cut faces is judged with the duty: it lives in DutySpec
        from springcad.config.specs import DutySpec
        assert DutySpec.surface == declared.pop("surface").default
    assert set(fields) == set(declared)
    for name, k in declared.items():
        if isinstance(k.default, str) and name.endswith("_kg_per_m3"):
            from springcad.materials import material_table
            assert fields[name] == material_table()[k.default].density_kg_per_m3
        else:
            assert fields[name] == k.default


def test_material_doc_names_every_built_in_material():
    from springcad.materials import material_table

    doc = keys("material")["name"].doc
    assert all(name in doc for name in material_table())


NUMERIC = [(s, k) for s, ks in SECTIONS.items() for k in ks if k.kind in ("float", "int")]


@pytest.mark.parametrize("section,key", NUMERIC, ids=[f"{s}.{k.name}" for s, k in NUMERIC])
def test_every_number_is_refused_outside_its_range_with_the_range(section, key):
    """Just outside each bound, 1e300, inf, nan, a 400-digit integer, a bool, a string,
    a list: one ConfigError naming the key and the allowed range."""
    step = 1 if key.kind == "int" else max(abs(key.hi) * 1e-3, 1e-9)
    bad = [key.hi + step, 1e300, -1e300, float("inf"), float("nan"), int("9" * 400), True,
           "12", [1, 2], {"a": 1}]
    if not key.lo_open:
        bad.append(key.lo - (1 if key.kind == "int" else max(abs(key.lo) * 1e-3, 1e-9)))
    if key.kind == "int":
        bad.append(float(key.lo))
    for value in bad:
        data = set_key(paper_s1(), section, key.name, value)
        with pytest.raises(ConfigError) as info:
            job_from_dict(data)
        msg = str(info.value)
        assert "\n" not in msg and key.name in msg, msg
        assert key.allowed in msg, msg


def test_loading_imports_nothing_heavy_and_repeats_exactly():
    """Loading a job is config work only: no CAD, mesher, solver or plotting import, and the
    same file gives the same job each time. Its speed (< 10 ms a load) is measured by
    bench/bench_config_load.py, not asserted here (a timed test fails under load)."""
    code = ("import sys; from springcad.config import load_job; "
            f"load_job({str(template('paper_S2_3xS1'))!r}); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & set(sys.argv[1:])))")
    heavy = ["build123d", "OCP", "pyvista", "skfem", "pytetwild", "matplotlib", "scipy"]
    out = subprocess.run([sys.executable, "-c", code, *heavy], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout.strip()
    assert out == "[]", f"loading a job imported {out}"
    first = load_job(template("paper_S2_3xS1"))
    assert all(load_job(template("paper_S2_3xS1")) == first for _ in range(3))


SECTION_SHAPES = {
    "material as a string": ("material", "x"),
    "springs as an integer": ("springs", 5),
    "stack as an array": ("stack", [1, 2]),
    "hardware as a bool": ("hardware", True),
    "analysis as a float": ("analysis", 1.5),
    "job as a string": ("job", "x"),
}


@pytest.mark.parametrize("case", list(SECTION_SHAPES))
def test_a_section_of_the_wrong_type_is_refused(case):
    section, value = SECTION_SHAPES[case]
    data = paper_s1()
    data[section] = value
    with pytest.raises(ConfigError, match=rf"'{section}' = .*must be a table"):
        job_from_dict(data)


def test_a_spring_table_of_the_wrong_type_is_refused():
    data = paper_s1()
    data["springs"]["S1"] = [1, 2]
    with pytest.raises(ConfigError, match=r"'springs\.S1' = \[1, 2\]: must be a table"):
        job_from_dict(data)


NAMES = {
    "job name a list": (("job", "name"), [1, 2], r"job\.name.*\[1, 2\].*must be a string.*array"),
    "job name non-ASCII": (("job", "name"), "ünï", r"job\.name.*printable ASCII"),
    "job name a path": (("job", "name"), "a/b", r"job\.name.*without /"),
    "job name too long": (("job", "name"), "x" * 65, r"job\.name.*1 to 64 characters"),
    "description a number": (("job", "description"), 5, r"job\.description.*must be a string"),
    "description control char": (("job", "description"), "a\x00b", r"job\.description.*printable"),
    "material name a list": (("material", "name"), [1, 2], r"material\.name.*must be a string"),
    "heat treatment non-ASCII": (("material", "heat_treatment"), "trempé",
                                 r"material\.heat_treatment.*ASCII"),
}


@pytest.mark.parametrize("case", list(NAMES))
def test_names_must_be_usable_in_every_export(case):
    (section, key), value, pattern = NAMES[case]
    data = paper_s1()
    data.setdefault(section, {})[key] = value
    with pytest.raises(ConfigError, match=pattern):
        job_from_dict(data)


@pytest.mark.parametrize("name", ["Sé", "S 1", "S/1", "x" * 33, "-S", "Ω"])
def test_spring_names_are_ascii_file_names(name):
    data = paper_s1()
    data["springs"] = {name: data["springs"]["S1"]}
    data["stack"]["sequence"] = [name]
    with pytest.raises(ConfigError, match=r"springs\.<name>.*letters, digits, _ and -"):
        job_from_dict(data)


def test_job_name_from_a_non_ascii_file_name_is_made_safe(tmp_path):
    data = paper_s1()
    del data["job"]["name"]
    path = tmp_path / "ressort é.toml"
    from tests.geometry.cad_fixtures import toml_text
    path.write_text(toml_text(data))
    assert load_job(path).name == "ressort"


def test_non_utf8_config_names_file_and_byte_offset(tmp_path):
    raw = template("paper_S1").read_bytes()
    path = tmp_path / "latin1.toml"
    path.write_bytes(b"# caf\xe9\n" + raw)
    with pytest.raises(ConfigError, match=r"latin1\.toml' is not UTF-8: byte 0xe9 at byte offset "
                                          r"5 \(line 1, column 6\).*save the file as UTF-8"):
        load_job(path)
    path.write_bytes(raw.decode().encode("utf-16"))
    with pytest.raises(ConfigError, match="is UTF-16"):
        load_job(path)
    path.write_bytes(b"\xef\xbb\xbf" + raw)  # a UTF-8 byte-order mark is fine
    assert load_job(path).name == "paper_S1"


@pytest.mark.parametrize("tail", ["x = " + "[" * 1000 + "]" * 1000,
                                  "x = " + "{a = " * 1000 + "1" + "}" * 1000,
                                  "[" + ".".join(["a"] * 1000) + "]\nx = 1"])
def test_deep_nesting_is_refused_not_a_recursion_error(tmp_path, tail):
    path = tmp_path / "deep.toml"
    path.write_text(template("paper_S1").read_text() + "\n" + tail + "\n")
    with pytest.raises(ConfigError) as info:
        load_job(path)
    assert "\n" not in str(info.value) and len(str(info.value)) < 500


def test_huge_integer_is_refused_with_a_short_message():
    data = set_key(paper_s1(), "springs.<name>", "n_flexures", int("9" * 400))
    with pytest.raises(ConfigError) as info:
        job_from_dict(data)
    assert len(str(info.value)) < 300 and "2 to 199" in str(info.value)


ISSUE_VALUES = {  # the values the issue found crashing or hanging, each refused with the range
    "outer radius 1e6 (hang)": ("springs.<name>", "outer_radius_mm", 1e6, "3 to 250 mm"),
    "outer radius 1e300": ("springs.<name>", "outer_radius_mm", 1e300, "3 to 250 mm"),
    "thickness 1e300": ("springs.<name>", "thickness_mm", 1e300, "0.2 to 100 mm"),
    "deflection 1e-6 deg": ("springs.<name>", "max_deflection_deg", 1e-6, "0.05 to 89 deg"),
    "stiffness 1e-6": ("springs.<name>", "target_stiffness_Nm_per_rad", 1e-6, "0.001 to 100000"),
    "tolerance 1e300": ("manufacturing", "t_spring_mm", 1e300, "0 to 0.5 mm"),
    "gap 1e300": ("manufacturing", "w_gap_mm", 1e300, "0.005 to 1 mm"),
    "web 1e300": ("manufacturing", "min_web_mm", 1e300, "0.02 to 5 mm"),
    "slot 50": ("manufacturing", "min_slot_width_mm", 50, "0.02 to 2 mm"),
    "fastener 50": ("hardware", "fastener_diameter_mm", 50, "0.5 to 12 mm"),
    "fastener count 1000": ("hardware", "fastener_count", 1000, "0 to 199"),
    "shaft 0.001": ("hardware", "shaft_diameter_mm", 0.001, "1 to 100 mm"),
    "spacer 1e6": ("hardware", "rim_spacer_thickness_mm", 1e6, "0.1 to 20 mm"),
    "samples 1e9": ("analysis", "monte_carlo_samples", 10 ** 9, "1 to 1000000"),
    "samples 2^63-1": ("analysis", "monte_carlo_samples", 2 ** 63 - 1, "1 to 1000000"),
}


@pytest.mark.parametrize("case", list(ISSUE_VALUES))
def test_issue_values_are_refused_at_load(case):
    section, key, value, allowed = ISSUE_VALUES[case]
    with pytest.raises(ConfigError, match=re.escape(allowed)):
        job_from_dict(set_key(paper_s1(), section, key, value))


CROSS = {
    "root above outer": (("springs.<name>", "root_radius_mm", 40.0), r"smaller than outer_radius"),
    "root below contact": (("springs.<name>", "root_radius_mm", 5.0), r"larger than contact_radius"),
    "0.01 mm rim (hang)": (("springs.<name>", "root_radius_mm", 33.49),
                           r"leaves a rim of 0\.01 mm; the rim needs at least 2\.3 mm"),
    "tip ball above half r_c": (("springs.<name>", "tip_radius_mm", 3.0), r"below half the contact"),
    "slot below the kerf": (("manufacturing", "min_slot_width_mm", 0.2), r"at least the kerf.*0\.3 mm"),
    "more fasteners than flexures": (("hardware", "fastener_count", 29), r"at most n_flexures = 28"),
    "bolt not ISO": (("hardware", "fastener", "bolt"), r"ISO 4762 screw size.*1\.6, 2, 2\.5"),
    "shaft over contact radius": (("hardware", "shaft_diameter_mm", 6.0), r"smaller than the contact"),
}


@pytest.mark.parametrize("case", list(CROSS))
def test_cross_key_consistency(case):
    (section, key, value), pattern = CROSS[case]
    with pytest.raises(ConfigError, match=pattern):
        job_from_dict(set_key(paper_s1(), section, key, value))


def test_rim_to_rim_joints_need_fasteners():
    """Without rim holes the rim joint cannot be assembled (the build failed its joint check)."""
    data = tomllib.loads(template("paper_2xS1").read_text())
    data["hardware"] = {"fastener_count": 0}
    with pytest.raises(ConfigError, match=r"fastener_count.*at least 1.*1 rim-to-rim joint"):
        job_from_dict(data)
    data["stack"]["input"] = "rim"  # joined shaft to shaft: no rim joint, no fasteners needed
    assert job_from_dict(data).hardware.fastener_count == 0


@pytest.mark.parametrize("key", ["centre_spacer_thickness_mm", "centre_spacer_clearance_mm"])
def test_removed_keys_are_refused_with_the_reason(key):
    data = paper_s1()
    data["hardware"] = {key: 0.5}
    with pytest.raises(ConfigError, match=rf"hardware\.{key}.*was removed.*delete this key"):
        job_from_dict(data)


@pytest.mark.parametrize("key,kind", [("rim_spacer_density_kg_per_m3", "rim_spacer"),
                                      ("plastic_density_kg_per_m3", "centre_spacer"),
                                      ("plastic_density_kg_per_m3", "bushing")])
def test_hardware_densities_change_the_part_masses(key, kind):
    """Each density key scales the mass of its parts (and so the stack mass) exactly."""
    from springcad.design.job import design_job

    data = tomllib.loads(template("paper_S2_3xS1").read_text())
    base = design_job(job_from_dict(data)).stack
    data.setdefault("hardware", {})[key] = 2 * getattr(HardwareSpec(), key)
    heavy = design_job(job_from_dict(data)).stack

    def parts(st):
        return [c for c in st.components if c.kind == kind]

    assert parts(base), kind
    for a, b in zip(parts(base), parts(heavy)):
        assert b.density_kg_per_m3 == 2 * a.density_kg_per_m3
        assert b.mass_kg == pytest.approx(2 * a.mass_kg)
    extra = sum(c.mass_kg for c in parts(base) if c.in_mass)
    assert heavy.mass_kg - base.mass_kg >= extra * (1 - 1e-9)


def test_default_min_tip_radius_follows_a_thick_wire():
    """The 0.3 mm default ball is below what a 0.5 mm wire + 0.1 mm spark gap can cut: the
    default moves up to 0.35 mm instead of failing on a key the user never wrote."""
    data = tomllib.loads(template("default").read_text())
    data["springs"]["S1"].pop("min_tip_radius_mm")
    data["manufacturing"].update(wire_diameter_mm=0.5, spark_gap_mm=0.1, min_slot_width_mm=0.7)
    assert job_from_dict(data).springs["S1"].min_tip_radius_mm == pytest.approx(0.35)


WARNINGS = {
    "min tip ignored": (lambda d: d["springs"]["S1"].update(min_tip_radius_mm=0.3),
                        r"min_tip_radius_mm = 0\.3 is ignored because tip_radius_mm"),
    "one-sample Monte Carlo": (lambda d: d.update(analysis={"monte_carlo_samples": 1}),
                               r"monte_carlo_samples = 1.*spread is zero"),
    "zero tolerances": (lambda d: d["manufacturing"].update(t_spring_mm=0, t_shaft_mm=0),
                        r"zero spread"),
    "unused spring": (lambda d: d["springs"].update(S9=dict(d["springs"]["S1"])),
                      r"S9 are defined but not in stack\.sequence"),
}


@pytest.mark.parametrize("case", list(WARNINGS))
def test_plausibility_warnings_on_the_job(case):
    mutate, pattern = WARNINGS[case]
    data = paper_s1()
    mutate(data)
    job = job_from_dict(data)
    assert any(re.search(pattern, w) for w in job.warnings), job.warnings
    assert not job_from_dict(paper_s1()).warnings


def test_zero_spread_statistics_are_what_the_warning_says():
    from springcad.design.job import design_job

    data = paper_s1()
    data["analysis"] = {"monte_carlo_samples": 1}
    b = design_job(job_from_dict(data)).stack.backlash
    assert b.mc_std == 0.0 and math.isfinite(b.mc_mean)


def test_old_stiffness_key_is_read_with_a_deprecation_warning():
    """springs.<name>.stiffness_Nm_per_rad was renamed target_stiffness_Nm_per_rad: a config
    with the old name loads to the same spec and says so; both names at once are refused."""
    new = job_from_dict(paper_s1())
    data = paper_s1()
    spring = data["springs"]["S1"]
    spring["stiffness_Nm_per_rad"] = spring.pop("target_stiffness_Nm_per_rad")
    old = job_from_dict(data)
    assert old.springs == new.springs
    assert old.warnings[0] == ("springs.S1.stiffness_Nm_per_rad is deprecated: it is now "
                               "springs.S1.target_stiffness_Nm_per_rad (same value and unit); "
                               "rename the key")
    assert old.warnings[1:] == new.warnings
    spring["stiffness_Nm_per_rad"] = -1.0  # a bad value names the key as written
    with pytest.raises(ConfigError, match=r"springs\.S1\.stiffness_Nm_per_rad' = -1\.0: must be"):
        job_from_dict(data)
    spring["target_stiffness_Nm_per_rad"] = 150.0
    with pytest.raises(ConfigError, match="old name of springs.S1.target_stiffness_Nm_per_rad, "
                                          "which is also given"):
        job_from_dict(data)
