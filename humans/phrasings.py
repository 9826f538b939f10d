"""Paraphrase banks: the many ways people ask the robot for the same thing.

``humans/phrasings.xml`` holds, for each request a script can name
(``<say request="follow"/>``), phrasings tagged with a style: ``plain``,
``polite``, ``terse``, ``chatty`` or ``vague`` (underspecified: "come on",
"this thing here"). A phrasing may hold one slot, ``{about}``, filled from
the say's ``about=`` ("the kitchen", "my favourite cup"). A person draws a
style by her profile's weights, then a phrasing of that style; a rephrasing
avoids the phrasing she used last. The banks were written for the simulated
users, independently of the robot's understanding corpus: many of their
phrasings are ones the robot's grammar does not know, as with real users.

It is the one bank: ``homesim generate`` words its tours from it too, and its
``<talk>`` lines are what bystanders, radios and TVs say. Its ``<vocabulary>``
holds a person's words for each object type; a phrasing about a plural word
("my keys") is said in agreement ("These are my keys", :meth:`Bank.render`).
No phrasing is an utterance of the robot's understanding corpus
(tests/test_phrasing_bank.py).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from homesim.errors import InputError
from homesim.xmlio import parse_file

BANK_PATH = Path(__file__).with_name("phrasings.xml")

#: The styles a phrasing may have (a profile weighs them).
STYLES = ("plain", "polite", "terse", "chatty", "vague")

_SLOT = re.compile(r"\{([^}]*)\}")


@dataclass(frozen=True)
class Phrasing:
    text: str
    style: str
    line: int | None = None

    @property
    def has_slot(self) -> bool:
        return "{about}" in self.text

    def render(self, about: str | None) -> str:
        return self.text.replace("{about}", about or "it")


def side_request(side: str) -> tuple[str, str | None]:
    """The request and slot filling for answering "which one?" by position: ``which-side`` with
    "left"/"right", but the middle one has its own wording (``which-middle``: "the one in the
    middle"), since "the one on your middle" is no English and the robot would not hear a side."""
    return ("which-middle", None) if side == "middle" else ("which-side", side)


#: Verb and pronoun agreement for a plural thing ("This is my keys" -> "These are my keys"), in order.
_AGREE = ((r"\b(this|that) one\b", lambda m: _plural(m.group(1))),
          (r"\b(this|that) thing\b", lambda m: _plural(m.group(1)) + " things"),
          (r"\b(these|those)( here)? is\b", lambda m: m.group(1) + (m.group(2) or "") + " are"),
          (r"\b(this|that)( here)? is\b", lambda m: _plural(m.group(1)) + (m.group(2) or "") + " are"),
          (r"\bhere is\b", lambda m: "here are"), (r"\bwhere's\b", lambda m: "where are"),
          (r"\bthat is\b", lambda m: "those are"), (r"\bit is\b", lambda m: "they are"),
          (r"\bit's\b", lambda m: "they are"), (r"\b(where|remember) it\b", lambda m: m.group(1) + " them"),
          (r"\bthey is\b", lambda m: "they are"), (r"\bwhere them is\b", lambda m: "where they are"),
          (r"\bthis\b", lambda m: "these"), (r"\b(where (?:my|the) [a-z ]+) is\b", lambda m: m.group(1) + " are"))


def _plural(word: str) -> str:
    return {"this": "these", "that": "those"}[word.lower()]


def _agree(text: str) -> str:
    """``text`` about a plural thing, verbs and pronouns in agreement (the first letter's case kept)."""
    for pattern, repl in _AGREE:
        def keep_case(m: re.Match[str], repl: object = repl) -> str:
            out = repl(m)  # type: ignore[operator]
            return out[:1].upper() + out[1:] if m.group(0)[:1].isupper() else out

        text = re.sub(pattern, keep_case, text, flags=re.IGNORECASE)
    return text


@dataclass(frozen=True)
class Bank:
    """Every request's phrasings (request name -> phrasings in file order), the talk not
    addressed to the robot, and a person's words for each object type."""

    requests: dict[str, tuple[Phrasing, ...]]
    source: str
    talk: dict[str, tuple[str, ...]] = field(default_factory=dict)
    #: object type -> a person's words for it (first: the usual one)
    object_words: dict[str, tuple[str, ...]] = field(default_factory=dict)
    plurals: frozenset[str] = frozenset()

    def render(self, phrasing: Phrasing, about: str | None) -> str:
        """``phrasing`` with its slot filled, verb and pronoun in agreement when ``about`` is plural."""
        text = phrasing.render(about)
        if about and any(about.lower().endswith(w) for w in self.plurals):
            text = _agree(text)
        return text

    def line(self, rng: np.random.Generator, name: str) -> str:
        """One line of a ``<talk>`` (what bystanders, radios and TVs say)."""
        try:
            lines = self.talk[name]
        except KeyError:
            raise KeyError(f"no talk {name!r} in the paraphrase bank {self.source}; known: {', '.join(sorted(self.talk))}") from None
        return lines[int(rng.integers(len(lines)))]

    def phrasings(self, request: str) -> tuple[Phrasing, ...]:
        try:
            return self.requests[request]
        except KeyError:
            raise KeyError(f"no request {request!r} in the paraphrase bank {self.source}; known: {', '.join(sorted(self.requests))}") from None

    def draw(self, rng: np.random.Generator, request: str, style_weights: tuple[tuple[str, float], ...] = (), avoid: str | None = None,
             *, slotted: bool = False, about: str | None = None) -> Phrasing:
        """One phrasing of ``request``: a style by ``style_weights`` (all alike when empty), then one of its phrasings.

        ``avoid``: a phrasing's text not to draw again (a rephrasing), when the bank has another.
        ``slotted``: only phrasings that say what the request is about (``{about}``); ``about``:
        the slot's filling, so that ``avoid`` may be the words she said.
        """
        options = self.phrasings(request)
        if slotted:
            options = tuple(p for p in options if p.has_slot) or options
        pool = options
        if style_weights:
            styles = [s for s, w in style_weights if w > 0 and any(p.style == s for p in options)]
            if styles:
                w = np.array([dict(style_weights)[s] for s in styles], dtype=float)
                style = styles[int(rng.choice(len(styles), p=w / w.sum()))]
                pool = tuple(p for p in options if p.style == style)
        if avoid is not None:
            def other(p: Phrasing) -> bool:
                return p.text != avoid and self.render(p, about) != avoid

            fresh = tuple(p for p in pool if other(p)) or tuple(p for p in options if other(p))
            pool = fresh or pool
        return pool[int(rng.integers(len(pool)))]


def load_bank(path: str | Path = BANK_PATH) -> Bank:
    """Read a paraphrase bank; InputError naming file and line for a bad entry."""
    source = str(path)
    root = parse_file(path)
    if root.tag != "phrasings":
        raise InputError(f"root element <{root.tag}> is not <phrasings>", source=source, line=root.sourceline)
    for el in root:
        if isinstance(el.tag, str) and el.tag not in ("request", "talk", "vocabulary"):
            raise InputError(f"<{el.tag}> is not part of a bank (<request>, <talk>, <vocabulary>)", source=source, line=el.sourceline)
    requests: dict[str, tuple[Phrasing, ...]] = {}
    talk: dict[str, tuple[str, ...]] = {}
    for el in root.iterfind("talk"):
        name = el.get("name")
        if not name or name in talk:
            raise InputError(f"<talk> needs a name= of its own ({name!r})", source=source, line=el.sourceline)
        lines = tuple(" ".join((ph.text or "").split()) for ph in el.iterfind("say"))
        if not lines or not all(lines):
            raise InputError(f"talk {name!r}: an empty line, or none", source=source, line=el.sourceline)
        talk[name] = lines
    words, plurals = _vocabulary(root, source)
    for req in root.iterfind("request"):
        name = req.get("name")
        if not name:
            raise InputError("<request> needs name=", source=source, line=req.sourceline)
        if name in requests:
            raise InputError(f"request {name!r} is given twice", source=source, line=req.sourceline)
        items = []
        for ph in req.iterfind("say"):
            text = " ".join((ph.text or "").split())
            style = ph.get("style", "plain")
            if not text:
                raise InputError("an empty phrasing", source=source, line=ph.sourceline)
            if style not in STYLES:
                raise InputError(f"style {style!r}: one of {', '.join(STYLES)}", source=source, line=ph.sourceline)
            bad = [s for s in _SLOT.findall(text) if s != "about"]
            if bad:
                raise InputError(f"unknown slot {{{bad[0]}}}: a phrasing has only {{about}}", source=source, line=ph.sourceline)
            items.append(Phrasing(text, style, ph.sourceline))
        if not items:
            raise InputError(f"request {name!r} has no phrasing", source=source, line=req.sourceline)
        requests[name] = tuple(items)
    return Bank(requests, source, talk, words, plurals)


def _vocabulary(root: object, source: str) -> tuple[dict[str, tuple[str, ...]], frozenset[str]]:
    """``<vocabulary><object type=...><word [plural="true"]>...``: words per object type."""
    words: dict[str, tuple[str, ...]] = {}
    plurals: set[str] = set()
    for voc in root.iterfind("vocabulary"):  # type: ignore[attr-defined]
        for ob in voc.iterfind("object"):
            typ = ob.get("type")
            if not typ or typ in words:
                raise InputError(f"<object> needs a type= of its own ({typ!r})", source=source, line=ob.sourceline)
            ws = []
            for w in ob.iterfind("word"):
                text = " ".join((w.text or "").split()).lower()
                if not text or not all(part.isalpha() for part in text.split()):
                    raise InputError(f"object {typ!r}: a word is letters only ({text!r})", source=source, line=w.sourceline)
                if w.get("plural", "false") not in ("true", "false"):
                    raise InputError("plural= is true or false", source=source, line=w.sourceline)
                if w.get("plural") == "true":
                    plurals.add(text)
                ws.append(text)
            if not ws:
                raise InputError(f"object {typ!r} has no <word>", source=source, line=ob.sourceline)
            words[typ] = tuple(ws)
    return words, frozenset(plurals)


@lru_cache(maxsize=1)
def default_bank() -> Bank:
    """The bank shipped in ``humans/phrasings.xml`` (read once per process)."""
    return load_bank(BANK_PATH)
