"""Validation cases: the paper's measured springs against springcad's predictions."""
