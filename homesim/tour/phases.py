"""BIRON's phases on a timeline: the papers' B-E plus teaching and good-bye, from the supervisor's log.

A phase starts where the execution supervisor applied one of the events of
:data:`PHASE_EVENTS`; "following" (D) starts where the robot starts driving
after a follow request (the first non-zero ``/robot/base/cmd``). Spans are
named by what they measure (:class:`BironSpans`): speech detection (the
microphones hearing an utterance, from its start to the recognised words going
out), speech recognition (the understanding's time to the frame), the ES's
reconfiguration (from its decision, its log record, to its first order or
condition) and the robot's speech (the speaker's status ``speaking``: from the
start to the end it announces; its ``done`` status gets the same span, so the
speech is one span on the speaker's lane). Importing this module registers both with
:func:`homesim.traceview.register_phases` and :func:`~homesim.traceview.register_spans`.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import replace
from typing import Any

from robot.contract import ES_LOG

from ..traceview import Span, label_of, register_phases, register_spans

#: Phases: an event the ES applied -> (mark, label); "following" is the first follow status after a follow request.
PHASE_EVENTS: dict[str, tuple[str, str]] = {
    "greeting": ("B", "greeting"), "follow": ("C", "follow request"), "stop": ("E", "stop"),
    "object_teaching": ("T", "teaching an object"), "place_teaching": ("T", "teaching a place"),
    "goodbye": ("G", "good-bye"),
}
BASE_CMD = "/robot/base/cmd"
SPEECH = "/robot/audio/speech"
FRAMES = "/robot/speech/frames"
ES_SENDER = "supervisor"
ES_OUTPUTS = ("/robot/es/orders/", "/robot/es/conditions/")
SPEAKER_STATUS = "/robot/speaker/status"
_START = re.compile(r' start="([0-9.eE+-]+)"')
_END = re.compile(r' end="([0-9.eE+-]+)"')
_V = re.compile(r' v="([-0-9.eE+]+)"')
_EVENT = re.compile(r' event="([^"]+)"')
#: The span kind of an event's wait in the ES's queue (delivered -> the ES's record of its decision): the
#: queue holds an event until older ones can no longer arrive, so this is waiting, not the ES working.
ES_QUEUE = "ES queue (waiting)"
#: Decisions remembered until their first output (bounded).
_DECIDED = 256


class BironPhases:
    """One timeline's phase marker (a follow request waits for the first follow status)."""

    def __init__(self) -> None:
        self.following = False

    def __call__(self, ch: str, rec: dict[str, Any]) -> Iterable[tuple[str, str]]:
        if ch == ES_LOG and 'kind="applied"' in rec.get("xml", ""):
            name = label_of(rec).split(" ", 1)[-1]
            self.following = self.following or name == "follow"
            return (PHASE_EVENTS[name],) if name in PHASE_EVENTS else ()
        if ch == BASE_CMD and self.following:
            v = _V.search(rec.get("xml", ""))
            if v is not None and abs(float(v.group(1))) > 1e-6:  # the robot starts driving after the partner
                self.following = False
                return (("D", "following (driving)"),)
        return ()


class BironSpans:
    """One timeline's span marker: speech detection, speech recognition, an event's wait in the ES's queue,
    the ES's reconfiguration, the robot's speech."""

    def __init__(self) -> None:
        self.decided: dict[str, float] = {}
        self.speaking: Span | None = None  # the speaker's current speech, until its done status

    def __call__(self, ch: str, rec: dict[str, Any], span: Span | None) -> Span | None:
        t = rec["t"]
        if ch == ES_LOG and rec.get("sender") == ES_SENDER:
            ev = _EVENT.search(rec.get("xml", ""))
            if ev is not None:
                if len(self.decided) >= _DECIDED:
                    self.decided.pop(next(iter(self.decided)))
                self.decided[ev.group(1)] = t
            if span is not None:  # delivered -> decided: the event waited in the ES's time-ordered queue
                return replace(span, kind=ES_QUEUE)
            return None
        if ch == SPEECH:  # detection: while the person speaks, until the recognised words go out
            st = _START.search(rec.get("xml", ""))
            if st is not None and float(st.group(1)) < t:
                return Span(rec["sender"], float(st.group(1)), t, "", rec["id"], "speech detection")
            return None
        if ch == SPEAKER_STATUS:
            xml = rec.get("xml", "")
            st, en = _START.search(xml), _END.search(xml)
            if xml.startswith("<speaking") and st is not None and en is not None and float(en.group(1)) > float(st.group(1)):
                causes = rec.get("causes", ())
                self.speaking = Span(rec["sender"], float(st.group(1)), float(en.group(1)), causes[0] if causes else "", rec["id"], "robot speech")
                return self.speaking
            if xml.startswith("<done") and self.speaking is not None and self.speaking.start <= t:
                done, self.speaking = self.speaking, None
                return replace(done, end=min(done.end, t), effect=rec["id"])  # cut short when the speech was
            return None
        if ch == FRAMES and span is not None:
            return replace(span, kind="speech recognition")
        if rec.get("sender") == ES_SENDER and ch.startswith(ES_OUTPUTS):
            causes = rec.get("causes", ())
            at = self.decided.get(causes[0]) if causes else None
            if at is not None and at <= t:  # the ES's own time: its decision -> this output leaving
                return Span(ES_SENDER, at, t, causes[0], rec["id"], "ES reconfiguration")
        return None


register_phases(BironPhases)
register_spans(BironSpans)
