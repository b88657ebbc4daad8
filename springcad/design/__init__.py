"""Design math: pure functions on floats, arrays and exact 2D curves (no CAD, no files)."""
