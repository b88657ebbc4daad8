"""Which camshaft part each spring of a stack engages, from the alternation rule.

The rule itself (rim-to-rim and shaft-to-shaft joints alternate) lives in
:mod:`springcad.connections`, below the config that checks it; its names are
imported here for the design modules that read both.
"""

from __future__ import annotations

from springcad.connections import RIM, SHAFT, connection_sequence

__all__ = ["RIM", "SHAFT", "camshaft_indices", "connection_sequence"]


def camshaft_indices(joints) -> tuple[int, ...]:
    """Camshaft part index of each spring (springs joined shaft-to-shaft share one)."""
    idx, out = 0, [0]
    for j in joints:
        if j != SHAFT:
            idx += 1
        out.append(idx)
    return tuple(out)
