"""A family's law chosen beside an effect the audit rejects is chosen again without it.

The lag family's first-order filter only delays (its time constant is not negative);
chosen beside a friction it takes up a small delay. When the audit rejects the friction,
the record asks the lag family for what the friction did: on one ramp rate a friction
that lets go at rest is a damper, a lag read negative. Kept as a filter, the lag refits
to zero and the search's backward pass removes it (held-out C F05_tanh_drift_1rate_levels,
seed 1: friction rejected, the filter removed, only a drift named, flagged unexplained).
The loop chooses the laws again after each rejection (:func:`springcad.fit.loop._run_loop`).
Known truth: a regularised-Coulomb friction on the staircase at one speed, written here.
"""

import numpy as np

from issue24_records import ramps, tanh_friction
from springcad.fit.data import make_record
from springcad.fit.effects import get_effect
from springcad.fit.laws import choose_laws
from springcad.fit.loop import _spring
from springcad.fit.other_laws import OTHER_LAWS
from springcad.fit.search import LoopSettings, Search, State
from springcad.fit.segment import segment
from springcad.fit.signals import make_signals
from springcad.fit.steps import backward, drop
from springcad.fit.torque_model import TorqueModel

K_NM_PER_RAD = 40.0
FRICTION_NM = 0.25


def _search():
    rng = np.random.default_rng(5)
    t, th = ramps([5, 10, 15, 20], [10.0])
    tau = K_NM_PER_RAD * th + tanh_friction(t, th, FRICTION_NM, 0.01)
    record = make_record(t, tau + rng.normal(0, 0.03, t.size), th + rng.normal(0, 8e-4, t.size))
    sig = make_signals(record, segment(record))
    lp = Search(sig, LoopSettings())
    base, _ = _spring(sig, lp)
    lp.update_noise(base)
    return lp, base


def test_a_filter_chosen_beside_a_dropped_friction_gives_way_to_a_damper():
    lp, base = _search()
    f_scale = lp.f_scale(base)
    flt = next(law for law in OTHER_LAWS["time_lag"] if law.law == "first_order_filter")
    model = TorqueModel((get_effect("hysteresis"), flt), base.model.scales)
    x0 = model.transfer(base.model, base.x)
    state = State(model, lp.refit(model, x0, None, f_scale))
    # the audit's rejection of the friction: the filter, refitted alone, cannot lead
    steps = []
    alone = drop(state, "hysteresis", lp, f_scale, steps, {"reason": "test"})
    assert alone.model.names == ("time_lag",)
    tau_s = alone.model.report(alone.x)["filter_time_constant_s"]
    assert tau_s < 1e-3
    score_filter = lp.cv_score(alone.model, alone.x, None, f_scale)[0]
    # kept as a filter, the backward pass removes it: the record then names nothing
    kept, _ = backward(alone, score_filter, f_scale, lp, [])
    assert kept.model.names == ()
    # chosen again, the family's law is a damper (or a lag read negative) of the
    # friction's size at the ramps' speed, and the criterion drops by far more than the
    # loop's gain threshold
    chosen, info = choose_laws(alone, lp, f_scale)
    law = next(e for e in chosen.model.effects if e.name == "time_lag").law
    assert law in ("viscous", "pure_delay"), info
    score = lp.cv_score(chosen.model, chosen.x, None, f_scale)[0]
    assert score_filter - score > 10 * lp.s.gain_threshold
    report = chosen.model.report(chosen.x)
    damping = report.get("viscous_damping_Nms_per_rad",
                         report.get("equivalent_viscous_damping_Nms_per_rad"))
    speed = np.radians(10.0)
    assert abs(damping * speed - FRICTION_NM) < 0.3 * FRICTION_NM
