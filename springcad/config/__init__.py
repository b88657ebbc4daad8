"""Job configuration: one TOML file describes a job.

Sections (units in key names; see ``templates/``, the README table and
:data:`springcad.config.schema.SECTIONS`, where every key is declared once):

``[job]``            name, description
``[material]``       name (built-in table), overrides, design_stress_MPa or safety_factor
``[springs.<name>]`` one table per spring design
``[stack]``          sequence of spring names and the input connection
``[manufacturing]``  process, tolerances, tip-to-cam gap, wire EDM limits
``[hardware]``       fasteners, spacers, shaft, bushing, densities of the non-steel parts
``[analysis]``       Monte Carlo samples and seed

Loading validates everything before any work (encoding, TOML, section and key
types, ranges, cross-key consistency); a bad value raises :class:`ConfigError`
naming the key, the value and what is allowed. Internally lengths are mm,
torques N*mm, stresses MPa, angles rad.
"""

from springcad.config.load import job_from_dict, load_job, read_toml
from springcad.config.schema import (CONNECTIONS, FASTENER_KINDS, FLEXURE_SHAPES, PROCESSES,
                                     SECTIONS, TOLERANCE_DISTRIBUTIONS, Key)
from springcad.config.specs import (AnalysisSpec, HardwareSpec, Job, ManufacturingSpec,
                                    MaterialSpec, SpringSpec, StackSpec)
from springcad.errors import ConfigError

__all__ = ["AnalysisSpec", "CONNECTIONS", "ConfigError", "FASTENER_KINDS", "FLEXURE_SHAPES",
           "HardwareSpec", "Job", "Key", "ManufacturingSpec", "MaterialSpec", "PROCESSES",
           "SECTIONS", "SpringSpec", "StackSpec", "TOLERANCE_DISTRIBUTIONS", "job_from_dict", "load_job", "read_toml"]
