"""Cases of the held-out fit test A, each with its truth label decided from physics.

Labelling rules (decided before any fit was run on these records):

- ``required``: library effects that are present and whose law the library's name describes
  (pure delay -> ``time_lag``; viscous damping c*v -> ``time_lag`` too, since K*theta(t+c/K)
  = K*theta + c*v to first order; Coulomb-like friction with a small presliding angle ->
  ``hysteresis``; dead band -> ``backlash``; ...). A tuple is a group the record cannot
  separate: any one member named, several named, or the group reported as confounded is right.
  Groups used: friction vs pure delay on a single constant speed without holds; torque offset
  vs angle offset on a spring with nothing that anchors the angle zero (T = K(theta + c/K)).
- ``allowed``: names that may appear in addition (a library law that partly mimics an
  out-of-library law, e.g. ``stiffening`` beside a hard stop). Any other name is wrong.
- ``unexplained``: True when the record holds structure no library law describes, and the
  case is sized so that it is clearly above the noise (the ``ool/sig`` column prints the RMS of
  that structure over the torque noise, after a best line in angle, as a check: it is NOT used
  to decide the label).
- ``k_check``: all effects in the library (or exactly equivalent to a library law), so K must
  come out within 2 % of the truth. ``k_alts``: several stiffnesses that are each a fair
  reading of "K" (asymmetric spring: K+, K- and their mean).
- ``refuse``: a unit mistake the CLI must refuse with exit 1 or 2 and a message.

Spec keys (see ``heldout_fit_a_sim.simulate``): fs (Hz), path, K (N·m/rad), noise_frac
(torque noise as a fraction of peak torque), backlash (rad), hertz (b rad, contact yield at
peak rad), k3, K_neg, stop (angle fraction, K multiple), sls (K1/K, tau_r s), friction tuple,
delay (s), filter (s), offset_frac, drift_frac, settle (fraction, tau/record), clip_frac,
angle_offset (rad), angle_noise (rad), quant_counts (per turn), outliers, ar1.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from heldout_fit_a_sim import multi_rate, random_levels, sine_path, staircase


@dataclass
class Case:
    name: str
    physics: str
    build: object  # rng -> spec dict
    required: list = field(default_factory=list)
    allowed: set = field(default_factory=set)
    unexplained: bool = False
    k_check: bool = True
    in_library: bool = True
    asym: bool = False
    angle_unit: str = "rad"  # unit the file is written in
    torque_unit: str = "Nm"
    opts: list = field(default_factory=list)  # CLI unit options ("{K}" -> target stiffness)
    refuse: bool = False
    columns: tuple = ("time_s", "torque_Nm", "deflection_rad")


def lu(rng, lo, hi):
    """Log-uniform draw in [lo, hi]."""
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def stair(rng, speed=0.6, hold=1.0, shape="linear", n=3):
    A = rng.uniform(0.25, 0.4)
    return staircase([A * (i + 1) / n for i in range(n)], speed, hold, shape)


def tri(rng, speed=0.6, hold=0.0, n=6, shape="linear"):
    return multi_rate(rng.uniform(0.25, 0.4), [speed], n, shape, hold)


def base(rng, path, fs=1000, K=None, noise=None):
    return dict(fs=fs, path=path, K=K if K is not None else lu(rng, 80, 800),
                noise_frac=noise if noise is not None else rng.uniform(0.002, 0.004))


TGT = ["--target-stiffness", "{K}"]


def _cases():
    C = []
    add = C.append
    # ---------------------------------------------------------------- clean linear records
    add(Case("clean_stair", "linear spring, linear-ramp staircase with 1 s holds",
             lambda r: base(r, stair(r))))
    add(Case("clean_levels_deg", "linear spring, random levels (cosine ramps), file in degrees",
             lambda r: base(r, random_levels(r, r.uniform(0.2, 0.35), 12, 0.4, (0.5, 2.0), "cosine"), fs=500),
             angle_unit="deg", columns=("time_s", "torque_Nm", "deflection_deg"),
             opts=["--deflection-col", "deflection_deg", "--angle-unit", "deg"] + TGT))
    add(Case("clean_3rates_Nmm_quant", "linear spring, cosine ramps at 3 rates, N·mm, 16-bit encoder",
             lambda r: dict(base(r, multi_rate(0.3, [0.2, 0.6, 1.5], 2, "cosine"), fs=2000), quant_counts=2 ** 16),
             torque_unit="Nmm", columns=("time_s", "torque_Nmm", "deflection_rad"),
             opts=["--torque-col", "torque_Nmm", "--torque-unit", "Nmm"] + TGT))
    add(Case("clean_stack_K12_deg_Nmm", "soft stack K~12 to 1.1 rad, triangles with holds, deg + N·mm, own column names, 200 Hz",
             lambda r: base(r, multi_rate(1.1, [0.5], 4, "linear", 0.5), fs=200, K=lu(r, 10, 20)),
             angle_unit="deg", torque_unit="Nmm", columns=("t", "tau_Nmm", "defl_deg"),
             opts=["--time-col", "t", "--torque-col", "tau_Nmm", "--deflection-col", "defl_deg",
                   "--angle-unit", "deg", "--torque-unit", "Nmm"] + TGT))
    add(Case("clean_K1800_5kHz_ar1", "stiff spring K~1800 to 0.2 rad, cosine staircase, 5 kHz, AR(1) coloured noise",
             lambda r: dict(base(r, staircase([0.1, 0.2], 0.5, 0.8, "cosine"), fs=5000, K=lu(r, 1500, 2000)), ar1=0.8)))
    # ---------------------------------------------------------------- library effects alone
    add(Case("backlash_stair", "hard dead band b 10-30 mrad, linear staircase, 14-bit encoder",
             lambda r: dict(base(r, stair(r)), backlash=r.uniform(0.01, 0.03), quant_counts=2 ** 14), ["backlash"]))
    add(Case("hertz_stiff_backlash_tri", "gap b then a stiff Hertzian take-up (contact yields 5 % of b at peak), triangles with holds",
             lambda r: dict(base(r, tri(r, 0.5, 0.5, 5)), hertz=(b := r.uniform(0.015, 0.03), 0.05 * b)),
             ["backlash"]))
    add(Case("jenkins_stair", "Coulomb friction 2-3 % of peak with 0.5 mrad presliding, staircase with holds",
             lambda r: dict(base(r, stair(r)), friction=("jenkins", 0, 5e-4)) | _fric(r, 0.02, 0.03), ["hysteresis"]))
    add(Case("dahl_tri_holds", "Dahl friction 2 % of peak (1 mrad reversal angle), triangles with 0.8 s holds at the turns",
             lambda r: dict(base(r, tri(r, 0.5, 0.8, 5)), friction=("dahl", 0, 1e-3)) | _fric(r, 0.018, 0.025), ["hysteresis"]))
    add(Case("delay_2rates", "pure torque-channel delay 15-30 ms, linear ramps at 0.3 and 1.0 rad/s",
             lambda r: dict(base(r, multi_rate(0.3, [0.3, 1.0], 3)), delay=r.uniform(0.015, 0.03)), ["time_lag"]))
    add(Case("delay_stair_cos", "pure delay 5-15 ms, cosine staircase with holds, 2 kHz",
             lambda r: dict(base(r, stair(r, 0.8, 0.8, "cosine"), fs=2000), delay=r.uniform(0.005, 0.015)), ["time_lag"]))
    add(Case("viscous_3rates", "viscous damping c*v (2-3 % of peak at top speed), linear ramps at 3 rates with 0.3 s holds",
             lambda r: _viscous(r), ["time_lag"]))
    add(Case("drift_levels", "torque zero drifting linearly by 3-5 % of peak over the record, random levels",
             lambda r: dict(base(r, random_levels(r, 0.3, 14, 0.5, (0.5, 2.0))), drift_frac=r.uniform(0.03, 0.05)),
             ["drift"]))
    add(Case("toffset_tri", "torque zero offset 2-4 % of peak on a linear spring (same as an angle offset), triangles",
             lambda r: dict(base(r, tri(r)), offset_frac=r.uniform(0.02, 0.04)),
             [("torque_offset", "angle_offset")]))
    add(Case("aoffset_backlash_stair", "encoder zero off by 8-15 mrad, dead band 20 mrad centred on the true zero, staircase",
             lambda r: dict(base(r, stair(r)), backlash=0.02, angle_offset=r.uniform(0.008, 0.015) * r.choice([-1, 1])),
             ["angle_offset", "backlash"]))
    add(Case("stiffening_stair", "cubic hardening adding 6-10 % of torque at the peak, staircase",
             lambda r: _stiff(r, stair(r), 0.06, 0.10), ["stiffening"]))
    add(Case("asym_levels", "K- 12-20 % below K+, random levels", lambda r: _asym(r, random_levels(r, 0.3, 14, 0.5, (0.4, 1.5))),
             ["asymmetric_stiffness"], asym=True))
    add(Case("outliers_torque_tri", "12 isolated torque spikes of ~10 % of peak, triangles",
             lambda r: dict(base(r, tri(r)), outliers=("torque", 12, 0.10)), ["outliers"]))
    add(Case("outliers_angle_stair", "10 isolated deflection spikes of ~5 % of the amplitude, staircase",
             lambda r: dict(base(r, stair(r)), outliers=("angle", 10, 0.05)), ["outliers"]))
    # ---------------------------------------------------------------- pairs and triples (library)
    add(Case("fric_lag_1rate_noholds", "Coulomb 2 % + 20 ms delay on ONE constant speed, no holds: confounded",
             lambda r: dict(base(r, tri(r, 0.6, 0.0, 8)), friction=("jenkins", 0, 3e-4), delay=0.02) | _fric(r, 0.015, 0.025),
             [("hysteresis", "time_lag")]))
    add(Case("fric_lag_backlash_2rates", "Coulomb 2 % + 30 ms delay + 15 mrad dead band, linear ramps at 2 rates, no holds",
             lambda r: dict(base(r, multi_rate(0.3, [0.25, 0.9], 3)), friction=("jenkins", 0, 3e-4), delay=0.03,
                            backlash=0.015) | _fric(r, 0.018, 0.025),
             ["hysteresis", "time_lag", "backlash"]))
    add(Case("fric_lag_backlash_3rates_cos", "Dahl friction 2 % + 30 ms delay + 20 mrad dead band, cosine ramps at 3 rates",
             lambda r: dict(base(r, multi_rate(0.3, [0.2, 0.5, 1.2], 2, "cosine")), friction=("dahl", 0, 5e-4), delay=0.03,
                            backlash=0.02) | _fric(r, 0.018, 0.025),
             ["hysteresis", "time_lag", "backlash"]))
    add(Case("backlash_stiffening_stair", "dead band 15-25 mrad + cubic hardening 8 % at peak, cosine staircase",
             lambda r: _stiff(r, stair(r, 0.6, 1.0, "cosine"), 0.07, 0.09) | dict(backlash=r.uniform(0.015, 0.025)),
             ["backlash", "stiffening"]))
    add(Case("drift_offset_dahl_levels", "torque offset 3 % + linear drift 4 % + Dahl friction 2 %, random levels",
             lambda r: dict(base(r, random_levels(r, 0.3, 14, 0.5, (0.4, 1.5))), offset_frac=0.03, drift_frac=0.04,
                            friction=("dahl", 0, 8e-4)) | _fric(r, 0.018, 0.022),
             ["drift", "hysteresis", ("torque_offset", "angle_offset")]))
    add(Case("lag_asym_2rates", "20 ms delay + K- 15 % below K+, linear ramps at 2 rates",
             lambda r: _asym(r, multi_rate(0.3, [0.3, 1.0], 3)) | dict(delay=0.02),
             ["time_lag", "asymmetric_stiffness"], asym=True))
    add(Case("outliers_stiff_fric_stair", "torque spikes + cubic hardening 8 % + Coulomb 2 %, staircase with holds",
             lambda r: _stiff(r, stair(r), 0.07, 0.09) | dict(outliers=("torque", 10, 0.1), friction=("jenkins", 0, 5e-4))
             | _fric(r, 0.018, 0.025),
             ["outliers", "stiffening", "hysteresis"]))
    add(Case("lugre_viscous_2rates_holds", "LuGre bristle friction without Stribeck (Coulomb 2 %) + viscous 2 % at top speed, 2 rates with holds",
             lambda r: _lugre(r, multi_rate(0.3, [0.3, 1.0], 3, "linear", 0.5), stribeck=1.0, visc=0.02),
             ["hysteresis", "time_lag"]))
    add(Case("tanh_tri_noholds", "regularised Coulomb 2.5 % tanh(v/v0), v0 = 2 % of the speed, one speed, no reversal holds but 0.5 s rest at the end where it vanishes (Coulomb does not) and sharp turns a lag does not have",
             lambda r: _tanh(r, tri(r, 0.6, 0.0, 8), 0.6 * 0.02, 0.025) | dict(noise_frac=0.002), [("hysteresis", "time_lag")],
             {"hysteresis", "time_lag"}, unexplained=True, k_check=False, in_library=False))
    add(Case("stribeck_1rate_linear", "LuGre with Stribeck (Fs = 2 Fc) at ONE constant speed far above vs, no holds: plain Coulomb",
             lambda r: _lugre(r, tri(r, 0.6, 0.0, 8), stribeck=2.0, visc=0.0, vs=0.02),
             [("hysteresis", "time_lag")]))
    add(Case("fric_anglelag_1rate_noholds", "Coulomb 2 % + deflection channel 15 ms late (torque leads, same sign as friction), one speed, no holds: confounded",
             lambda r: dict(base(r, tri(r, 0.6, 0.0, 8)), friction=("jenkins", 0, 3e-4), angle_delay=0.015) | _fric(r, 0.015, 0.025),
             [("hysteresis", "time_lag")]))
    add(Case("anglelag_stair", "deflection channel 10-20 ms late (negative lag), linear staircase with holds",
             lambda r: dict(base(r, stair(r, 0.8, 1.0)), angle_delay=r.uniform(0.01, 0.02)), ["time_lag"]))
    add(Case("dahl_levels_deg", "Dahl friction 2 % on random levels, file in degrees",
             lambda r: dict(base(r, random_levels(r, 0.3, 14, 0.5, (0.4, 1.5))), friction=("dahl", 0, 8e-4)) | _fric(r, 0.018, 0.025),
             ["hysteresis"], angle_unit="deg", columns=("time_s", "torque_Nm", "angle"),
             opts=["--deflection-col", "angle", "--angle-unit", "deg"]))
    # ---------------------------------------------------------------- out of library, alone
    OOL = dict(unexplained=True, k_check=False, in_library=False)
    add(Case("tanh_stair_cos_holds", "regularised Coulomb 2.5 % that vanishes at rest (tanh, v0 0.01 rad/s), cosine staircase with 1.5 s holds",
             lambda r: _tanh(r, stair(r, 0.6, 1.5, "cosine"), 0.01, 0.025), [("hysteresis", "time_lag")],
             {"hysteresis", "time_lag"}, **OOL))
    add(Case("filter_stair_linear", "first-order torque-sensor low-pass tau 20-40 ms (not a pure delay), linear staircase at 1 rad/s with holds",
             lambda r: dict(base(r, stair(r, 1.0, 1.0)), filter=r.uniform(0.02, 0.04)), ["time_lag"], **OOL))
    add(Case("filter_slow_cos_inlib", "first-order sensor filter tau 10 ms on slow cosine ramps: equals a pure delay within noise",
             lambda r: dict(base(r, multi_rate(0.3, [0.1, 0.25, 0.5], 2, "cosine"), fs=500), filter=0.01), ["time_lag"]))
    add(Case("hardstop_stair", "hard stop (4x K) beyond 75 % of the largest amplitude, staircase",
             lambda r: dict(base(r, stair(r)), stop=(0.75, 4.0)), [], {"stiffening"}, **OOL))
    add(Case("clip_levels", "torque sensor clips at 85 % of the peak torque, random levels",
             lambda r: dict(base(r, random_levels(r, 0.3, 14, 0.5, (0.5, 1.5))), clip_frac=0.85), [], {"stiffening"}, **OOL))
    add(Case("relax_stair", "viscoelastic (standard linear solid) relaxation: 10 % of K relaxes with tau 0.6 s during 2 s holds",
             lambda r: dict(base(r, stair(r, 0.6, 2.0)), sls=(0.10, 0.6)), [], {"hysteresis", "time_lag"}, **OOL))
    add(Case("stribeck_cos_stair", "LuGre Stribeck friction Fs 3.5 %, Fc 1.5 %, vs 0.1 rad/s: breakaway hump at each cosine-ramp start",
             lambda r: _lugre(r, stair(r, 0.6, 1.0, "cosine"), stribeck=3.5 / 1.5, visc=0.0, vs=0.1, fc=0.015)
             | dict(noise_frac=0.002),
             ["hysteresis"], {"time_lag"}, **OOL))
    add(Case("hertz_soft_backlash_stair", "gap 20 mrad then a soft Hertzian contact (yields 30 mrad at peak): T^(2/3) take-up that a wider dead band + cubic follows to ~0.3 sigma",
             lambda r: dict(base(r, stair(r), noise=0.004), hertz=(0.02, 0.03)), ["backlash"], {"stiffening"},
             k_check=False, in_library=False))
    add(Case("settle_strong_levels", "thermal torque zero settling by 4 % of peak with tau = 12 % of the record (not linear)",
             lambda r: dict(base(r, random_levels(r, 0.3, 16, 0.5, (0.5, 1.5))), settle=(0.04, 0.12)),
             [("drift", "torque_offset", "angle_offset")], {"drift", "torque_offset", "angle_offset"}, **OOL))
    # ---------------------------------------------------------------- out of library beside library effects
    add(Case("filter_backlash_fric_2rates", "30 ms sensor low-pass + 15 mrad dead band + Coulomb 2 %, linear ramps at 2 rates with 0.5 s holds",
             lambda r: dict(base(r, multi_rate(0.3, [0.3, 1.0], 3, "linear", 0.5)), filter=0.03, backlash=0.015,
                            friction=("jenkins", 0, 3e-4)) | _fric(r, 0.018, 0.025),
             ["time_lag", "backlash", "hysteresis"], **OOL))
    add(Case("hardstop_drift_stair", "hard stop (5x K) beyond 80 % of the top amplitude + linear drift 4 %, staircase",
             lambda r: dict(base(r, stair(r)), stop=(0.8, 5.0), drift_frac=0.04), ["drift"], {"stiffening"}, **OOL))
    add(Case("relax_backlash_stair", "viscoelastic relaxation (12 % of K, tau 0.8 s) + 20 mrad dead band, staircase with 2 s holds",
             lambda r: dict(base(r, stair(r, 0.6, 2.0)), sls=(0.12, 0.8), backlash=0.02), ["backlash"],
             {"hysteresis", "time_lag"}, **OOL))
    add(Case("clip_outliers_tri", "torque clipping at 85 % of peak + 10 torque spikes (inside the range), triangles",
             lambda r: dict(base(r, tri(r)), clip_frac=0.85, outliers=("torque", 10, 0.08)), ["outliers"], {"stiffening"}, **OOL))
    add(Case("settle_weak_stair", "torque zero settling by 3 % with tau = 3x the record: a linear drift within noise",
             lambda r: dict(base(r, stair(r)), settle=(0.03, 3.0)), ["drift"], {"torque_offset", "angle_offset"}))
    add(Case("sine_dahl_lag", "Dahl friction 2 % + 10 ms delay on a sine at two frequencies (0.2, 0.6 Hz)",
             lambda r: dict(base(r, _two_sines()), friction=("dahl", 0, 5e-4), delay=0.01) | _fric(r, 0.018, 0.025),
             ["hysteresis", "time_lag"]))
    # ---------------------------------------------------------------- unit mistakes
    # unit-neutral column names, so only the data can show the mistake
    REF = dict(refuse=True, k_check=False, columns=("time_s", "torque", "deflection"))
    NEUTRAL = ["--torque-col", "torque", "--deflection-col", "deflection"]
    add(Case("unit_deg_as_rad", "file in degrees read as radians (no --angle-unit), target stiffness given",
             lambda r: base(r, stair(r)), angle_unit="deg", opts=NEUTRAL + TGT, **REF))
    add(Case("unit_Nmm_as_Nm", "torque in N·mm read as N·m (no --torque-unit), target stiffness given",
             lambda r: base(r, tri(r)), torque_unit="Nmm", opts=NEUTRAL + TGT, **REF))
    add(Case("unit_rad_as_deg", "file in radians read with --angle-unit deg (0.3 'degree' deflections), target given",
             lambda r: base(r, random_levels(r, 0.3, 10, 0.5, (0.5, 1.5))), opts=NEUTRAL + ["--angle-unit", "deg"] + TGT, **REF))
    return C


def _two_sines():
    return sine_path(0.3, (0.2, 0.6), (3, 6))


def _fric(r, lo, hi):
    """Friction magnitude as a fraction of peak torque, stored for the builder below."""
    return {"_fric_frac": r.uniform(lo, hi)}


def _viscous(r):
    s = base(r, multi_rate(0.3, [0.2, 0.5, 1.2], 2, "linear", 0.3))
    s["_visc_frac"] = r.uniform(0.02, 0.03)  # c * v_max as a fraction of peak torque
    s["friction"] = ("viscous", 0.0)
    s["_visc_vmax"] = 1.2
    return s


def _stiff(r, path, lo, hi):
    s = base(r, path)
    s["_k3_frac"] = r.uniform(lo, hi)
    return s


def _asym(r, path):
    s = base(r, path)
    s["K_neg"] = s["K"] * (1 - r.uniform(0.12, 0.2))
    return s


def _lugre(r, path, stribeck, visc, vs=0.05, fc=None):
    s = base(r, path)
    s["_fric_frac"] = fc if fc is not None else r.uniform(0.018, 0.025)
    s["friction"] = ("lugre", 0, stribeck, vs, 4e-4, 0.0)
    s["_visc_frac"] = visc
    s["_visc_vmax"] = 1.0
    return s


def _tanh(r, path, v0, frac=None):
    s = base(r, path)
    s["_fric_frac"] = frac if frac is not None else r.uniform(0.018, 0.025)
    s["friction"] = ("tanh", 0.0, v0)
    return s


CASES = _cases()
