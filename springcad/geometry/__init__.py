"""Geometry layer: build123d solids from the design's exact 2D profiles."""
