"""The whole springcad flow through the public API, as notebook cells.

Run it as a script (``python examples/notebook_flow.py``) or paste the cells
into Jupyter, where every result shows as a table with a drawing or a plot.
Design the paper's spring S1, verify it with plane-stress FEA (seconds),
simulate a bench test of the verified spring and fit the record.
"""

# %% load and design
from pathlib import Path

import springcad as sc

TEMPLATES = Path(__file__).resolve().parents[1] / "templates"

job = sc.load(TEMPLATES / "paper_S1.toml")
design = sc.design_job(job)
print(design)
spring = design.springs["S1"]
print(spring)

# %% verify with FEA (2D plane stress, three mesh levels)
verification = sc.verify(design, model="2d", levels=3)
print(verification)

# %% simulate a bench record of the verified stack (the paper's staircase protocol)
record = sc.simulate(verification, seed=1)
print(f"simulated {record.record.n_samples} samples, "
      f"K = {record.spring.stiffness_Nm_per_rad:.4g} N*m/rad")

# %% fit the record and compare with the design
result = sc.fit_record(record, design=verification.design)
print(result)
