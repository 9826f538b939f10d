"""BIRON's expectation kinds: what a scenario says the robot must perceive, say, decide and learn.

The mechanism (streaming checks, verdicts, the registry) and the kinds that
need only the world (``reached``, ``robot-near``, ``no-collision``,
``metric``) are :mod:`homesim.scenario.expectations`; importing this module
registers the kinds that read the robot's channels and knowledge.

Evidence is never mixed up:

* ground truth (the world, step by step) for ``reached``, ``robot-near``,
  ``following-distance`` and the contact log for ``no-collision``;
* the robot's own sensor messages for ``legs-seen`` (the reference leg
  detector on each published scan), ``face-seen``, ``sound-heard``;
* what the robot did, as it went over the bus: ``robot-says`` (the dialog's
  ``/robot/speaker/say``), ``state-reached``, ``event-applied`` and ``event-rejected`` (the
  supervisor's decision log ``/robot/es/log``);
* what the robot knows at the end (its scene model, queried by the runner):
  ``object-learned``, ``place-learned``;
* the run's metrics (``homesim.tour.metrics``): ``metric``.

``absent``/``never="true"`` turns a check around: nothing of the kind may
happen in the window.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from lxml import etree

from robot.contract import ES_LOG, ES_STATUS, FACES, SAY, SCAN, SOURCES

from ..message import Message
from ..geometry import wrap_angle
from ..scenario.expectations import CHECKS, Check, EventCheck, Expectations, Verdict, register_check
from ..scenario.model import window_of
from ..world.reference_legs import detect_leg_pairs
from ..world.world import World
from .metrics.es import EsRecord



# ----------------------------------------------------------------- percepts
class PerceptCheck(Check):
    """legs-seen / face-seen / sound-heard: the closest percept to a bearing in a window."""

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.want = float(self.e.get("bearing"))  # type: ignore[arg-type]
        self.tol = float(self.e.get("tolerance"))  # type: ignore[arg-type]
        self.n = 0
        self.best = math.inf
        self.best_bearing = 0.0
        kind = self.e.kind
        self.channels = {"legs-seen": (SCAN,), "face-seen": (FACES,), "sound-heard": (SOURCES,)}[kind]
        self.noun = {"legs-seen": "leg pairs", "face-seen": "faces", "sound-heard": "sound directions"}[kind]

    def bearings(self, m: Message) -> list[float]:
        if self.e.kind == "legs-seen":
            ranges = np.asarray(m.attachments["ranges"])
            start = math.radians(float(m.xml.get("min_angle")))
            step = math.radians(float(m.xml.get("resolution")))
            angles = start + step * np.arange(ranges.shape[0])
            pairs = detect_leg_pairs(ranges, angles, max_range=float(m.xml.get("max_range")))
            return [p.bearing for p in pairs if not p.single]
        tag = "face" if self.e.kind == "face-seen" else "source"
        return [math.radians(float(x.get("bearing"))) for x in m.xml.iterfind(tag)]

    def on_message(self, m: Message) -> None:
        if not (self.t0 <= m.created <= self.t1):
            return
        for b in self.bearings(m):
            self.n += 1
            err = abs(float(wrap_angle(b - self.want)))
            if err < self.best:
                self.best, self.best_bearing = err, b

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if not self.n:
            return self.never, f"no {self.noun} at all between {self.t0:g} and {self.t1:g} s"
        near = self.best <= self.tol
        closest = f"closest of {self.n} {self.noun} at {math.degrees(self.best_bearing):.1f} deg"
        wanted = f"{math.degrees(self.want):.1f} +- {math.degrees(self.tol):.1f}"
        if self.never:
            return not near, f"{closest} ({'inside' if near else 'outside'} {wanted}, where none should be)"
        return near, f"{closest} (wanted {wanted})"


# --------------------------------------------------------- what the robot did
def _say_text(m: Message) -> str:
    return m.xml.get("text") or (m.xml.text or "").strip()


class RobotSaysCheck(EventCheck):
    """The robot says something matching ``pattern`` (a case-insensitive regular expression)."""

    channels = (SAY,)

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.pattern = re.compile(str(self.e.get("pattern")), re.IGNORECASE)

    def on_message(self, m: Message) -> None:
        text = _say_text(m)
        if self.pattern.search(text):
            self.hit(m.created, f"the robot said {text!r}")

    def what(self) -> str:
        return f"robot speech matching /{self.pattern.pattern}/"


class StateTracker(EsRecord):
    """The supervisor's current state, from its status and decision log (what the trace shows).

    An instance of the run's :class:`~homesim.tour.metrics.es.EsRecord` (one reading of the log, written
    once), asked one thing; each check keeps its own, fed the same messages."""

    def update(self, m: Message) -> str | None:
        """Return the new state when ``m`` changes it."""
        changed = self.on_message(m)
        return None if changed is None else changed[1]


class StateReachedCheck(EventCheck):
    """The supervisor enters ``state`` (or, with never=, does not)."""

    channels = (ES_LOG, ES_STATUS)

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.state = str(self.e.get("state"))
        self.tracker = StateTracker()

    def on_message(self, m: Message) -> None:
        if self.tracker.update(m) == self.state:
            self.hit(m.created, f"the supervisor entered {self.state}")

    def what(self) -> str:
        return f"entry into state {self.state}"


class EsRecordCheck(EventCheck):
    """A decision of the supervisor's log (``kind``) on an event named ``event`` (in ``state``, if given)."""

    channels = (ES_LOG,)
    kind = ""

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.event = str(self.e.get("event"))
        self.state = self.e.get("state")

    def on_message(self, m: Message) -> None:
        x = m.xml
        if x.get("kind") == self.kind and x.get("name") == self.event and self.state in (None, x.get("state")) and self.wanted(x):
            self.hit(m.created, self.describe(x))

    def wanted(self, x: etree._Element) -> bool:
        return True

    def describe(self, x: etree._Element) -> str:  # pragma: no cover - overridden
        raise NotImplementedError


