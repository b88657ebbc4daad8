"""springcad: compact series torsion springs from spec to EDM drawings.

Internal units: lengths in mm, forces in N, stresses in MPa (N/mm^2),
torques in N*mm, angles in rad, masses in kg. Public result keys carry
their unit in the name (``stiffness_Nm_per_rad``).

``import springcad`` stays light: CAD, meshing and plotting libraries
are imported by the modules that use them.
"""

__version__ = "0.1.0"
