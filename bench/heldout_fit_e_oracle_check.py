"""Oracle self-check: on library-only records (truth hints perturbed) E must be ~0."""
import math, sys
import numpy as np
sys.path.insert(0, '/work/wt/fitgen3/bench')
import heldout_fit_e as H
from heldout_fit_e_oracle import structure
from heldout_fit_e_sim import simulate
for i, b in enumerate(H.BUILDERS[:35]):
    rng = np.random.default_rng([1, i]); c = b(rng); ph = c.physics
    if ph.spikes_T or ph.spikes_th or ph.counts_per_rev or ph.angle_drift: continue
    rec = simulate(ph, c.protocol, c.fs_hz, rng)
    hints = dict(K=ph.K*1.05, b=ph.backlash_rad*1.3 or 0.01, tau=ph.lag_s*1.3, th0=0.0)
    if ph.friction: hints.update(H=ph.fr['H']*0.7, pre=ph.fr['pre']*2)
    sig = math.sqrt(ph.sigma_T**2*(1+ph.rho_T)/(1-ph.rho_T)+(ph.K*ph.sigma_th)**2)
    eff = set().union(*c.alternatives) | c.optional
    E, r, p = structure(rec.t, rec.angle_clean, rec.torque_clean, eff, hints, sig)
    print(f"{c.name:40s} E={E:9.3g}")
