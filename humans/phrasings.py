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
"""

from __future__ import annotations

import re
from dataclasses import dataclass
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


@dataclass(frozen=True)
class Bank:
    """Every request's phrasings (request name -> phrasings in file order)."""

    requests: dict[str, tuple[Phrasing, ...]]
    source: str

    def phrasings(self, request: str) -> tuple[Phrasing, ...]:
        try:
            return self.requests[request]
        except KeyError:
            raise KeyError(f"no request {request!r} in the paraphrase bank {self.source}; known: {', '.join(sorted(self.requests))}") from None

    def draw(self, rng: np.random.Generator, request: str, style_weights: tuple[tuple[str, float], ...] = (), avoid: str | None = None) -> Phrasing:
        """One phrasing of ``request``: a style by ``style_weights`` (all alike when empty), then one of its phrasings.

        ``avoid``: a phrasing's text not to draw again (a rephrasing), when the bank has another.
        """
        options = self.phrasings(request)
        pool = options
        if style_weights:
            styles = [s for s, w in style_weights if w > 0 and any(p.style == s for p in options)]
            if styles:
                w = np.array([dict(style_weights)[s] for s in styles], dtype=float)
                style = styles[int(rng.choice(len(styles), p=w / w.sum()))]
                pool = tuple(p for p in options if p.style == style)
        if avoid is not None:
            fresh = tuple(p for p in pool if p.text != avoid) or tuple(p for p in options if p.text != avoid)
            pool = fresh or pool
        return pool[int(rng.integers(len(pool)))]


def load_bank(path: str | Path = BANK_PATH) -> Bank:
    """Read a paraphrase bank; InputError naming file and line for a bad entry."""
    source = str(path)
    root = parse_file(path)
    if root.tag != "phrasings":
        raise InputError(f"root element <{root.tag}> is not <phrasings>", source=source, line=root.sourceline)
    requests: dict[str, tuple[Phrasing, ...]] = {}
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
    return Bank(requests, source)


@lru_cache(maxsize=1)
def default_bank() -> Bank:
    """The bank shipped in ``humans/phrasings.xml`` (read once per process)."""
    return load_bank(BANK_PATH)
