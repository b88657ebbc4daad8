"""The contact sweep's speed-ups leave its numbers where they were: the sweep as it ran before
(BLAS with its thread pool, each cam offset's dilation ramp solved once per direction) against
the sweep as it runs now (one BLAS thread, each direction from its own reset solver state, the
"-" one in a second process), on the paper's S1 and the default job's spring.

Tolerances: the Newton iterations stop at increments, penetrations and residuals of 1e-7
(mm, relative); a different BLAS reduction order or a different tangent history moves the
converged state within them. Measured differences: 6e-10 relative on forces, stresses and
torques, 1e-10 mm on gaps and 2e-11 on the equilibrium residuals. Held here: 1e-7 relative or
1e-8 absolute (mm, N, MPa), every flag, verdict and text equal."""

from __future__ import annotations

import math

import pytest

from fea_helpers import TEMPLATES

pytest.importorskip("threadpoolctl")


def _compare(old, new, path=""):
    """Every leaf equal; floats within 1e-7 relative or 1e-8 absolute."""
    if isinstance(old, dict):
        assert set(old) == set(new), path
        for k in old:
            if k != "timings_s":
                _compare(old[k], new[k], f"{path}/{k}")
    elif isinstance(old, (list, tuple)):
        assert len(old) == len(new), path
        for i, (a, b) in enumerate(zip(old, new)):
            _compare(a, b, f"{path}[{i}]")
    elif isinstance(old, float) and not math.isnan(old):
        assert new == pytest.approx(old, rel=1e-7, abs=1e-8), path
    elif isinstance(old, float):
        assert math.isnan(new), path
    else:
        assert old == new, path


@pytest.mark.parametrize("template,spring", [("paper_S1.toml", "S1"), ("default.toml", None)])
def test_sweep_numbers_as_before_the_speed_ups(template, spring, monkeypatch):
    from threadpoolctl import threadpool_limits

    import fea.contact as contact
    from springcad.config import load_job
    from springcad.design.job import design_job

    job = design_job(load_job(TEMPLATES / template))
    design = job.springs[spring] if spring else next(iter(job.springs.values()))
    new = contact.contact_sweep(design)
    assert new.at_max is not None and len(new.steps) == 2

    each_once = contact.offset_path
    with monkeypatch.context() as m, threadpool_limits(limits=2, user_api="blas"):
        # the ramp solved for every path, as before
        m.setattr(contact, "offset_path",
                  lambda sc, curve, offset, sign, theta_max, steps, end=None, rest=None:
                  each_once(sc, curve, offset, sign, theta_max, steps, end=end))
        old = contact._contact_sweep(design)
    _compare(old.to_dict(), new.to_dict())


def test_the_directions_in_two_processes_give_the_serial_sweep(monkeypatch):
    """The "-" direction solved in a second process beside the "+" one gives, number for
    number, the sweep that solves both in this process (on the solver state reset between
    them): what fea.json holds does not depend on the parallel steps."""
    import json

    import fea.contact as contact
    from springcad.config import load_job
    from springcad.design.job import design_job
    from springcad.parallel import enabled

    if not enabled():
        pytest.skip("fork not available or switched off: both runs would be serial")
    design = next(iter(design_job(load_job(TEMPLATES / "default.toml")).springs.values()))
    beside = contact.contact_sweep(design)
    monkeypatch.setenv("SPRINGCAD_PARALLEL", "0")
    serial = contact.contact_sweep(design)
    text = [json.dumps({k: v for k, v in s.to_dict().items() if k != "timings_s"},
                       sort_keys=True) for s in (beside, serial)]
    assert text[0] == text[1]
    assert beside.at_max is not None and set(beside.steps) == {"+", "-"}
