"""Bench data: ingest, segment, fit the paper's models, close the loop on the residual.

Flow::

    CSV ─► data.read_bench_csv ─► BenchRecord
        ─► segment.segment (half-cycles, excursions, folds)
        ─► models.fit_paper_models (linear, deadband eq. 4, logit eqs. 5–9)
        ─► loop.run_loop over effects.LIBRARY on torque_model.TorqueModel:
             search (held-out criterion) ─► evidence (audit across record splits)
             ─► identify (confounded pairs, protocol advice) ─► inference
             (clustered confidence intervals) ─► residual + localise (what is
             left, and where)
        ─► compare.compare_with_design (optional) ─► analysis.FitResult

``bench.simulate`` produces records under any ``protocols`` protocol (the
paper's staircase at one or more rates, with holds, or sine sweeps) with
effects injected, for planning tests and for the test suite.

Units: torque N·m, angles rad, time s, stiffness N·m/rad (the bench CSV is in N·m).
"""

from springcad.fit.analysis import FitResult, fit_record
from springcad.fit.bench import BenchNoise, BenchSpring, Protocol, SimulatedRecord, simulate
from springcad.fit.data import BenchRecord, ColumnMap, make_record, read_bench_csv, to_csv_text
from springcad.fit.effects import EFFECT_NAMES, LIBRARY
from springcad.fit.loop import LoopSettings
from springcad.fit.protocols import SineSweep

__all__ = [
    "BenchNoise", "BenchRecord", "BenchSpring", "ColumnMap", "EFFECT_NAMES", "FitResult",
    "LIBRARY", "LoopSettings", "Protocol", "SimulatedRecord", "SineSweep", "fit_record",
    "make_record",
    "read_bench_csv", "simulate", "to_csv_text",
]
