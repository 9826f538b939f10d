"""``homesim afsm show FILE --format dot|mermaid`` and ``homesim afsm check FILE``.

``check`` prints every problem found (one per line: file:line: <element>:
message) and exits with 1 when there is any, 0 when the machine loads.
``show`` prints the rendering on stdout (pipe it to ``dot -Tsvg``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..documents import example
from ..errors import OptionError
from .loader import check_file, load
from .render import to_dot, to_mermaid


def register(subparsers: Any) -> None:
    """Add the ``afsm`` command and its ``show``/``check`` subcommands."""
    machine = example("AFSM", "MY_MACHINE.scxml")
    p = subparsers.add_parser("afsm", help="look at and check AFSM (SCXML) documents",
                              examples=[f"homesim afsm show {machine} > machine.dot",
                                        f"homesim afsm check {machine}"])
    sub = p.add_subparsers(dest="afsm_command", metavar="ACTION")
    show = sub.add_parser("show", help="render an AFSM as Graphviz DOT or Mermaid",
                          examples=[f"homesim afsm show {machine} | dot -Tsvg > machine.svg  (Graphviz)",
                                    f"homesim afsm show {machine} --format mermaid --current Interacting"])
    show.add_argument("file", type=Path, help=f"an AFSM (SCXML) document, e.g. {machine}")
    show.add_argument("--format", choices=("dot", "mermaid"), default="dot", help="the notation")
    show.add_argument("--current", default=None, metavar="STATE", help="highlight this state")
    show.add_argument("--no-sends", action="store_true", help="leave orders/conditions off the labels")
    show.set_defaults(func=_show)
    chk = sub.add_parser("check", help="report every problem of an AFSM document",
                         examples=[f"homesim afsm check {machine}"])
    chk.add_argument("file", type=Path, help=f"an AFSM (SCXML) document, e.g. {machine}")
    chk.set_defaults(func=_check)
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])


def _show(args: argparse.Namespace) -> int:
    m = load(str(args.file))
    if args.current is not None and args.current not in m.states:
        near = ", ".join(sorted(m.leaves())[:8])
        raise OptionError("--current", f"no state {args.current!r} in {args.file} (states include: {near})")
    render = to_dot if args.format == "dot" else to_mermaid
    sys.stdout.write(render(m, current=args.current, sends=not args.no_sends))
    return 0


def _check(args: argparse.Namespace) -> int:
    problems = check_file(str(args.file))
    for p in problems:
        print(p)
    if problems:
        print(f"{args.file}: {len(problems)} problem{'s' if len(problems) > 1 else ''}", file=sys.stderr)
        return 1
    m = load(str(args.file))
    print(f"{args.file}: ok ({len(m.leaves())} states, {len(m.categories())} categories, "
          f"{sum(1 for _ in m.transitions())} transitions)")
    return 0
