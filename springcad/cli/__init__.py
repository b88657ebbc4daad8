"""The ``springcad`` command line: thin subcommands over the library.

Each subcommand lives in its own module exposing ``register(subparsers)``,
which adds its parser and sets ``func`` to a callable ``(args) -> int``.
:func:`main` turns every outcome into one exit status (:data:`EXIT_STATUS_HELP`)
and at most one error line: domain errors name the key or part and what to
change; an unexpected exception writes its traceback to a log file and prints
a pointer to it (the traceback itself only with ``--debug``). SIGINT and
SIGTERM unwind normally, so temporary output folders are removed.
"""

from __future__ import annotations

import argparse
import datetime
import importlib
import os
import signal
import sys
import tempfile
import traceback
from pathlib import Path

from springcad.errors import (EXIT_BAD_INPUT, EXIT_CHECK_FAILED, EXIT_INTERNAL, CheckFailed,
                              Interrupted, SpringcadError, StageError, one_line)
from springcad.options import spelled
from springcad.version import __version__

#: subcommand modules, in the order ``--help`` lists them
SUBCOMMANDS = ("design", "build", "verify", "simulate", "fit", "paper", "synthesize", "explore")

EXIT_STATUS_HELP = """exit status:
  0    success
  1    a verification or check ran and failed (the message and outputs say why)
  2    bad input or usage: config, data file, output folder or option (nothing written)
  3    internal error: a log file with the traceback is written and named (--debug
       prints the traceback instead)
  130  interrupted (Ctrl-C); 143 terminated (SIGTERM): temporary folders are removed"""

#: exit statuses of an interrupted run (128 + signal number, as shells report them)
EXIT_SIGINT, EXIT_SIGTERM = 128 + signal.SIGINT, 128 + signal.SIGTERM


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="springcad",
        description="Design, build, FEA-verify and bench-check series torsion springs.",
        epilog=EXIT_STATUS_HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"springcad {__version__}")
    parser.add_argument("--debug", action="store_true",
                        help="print the full traceback of an internal error (exit status 3)")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"springcad.cli.{name}")
        except ModuleNotFoundError as err:
            if err.name != f"springcad.cli.{name}":
                raise
            continue
        module.register(sub)
    for p in sub.choices.values():
        p.epilog = EXIT_STATUS_HELP
        p.formatter_class = argparse.RawDescriptionHelpFormatter
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="print the full traceback of an internal error")
    return parser


def _raise_interrupted(signum, frame):
    raise Interrupted(signum)


def crash_log(command: str, text: str) -> Path | None:
    """Write ``text`` to a fresh log file; its path, or None if nothing could be written."""
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    for folder in (Path(tempfile.gettempdir()), Path.cwd()):
        try:
            fd, name = tempfile.mkstemp(prefix=f"springcad-{command}-{stamp}-", suffix=".log",
                                        dir=folder)
            with os.fdopen(fd, "w") as fh:
                fh.write(text)
            return Path(name)
        except OSError:
            continue
    return None


def _internal_error(command: str, err: BaseException, debug: bool) -> int:
    text = "".join(traceback.format_exception(err))
    if debug:
        print(text, file=sys.stderr, end="")
        print(f"springcad {command}: internal error (exit status 3)", file=sys.stderr)
        return EXIT_INTERNAL
    log = crash_log(command, f"springcad {__version__}\nargv: {sys.argv}\n\n{text}")
    where = f"traceback in {log}" if log else "the traceback could not be saved"
    print(f"springcad {command}: internal error: {one_line(f'{type(err).__name__}: {err}', 200)}"
          f" ({where}; rerun with --debug to see it; please report it)", file=sys.stderr)
    return EXIT_INTERNAL


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (see :data:`EXIT_STATUS_HELP`)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:  # --help, --version (0) and usage errors (2)
        return exit_.code if isinstance(exit_.code, int) else EXIT_BAD_INPUT
    command = args.command
    previous = signal.signal(signal.SIGTERM, _raise_interrupted) if _main_thread() else None
    try:
        with spelled("flag"):  # messages name this door's flags, not the API's parameters
            return int(args.func(args) or 0)
    except CheckFailed as err:
        print(f"springcad {command}: failed: {one_line(err, 2000)}", file=sys.stderr)
        return EXIT_CHECK_FAILED
    except StageError as err:  # a library failed on this input: the details go to a log
        log = crash_log(command, "".join(traceback.format_exception(err)))
        where = f" (details in {log})" if log else ""
        print(f"springcad {command}: error: {one_line(err, 2000)}{where}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except SpringcadError as err:
        print(f"springcad {command}: error: {one_line(err, 2000)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(f"springcad {command}: interrupted; temporary files removed", file=sys.stderr)
        return EXIT_SIGINT
    except Interrupted:
        print(f"springcad {command}: terminated; temporary files removed", file=sys.stderr)
        return EXIT_SIGTERM
    except Exception as err:  # noqa: BLE001 - the one place every other failure is caught
        signum = _interrupt_behind(err)
        if signum == signal.SIGINT:
            print(f"springcad {command}: interrupted; temporary files removed", file=sys.stderr)
            return EXIT_SIGINT
        if signum == signal.SIGTERM:
            print(f"springcad {command}: terminated; temporary files removed", file=sys.stderr)
            return EXIT_SIGTERM
        return _internal_error(command, err, getattr(args, "debug", False))
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _interrupt_behind(err: BaseException) -> int | None:
    """The signal behind an exception that a library raised while handling an interrupt.

    A signal that arrives while a C extension initialises (importing OCP during
    ``build``) surfaces as ``ImportError: initialization failed`` whose cause is the
    KeyboardInterrupt or :class:`Interrupted`; that is an interrupted run, not a bug.
    """
    seen = set()
    while err is not None and id(err) not in seen:
        seen.add(id(err))
        if isinstance(err, KeyboardInterrupt):
            return signal.SIGINT
        if isinstance(err, Interrupted):
            return signal.SIGTERM
        err = err.__cause__ or err.__context__
    return None


def _main_thread() -> bool:
    import threading

    return threading.current_thread() is threading.main_thread()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
