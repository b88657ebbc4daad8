"""How the springs of a series stack are joined: the paper's alternation rule, once.

Consecutive springs alternate between sharing a rim (rim-to-rim, bolted) and
sharing a camshaft (shaft-to-shaft). With the input on the first spring's
camshaft ("shaft") the first joint is rim-to-rim; with the input on its rim,
shaft-to-shaft. For odd n the output is then the other kind of connection;
for even n it is the same kind as the input (paper Section II-A).

The stack design, the hardware layout and the geometry checks all read the
rule from here.
"""

from __future__ import annotations

RIM, SHAFT = "rim", "shaft"
CONNECTIONS = (RIM, SHAFT)


def other(connection: str) -> str:
    """The other kind of connection: rim for shaft, shaft for rim."""
    return SHAFT if connection == RIM else RIM


def output_connection(n_springs: int, input_connection: str) -> str:
    """The alternation rule: the output of n springs is the input's kind for even n, else the other."""
    return input_connection if n_springs % 2 == 0 else other(input_connection)


def connection_sequence(n_springs: int, input_connection: str) -> tuple[tuple[str, ...], str]:
    """Joints between consecutive springs and the output connection.

    Returns:
        (joints, output): ``joints[i]`` is "rim" (rim-to-rim) or "shaft"
        (shaft-to-shaft) between springs i and i+1; the joints alternate,
        starting with the other kind than the input (the first spring's free side).
    """
    first = other(input_connection)
    joints = tuple(first if i % 2 == 0 else input_connection for i in range(n_springs - 1))
    return joints, output_connection(n_springs, input_connection)


def camshaft_indices(joints) -> tuple[int, ...]:
    """Camshaft part index of each spring (springs joined shaft-to-shaft share one)."""
    idx, out = 0, [0]
    for j in joints:
        if j != SHAFT:
            idx += 1
        out.append(idx)
    return tuple(out)