class EventAppliedCheck(EsRecordCheck):
    """The supervisor applies an event named ``event`` (leaving ``state``, if given)."""

    kind = "applied"

    def describe(self, x: etree._Element) -> str:
        return f"{self.event} from {x.get('source')} applied: {x.get('state')} -> {x.get('to')}"

    def what(self) -> str:
        state = f" in {self.state}" if self.state else ""
        return f"{self.event} applied{state}"


class EventRejectedCheck(EsRecordCheck):
    """The supervisor rejects an event named ``event`` (with ``reason``, in ``state`` if given)."""

    kind = "rejected"

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.reason = self.e.get("reason")

    def wanted(self, x: etree._Element) -> bool:
        return self.reason is None or x.get("reason") == self.reason

    def describe(self, x: etree._Element) -> str:
        return f"{self.event} from {x.get('source')} rejected ({x.get('reason')}) in {x.get('state')}"

    def what(self) -> str:
        reason = f" as {self.reason}" if self.reason else ""
        return f"rejection of {self.event}{reason}"


# ------------------------------------------------------------ what it knows
def matches(doc: etree._Element, wanted: Mapping[str, str]) -> bool:
    """Does a knowledge document say every ``key=value`` of ``wanted``?

    A key is said by an attribute of the document (``type="cup"``) or by a
    descendant element of that name with ``name=`` (``<COLOUR name="red"/>``;
    ``name`` is also said by a ``<TITLE name=>``), case-insensitively.
    """
    for key, value in wanted.items():
        v = value.lower()
        said = {str(val).lower() for k, val in doc.attrib.items() if str(k).lower() == key}
        for el in doc.iter():
            if not isinstance(el.tag, str):
                continue
            tag = etree.QName(el).localname.lower()
            if tag == key or (key == "name" and tag == "title"):
                said.add((el.get("name") or el.get("val") or (el.text or "")).strip().lower())
            elif key == "attribute" and tag == "attribute":
                said.add((el.get("name") or "").lower())
        if v not in said:
            return False
    return True


def _distance_to_outline(poly: Sequence[tuple[float, float]], x: float, y: float) -> float:
    """Shortest distance from (x, y) to a polygon's edges (metres)."""
    best = math.inf
    for (ax, ay), (bx, by) in zip(poly, list(poly[1:]) + [poly[0]]):
        dx, dy = bx - ax, by - ay
        n = dx * dx + dy * dy
        u = 0.0 if n == 0 else min(1.0, max(0.0, ((x - ax) * dx + (y - ay) * dy) / n))
        best = min(best, math.hypot(x - ax - u * dx, y - ay - u * dy))
    return best


