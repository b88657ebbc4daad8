"""Issue 24, held-out generator C's misses: the unexplained test, the audit on short records.

Records written here with the physics of ``issue24_records`` (not ``springcad.fit.bench``).
Units: N·m, rad, s.
"""

import numpy as np
import pytest

from issue24_records import dahl_friction, deadband, first_order, ramps
from springcad.fit.analysis import fit_record
from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.evidence import WHOLE, audit, split_parts
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.torque_model import TorqueModel

K = 40.0


@pytest.mark.parametrize("friction_Nm, supported", [(0.0, False), (0.1, True)])
def test_an_effect_on_a_record_too_short_to_split_must_be_supported_on_the_whole_record(
        friction_Nm, supported):
    # one cycle (three runs): no split applies; a friction fitted to noise alone is not
    # supported on the whole record, a true 0.1 N·m friction is (its standard error is
    # about 1e-3 N·m)
    t, th = ramps([10], [12.0])
    rng = np.random.default_rng(5)
    rec = make_record(t, K * th + dahl_friction(th, friction_Nm, 0.004)
                      + rng.normal(0, 0.03, t.size), th + rng.normal(0, 8e-4, t.size))
    sig = make_signals(rec, segment(rec))
    idx = np.arange(sig.n)
    assert split_parts(sig, idx) == {}
    model = TorqueModel((get_effect("hysteresis"),), sig.scales)
    x0 = model.transfer(TorqueModel((), sig.scales), np.array([K]),
                        {"hysteresis": np.array([0.05, 0.004])})
    x = model.fit(sig, idx, x0, 0.09)
    ev = audit(model, x, sig, idx, 0.09, 1e-3, 3.0).effects["hysteresis"]
    (check,) = ev.checks
    assert check.split == WHOLE and check.supported is supported
    if supported:
        assert ev.ok and check.values[0] == pytest.approx(friction_Nm, rel=0.05)
    else:
        assert not ev.ok and abs(check.support_z) < 3.0


def test_a_torque_filter_read_as_a_delay_leaves_structure_after_every_start_stop_and_turn():
    # a 20 ms first-order torque filter on a stack with a 0.04 rad crossover, two ramp rates
    # with holds: the lag family is fitted with the filter law, and a pure delay in its
    # place leaves structure locked to the protocol's events (a delay shifts a turn, a
    # filter rounds it), so the record is flagged with a finding that names the law
    t, th = ramps([6, 12, 18], [18.0, 5.0], hold_s=0.5, fs=1000.0)
    rng = np.random.default_rng(1)
    tau = first_order(t, 12.0 * deadband(th, 0.02), 0.02)
    loop = fit_record(make_record(t, tau + rng.normal(0, 0.004, t.size),
                                  th + rng.normal(0, 1e-4, t.size))).loop
    assert set(loop.final.effects) == {"backlash", "time_lag"}
    # the record's filter acts on the torque (after the crossover): that law, not the
    # deflection filter put through the crossover
    assert loop.laws["time_lag"]["law"] == "torque_filter"
    p = loop.final.params()
    assert p["torque_filter_time_constant_s"] == pytest.approx(0.02, rel=0.05)
    assert p["backlash_rad"] == pytest.approx(0.04, rel=0.05)
    assert loop.unexplained
    found = [f for f in loop.localisation["findings"] if f["kind"] == "law_outside_library"]
    assert [(f["family"], f["law"]) for f in found] == [("time_lag", "torque_filter")]
    # the filter itself leaves nothing locked to the events
    assert not loop.structure["tests"]["by_protocol_phase"]["significant"]
