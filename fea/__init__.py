"""Finite-element verification of flexure rings (scikit-fem, gmsh, CalculiX cross-check).

Rooms: :mod:`fea.geometry` (sector and ring faces from the design curves),
:mod:`fea.mesh` (quadratic meshes and their quality), :mod:`fea.problem`
(material, supports, cam load), :mod:`fea.solve` (checked linear solves),
:mod:`fea.results` (stiffness, stresses), :mod:`fea.convergence` (Richardson),
:mod:`fea.calculix` (independent solver), :mod:`fea.verify` (verification,
correction loop, stacks). Importing :mod:`fea` is light; heavy libraries are
imported where they are used.
"""
