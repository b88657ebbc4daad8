"""The whole springcad flow through the public API, as notebook cells.

Run it as a script (``python examples/notebook_flow.py [OUT_DIR]``) or paste
the cells into Jupyter, where every result shows as a table with a drawing or
a plot. Design the paper's spring S1, verify it with plane-stress FEA
(seconds), build and check its parts, export the CAD files, drawings and
``report.html``, then simulate a bench test of the verified spring and fit
the record. Set ``RENDER = True`` for the assembly and stress PNGs (slower).
"""

# %% load and design
import sys
import tempfile
from pathlib import Path

import springcad as sc

TEMPLATES = Path(__file__).resolve().parents[1] / "templates"
OUT = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp()) / "S1"
RENDER = False

job = sc.load(TEMPLATES / "paper_S1.toml")
design = sc.design_job(job)
print(design)
spring = design.springs["S1"]
print(spring)

# %% verify with FEA (2D plane stress, three mesh levels); keep the fields for the stress PNGs
verification = sc.verify(design, model="2d", levels=3, keep_fields=RENDER)
print(verification)

# %% build the parts of the verified (width-corrected) design and check them
built = sc.build(verification, accept_violations=True)
print(built)

# %% export STEP/DXF/drawings/BOM and report.html into one folder
built = sc.export_build(built, OUT, render=RENDER)
print(f"open {built.report_html} in a web browser")

# %% simulate a bench record of the verified stack (the paper's staircase protocol)
record = sc.simulate(verification, seed=1)
print(f"simulated {record.record.n_samples} samples, "
      f"K = {record.spring.stiffness_Nm_per_rad:.4g} N*m/rad")

# %% fit the record and compare with the design
result = sc.fit_record(record, design=verification.design)
print(result)
