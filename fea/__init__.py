"""Finite-element verification of flexure rings (scikit-fem, gmsh, CalculiX cross-check).

Rooms
    :mod:`fea.geometry`    one-flexure sector and full ring faces from the exact design curves
    :mod:`fea.mesh`        quadratic face meshes from the exact curves (gmsh) and their extrusion
    :mod:`fea.mesh_size`   element size rules over the ring face
    :mod:`fea.mesh_solid`  quadratic tets of any CAD solid (gmsh or pytetwild)
    :mod:`fea.mesh_quality`  quality report and rejection of broken meshes
    :mod:`fea.problem`     material, supports, cam load, vectorised assembly
    :mod:`fea.solve`       checked direct solves (PARDISO / SuperLU)
    :mod:`fea.results`     stiffness, von Mises, peak stress and where it is
    :mod:`fea.convergence` Richardson extrapolation, stated discretisation error
    :mod:`fea.calculix`    the identical model solved by CalculiX
    :mod:`fea.study`       one geometry meshed and solved on its levels (K, stress, 3D factor)
    :mod:`fea.verdict`     verified spring, stack and job: pass/fail, reasons, ``fea.json``
    :mod:`fea.verify`      verification and the correction loop (``verify_job``)
    :mod:`fea.contact`     cam-flexure contact sweep to +-theta_max (torque-angle curve)
    :mod:`fea.contact_path`    the sweep's continuation along the cam angle and the cam's dilation
    :mod:`fea.contact_result`  the sweep's options, steps and result, and its flags
    :mod:`fea.contact_solver`  rigid-cam contact: closest points, Newton + exact complementarity
    :mod:`fea.nonlinear`   total Lagrangian (large-rotation) elasticity for the contact sweep

Choices (and the measurements behind them; paper springs S1/S2, 2-core machine)
    - Quadratic elements only (linear tets lock). The default model solves the
      one-flexure sector (free sides, outer rim held) in 2D plane stress on
      three nested levels (5k-84k DOFs, 0.1-1 s each) and multiplies by the
      3D factor from quadratic tets of the same face extruded through the
      thickness (+0.42 % on K for S1, +0.54 % for S2). A pure 3D study
      (``model="3d"``) agrees with it within 0.02 %.
    - gmsh meshes the exact curves (the flexure-edge B-splines rebuilt
      knot for knot): nodes on the true surface, mesh area = CAD area to
      1e-6, nested uniform refinement (clean Richardson). pytetwild is
      selectable for any solid (``mesh_solid``, ``mesher="pytetwild"``); its
      envelope shrinks the sector by 0.2 % in volume, K within 0.1 %.
    - Cam load: a smooth cos^2 tangential traction patch centred on the
      contact point; a rigid flat cam pad gives the same K within 0.01 %.
    - Sector vs the full ring built from the same elements: +0.12 % (ring
      stiffer: its rim is continuous). Rim held at its 7 dowel holes instead
      of the outer face: K x 0.991.
    - K converges at h^3.5 (2D) / h^3.0 (3D, layers doubling); stated
      discretisation errors are ~0.03 %. CalculiX on the identical C3D10 mesh:
      K within 5e-7, nodal peak stress within 0.13-1.5 %, time ratio
      scikit-fem / CalculiX 0.5-1.0.

Importing :mod:`fea` is light; heavy libraries are imported where they are used.
"""
