"""Label audit for the held-out fit test A: how well can library laws describe a record?

For one case, the noiseless record (library outliers removed) is fitted by least squares
with a library-like model written here (not springcad's):

    T = K*phi + k3*phi^3 + dK*phi*[phi<0] + c0 + c1*t + H*J_p(theta_m(t - d or t))
    phi = deadband(theta_m(t - d) - theta0, b)

over grids of the lag d (-40..+40 ms), the dead band b (only if the case has a gap), the
angle zero theta0 (only if the case has an angle offset) and the presliding angle p of the
Coulomb friction J_p (only if the case has friction). The result is the RMS residual over
the torque noise sigma ("lib/sig"): about 0 when the record is inside this library, and the
size of what no library law describes otherwise. The labelling rule it checks: a record is
``unexplained`` when lib/sig >= 0.5 (structure of 0.5 sigma RMS over >= 10 000 samples is
far above noise for any residual test). It does not decide scores, except under the
README rule (``heldout_fit_a.py --rule readme``, the default): there the label of a record
with physics outside the library is decided from it as generator E decides its own, by the
excess chi-square ``N·(lib/sig)²`` (>= 2000: flagged, <= 200: not, between: either), with a
viscous damper ``c·dθ/dt`` among the laws (``damper=True``: the README puts a damper within
``time_lag``'s meaning, the lag's other law beside the pure delay).
"""

from __future__ import annotations

import numpy as np

from heldout_fit_a_sim import deadband, jenkins, simulate

UNEXPLAINED_LIB_SIG = 0.5
STEP = 4  # use every 4th sample (speed)


def library_residual(spec, seed_rng, damper=False):
    """RMS residual (over the torque noise) of the best library-like fit to the noiseless record.

    ``damper``: the lag is a pure delay d or (at d = 0) a viscous damper c·dθ/dt.
    """
    sp = {k: v for k, v in spec.items() if k not in ("outliers", "quant_counts", "ar1")}
    sp["noise_frac"] = 1e-12
    sp["angle_noise"] = 0.0
    rec = simulate(sp, seed_rng)
    sigma = spec.get("noise_frac", 0.003) * rec["peak_torque_Nm"]
    t_full, th_full = rec["t_s"], rec["deflection_rad"]
    t = t_full[::STEP]
    T = rec["torque_Nm"][::STEP]
    A = rec["amp_rad"]
    gaps = [0.0]
    if "backlash" in spec or "hertz" in spec:
        b0 = spec.get("backlash", spec.get("hertz", (0.0,))[0] if "hertz" in spec else 0.0)
        gaps = [f * b0 for f in (0.0, 0.5, 0.8, 0.9, 1.0, 1.1, 1.2, 1.5, 2.0)]
    zeros = [0.0]
    if "angle_offset" in spec and len(gaps) > 1:
        zeros = sorted(set(np.linspace(-0.02, 0.02, 9)) | {spec["angle_offset"]})
    fric = [None]
    if spec.get("friction") is not None and spec["friction"][0] != "viscous":
        fric = [(jenkins(th_full, 1.0, 1.0 / p), delayed)
                for p in (1e-5, 1e-4, 3e-4, 1e-3, 3e-3) for delayed in (0, 1)]

    def late(x, d):  # x(t - d) at the kept samples, interpolated at the full rate
        return np.interp(t - d, t_full, x)

    rate = np.gradient(th_full, t_full)[::STEP] * 0.01 / A  # a damper's shape, scaled

    def resid(d, b, z, J, damp=False):
        phi = deadband(late(th_full, d) - z, b) / A
        cols = [phi, phi ** 3, phi * (phi < 0), np.ones_like(t), t / t[-1]]
        if J is not None:  # a torque lag delays the friction too, an angle lag does not
            cols.append(late(J[0], d * J[1]))
        if damp:
            cols.append(rate)
        B = np.column_stack(cols)
        x = np.linalg.lstsq(B, T, rcond=None)[0]
        return float(np.sqrt(np.mean((T - B @ x) ** 2)))

    best = (np.inf, 0.0, 0.0, 0.0, None)
    for d in np.arange(-0.04, 0.0401, 0.002):
        for b in gaps:
            for z in zeros:
                for J in fric:
                    r = resid(d, b, z, J)
                    if r < best[0]:
                        best = (r, d, b, z, J)
    _, d0, b, z, J = best
    for d in np.arange(d0 - 0.002, d0 + 0.00201, 0.00025):
        r = resid(d, b, z, J)
        best = min(best, (r, d, b, z, J), key=lambda x: x[0])
    if damper:
        for b in gaps:
            for z in zeros:
                for J in fric:
                    r = resid(0.0, b, z, J, True)
                    best = min(best, (r, 0.0, b, z, J), key=lambda x: x[0])
    return best[0] / sigma
