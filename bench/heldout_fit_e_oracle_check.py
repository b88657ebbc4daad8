"""Oracle self-check: on generator E's library-only records, E must be far below 200.

Run: ``python bench/heldout_fit_e_oracle_check.py [--seed 1]``. The oracle's library laws
(presliding friction vectorised per run) are fitted, from perturbed starts, to records the
simulator made with its own sample-by-sample laws; what is left is the oracle's own error.
Measured 2026-11-26, seed 1: largest E 8.2 (friction and a delay on one rate), the rest < 6.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import heldout_fit_e as H
from heldout_fit_e_oracle import structure
from heldout_fit_e_sim import simulate
ap = argparse.ArgumentParser()
ap.add_argument("--seed", type=int, default=1)
seed = ap.parse_args().seed
for i, b in enumerate(H.BUILDERS[:35]):
    rng = np.random.default_rng([seed, i]); c = b(rng); ph = c.physics
    if ph.spikes_T or ph.spikes_th or ph.counts_per_rev or ph.angle_drift: continue
    rec = simulate(ph, c.protocol, c.fs_hz, rng)
    hints = dict(K=ph.K*1.05, b=ph.backlash_rad*1.3 or 0.01, tau=ph.lag_s*1.3, th0=0.0)
    if ph.friction: hints.update(H=ph.fr['H']*0.7, pre=ph.fr['pre']*2)
    sig = math.sqrt(ph.sigma_T**2*(1+ph.rho_T)/(1-ph.rho_T)+(ph.K*ph.sigma_th)**2)
    eff = set().union(*c.alternatives) | c.optional
    E, r, p = structure(rec.t, rec.angle_clean, rec.torque_clean, eff, hints, sig)
    print(f"{c.name:40s} E={E:9.3g}")
