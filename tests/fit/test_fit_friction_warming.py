"""A friction whose level follows the contact's temperature is no late channel (issue 24,
generator G's temperature-dependent friction on sines).

Known truth: a linear spring with Dahl friction whose level falls as the contact warms
(``C·dΔT/dt = |f·dθ/dt| - ΔT/R``, ``F = F0·(1 - ΔT)``: faster blocks heat it more), on a
stepped sine sweep; no lag. The control: the same protocol with a constant friction and
a true 10 ms lag. References: the simulated truth of each record.
"""

import numpy as np

from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.patches import stiffness_patches
from springcad.fit.protocols import SineSweep

from tests.fit.fit_helpers import K, loop_on_record

SWEEP = SineSweep(amplitudes_rad=(0.15, 0.3), frequencies_hz=(0.25, 0.5, 1.0, 2.0), cycles=3,
                  sample_rate_hz=500.0)
FRICTION_NM = 0.3
PRESLIDING_RAD = 0.004
#: the warming's time constant (s) and the level's fall at the power of the fastest block
THERMAL_S = 5.0
DROP = 0.4


def _friction(t, theta, warming: bool):
    """Dahl friction (N·m) along ``theta`` whose level falls with the contact's warming."""
    rate = np.gradient(theta, t)
    p_ref = FRICTION_NM * float(np.max(np.abs(rate))) * 2 / np.pi
    heat = 0.0
    f = 0.0
    out = np.empty_like(theta)
    for i in range(theta.size):
        dt = t[i] - t[i - 1] if i else 0.0
        d = theta[i] - theta[i - 1] if i else 0.0
        level = FRICTION_NM * (1.0 - heat) if warming else FRICTION_NM
        if d != 0.0:
            target = level if d > 0 else -level
            f = target - (target - f) * np.exp(-abs(d) / PRESLIDING_RAD)
        out[i] = f
        # ΔT/ΔT_ref reaches DROP at the fastest block's mean power
        heat += dt / THERMAL_S * (DROP * abs(f * rate[i]) / p_ref - heat)
    return out


def _record(warming: bool, lag_s: float = 0.0, seed: int = 1):
    rng = np.random.default_rng(seed)
    t = SWEEP.times()
    theta = SWEEP.deflection(t)
    late = SWEEP.deflection(t - lag_s) if lag_s else theta
    torque = K * late + _friction(t, late, warming) + 0.02 * rng.normal(size=t.size)
    return make_record(t, torque, theta + 5e-5 * rng.normal(size=t.size))


def test_a_warming_friction_names_no_lag():
    res, sig = loop_on_record(_record(warming=True))
    assert "hysteresis" in res.final.effects
    assert "time_lag" not in res.final.effects
    state = res.final
    idx = state.inliers(np.arange(sig.n))
    model = state.model.with_effect(get_effect("time_lag"))
    x = model.transfer(state.model, state.x, {"time_lag": np.array([-0.005])})
    x = model.fit(sig, idx, x, f_scale=0.05, max_nfev=200)
    # a lag fitted beside the one-level friction loses most of its size with the level free
    assert "time_lag" in stiffness_patches(model, x, sig, idx, SWEEP.sample_rate_hz,
                                           freed=("hysteresis",))


def test_a_true_lag_beside_a_constant_friction_is_kept():
    res, _ = loop_on_record(_record(warming=False, lag_s=0.01))
    assert {"hysteresis", "time_lag"} <= set(res.final.effects)
    lag = res.intervals["lag_s"]
    assert lag["ci_low"] <= 0.01 <= lag["ci_high"], lag
