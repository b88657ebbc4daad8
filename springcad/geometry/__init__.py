"""Geometry layer: build123d solids from the design's exact 2D profiles.

``profile`` (faces and prisms from exact curves, contour checks), ``base`` (the
z-prism part base class and measurements), ``disk`` (flexure ring, camshaft),
``spacers``, ``adapters``, ``fasteners``, ``families`` (the registry that builds
each part kind from its plan), ``placement``, ``stack`` (placing the parts of a
stack), ``checks`` with ``edm`` (wire-EDM rules) and ``interference``.
"""
