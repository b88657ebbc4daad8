"""Jobs and built stacks shared by the geometry and export tests.

Stacks are built in-process from the S1/S2 templates' data with a ``[stack]``
sequence (the paper's Table I configurations), once per test session.
"""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path

import pytest

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"

#: paper Table I configurations: template file (all drive the first camshaft)
TABLE_I = {
    "S1": "paper_S1.toml",
    "S2": "paper_S2.toml",
    "2xS1": "paper_2xS1.toml",
    "2xS2": "paper_2xS2.toml",
    "4xS1": "paper_4xS1.toml",
    "S1+2xS2": "paper_S1_2xS2.toml",
    "S2+3xS1": "paper_S2_3xS1.toml",
}
#: other templates built in-process (the README's default job)
OTHER_TEMPLATES = {"default": "default.toml"}
#: the same springs driven through the first rim (built in-process): rim flanges at the
#: input, and for S2+3xS1 only floating camshafts
RIM_INPUT = {
    "2xS2 rim": (["S2", "S2"], "rim"),
    "S2+3xS1 rim": (["S2", "S1", "S1", "S1"], "rim"),
}


def job_data(sequence, input_connection="shaft", **sections) -> dict:
    """Parsed-TOML dict of a job with the springs of the S1/S2 templates."""
    docs = [tomllib.loads((TEMPLATES / f"paper_{n}.toml").read_text()) for n in ("S1", "S2")]
    data = dict(docs[0])
    springs = {**docs[0]["springs"], **docs[1]["springs"]}
    data["springs"] = {k: v for k, v in springs.items() if k in sequence}
    data["stack"] = {"sequence": list(sequence), "input": input_connection}
    data["job"] = {"name": "x".join(sequence) if len(set(sequence)) == 1 and len(sequence) > 1
                   else "+".join(sequence), "description": "test stack"}
    for key, table in sections.items():
        data[key] = {**data.get(key, {}), **table}
    return data


def toml_text(data: dict) -> str:
    """Write a job dict back as TOML (tables of scalars, lists and inline tables)."""
    def value(v):
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):  # inline table ([[duty.blocks]] entries)
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        return repr(v)

    lines = []
    for section, table in data.items():
        if section == "springs":
            for name, spec in table.items():
                lines.append(f"[springs.{name}]")
                lines += [f"{k} = {value(v)}" for k, v in spec.items()]
        else:
            lines.append(f"[{section}]")
            lines += [f"{k} = {value(v)}" for k, v in table.items()]
        lines.append("")
    return "\n".join(lines)


@functools.cache
def design(name: str):
    """JobDesign of a Table I template or a rim-input variant (cached for the session)."""
    from springcad.config import job_from_dict, load_job
    from springcad.design.job import design_job

    if name in TABLE_I or name in OTHER_TEMPLATES:
        return design_job(load_job(TEMPLATES / {**TABLE_I, **OTHER_TEMPLATES}[name]))
    sequence, inp = RIM_INPUT[name]
    return design_job(job_from_dict(job_data(sequence, inp)))


@functools.cache
def assembly(name: str):
    """Built StackAssembly of :func:`design` (cached for the session)."""
    from springcad.geometry.stack import build_stack

    return build_stack(design(name))


@pytest.fixture(scope="session")
def s1_design():
    return design("S1")


@pytest.fixture(scope="session")
def s1_stack():
    return assembly("S1")


@pytest.fixture(scope="session")
def stack_4xs1():
    return assembly("4xS1")


@pytest.fixture(scope="session")
def ring_s1(s1_stack):
    return s1_stack.part_named("S1-RING")


@pytest.fixture(scope="session")
def cam_s1(s1_stack):
    return s1_stack.instance("camshaft_1").part