class LearnedCheck(Check):
    """``object-learned`` / ``place-learned``: the scene model holds a matching document at the end.

    A ``place-learned`` with a target (``room=``, ``place=`` or ``point=``) also checks,
    against ground truth, *where* the robot stored the place: inside the room (or at most
    ``within`` metres outside its outline: the robot may stand in the doorway) or within
    ``within`` metres of the place or point. A name stored in the wrong room (a user's
    uncorrected slip) does not pass.
    """

    knowledge = True
    ROOM_MARGIN = 0.5  # m outside a room's outline still counted as in it (doorways)
    POINT_WITHIN = 1.0

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.kb = "objects" if self.e.kind == "object-learned" else "places"
        self.where = self.e.get("where")
        within = self.e.get("within")
        self.within = (float(within) if within is not None  # type: ignore[arg-type]
                       else self.ROOM_MARGIN if getattr(self.where, "kind", None) == "room" else self.POINT_WITHIN)
        self.wanted = {k: str(v) for k, v in self.e.attrs if k not in ("never", "where", "within") and v is not None}

    def stored_at(self, doc: etree._Element) -> tuple[float, float] | None:
        try:
            return float(doc.get("x")), float(doc.get("y"))  # type: ignore[arg-type]
        except (TypeError, ValueError):
            return None

    def describe_place(self, xy: tuple[float, float] | None) -> str:
        if xy is None:
            return "without a position"
        room = self.world.room_of(*xy)
        return f"at ({xy[0]:.2f}, {xy[1]:.2f}) " + (f"in the {room}" if room else "outside every room")

    def in_place(self, xy: tuple[float, float] | None) -> bool:
        if xy is None:
            return False
        t = self.where
        if t.kind == "room":  # type: ignore[union-attr]
            if self.world.room_of(*xy) == t.name:  # type: ignore[union-attr]
                return True
            poly = next(p for n, p in self.world._room_polys if n == t.name)  # type: ignore[union-attr]
            return _distance_to_outline(poly, *xy) <= self.within
        gx, gy, _ = self.world.target_point(t)
        return math.hypot(xy[0] - gx, xy[1] - gy) <= self.within

    def target_text(self) -> str:
        t = self.where
        if t.kind == "room":  # type: ignore[union-attr]
            return f"in the {t.name} (or within {self.within:g} m of it)"  # type: ignore[union-attr]
        if t.kind == "point":  # type: ignore[union-attr]
            return f"within {self.within:g} m of ({t.x:g}, {t.y:g})"  # type: ignore[union-attr]
        return f"within {self.within:g} m of the {t.kind} {t.name}"  # type: ignore[union-attr]

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        docs = context.get("knowledge", {}).get(self.kb)
        if docs is None:
            return False, f"no scene model answered a query of the {self.kb} base at the end of the run"
        found = [d for d in docs if matches(d, self.wanted)]
        named = found
        if self.where is not None:
            found = [d for d in named if self.in_place(self.stored_at(d))]
        if self.never:
            where = f" {self.target_text()}" if self.where is not None else ""
            return not found, f"{len(found)} of {len(docs)} {self.kb} match{where}"
        if found:
            return True, f"the scene model holds {etree.tostring(found[0], encoding='unicode')[:160]}"
        if named:
            stored = "; ".join(self.describe_place(self.stored_at(d)) for d in named)
            return False, (f"the robot stored {self.wanted.get('name', self.wanted)!r} {stored}, "
                           f"not {self.target_text()}")
        return False, f"none of the {len(docs)} {self.kb} in the scene model matches {self.wanted}"


class FollowingDistanceCheck(Check):
    """While the supervisor is in Following (after ``settle`` s), the true distance to ``who`` stays in [min, max]."""

    steps = True
    channels = (ES_LOG, ES_STATUS)

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.who = str(self.e.get("who"))
        self.lo = float(self.e.get("min"))  # type: ignore[arg-type]
        self.hi = float(self.e.get("max"))  # type: ignore[arg-type]
        self.fraction = float(self.e.get("fraction"))  # type: ignore[arg-type]
        self.settle = float(self.e.get("settle"))  # type: ignore[arg-type]
        self.tracker = StateTracker()
        self.n = self.inside = 0
        self.closest, self.farthest = math.inf, 0.0

    def on_message(self, m: Message) -> None:
        self.tracker.update(m)

    def on_step(self, world: World) -> None:
        t = world.time
        if self.tracker.state != "Following" or t - self.tracker.since < self.settle or not (self.t0 <= t <= self.t1):
            return
        h = world.humans[self.who]
        if not h.present:
            return
        rx, ry, _ = world.robot.pose
        x, y = h.position
        d = math.hypot(x - rx, y - ry)
        self.n += 1
        self.inside += self.lo <= d <= self.hi
        self.closest, self.farthest = min(self.closest, d), max(self.farthest, d)

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if not self.n:
            return False, f"the robot never followed {self.who} (Following for more than {self.settle:g} s) {self.window()}"
        share = self.inside / self.n
        detail = (f"{100 * share:.0f}% of {self.n} steps in [{self.lo:g}, {self.hi:g}] m "
                  f"(wanted >= {100 * self.fraction:.0f}%; closest {self.closest:.2f} m, farthest {self.farthest:.2f} m)")
        return share >= self.fraction, detail


for _kind, _check in {
    "legs-seen": PerceptCheck,
    "face-seen": PerceptCheck,
    "sound-heard": PerceptCheck,
    "robot-says": RobotSaysCheck,
    "state-reached": StateReachedCheck,
    "event-rejected": EventRejectedCheck,
    "event-applied": EventAppliedCheck,
    "object-learned": LearnedCheck,
    "place-learned": LearnedCheck,
    "following-distance": FollowingDistanceCheck,
}.items():
    register_check(_kind, _check)

#: Kinds that need the scene model's contents at the end (the runner queries it).
KNOWLEDGE_KINDS = frozenset(k for k, c in CHECKS.items() if getattr(c, "knowledge", False))

__all__: Sequence[str] = ("Verdict", "Expectations", "CHECKS", "matches", "window_of")
