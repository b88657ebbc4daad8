"""Stack math: alternation rules, camshaft sharing, tolerance stack statistics."""

import math

import pytest

from springcad.design.stack import camshaft_indices, connection_sequence
from springcad.design.tolerance import Interface, stack_backlash


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5])
@pytest.mark.parametrize("inp", ["shaft", "rim"])
def test_alternation_rules(n, inp):
    joints, out = connection_sequence(n, inp)
    assert len(joints) == n - 1
    assert all(a != b for a, b in zip(joints, joints[1:]))  # consecutive joints alternate
    if joints:
        assert joints[0] == ("rim" if inp == "shaft" else "shaft")
    # odd n: the output is the other kind; even n: the same kind (paper Section II-A)
    assert out == (inp if n % 2 == 0 else {"shaft": "rim", "rim": "shaft"}[inp])


def test_shaft_to_shaft_springs_share_a_camshaft():
    assert camshaft_indices(("rim", "shaft", "rim")) == (0, 1, 1, 2)
    assert camshaft_indices(("shaft", "rim")) == (0, 0, 1)


def _interfaces(n, t_spring=0.05, t_shaft=0.02, shared=()):
    cams = list(range(n))
    for i in shared:
        cams[i + 1] = cams[i]
    return [Interface(5.5, 0.025, t_spring, t_shaft, c) for c in cams]


def test_worst_case_adds_and_monte_carlo_stays_inside():
    b = stack_backlash(_interfaces(4), samples=20000, seed=7)
    one = 2 * math.atan(2 * (0.025 + 0.07) / 11)
    assert b.worst_max == pytest.approx(4 * one)
    assert b.worst_min <= b.rss_min <= b.nominal <= b.rss_max <= b.worst_max
    assert b.worst_min <= b.mc_p01 < b.mc_mean < b.mc_p99 <= b.worst_max
    assert b.mc_mean == pytest.approx(b.nominal, abs=3 * b.mc_std / math.sqrt(20000) + 1e-4)
    # uniform deviations: std of the sum of 8 independent U(-t, t) terms, linearised
    g = 2 / 5.5
    expected_std = math.sqrt(4 * (g * 0.05) ** 2 / 3 + 4 * (g * 0.02) ** 2 / 3)
    assert b.mc_std == pytest.approx(expected_std, rel=0.03)


def test_monte_carlo_is_seeded():
    a = stack_backlash(_interfaces(3), samples=5000, seed=3)
    b = stack_backlash(_interfaces(3), samples=5000, seed=3)
    c = stack_backlash(_interfaces(3), samples=5000, seed=4)
    assert a == b and a.mc_mean != c.mc_mean


def test_shared_camshaft_is_correlated():
    """A camshaft shared by two interfaces moves both gaps together: larger spread."""
    free = stack_backlash(_interfaces(2, t_spring=0.0, t_shaft=0.03), samples=40000, seed=1)
    shared = stack_backlash(_interfaces(2, t_spring=0.0, t_shaft=0.03, shared=(0,)),
                            samples=40000, seed=1)
    assert shared.mc_std == pytest.approx(math.sqrt(2) * free.mc_std, rel=0.03)
    assert shared.rss_max - shared.nominal == pytest.approx(
        math.sqrt(2) * (free.rss_max - free.nominal), rel=1e-9)


def test_interference_warning_only_when_possible(paper_designs):
    assert any("interference" in n for n in paper_designs["paper_4xS1"].stack.notes())
    from springcad.config import job_from_dict
    from springcad.design.job import design_job
    import tomllib
    from tests.conftest import template

    data = tomllib.loads(template("paper_S1").read_text())
    data["manufacturing"].update(t_spring_mm=0.01, t_shaft_mm=0.01)
    stack = design_job(job_from_dict(data)).stack
    assert stack.backlash.worst_min > 0
    assert stack.backlash.mc_interference_fraction == 0
    assert not any("interference" in n for n in stack.notes())


def test_stack_mass_counts_hardware(paper_designs):
    st = paper_designs["paper_4xS1"].stack
    kinds = {c.kind for c in st.components}
    assert {"flexure_ring", "camshaft", "rim_spacer", "centre_spacer", "rim_washer", "bushing",
            "alignment_shaft", "fastener"} <= kinds
    springs = sum(c.mass_kg for c in st.components if c.kind == "flexure_ring")
    assert springs == pytest.approx(4 * st.springs[0].mass_kg)
    assert st.mass_kg > springs
    assert st.energy_J == pytest.approx(4 * st.springs[0].energy_J, rel=2e-3)
    two = paper_designs["paper_2xS1"].stack
    assert {c.kind for c in two.components}.isdisjoint({"bushing", "alignment_shaft"})


@pytest.mark.parametrize("n", [1, 2, 3, 4])
@pytest.mark.parametrize("inp", ["shaft", "rim"])
def test_the_config_checks_the_rule_the_design_builds(n, inp):
    """The config's output check and its fasteners-for-rim-joints check read the same rule
    as the stack design: the output the design gives loads, the other is refused, and a
    fastener-less stack is refused exactly when the design has a rim-to-rim joint."""
    import tomllib

    import springcad as sc
    from springcad.config import ConfigError, job_from_dict
    from tests.conftest import template

    data = tomllib.loads(template("paper_S1").read_text())
    data["stack"] = {"sequence": ["S1"] * n, "input": inp}
    st = sc.design_job(data).raw.stack
    other = {"shaft": "rim", "rim": "shaft"}[st.output]
    assert job_from_dict({**data, "stack": {**data["stack"], "output": st.output}}).stack
    with pytest.raises(ConfigError, match=rf"stack\.output.*must be '{st.output}' for {n} spring"):
        job_from_dict({**data, "stack": {**data["stack"], "output": other}})
    rim_joints = sum(j == "rim" for j in st.joints)
    fastenerless = {**data, "hardware": {**data.get("hardware", {}), "fastener_count": 0}}
    if rim_joints:
        with pytest.raises(ConfigError,
                           match=rf"at least 1: this stack has {rim_joints} rim-to-rim"):
            job_from_dict(fastenerless)
    else:
        assert job_from_dict(fastenerless).hardware.fastener_count == 0
