"""Which home-tour capability an expectation checks, rates with Wilson intervals, failure causes.

A study reports per capability (greeting, self-explanation, following, ...)
how many runs showed it working. A scenario's expectations say what must
happen, not which capability it belongs to, so :func:`capability_of` maps
each expectation to one by its kind and its key attribute (the event, the
state, the metric's name, the robot's words), as the home tour's dialog and
supervisor name them. A run *passes* a capability when every expectation of
that capability holds; a run without such an expectation does not count for
it. :func:`wilson` gives the 95 % score interval of a rate (Wilson, 1927:
right coverage also for small n and rates near 0 or 1, unlike p +- 1.96 se).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

from ..scenario.model import Expectation
from humans.phrasings import default_bank

_WORDS = default_bank().object_words
OBJECT_WORDS = sorted({w for words in _WORDS.values() for w in words} | set(_WORDS), key=len, reverse=True)

#: The capabilities, in the order of a home tour (tables and plots use it).
CAPABILITIES = ("greeting", "self-explanation", "place teaching", "following", "partner kept", "object teaching",
                "where-is", "go-to", "good-bye", "conversation", "no collision", "perception", "robustness", "network", "user script",
                "other")

_EVENTS = {
    "greeting": "greeting", "partner_found": "greeting", "follow": "following", "stop": "following",
    "partner_lost": "partner kept", "object_teaching": "object teaching", "object_recognized": "object teaching",
    "place_teaching": "place teaching", "query_object": "where-is", "goto": "go-to", "goal_reached": "go-to",
    "navigation_failed": "go-to", "goodbye": "good-bye", "potential_partner": "greeting",
    "module_failed": "robustness", "module_recovered": "robustness",
}
_STATES = {"Interacting": "greeting", "PotentialPartner": "greeting", "Following": "following",
           "Navigating": "go-to", "AskingForHelp": "go-to", "Object": "object teaching",
           "ObjectTeaching": "object teaching",
           "LookingAround": "partner kept", "TechnicalFailure": "robustness"}
_METRICS = {"following": "following", "navigation": "go-to", "teaching": "object teaching", "tracking": "perception",
            "social": "no collision", "network": "network",
            "dialog": "conversation"}  # the dialog's own figures: no question asked a third time, ...
#: The robot's words (robot-says patterns), first match wins.
_SAYS = ((r"good-?bye|\bbye\b", "good-bye"),
         (r"i am biron|hello|\bhi\b|can't see you", "greeting"),  # "I can't see you": a greeting it could not place
         (r"following|too fast|slow|stop first", "following"),
         (r"you left|look around", "partner kept"),
         (r"did not understand", "partner kept"),  # never said to others' chat: she stays the one it talks to
         (r"step aside|still looking", "object teaching"),
         (r"technical|support|technician", "robustness"),
         (r"follow you|show me|ask me|can do", "self-explanation"),
         (r"going to|arrived|help|cannot get", "go-to"),
         (r"learned|could not (find|\(see)|found nothing", "object teaching"),  # "could not (see|find)": a look that failed
         (r"remember", "place teaching"),
         (r"\bis\b|don't know|seen the", "where-is"),
         (r"\b(" + "|".join(OBJECT_WORDS) + r")\b", "where-is"))  # the robot naming an object: a where-is answer


def capability_of(e: Expectation, context: Sequence[Expectation] = ()) -> str:
    """The capability an expectation checks; ``context``: the scenario's other expectations (a
    ``robot-near`` is following where the scenario checks following, go-to where it only sends the robot)."""
    k = e.kind
    if k == "object-learned":
        return "object teaching"
    if k == "place-learned":
        return "place teaching"
    if k == "no-collision":
        return "no collision"
    if k == "following-distance":
        return "following"
    if k == "robot-inside":  # it does not drive out of the flat after someone who left
        return "following"
    if k in ("legs-seen", "face-seen", "sound-heard"):
        return "perception"
    if k == "reached":  # a simulated person got where the script sends them: the user, not the robot
        return "user script"
    if k == "robot-near":  # following where the scenario checks following, else go-to where it sends the robot
        follows = any((c.kind == "state-reached" and c.get("state") == "Following") or c.kind == "following-distance" for c in context)
        sends = any(c.kind == "state-reached" and c.get("state") == "Navigating" for c in context) or any(
            c.kind == "robot-says" and re.search("going to|arrived", str(c.get("pattern")), re.I) for c in context)
        return "go-to" if sends and not follows else "following"
    if k in ("event-applied", "event-rejected"):
        return _EVENTS.get(str(e.get("event")), "other")
    if k == "state-reached":
        return _STATES.get(str(e.get("state")), "other")
    if k == "metric":
        return _METRICS.get(str(e.get("name")).split(".")[0], "other")
    if k == "robot-says":
        text = str(e.get("pattern") or "").lower()
        for pattern, cap in _SAYS:
            if re.search(pattern, text):
                return cap
    return "other"


def wilson(passed: int, runs: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """The Wilson score interval of passed/runs (95 % by default); (0, 1) with no runs."""
    if runs <= 0:
        return 0.0, 1.0
    if not 0 <= passed <= runs:
        raise ValueError(f"passed={passed} is not within 0..runs={runs}")
    p = passed / runs
    z2 = z * z
    centre = (p + z2 / (2 * runs)) / (1 + z2 / runs)
    half = z * math.sqrt(p * (1 - p) / runs + z2 / (4 * runs * runs)) / (1 + z2 / runs)
    lo, hi = max(0.0, centre - half), min(1.0, centre + half)
    # the interval always holds the observed rate (rounding at p = 0 or 1 aside)
    return min(lo, p), max(hi, p)


def rate(passed: int, runs: int) -> dict[str, object]:
    """``{"runs", "passed", "rate", "ci95"}`` as a study table cell."""
    lo, hi = wilson(passed, runs)
    return {"runs": runs, "passed": passed, "rate": passed / runs if runs else None, "ci95": [round(lo, 4), round(hi, 4)]}


_NUMBER = re.compile(r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?( ?(ns|ms|s|m))?\b")
_QUOTED = re.compile(r"'[^']*'|\"[^\"]*\"|\{[^}]*\}|/[^/ ][^/]*/")


def cause_of(kind: str, detail: str, names: Sequence[str] = ()) -> str:
    """A failure's cause as a group key: the kind and what the check said, with numbers, times,
    quoted text and the scenario's ``names`` (rooms, objects, people) taken out ("the robot never
    entered kitchen between 0 and 140 s" and the same for the study are one cause)."""
    text = _QUOTED.sub("…", detail)
    for name in sorted(names, key=len, reverse=True):
        if name:
            text = re.sub(rf"\b{re.escape(name)}\b", "…", text)
    text = _NUMBER.sub("N", text)
    text = re.sub(r"\s+", " ", text).strip()
    return f"{kind}: {text}"[:200]
