"""Timing of the interaction (the papers' Fig. 6), measured on the bus.

For each recognised utterance (``/robot/audio/speech``, created when the
recogniser is done) the time until the grammar's frame
(``/robot/speech/frames``), until the dialog's event to the supervisor
(``/robot/es/events`` from ``dialog``) and until the robot starts to answer
(``/robot/speaker/say``). For the supervisor, two different times:

- ``es_reconfiguration_s``: its own processing time, from an applied
  transition's decision (``/robot/es/log``) to its first order or condition
  leaving (the papers' "less than 20 ms to reconfigure the system");
- ``es_event_age_at_decision_s``: from an event's creation to the ES's
  decision on it (applied or rejected): the network latency, the time the
  event waited in the queue and the ES's busy time together.

Each is a running mean/std/min/max. A stage that did not happen before the
next utterance is not counted.
"""

from __future__ import annotations

from typing import Any

from . import Observer
from .stats import Running


class Timing(Observer):
    channels = ("/robot/audio/speech", "/robot/speech/frames", "/robot/es/events", "/robot/es/log", "/robot/speaker/say",
                "/robot/es/orders", "/robot/es/conditions")

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.recognised: float | None = None
        self.pending: set[str] = set()
        self.stages = {"to_frame": Running(), "to_event": Running(), "to_answer": Running()}
        self.decision = Running()
        self.reconfiguration = Running()
        self._decided: dict[str, float] = {}  # applied event id -> decision time, until its first output (bounded)
        self.messages = 0

    def on_message(self, m: Any) -> None:
        ch = m.channel
        if ch == "/robot/audio/speech":
            if m.xml.get("self") == "true":
                return
            self.recognised = m.created
            self.pending = {"to_frame", "to_event", "to_answer"}
            return
        if ch == "/robot/es/log":
            created = m.xml.get("created")
            if created is not None and m.xml.get("kind") != "retained":
                self.decision.add(m.created - float(created))
            if m.xml.get("kind") == "applied" and m.xml.get("outputs", "0") != "0":
                if len(self._decided) > 64:
                    self._decided.pop(next(iter(self._decided)))
                self._decided[m.xml.get("event", "")] = m.created
            return
        if ch.startswith("/robot/es/orders/") or ch.startswith("/robot/es/conditions/"):
            t = self._decided.pop(m.causes[0], None) if m.causes else None
            if t is not None:
                self.reconfiguration.add(m.created - t)
            return
        if ch == "/robot/speaker/say" and not (m.xml.get("text") or m.xml.text or "").strip():
            return  # an empty say only silences the robot (barge-in): no answer
        stage = {"/robot/speech/frames": "to_frame", "/robot/speaker/say": "to_answer"}.get(ch)
        if ch == "/robot/es/events" and m.sender == "dialog":
            stage = "to_event"
        if stage is not None and stage in self.pending and self.recognised is not None:
            self.pending.discard(stage)
            self.stages[stage].add(m.created - self.recognised)

    def summary(self) -> dict[str, Any]:
        out: dict[str, Any] = {f"recognised_{k}_s": v.as_dict() for k, v in self.stages.items()}
        out["es_reconfiguration_s"] = self.reconfiguration.as_dict(6)
        out["es_event_age_at_decision_s"] = self.decision.as_dict(6)
        return out


OBSERVERS = {"timing": Timing}
