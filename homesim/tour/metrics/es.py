"""The supervisor's record of a run, from its decision log (the summary's ``es``).

Not a registered metric: the runner keeps one :class:`EsRecord` for every
run, because the transcript, ``run.es_state`` and the summary all need it.
It reads ``/robot/es/status`` (the initial state) and ``/robot/es/log``
(every decision), and counts; it keeps no records.
"""

from __future__ import annotations

from typing import Any

from robot.contract import ES_LOG, ES_STATUS

from ...message import Message



class EsRecord:
    """Counts the supervisor's decisions and follows its state."""

    channels = (ES_LOG, ES_STATUS)

    def __init__(self) -> None:
        self.state: str | None = None
        self.since = 0.0
        self.transitions = 0
        self.applied = 0
        self.retained = 0
        self.rejected = {"expired": 0, "inapplicable": 0}
        self.visits: dict[str, int] = {}

    def on_message(self, m: Message) -> tuple[str, str] | None:
        """Update from one message; return ``(old, new)`` when the state changed."""
        x = m.xml
        if m.channel == ES_STATUS:
            new = x.get("state")
        else:
            kind = x.get("kind")
            if kind == "rejected":
                reason = x.get("reason", "")
                self.rejected[reason] = self.rejected.get(reason, 0) + 1
                return None
            if kind == "retained":
                self.retained += 1
                return None
            self.applied += 1
            new = x.get("to")
            if new != x.get("state"):
                self.transitions += 1
        if new is None or new == self.state:
            return None
        old, self.state, self.since = self.state or "", new, m.created
        self.visits[new] = self.visits.get(new, 0) + 1
        return old, new

    def summary(self) -> dict[str, Any]:
        return {
            "final_state": self.state,
            "transitions": self.transitions,
            "applied": self.applied,
            "rejected_expired": self.rejected.get("expired", 0),
            "rejected_inapplicable": self.rejected.get("inapplicable", 0),
            "retained": self.retained,
            "states_entered": dict(sorted(self.visits.items())),
        }
