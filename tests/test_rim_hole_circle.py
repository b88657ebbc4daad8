"""The root radius a rim-pinned stack allows keeps the rim spacer's web inside its holes
when large bolts pull the hole circle in (held-out seed 2614 g04: three 17-4PH disks of
R 90 mm, M5 bolts, a 1 mm spacer: the design's roots sat 0.4 mm past the spacer's inner
edge and the design was refused at the spacer check after 180 s)."""

from springcad.config import job_from_dict
from springcad.design.hardware import rim_spacer_rim_mm
from springcad.design.job import _bolt_circle_mm, design_job, shared_rim_limit_mm

G04 = {
    "material": {"name": "17-4ph_h900", "design_stress_MPa": 810.0},
    "springs": {"A": {"stiffness_Nm_per_rad": 570, "max_deflection_deg": 15,
                      "outer_radius_mm": 90.0, "thickness_mm": 7.5, "contact_radius_mm": 23.5}},
    "stack": {"sequence": ["A", "A", "A"], "input": "shaft"},
    "manufacturing": {"process": "wire_edm", "t_spring_mm": 0.02, "t_shaft_mm": 0.02,
                      "w_gap_mm": 0.03},
    "hardware": {"fastener": "bolt", "fastener_diameter_mm": 5.0, "fastener_count": 3,
                 "shaft_diameter_mm": 10.0, "rim_spacer_thickness_mm": 1.0}}


def test_the_root_limit_keeps_the_spacer_web_inside_a_bolt_circle_pulled_in():
    job = job_from_dict(G04)
    spacer_inside_mm = 0.5 * rim_spacer_rim_mm(job.hardware, job.manufacturing)
    assert _bolt_circle_mm(job) < 90.0 - spacer_inside_mm     # the bolts bind, not the rim
    assert shared_rim_limit_mm(job) <= _bolt_circle_mm(job) - spacer_inside_mm + 1e-9


def test_the_stack_designs_with_its_spacer():
    design = design_job(job_from_dict(G04), explain=False)
    spring = design.springs["A"]
    assert spring.root_radius_mm <= shared_rim_limit_mm(design.job) + 1e-9
