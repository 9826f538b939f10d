"""Recognised words -> grammar tokens: the lexicon, fillers, repetitions and self-corrections.

The recogniser's vocabulary lives in ``lexicon.tsv`` (phrase, terminal, value).
:meth:`Lexicon.tokens` turns a word string into the terminals the grammar
(``hometour.lark``) is written in, in four steps a spoken-language front end
needs before any parser:

1. words: lower case, punctuation dropped, "anna's" split into "anna" + POSS;
2. longest-match look-up of multi-word phrases ("remote control", "living room");
   fillers and politeness words (terminal ``-``) are dropped; words not in the
   lexicon are *unknown*: skipped and reported, never an error;
3. self-corrections: "the red, no, the blue cup" - an editing term (``no``
   not at the start, ``sorry``, ``i mean``, ...) and the reparandum before it
   are removed: the repair's first token is aligned backwards with the latest
   token of the same word class ("the" <- "the", "blue" <- "red");
4. repetitions: an n-gram (n <= 3) said twice in a row is kept once
   ("this is this is my cup").

Nothing here raises on odd input: any word string gives a (maybe empty) token list.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

LEXICON_FILE = Path(__file__).with_name("lexicon.tsv")

#: Terminal of a word dropped without being reported (fillers, politeness).
DROP = "-"
#: Terminal of an editing term that introduces a self-correction.
EDIT = "EDIT"

_WORD = re.compile(r"[a-z0-9]+(?:'[a-z]+)?")


@dataclass(frozen=True, slots=True)
class Tok:
    """One grammar token: terminal, canonical value and the words said for it."""

    type: str
    value: str
    text: str

    def __str__(self) -> str:  # lark makes a str of each token's value: keep it cheap (no dataclass repr)
        return self.text


@dataclass(slots=True)
class Tokens:
    """The tokens of an utterance and what the front end took out."""

    tokens: list[Tok]
    unknown: list[str] = field(default_factory=list)  # words not in the lexicon, in order
    corrected: list[str] = field(default_factory=list)  # words removed by a self-correction
    repeated: list[str] = field(default_factory=list)  # words removed as repetitions
    words: int = 0  # how many words the utterance had


class LexiconError(ValueError):
    """The lexicon file is malformed (names file and line)."""


class Lexicon:
    """Phrase -> (terminal, value) with longest-match look-up over words."""

    def __init__(self, entries: dict[tuple[str, ...], tuple[str, str]]) -> None:
        self.entries = entries
        self.longest = max((len(k) for k in entries), default=1)
        # first word -> the phrase lengths starting with it, longest first (one dict look-up per word)
        lengths: dict[str, set[int]] = {}
        for k in entries:
            lengths.setdefault(k[0], set()).add(len(k))
        self.lengths = {w: sorted(ls, reverse=True) for w, ls in lengths.items()}
        # Fillers that may fall inside a phrase ("the living, uh, room"): single dropped words
        # that are part of no multi-word phrase go before the phrases are matched.
        in_phrases = {w for k in entries if len(k) > 1 for w in k}
        self.hesitations = frozenset(k[0] for k, (t, _) in entries.items() if len(k) == 1 and t == DROP and k[0] not in in_phrases)
        self.terminals = frozenset(t for t, _ in entries.values())

    @classmethod
    def load(cls, path: str | Path = LEXICON_FILE) -> Lexicon:
        """Read a lexicon TSV; raises :class:`LexiconError` naming file and line."""
        entries: dict[tuple[str, ...], tuple[str, str]] = {}
        for n, line in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), 1):
            if not line.strip() or line.startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != 3 or not all(p.strip() for p in parts):
                raise LexiconError(f"{path}:{n}: expected 'phrase<TAB>terminal<TAB>value', got {line!r}")
            phrase, term, value = (p.strip() for p in parts)
            if term != DROP and not re.fullmatch(r"[A-Z][A-Z_]*", term):
                raise LexiconError(f"{path}:{n}: terminal {term!r} is not an upper-case name")
            key = tuple(phrase.split())
            if key in entries:
                raise LexiconError(f"{path}:{n}: phrase {phrase!r} is listed twice")
            entries[key] = (term, value)
        return cls(entries)

    # ------------------------------------------------------------------ words
    @staticmethod
    def words(text: str) -> list[str]:
        """Lower-case words; "anna's" becomes "anna" + "POSS" (the possessive), "let's" stays."""
        out: list[str] = []
        for w in _WORD.findall(text.lower()):
            if w.endswith("'s") and w not in ("let's", "that's", "it's", "what's", "where's", "here's", "children's"):
                out += [w[:-2], "POSS"]
            elif w in ("that's", "it's", "what's", "where's", "here's"):
                out += [w[:-2], "is"]
            else:
                out.append(w)
        return out

    def tokens(self, text: str) -> Tokens:
        """The grammar tokens of ``text`` after fillers, unknown words, corrections and repetitions."""
        words = self.words(text)
        hes = self.hesitations
        words = [w for w in words if w not in hes]
        toks: list[Tok] = []
        unknown: list[str] = []
        i, n = 0, len(words)
        entries = self.entries
        lengths = self.lengths
        while i < n:
            for k in lengths.get(words[i], ()):
                if i + k > n:
                    continue
                key = tuple(words[i : i + k])
                hit = entries.get(key)
                if hit is not None:
                    term, value = hit
                    if term != DROP:
                        toks.append(Tok(term, value, words[i] if k == 1 else " ".join(key)))
                    i += k
                    break
            else:
                unknown.append(words[i])
                i += 1
        toks = _sides(toks)
        out = Tokens(toks, unknown, words=n)
        out.tokens = _repairs(out.tokens, out.corrected)
        out.tokens = _repetitions(out.tokens, out.repeated)
        return out


#: Words that name a side after an article or before "one"/a noun ("the right one", "at the back",
#: "the right cup") and something else elsewhere ("right!", "go back").
_SIDE_WORDS = {"right": "right", "back": "back"}
_BEFORE_SIDE = frozenset({"THE", "A", "THIS", "THAT"})
_AFTER_SIDE = frozenset({"ONE", "OBJ", "COLOUR", "ATTR"})


def _sides(toks: list[Tok]) -> list[Tok]:
    """Read "right" and "back" as a side where the words around them say so."""
    for i, t in enumerate(toks):
        side = _SIDE_WORDS.get(t.text)
        if side is None:
            continue
        before = toks[i - 1].type if i else ""
        after = toks[i + 1].type if i + 1 < len(toks) else ""
        if before in _BEFORE_SIDE or (after in _AFTER_SIDE and before not in ("GO", "COME", "IS", "YES")):
            toks[i] = Tok("SIDE", side, t.text)
    return toks


# Word classes for aligning a repair with its reparandum: a determiner replaces a determiner, etc.
_CLASS = {"A": "DET", "THE": "DET", "MY": "DET", "YOUR": "DET", "OUR": "DET", "THIS": "DEIXIS", "THAT": "DEIXIS"}


def _cls(t: Tok) -> str:
    return _CLASS.get(t.type, t.type)


def _repairs(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """Take out "reparandum + editing term" before each repair ("the red no the blue cup")."""
    changed = True
    while changed:
        changed = False
        for e in range(1, len(toks)):
            t = toks[e]
            if t.type != EDIT and t.type != "NO":
                continue
            if t.type == "NO" and all(x.type == "NO" for x in toks[:e]):
                continue  # "no", "no no": an answer, not a correction
            end = e + 1
            while end < len(toks) and toks[end].type in (EDIT, "NO"):
                end += 1  # "no sorry", "no no"
            if end >= len(toks):
                removed += [x.text for x in toks[e:]]
                del toks[e:]  # a trailing "sorry": nothing repaired
                changed = True
                break
            cls = _cls(toks[end])
            start = next((k for k in range(e - 1, -1, -1) if _cls(toks[k]) == cls), None)
            if start is None:
                start = e  # no aligned word: drop only the editing term(s)
            removed += [x.text for x in toks[start:end]]
            del toks[start:end]
            changed = True
            break
    return toks


def _repetitions(toks: list[Tok], removed: list[str]) -> list[Tok]:
    """Keep one copy of an n-gram (n = 3, 2, 1) said twice in a row."""
    for n in (3, 2, 1):
        i = 0
        while i + 2 * n <= len(toks):
            a = [(t.type, t.value) for t in toks[i : i + n]]
            b = [(t.type, t.value) for t in toks[i + n : i + 2 * n]]
            if a == b and not (n == 1 and toks[i].type in ("HELLO", "GOODBYE", "YES", "NO")):
                removed += [t.text for t in toks[i + n : i + 2 * n]]
                del toks[i + n : i + 2 * n]
            else:
                i += 1
    return toks
