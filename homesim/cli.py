"""The ``homesim`` command.

Each subcommand lives in its own module, which exposes
``register(subparsers)``; this file only lists them. Errors from user input
(``HomesimError``) print one clear line and exit with status 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__
from . import cliargs
from .cliargs import OneLineParser
from .realtime import MAX_WATCHDOG_S, Watchdog
from .errors import HomesimError

#: Modules that add subcommands (each has ``register(subparsers)``).
SUBCOMMAND_MODULES: list[str] = [
    "homesim.demo",
    "homesim.tour.run_cli",
    "homesim.afsm.cli",
    "homesim.check",
    "homesim.memory.cli",
    "homesim.tour.plot_cli",
    "homesim.tour.export_cli",
    "homesim.tour.trace_cli",
    "homesim.tour.sweep",
    "homesim.tour.generate",
    "homesim.tour.study",
]


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="homesim", description="Deterministic simulator of BIRON's home tour.")
    parser.add_argument("--version", action="version", version=f"homesim {__version__}")
    parser.add_argument("--watchdog", type=cliargs.seconds(positive=True, high=MAX_WATCHDOG_S), default=None, metavar="WALL_SECONDS",
                        help="dump every stack and exit (status 1) after this many seconds of wall time (for runs that hang)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in SUBCOMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse's refusals (one line, see OneLineParser), --help, --version
        return exc.code if isinstance(exc.code, int) else 2
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        if args.watchdog is not None:
            with Watchdog(args.watchdog):
                return int(args.func(args) or 0)
        return int(args.func(args) or 0)
    except HomesimError as exc:
        print(f"homesim: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the environment (disk full, permissions), not the program: one line
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"homesim: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
