"""The closest known name to a mistyped one (difflib), for 'did you mean' in every refusal.

Used by the command line (options, subcommands, choices), the scenario checks
(states, events, places, people) and the schema messages (elements,
attributes, values), so a typo gets the same kind of answer everywhere.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

#: difflib's similarity ratio a known name needs to be suggested.
CUTOFF = 0.6


def closest(word: str, known: Iterable[str]) -> str | None:
    """The known name closest to ``word`` (difflib's ratio ≥ :data:`CUTOFF`), or None."""
    found = difflib.get_close_matches(word, list(known), n=1, cutoff=CUTOFF)
    return found[0] if found else None


def did_you_mean(word: str, known: Iterable[str]) -> str:
    """``" (did you mean 'x'?)"`` when something known is close to ``word``, else ``""``."""
    near = closest(word, known)
    return f" (did you mean {near!r}?)" if near is not None else ""
