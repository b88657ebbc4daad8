"""Exports: STEP/STL, wire-EDM DXF, vendor drawings (SVG/PDF), bill of materials, renders."""
