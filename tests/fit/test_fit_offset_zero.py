"""An offset must show at zero deflection (issue 24, generator G's quadratic torque sensor).

Known truth: a linear spring read by a torque sensor whose gain grows with the torque,
``T·(1 + a·T/T_fs)`` (even in deflection, zero at zero deflection: no offset), against the
same spring with a true torque offset. References: the simulated truth of each record.
"""

import numpy as np

from springcad.fit.effects import get_effect
from springcad.fit.patches import offset_patches
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

from tests.fit.fit_helpers import K, loop_on_record, simulate_fast, with_extra_torque

#: quadratic gain error over the full scale: 6 % at the full scale, even in torque
QUADRATIC = 0.06


def _quadratic_sensor(sim):
    """``sim``'s record read by a sensor with gain ``1 + QUADRATIC·T/T_fs``."""
    full_scale = 1.3 * float(np.max(np.abs(sim.record.torque_Nm)))

    def extra(t, theta):
        torque = K * theta
        return QUADRATIC * torque * torque / full_scale
    return with_extra_torque(sim, extra)


def _fitted(rec, names):
    sig = make_signals(rec, segment(rec))
    model = TorqueModel(tuple(get_effect(n) for n in names), sig.scales)
    idx = np.arange(sig.n)
    x0 = model.transfer(TorqueModel((), sig.scales), np.array([K]))
    x = model.fit(sig, idx, x0, f_scale=0.05, max_nfev=200)
    return model, x, sig, idx


def test_an_offset_fitted_to_a_quadratic_sensor_is_not_shown_at_zero():
    rec = _quadratic_sensor(simulate_fast(seed=1))
    model, x, sig, idx = _fitted(rec, ("asymmetric_stiffness", "torque_offset"))
    # the offset takes up the parabola's mean over the range: clearly above noise
    assert abs(x[model.slice_of("torque_offset")][0]) > 0.01
    assert "torque_offset" in offset_patches(model, x, sig, idx)


def test_a_true_offset_is_shown_at_zero_beside_the_quadratic_sensor():
    rec = _quadratic_sensor(simulate_fast("torque_offset", seed=1))
    model, x, sig, idx = _fitted(rec, ("asymmetric_stiffness", "torque_offset"))
    assert offset_patches(model, x, sig, idx) == {}


def test_a_true_angle_offset_beside_backlash_is_shown_at_zero():
    rec = simulate_fast("angle_offset", seed=2).record
    model, x, sig, idx = _fitted(rec, ("backlash", "angle_offset"))
    assert offset_patches(model, x, sig, idx) == {}


def test_the_loop_names_no_offset_for_a_quadratic_sensor():
    # the search fits asymmetry, stiffening and both offsets cancelling at zero inside the
    # band it keeps; none of the offsets is the record's
    res, _ = loop_on_record(_quadratic_sensor(simulate_fast(seed=3)))
    assert not set(res.final.effects) & {"torque_offset", "angle_offset"}
    assert res.unexplained


def test_both_true_offsets_beside_an_off_centre_clearance_are_kept():
    rec = simulate_fast("angle_offset", "torque_offset", seed=4).record
    model, x, sig, idx = _fitted(rec, ("backlash", "angle_offset", "torque_offset"))
    assert offset_patches(model, x, sig, idx) == {}


def test_offsets_that_cancel_at_zero_are_one_kink_moved():
    # a torque offset equal to K times an angle offset beside an asymmetric stiffness: the
    # curve passes through zero, only the kink sits at the angle offset
    rec = simulate_fast(seed=5).record
    model, x, sig, idx = _fitted(rec, ("asymmetric_stiffness", "angle_offset", "torque_offset"))
    x = x.copy()
    theta0 = 0.03
    x[model.slice_of("angle_offset").start] = theta0
    x[model.slice_of("torque_offset").start] = x[0] * theta0
    assert set(offset_patches(model, x, sig, idx)) == {"angle_offset"}
