"""A lag must describe more than the structure left beside it (issue 24, generator F's
stick-slip friction on two ramp rates).

Known truth: a linear spring with a stick-slip bearing in parallel (a compliant contact
that sticks until its torque reaches the static level and slips back to the kinetic
one: a sawtooth), on the staircase at two speeds; no lag. The control: the same record
with its torque channel 15 ms late. References: the simulated truth of each record.
"""

import numpy as np

from springcad.fit.bench import BenchSpring, simulate
from springcad.fit.effects import get_effect
from springcad.fit.patches import lag_patches
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

from tests.fit.fit_helpers import K, TWO_RATES, loop_on_record, with_extra_torque

STATIC_NM = 0.3
KINETIC_NM = 0.2
CONTACT_NM_PER_RAD = 60.0
LAG_S = 0.015


def _stick_slip(theta):
    """Torque (N·m) of a contact of stiffness ``CONTACT_NM_PER_RAD`` dragged along
    ``theta``: it sticks until ``STATIC_NM`` and slips back to ``KINETIC_NM``."""
    out = np.empty_like(theta)
    anchor = theta[0]
    for i, th in enumerate(theta):
        f = CONTACT_NM_PER_RAD * (th - anchor)
        if abs(f) > STATIC_NM:
            anchor = th - np.sign(f) * KINETIC_NM / CONTACT_NM_PER_RAD
            f = CONTACT_NM_PER_RAD * (th - anchor)
        out[i] = f
    return out


def _record(lag_s=0.0, seed=2):
    sim = simulate(BenchSpring(K, lag_s=lag_s), protocol=TWO_RATES, seed=seed)
    t = sim.record.time_s
    late = TWO_RATES.deflection(t - lag_s)
    return with_extra_torque(sim, lambda t_, th_: _stick_slip(late))


def test_a_stick_slip_friction_on_two_rates_names_no_lag():
    res, _ = loop_on_record(_record())
    assert "hysteresis" in res.final.effects
    assert "time_lag" not in res.final.effects
    assert res.unexplained


def test_a_true_lag_beside_the_stick_slip_friction_is_kept():
    res, _ = loop_on_record(_record(lag_s=LAG_S))
    assert {"hysteresis", "time_lag"} <= set(res.final.effects)
    lag = res.final.model.report(res.final.x)["lag_s"]
    assert abs(lag - LAG_S) < 0.2 * LAG_S, lag


def _forced(rec):
    """Friction and a lag fitted to ``rec`` whether it asks for the lag or not."""
    sig = make_signals(rec, segment(rec))
    model = TorqueModel((get_effect("hysteresis"), get_effect("time_lag")), sig.scales)
    idx = np.arange(sig.n)
    x0 = model.transfer(TorqueModel((), sig.scales), np.array([K]))
    return model, model.fit(sig, idx, x0, f_scale=0.05, max_nfev=200), sig, idx


def test_a_lag_fitted_beside_the_sawtooth_is_a_patch_and_a_true_one_is_not():
    model, x, sig, idx = _forced(_record())
    # the lag the fit finds is a tenth of the control's: a part of the sawtooth
    assert abs(model.report(x)["lag_s"]) < 0.2 * LAG_S
    assert "time_lag" in lag_patches(model, x, sig, idx)
    model, x, sig, idx = _forced(_record(lag_s=LAG_S))
    assert lag_patches(model, x, sig, idx) == {}
