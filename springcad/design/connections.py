"""Which camshaft part each spring of a stack engages, and which rims are pinned to each
other, from the alternation rule.

The rule itself (rim-to-rim and shaft-to-shaft joints alternate) lives in
:mod:`springcad.connections`, below the config that checks it; its names are
imported here for the design modules that read both.
"""

from __future__ import annotations

from springcad.connections import RIM, SHAFT, connection_sequence

__all__ = ["RIM", "SHAFT", "camshaft_indices", "connection_sequence", "rim_groups"]


def camshaft_indices(joints) -> tuple[int, ...]:
    """Camshaft part index of each spring (springs joined shaft-to-shaft share one)."""
    idx, out = 0, [0]
    for j in joints:
        if j != SHAFT:
            idx += 1
        out.append(idx)
    return tuple(out)


def rim_groups(sequence, input_connection: str) -> list[tuple[str, ...]]:
    """Names of the springs whose rims are pinned to each other (rim-to-rim joints, also
    through a spring named twice in ``sequence``), one group per set, in sequence order;
    a spring joined by its rim to no other spring is a group of its own. The springs of
    one group share a rim hole pattern; those of different groups need not."""
    joints, _ = connection_sequence(len(sequence), input_connection)
    group = {name: {name} for name in sequence}
    for i, kind in enumerate(joints):
        if kind == RIM:
            merged = group[sequence[i]] | group[sequence[i + 1]]
            for name in merged:
                group[name] = merged
    out: list[tuple[str, ...]] = []
    for name in sequence:
        members = tuple(n for n in dict.fromkeys(sequence) if n in group[name])
        if members not in out:
            out.append(members)
    return out
