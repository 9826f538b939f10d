"""Word patterns: what a person listens for in the robot's words (``hears=``).

A small, safe pattern language over words, not characters, so a scenario
author writes what she would hear and cannot write a pattern that hangs the
run (matching is linear in the pattern and quadratic at worst in the
utterance's words; no backtracking).

Syntax (case-insensitive; punctuation in what the robot says is ignored)::

    is this the kitchen        the words, in this order, anywhere in the utterance
    yes|no                     alternatives (the whole pattern, or inside a group)
    shall i (follow|go to) *   a group of alternatives
    is this [the] kitchen      an optional part
    do you mean *              '*': any number of words (none too)
    is this _ cup              '_': exactly one word
    ^which one                 '^' at the start of an alternative: the utterance begins here
    kitchen$                   '$' at the end of an alternative: the utterance ends here

A word is letters, digits, ``'`` and ``-`` (any script's letters: ``zoë``,
``küche``; compared case-folded). Anything else (``.``, ``+``,
``\\d``, ``{``, ...) is refused by :func:`compile_words` with the column and
the syntax that is allowed: a pattern never means something its author did
not write.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Union

#: The longest pattern accepted (characters) and the deepest nesting of groups.
MAX_LENGTH = 500
MAX_DEPTH = 8

SYNTAX = "words, 'a|b', '(a|b)' groups, '[optional]' parts, '*' (any words), '_' (one word), '^' (start), '$' (end)"

# letters and digits of any script (``\\w`` without ``_``), apostrophes and hyphens
_WORD = re.compile(r"(?:[^\W_]|['-])+")
_TEXT_WORD = _WORD


class PatternError(ValueError):
    """A pattern that is not in the word-pattern syntax: ``column`` is 1-based."""

    def __init__(self, message: str, column: int) -> None:
        super().__init__(f"{message} (column {column}); a word pattern has {SYNTAX}")
        self.column = column


@dataclass(frozen=True)
class _Word:
    word: str


@dataclass(frozen=True)
class _Any:
    pass


@dataclass(frozen=True)
class _One:
    pass


@dataclass(frozen=True)
class _Seq:
    items: tuple[_Node, ...]
    start: bool = False
    end: bool = False


@dataclass(frozen=True)
class _Alt:
    options: tuple[_Seq, ...]


@dataclass(frozen=True)
class _Opt:
    inner: _Alt


_Node = Union[_Word, _Any, _One, _Seq, _Alt, _Opt]


def words_of(text: str) -> tuple[str, ...]:
    """An utterance as the words a listener matches: lower case, punctuation dropped.

    A hyphenated word is its parts ("Good-bye" -> good, bye), in the utterance as in a pattern:
    a listener who waits for "bye" hears it in "Good-bye!", and "good-bye" matches "good bye".
    """
    return tuple(p for w in _TEXT_WORD.findall(text) for p in w.casefold().split("-") if p)


class WordPattern:
    """A compiled word pattern; :meth:`search` says whether an utterance contains it."""

    def __init__(self, text: str, tree: _Alt) -> None:
        self.text = text
        self._tree = tree

    def __repr__(self) -> str:
        return f"WordPattern({self.text!r})"

    def search(self, utterance: str) -> bool:
        """Whether the pattern occurs in ``utterance`` (anywhere, unless anchored)."""
        toks = words_of(utterance)
        n = len(toks)
        for seq in self._tree.options:
            starts = frozenset([0]) if seq.start else frozenset(range(n + 1))
            ends = _ends(seq, starts, toks)
            if ends and (not seq.end or n in ends):
                return True
        return False

    def phrases(self) -> list[tuple[str, ...]]:
        """A few word sequences the pattern matches (its literal alternatives; '*' and '_' left out).

        Used by the checks to see whether what a person says could make the
        robot echo words that trigger the same handler again.
        """
        return _shortest(_phrases(self._tree))


def _phrases(node: _Node) -> list[tuple[str, ...]]:
    if isinstance(node, _Word):
        return [(node.word,)]
    if isinstance(node, (_Any, _One)):
        return [()]
    if isinstance(node, _Opt):
        return [()] + _phrases(node.inner)
    if isinstance(node, _Alt):
        out: list[tuple[str, ...]] = []
        for o in node.options:
            out += _phrases(o)
        return _shortest(out)
    acc: list[tuple[str, ...]] = [()]
    for it in node.items:
        acc = _shortest([a + b for a in acc for b in _phrases(it)])
    return acc


def _shortest(phrases: list[tuple[str, ...]]) -> list[tuple[str, ...]]:
    """At most 64 phrases, the shortest first (stable): a phrase without words, if any, is never cut off."""
    return sorted(phrases, key=len)[:64]


def _ends(node: _Node, starts: frozenset[int], toks: tuple[str, ...]) -> frozenset[int]:
    """Every position where ``node`` can end when it starts at one of ``starts``."""
    if not starts:
        return starts
    n = len(toks)
    if isinstance(node, _Word):
        return frozenset(i + 1 for i in starts if i < n and toks[i] == node.word)
    if isinstance(node, _One):
        return frozenset(i + 1 for i in starts if i < n)
    if isinstance(node, _Any):
        return frozenset(range(min(starts), n + 1))
    if isinstance(node, _Opt):
        return starts | _ends(node.inner, starts, toks)
    if isinstance(node, _Alt):
        out: frozenset[int] = frozenset()
        for o in node.options:
            e = _ends(o, frozenset([0]) & starts if o.start else starts, toks)
            if o.end:
                e = e & frozenset([n])
            out |= e
        return out
    cur = starts
    for it in node.items:
        cur = _ends(it, cur, toks)
        if not cur:
            break
    return cur


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text
        self.pos = 0

    def error(self, message: str, at: int | None = None) -> PatternError:
        return PatternError(message, (self.pos if at is None else at) + 1)

    def skip(self) -> None:
        while self.pos < len(self.text) and self.text[self.pos] == " ":
            self.pos += 1

    def peek(self) -> str:
        self.skip()
        return self.text[self.pos] if self.pos < len(self.text) else ""

    def alternatives(self, depth: int, closer: str) -> _Alt:
        if depth > MAX_DEPTH:
            raise self.error(f"groups nested deeper than {MAX_DEPTH}")
        options = [self.sequence(depth, closer)]
        while self.peek() == "|":
            self.pos += 1
            options.append(self.sequence(depth, closer))
        return _Alt(tuple(options))

    def sequence(self, depth: int, closer: str) -> _Seq:
        start = end = False
        at = self.pos
        if self.peek() == "^":
            start = True
            self.pos += 1
        items: list[_Node] = []
        while True:
            c = self.peek()
            if c == "" or c == "|" or c in ")]":
                if c != "" and c in ")]" and c != closer:
                    raise self.error(f"unmatched {c!r}")
                break
            if end:
                raise self.error("'$' must end its alternative")
            if c == "$":
                end = True
                self.pos += 1
            elif c == "*":
                if items and isinstance(items[-1], _Any):
                    raise self.error("'* *' means the same as '*'")
                items.append(_Any())
                self.pos += 1
            elif c == "_":
                items.append(_One())
                self.pos += 1
            elif c in "([":
                open_at = self.pos
                self.pos += 1
                inner = self.alternatives(depth + 1, ")" if c == "(" else "]")
                want = ")" if c == "(" else "]"
                if self.peek() != want:
                    raise self.error(f"{c!r} is never closed by {want!r}", open_at)
                self.pos += 1
                items.append(inner if c == "(" else _Opt(inner))
            elif c == "^":
                raise self.error("'^' must begin its alternative")
            else:
                m = _WORD.match(self.text, self.pos)
                if m is None:
                    raise self.error(f"unknown pattern syntax {c!r}")
                parts = [p for p in m.group().casefold().split("-") if p]
                if not parts:
                    raise self.error(f"unknown pattern syntax {c!r}")
                items.extend(_Word(p) for p in parts)  # "good-bye": the words good, bye (see words_of)
                self.pos = m.end()
        if not items and not (start and end):
            raise self.error("an empty alternative matches everything; write '*' if that is meant", at)
        return _Seq(tuple(items), start, end)


@lru_cache(maxsize=512)
def compile_words(text: str) -> WordPattern:
    """Compile a word pattern; PatternError (with the column) when it is not one."""
    if len(text) > MAX_LENGTH:
        raise PatternError(f"pattern is {len(text)} characters long, more than {MAX_LENGTH}", MAX_LENGTH)
    # not lower-cased here: that can change the length (and so every column after it);
    # each word is case-folded as it is read
    spaced = text.replace("\t", " ").replace("\n", " ")
    if not spaced.strip():
        raise PatternError("the pattern is empty", 1)
    p = _Parser(spaced)
    tree = p.alternatives(0, "")
    if p.peek() != "":
        raise p.error(f"unmatched {p.peek()!r}")
    return WordPattern(text, tree)
