"""How the springs of a series stack are joined: the paper's alternation rule, once.

Consecutive springs alternate between sharing a rim (rim-to-rim, bolted) and
sharing a camshaft (shaft-to-shaft). With the input on the first spring's
camshaft ("shaft") the first joint is rim-to-rim; with the input on its rim,
shaft-to-shaft. For odd n the output is then the other kind of connection;
for even n it is the same kind as the input (paper Section II-A).

This module imports nothing of springcad, so every layer reads the rule from here:
the config (the allowed connections, the output check, the rim joints that need
fasteners), the stack design and hardware layout, the geometry checks and the synthesis.
"""

from __future__ import annotations

RIM, SHAFT = "rim", "shaft"
#: the connections a stack's input (and output) can take; the default input first
CONNECTIONS = (SHAFT, RIM)


def other(connection: str) -> str:
    """The other kind of connection: rim for shaft, shaft for rim."""
    return SHAFT if connection == RIM else RIM


def output_connection(n_springs: int, input_connection: str) -> str:
    """The alternation rule: the output of n springs is the input's kind for even n, else
    the other."""
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


def rim_joint_count(n_springs: int, input_connection: str) -> int:
    """Number of rim-to-rim joints (pinned or bolted through the rim holes) in n springs."""
    return connection_sequence(n_springs, input_connection)[0].count(RIM)
