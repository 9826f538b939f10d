"""BIRON's phases on a timeline: the papers' B-E plus teaching and good-bye, from the supervisor's log.

A phase starts where the execution supervisor applied one of the events of
:data:`PHASE_EVENTS`; "following" (D) is the first follow status after a
follow request. Importing this module registers the marker with
:func:`homesim.traceview.register_phases`.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from ..traceview import label_of, register_phases

#: Phases: an event the ES applied -> (mark, label); "following" is the first follow status after a follow request.
PHASE_EVENTS: dict[str, tuple[str, str]] = {
    "greeting": ("B", "greeting"), "follow": ("C", "follow request"), "stop": ("E", "stop"),
    "object_teaching": ("T", "teaching an object"), "place_teaching": ("T", "teaching a place"),
    "goodbye": ("G", "good-bye"),
}
ES_LOG = "/robot/es/log"
FOLLOW_STATUS = "/robot/follow/status"


class BironPhases:
    """One timeline's phase marker (a follow request waits for the first follow status)."""

    def __init__(self) -> None:
        self.following = False

    def __call__(self, ch: str, rec: dict[str, Any]) -> Iterable[tuple[str, str]]:
        if ch == ES_LOG and 'kind="applied"' in rec.get("xml", ""):
            name = label_of(rec).split(" ", 1)[-1]
            self.following = self.following or name == "follow"
            return (PHASE_EVENTS[name],) if name in PHASE_EVENTS else ()
        if ch == FOLLOW_STATUS and self.following:
            self.following = False
            return (("D", "following"),)
        return ()


register_phases(BironPhases)
