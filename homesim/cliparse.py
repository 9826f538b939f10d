"""The ``homesim`` command line's parser: argparse with suggestions, examples and defaults in ``--help``.

Why argparse and not Click/Typer: every subcommand module already declares
its options with ``register(subparsers)`` and the tests walk the parser tree
(``tests/test_cli_hostile.py``); argparse keeps all of that and only needs
what Python 3.11's argparse lacks (3.12's ``suggest_on_error``):

- a refusal prints the (sub)command's usage, then ``prog: error: message``;
- an unknown option (``--untill 5``) or a mistyped subcommand or choice
  (``homesim rnu``, ``--format mermiad``) is answered with ``did you mean
  ...?`` (:mod:`difflib`, the closest known name);
- ``--help`` shows every default that is a value (not ``None``/``False``) and
  the examples each subcommand was registered with (``add_parser(...,
  examples=[...])``).

Shell completion is generated from the same tree by shtab
(:mod:`homesim.completion`).
"""

from __future__ import annotations

import argparse
import sys
import textwrap
from collections.abc import Sequence
from typing import Any, NoReturn

from .suggest import did_you_mean

#: The namespace attribute naming the deepest parser that took part (removed before the namespace is returned).
_LEAF = "_homesim_leaf_parser"


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions and examples as written; ``(default: X)`` after every option whose default is a value."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        default = action.default
        if ("default" in text or default is None or default is False or default is argparse.SUPPRESS
                or default == [] or isinstance(action, (argparse._HelpAction, argparse._VersionAction))):
            return text
        if action.option_strings or action.nargs in (argparse.OPTIONAL, argparse.ZERO_OR_MORE):
            return f"{text} (default: %(default)s)" if text else "default: %(default)s"
        return text


class SubcommandsAction(argparse._SubParsersAction):
    """Subcommands registered with a description and examples: ``add_parser(name, help=..., examples=[...])``."""

    def add_parser(self, name: str, **kwargs: Any) -> argparse.ArgumentParser:  # type: ignore[override]
        examples: Sequence[str] = kwargs.pop("examples", ())
        if kwargs.get("help") and "description" not in kwargs:
            text = kwargs["help"].replace("%%", "%")  # help is %-formatted by argparse, a description is not
            kwargs["description"] = textwrap.fill(text[:1].upper() + text[1:] + ".", width=78)
        if examples and "epilog" not in kwargs:
            kwargs["epilog"] = "examples:\n" + "\n".join(f"  {e}" for e in examples)
        kwargs.setdefault("formatter_class", HelpFormatter)
        parser = super().add_parser(name, **kwargs)
        parser.examples = list(examples)  # type: ignore[attr-defined]  (tests/test_cli_help.py reads them)
        return parser


class Parser(argparse.ArgumentParser):
    """An ArgumentParser that shows usage on error and suggests the closest option, subcommand or choice."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)
        self.register("action", "parsers", SubcommandsAction)

    #: The deepest parser of the last :meth:`parse_args` (this one until then).
    leaf: "Parser | None" = None

    def error(self, message: str) -> NoReturn:
        """Usage of this (sub)command, then ``prog: error: message`` on one line; exit status 2."""
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(self, args: Sequence[str] | None = None,  # type: ignore[override]
                         namespace: argparse.Namespace | None = None) -> tuple[argparse.Namespace, list[str]]:
        ns, extras = super().parse_known_args(args, namespace)
        if not hasattr(ns, _LEAF):  # a subcommand's parser returns first: the deepest one is kept
            setattr(ns, _LEAF, self)
        return ns, extras

    def parse_args(self, args: Sequence[str] | None = None,  # type: ignore[override]
                   namespace: argparse.Namespace | None = None) -> argparse.Namespace:
        ns, extras = self.parse_known_args(args, namespace)
        leaf: Parser = vars(ns).pop(_LEAF, self)
        self.leaf = leaf  # the (sub)command's parser: refusals found after parsing go through its error()
        if extras:
            leaf.error(f"unrecognized arguments: {' '.join(extras)}{leaf._suggest(extras)}")
        return ns

    def _suggest(self, extras: list[str]) -> str:
        """``did you mean`` for the first unknown option that is close to one of this parser's."""
        known = [s for a in self._actions if a.help is not argparse.SUPPRESS for s in a.option_strings]
        for token in extras:
            if token.startswith("-") and not _is_number(token):
                hint = did_you_mean(token.split("=", 1)[0], known)
                if hint:
                    return hint
        return ""

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        """An unknown subcommand or choice names the choices and the closest one."""
        if action.choices is not None and value not in action.choices:
            names = [str(c) for c in action.choices]
            raise argparse.ArgumentError(action, f"invalid choice: {value!r} (choose from {', '.join(names)})"
                                                 f"{did_you_mean(str(value), names)}")


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True
