"""The ``homesim`` command.

Each subcommand lives in its own module, which exposes
``register(subparsers)``; this file only lists them. The parser
(:mod:`homesim.cliparse`) is argparse with usage on error, ``did you mean``
suggestions, defaults and examples in ``--help``; ``homesim completion``
prints a shell completion script (shtab). Errors from user input
(``HomesimError``) print one clear line and exit with status 2. Output piped
into a reader that stops early (``| head``) ends the command quietly.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from . import __version__
from . import cliargs, completion
from .cliparse import Parser
from .realtime import MAX_WATCHDOG_S, Watchdog
from .errors import HomesimError, OptionError

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

#: Each subcommand's name and the module that adds it: ``homesim NAME ...`` imports only that module
#: (the others' imports, e.g. sweep's multiprocessing, are start-up time a run does not need).
#: ``tests/test_cli.py`` checks this table against what the modules register.
COMMANDS: dict[str, str] = {
    "demo": "homesim.demo",
    "run": "homesim.tour.run_cli", "replay": "homesim.tour.run_cli", "scenario": "homesim.tour.run_cli",
    "afsm": "homesim.afsm.cli",
    "check": "homesim.check",
    "memory": "homesim.memory.cli",
    "plot": "homesim.tour.plot_cli",
    "export": "homesim.tour.export_cli",
    "trace": "homesim.tour.trace_cli",
    "sweep": "homesim.tour.sweep",
    "generate": "homesim.tour.generate",
    "study": "homesim.tour.study",
    "completion": "homesim.completion",
}

#: Exit status after the reader of our output went away (128 + SIGPIPE, as a shell reports a process killed by it).
BROKEN_PIPE_STATUS = 141


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command tree (every module of :data:`SUBCOMMAND_MODULES` adds its subcommands).

    With ``command`` (a key of :data:`COMMANDS`) only the module adding it is imported and registered:
    the tree that parses that command's arguments exactly as the whole tree would (same parser, same
    usage and errors); top-level help, completion and unknown commands need the whole tree.
    """
    parser = Parser(prog="homesim", description="Deterministic simulator of BIRON's home tour.",
                    epilog="examples:\n  homesim run scenarios/home_tour.xml\n  homesim run --help\n"
                           "  homesim completion bash > ~/.local/share/bash-completion/completions/homesim")
    parser.add_argument("--version", action="version", version=f"homesim {__version__}")
    parser.add_argument("--watchdog", type=cliargs.seconds(positive=True, high=MAX_WATCHDOG_S), default=None, metavar="WALL_SECONDS",
                        help="dump every stack and exit (status 1) after this many seconds of wall time (for runs that hang)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    modules = SUBCOMMAND_MODULES if command is None else [COMMANDS[command]]
    for name in modules:
        if name != "homesim.completion":
            importlib.import_module(name).register(sub)
    if command is None or command == "completion":
        completion.register(sub, build_parser)
    return parser


def _command(argv: list[str]) -> str | None:
    """The subcommand ``argv`` names when no option but ``--watchdog`` stands before it, else None (build all)."""
    i = 0
    while i < len(argv):
        token = argv[i]
        if token == "--watchdog":
            i += 2
        elif token.startswith("--watchdog="):
            i += 1
        elif token in COMMANDS:
            return token
        else:  # --help, --version, an abbreviated option, an unknown command: the whole tree answers
            return None
    return None


def main(argv: list[str] | None = None) -> int:
    """Parse ``argv``, run the subcommand; the exit status (0 ok, 1 a check failed, 2 bad input)."""
    if argv is None:
        argv = sys.argv[1:]
    parser = build_parser(_command(argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse's refusals (usage + one line), --help, --version
        return exc.code if isinstance(exc.code, int) else 2
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        if args.watchdog is not None:
            with Watchdog(args.watchdog):
                status = int(args.func(args) or 0)
        else:
            status = int(args.func(args) or 0)
        sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's last flush
        return status
    except OptionError as exc:  # an option found wrong after parsing: the subcommand's usage and name, as argparse's own
        leaf = getattr(parser, "leaf", None) or parser
        try:
            leaf.error(str(exc))
        except SystemExit as stop:
            return stop.code if isinstance(stop.code, int) else 2
    except BrokenPipeError:  # `homesim ... | head`: the reader has what it wanted
        _silence_stdout()
        return BROKEN_PIPE_STATUS
    except HomesimError as exc:
        if _from_broken_pipe(exc):  # a print inside the simulation (the transcript) met the closed pipe
            _silence_stdout()
            return BROKEN_PIPE_STATUS
        print(f"homesim: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the environment (disk full, permissions), not the program: one line
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"homesim: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2


def _from_broken_pipe(exc: BaseException) -> bool:
    """Whether ``exc`` was caused by writing to a closed pipe (the simulation wraps a failing task's error)."""
    while exc is not None:
        if isinstance(exc, BrokenPipeError):
            return True
        exc = exc.__cause__  # type: ignore[assignment]
    return False


def _silence_stdout() -> None:
    """Point stdout at /dev/null so the interpreter's final flush does not fail again (Python's SIGPIPE recipe)."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # a test's capture: nothing to flush into a pipe
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, fd)
    os.close(devnull)


if __name__ == "__main__":
    sys.exit(main())
