"""Cases of held-out generator F: a simulator spec and its truth, drawn from a seed.

Truth (decided from physics, see bench/heldout_fit_f.md): ``required`` library names,
``optional`` names, ``confusable`` (friction vs delay cannot be told apart on this protocol),
``offset_pair`` (amendment after the first run, see heldout_fit_f.md: the spring is linear in
angle, so an angle offset d is exactly a torque offset -K*d and either name is right),
``kinds`` of every effect key in the spec ('lib', 'family', 'family_out', 'out', 'invisible'),
``k_true`` (acceptable K values, N·m/rad).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from heldout_fit_f_sim import series_stiffness


@dataclass
class Case:
    name: str
    spec: dict
    required: frozenset
    optional: frozenset = frozenset()
    confusable: bool = False
    offset_pair: bool = False
    kinds: dict = field(default_factory=dict)
    k_true: tuple = ()

    @property
    def k_scored(self):
        return all(k in ("lib", "invisible") for k in self.kinds.values())


def _noise(rng, rho=0.0, enc_bits=None):
    return {"torque_pct": float(rng.uniform(0.15, 0.6)),
            "angle_sd": float(10 ** rng.uniform(-5, -3.7)), "rho": rho, "enc_bits": enc_bits}


def _springs(ks, rng, gap=0.0, **extra):
    return [{"k": float(k * rng.uniform(0.9, 1.1)), "gap_rad": gap, **extra} for k in ks]


def _peak(springs, amp):
    return series_stiffness(springs) * amp


def _sign(rng):
    return float(rng.choice([-1.0, 1.0]))


def build_cases(seed):
    """All cases of generator F for ``seed`` (parameters drawn per case from the seed)."""
    out = []

    def add(name, spec, required, optional=(), confusable=False, kinds=None, k_true=None,
            offset_pair=False):
        sp = spec["springs"]
        kt = k_true or (series_stiffness(sp),)
        out.append(Case(name, spec, frozenset(required), frozenset(optional), confusable,
                        offset_pair, kinds or {}, tuple(kt)))

    def R(i):
        return np.random.default_rng([seed, i])

    # ---------------------------------------------------------------- library laws only
    r = R(1)
    sp = _springs([150], r, gap=float(r.uniform(0.01, 0.03)))
    add("L01_staircase_backlash",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "protocol": ("staircase", {"amps_rad": [0.05, 0.1, 0.15, 0.2, 0.25, 0.3],
                                    "rate_rad_s": float(r.uniform(0.1, 0.2)),
                                    "hold_s": float(r.uniform(0.5, 1.5))})},
        {"backlash"}, kinds={"gap": "lib"})

    r = R(2)
    sp = _springs([150, 150, 75], r, gap=float(r.uniform(0.008, 0.015)))
    add("L02_stack3_2rates_friction_delay_backlash",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(r.uniform(0.02, 0.04) * _peak(sp, 0.8)),
                      "x0": 2e-3},
         "lag": {"law": "delay", "d": float(r.uniform(0.015, 0.035))},
         "protocol": ("ramps", {"amp_rad": 0.8, "rates_rad_s": [0.2, 0.6], "hold_s": 1.0,
                                "cycles": 2})},
        {"backlash", "hysteresis", "time_lag"},
        kinds={"gap": "lib", "friction": "lib", "lag": "lib"})

    r = R(3)
    sp = _springs([150], r)
    k = sp[0]["k"]
    add("L03_sines_stiffening_offset_Nmm_deg",
        {"fs": 200, "springs": sp, "fmt": "nmm_deg", "noise": _noise(r),
         "k3": float(r.uniform(0.05, 0.1) * k / 0.3**2),
         "torque_offset": float(_sign(r) * r.uniform(0.005, 0.015) * k * 0.3),
         "protocol": ("sine_sweep", {"parts": [(0.15, 0.1, 2), (0.3, 0.2, 3), (0.3, 0.5, 4)]})},
        {"stiffening", "torque_offset"}, kinds={"k3": "lib", "torque_offset": "lib"})

    r = R(4)
    sp = _springs([150, 150], r)
    for s in sp:
        s["k_neg"] = 0.87 * s["k"]
    kp, kn = series_stiffness(sp), series_stiffness(sp, "k_neg")
    add("L04_stack2_levels_asymmetric_drift_deg",
        {"fs": 500, "springs": sp, "fmt": "deg", "noise": _noise(r),
         "drift": {"rate": float(_sign(r) * r.uniform(0.015, 0.03) * kp * 0.5 / 40.0)},
         "protocol": ("random_levels", {"amp_rad": 0.5, "rate_rad_s": 0.3, "n_levels": 14,
                                        "hold_range_s": (0.5, 2.0),
                                        "level_seed": int(r.integers(1 << 30))})},
        {"asymmetric_stiffness", "drift"}, kinds={"k_neg": "lib", "drift": "lib"},
        k_true=(kp, kn, 0.5 * (kp + kn)))

    r = R(5)
    sp = _springs([300], r)
    add("L05_3rates_outliers_angle_offset",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "outliers": {"n": 12, "frac": 0.08},
         "angle_offset": float(_sign(r) * r.uniform(0.005, 0.012)),
         "protocol": ("ramps", {"amp_rad": 0.25, "rates_rad_s": [0.1, 0.25, 0.6], "hold_s": 0.8,
                                "cycles": 1, "shape": "cos"})},
        {"outliers", "angle_offset"}, kinds={"outliers": "lib", "angle_offset": "lib"},
        offset_pair=True)

    r = R(6)
    sp = _springs([75], r)
    add("L06_chirp_delay_counts_cogging",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r, enc_bits=16),
         "lag": {"law": "delay", "d": float(r.uniform(0.006, 0.02))},
         "cogging": {"A": 2e-3, "n": 24},
         "protocol": ("chirp", {"amp_rad": 0.3, "f0_hz": 0.05, "f1_hz": 1.5, "duration_s": 40.0})},
        {"time_lag"}, kinds={"lag": "lib", "cogging": "invisible"})

    r = R(7)
    sp = _springs([75, 75], r, gap=0.015, gap_center_rad=float(_sign(r) * r.uniform(0.003, 0.006)))
    add("L07_stack2_staircase_offcentre_backlash_friction",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(0.02 * _peak(sp, 0.5)), "x0": 3e-3},
         "protocol": ("staircase", {"amps_rad": [0.1, 0.2, 0.3, 0.4, 0.5], "rate_rad_s": 0.25,
                                    "hold_s": 1.0, "shape": "cos"})},
        {"backlash", "angle_offset", "hysteresis"},
        kinds={"gap": "lib", "gap_center": "lib", "friction": "lib"})

    r = R(8)
    sp = _springs([600], r)
    add("L08_2kHz_coloured_noise_eccentric_encoder",
        {"fs": 2000, "springs": sp, "fmt": "si", "noise": _noise(r, rho=0.95),
         "ecc": {"e": 1.5e-3, "G": 1.0, "phi": float(r.uniform(0, 2 * np.pi))},
         "protocol": ("ramps", {"amp_rad": 0.2, "rates_rad_s": [0.1, 0.3], "hold_s": 1.5,
                                "cycles": 1})},
        set(), optional={"angle_offset"}, kinds={"ecc": "lib"}, offset_pair=True)

    r = R(9)
    sp = _springs([150], r)
    add("L09_one_rate_triangles_friction",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(0.025 * _peak(sp, 0.3)), "x0": 2e-3},
         "protocol": ("ramps", {"amp_rad": 0.3, "rates_rad_s": [0.2], "hold_s": 0.0,
                                "cycles": 5})},
        {"hysteresis"}, confusable=True, kinds={"friction": "lib"})

    r = R(10)
    sp = _springs([1200], r)
    add("L10_5kHz_stiff_angle_delay_offset",
        {"fs": 5000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "lag": {"law": "angle_delay", "d": float(r.uniform(0.002, 0.005))},
         "torque_offset": float(_sign(r) * 0.01 * _peak(sp, 0.15)),
         "protocol": ("ramps", {"amp_rad": 0.15, "rates_rad_s": [0.3, 0.9], "hold_s": 0.5,
                                "cycles": 2})},
        {"time_lag", "torque_offset"}, kinds={"lag": "lib", "torque_offset": "lib"})

    # ---------------------------------------------- families with other laws, and outside
    r = R(11)
    sp = _springs([150, 75], r)
    F = float(0.03 * _peak(sp, 0.6))
    add("O01_stack2_lugre_stribeck_2rates",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "lugre", "F": F, "Fs": 1.6 * F, "vs": 0.03, "x0": 1.5e-3,
                      "s1": 0.05 * F / 0.1, "s2": 0.3 * F / 0.4},
         "protocol": ("ramps", {"amp_rad": 0.6, "rates_rad_s": [0.1, 0.4], "hold_s": 1.0,
                                "cycles": 2})},
        {"hysteresis"}, optional={"time_lag"}, kinds={"friction": "family"})

    r = R(12)
    sp = _springs([150], r)
    add("O02_one_rate_triangles_tanh_coulomb_deg",
        {"fs": 1000, "springs": sp, "fmt": "deg", "noise": _noise(r),
         "friction": {"law": "tanh", "F": float(0.03 * _peak(sp, 0.3)), "v0": 0.05},
         "protocol": ("ramps", {"amp_rad": 0.3, "rates_rad_s": [0.25], "hold_s": 0.0,
                                "cycles": 6})},
        {"hysteresis"}, confusable=True, kinds={"friction": "family"})

    r = R(13)
    sp = _springs([75], r)
    add("O03_sines_tanh_coulomb_drift",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "tanh", "F": float(0.03 * _peak(sp, 0.3)), "v0": 0.15},
         "drift": {"rate": float(_sign(r) * 0.02 * _peak(sp, 0.3) / 45.0)},
         "protocol": ("sine_sweep", {"parts": [(0.3, 0.1, 3), (0.3, 0.3, 4), (0.2, 0.8, 6)]})},
        {"hysteresis", "drift"}, kinds={"friction": "family", "drift": "lib"})

    r = R(14)
    sp = _springs([150, 150], r)
    K = series_stiffness(sp)
    add("O04_stack2_viscous_damper_2rates_Nmm_deg",
        {"fs": 500, "springs": sp, "fmt": "nmm_deg", "noise": _noise(r),
         "friction": {"law": "viscous", "c": float(K * r.uniform(0.01, 0.03))},
         "protocol": ("ramps", {"amp_rad": 0.5, "rates_rad_s": [0.15, 0.5], "hold_s": 1.0,
                                "cycles": 2, "shape": "cos"})},
        {"time_lag"}, kinds={"friction": "lib"})

    r = R(15)
    sp = _springs([75, 75], r, gap=0.02)
    add("O05_stack2_torque_filter_backlash",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "lag": {"law": "filter1", "tau": float(r.uniform(0.01, 0.025))},
         "protocol": ("staircase", {"amps_rad": [0.2, 0.4, 0.6], "rate_rad_s": 0.3,
                                    "hold_s": 1.0})},
        {"backlash", "time_lag"}, kinds={"gap": "lib", "lag": "family"})

    r = R(16)
    sp = _springs([150, 150, 150], r, gap=0.006)
    peak = _peak(sp, 0.75)
    for s in sp:
        s["hertz_k"] = float(0.3 * peak / r.uniform(0.004, 0.008) ** 1.5)
    add("O06_stack3_hertzian_takeup",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "protocol": ("staircase", {"amps_rad": [0.15, 0.3, 0.45, 0.6, 0.75], "rate_rad_s": 0.3,
                                    "hold_s": 0.8, "shape": "cos"})},
        {"backlash"}, optional={"stiffening"}, kinds={"gap": "family"})

    r = R(17)
    sp = _springs([150], r)
    add("O07_maxwell_bushing_long_holds",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "maxwell": {"k": 0.15 * sp[0]["k"], "tau": float(r.uniform(0.4, 1.5))},
         "protocol": ("staircase", {"amps_rad": [0.1, 0.2, 0.3], "rate_rad_s": 0.3,
                                    "hold_s": 3.0})},
        set(), optional={"time_lag"}, kinds={"maxwell": "out"})

    r = R(18)
    sp = _springs([150, 150], r, gap=0.012)
    add("O08_stack2_hard_stop_backlash",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "stop": {"theta": 0.85 * 0.75, "k": 5 * series_stiffness(sp)},
         "protocol": ("staircase", {"amps_rad": [0.2, 0.4, 0.6, 0.75], "rate_rad_s": 0.3,
                                    "hold_s": 1.0})},
        {"backlash"}, kinds={"gap": "lib", "stop": "out"})

    r = R(19)
    sp = _springs([300], r)
    add("O09_levels_clipping_sensor_friction",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(0.02 * _peak(sp, 0.3)), "x0": 2e-3},
         "clip": {"T": 0.85 * _peak(sp, 0.3)},
         "protocol": ("random_levels", {"amp_rad": 0.3, "rate_rad_s": 0.2, "n_levels": 16,
                                        "hold_range_s": (0.5, 1.5),
                                        "level_seed": int(r.integers(1 << 30))})},
        {"hysteresis"}, kinds={"friction": "lib", "clip": "out"})

    r = R(20)
    sp = _springs([75], r)
    peak = _peak(sp, 0.3)
    add("O10_stick_slip_2rates",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "stickslip", "Fs": 0.04 * peak, "Fk": 0.024 * peak, "x_stick": 8e-3},
         "protocol": ("ramps", {"amp_rad": 0.3, "rates_rad_s": [0.08, 0.2], "hold_s": 1.0,
                                "cycles": 2})},
        {"hysteresis"}, kinds={"friction": "family_out"})

    r = R(21)
    sp = _springs([150], r, gap=0.02)
    add("O11_mains_hum_backlash",
        {"fs": 1000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "hum": {"A": 0.008 * _peak(sp, 0.3), "f": 50.0},
         "protocol": ("staircase", {"amps_rad": [0.1, 0.2, 0.3], "rate_rad_s": 0.2,
                                    "hold_s": 1.0})},
        {"backlash"}, kinds={"gap": "lib", "hum": "out"})

    r = R(22)
    sp = _springs([300], r)
    add("O12_tooth_ripple_angle_delay_sines",
        {"fs": 2000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "tooth": {"A": 0.008 * _peak(sp, 0.3), "n": 28, "phi": float(r.uniform(0, 6.28))},
         "lag": {"law": "angle_delay", "d": float(r.uniform(0.01, 0.025))},
         "protocol": ("sine_sweep", {"parts": [(0.3, 0.2, 3), (0.3, 0.5, 5)]})},
        {"time_lag"}, kinds={"lag": "lib", "tooth": "out"})

    r = R(23)
    sp = _springs([150], r)
    add("O13_stiffness_step_mid_test",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "kstep": {"frac": -0.07, "t_frac": float(r.uniform(0.4, 0.6))},
         "protocol": ("ramps", {"amp_rad": 0.3, "rates_rad_s": [0.15], "hold_s": 1.0,
                                "cycles": 6})},
        set(), kinds={"kstep": "out"})

    r = R(24)
    sp = _springs([75, 150], r, gap=0.01)
    add("O14_stack2_settling_zero_backlash_200Hz",
        {"fs": 200, "springs": sp, "fmt": "si", "noise": _noise(r),
         "settle": {"A": float(_sign(r) * 0.025 * _peak(sp, 0.6)), "tau_frac": 0.2},
         "protocol": ("random_levels", {"amp_rad": 0.6, "rate_rad_s": 0.3, "n_levels": 14,
                                        "hold_range_s": (0.5, 2.0),
                                        "level_seed": int(r.integers(1 << 30))})},
        {"backlash"}, optional={"drift", "torque_offset"}, kinds={"gap": "lib", "settle": "out"})

    r = R(25)
    sp = _springs([600], r)
    add("O15_warming_stiffness_angle_offset_deg",
        {"fs": 500, "springs": sp, "fmt": "deg", "noise": _noise(r),
         "tempK": {"frac": -0.04, "tau_frac": 0.3},
         "angle_offset": float(_sign(r) * 0.004),
         "protocol": ("staircase", {"amps_rad": [0.05, 0.1, 0.15, 0.2, 0.25], "rate_rad_s": 0.1,
                                    "hold_s": 1.5, "shape": "cos"})},
        {"angle_offset"}, kinds={"tempK": "out", "angle_offset": "lib"}, offset_pair=True)

    r = R(26)
    sp = _springs([150], r)
    add("O16_geared_encoder_eccentricity_friction",
        {"fs": 500, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(0.02 * _peak(sp, 0.3)), "x0": 2e-3},
         "ecc": {"e": 1e-3, "G": 15.0, "phi": float(r.uniform(0, 6.28))},
         "protocol": ("ramps", {"amp_rad": 0.3, "rates_rad_s": [0.1, 0.3], "hold_s": 1.0,
                                "cycles": 2, "shape": "cos"})},
        {"hysteresis"}, kinds={"friction": "lib", "ecc": "out"})

    r = R(27)
    sp = _springs([75], r)
    add("O17_sines_second_order_filter_friction_2kHz",
        {"fs": 2000, "springs": sp, "fmt": "si", "noise": _noise(r),
         "friction": {"law": "dahl", "F": float(0.02 * _peak(sp, 0.25)), "x0": 2e-3},
         "lag": {"law": "filter2", "tau": float(r.uniform(0.005, 0.012))},
         "protocol": ("sine_sweep", {"parts": [(0.25, 0.2, 3), (0.25, 0.6, 5), (0.15, 1.5, 8)]})},
        {"hysteresis", "time_lag"}, kinds={"friction": "lib", "lag": "family"})
    return out
