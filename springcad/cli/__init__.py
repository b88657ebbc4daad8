"""The ``springcad`` command line: thin subcommands over the library.

Each subcommand lives in its own module exposing ``register(subparsers)``,
which adds its parser and sets ``func`` to a callable ``(args) -> int``.
Domain errors become one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from springcad.errors import SpringcadError

#: subcommand modules, in the order ``--help`` lists them
SUBCOMMANDS = ("design", "build", "verify", "simulate", "fit", "paper", "synthesize", "explore")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="springcad",
        description="Design, build, FEA-verify and bench-check series torsion springs.")
    sub = parser.add_subparsers(dest="command", required=True)
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"springcad.cli.{name}")
        except ModuleNotFoundError as err:
            if err.name != f"springcad.cli.{name}":
                raise
            continue
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except SpringcadError as err:
        print(f"springcad {args.command}: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
