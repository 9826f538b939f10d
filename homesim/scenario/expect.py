"""Expectations: what a scenario says must happen, checked *as the run goes*.

Each expectation of a scenario becomes one streaming check that sees the
messages sent on the channels it names (through one
:class:`~homesim.observe.Dispatcher`) and, if it needs ground truth, the
world after each physics step; it keeps a few numbers, never the messages,
so a run's memory does not grow with its length. At the end
:meth:`Expectations.verdicts` turns each check into a :class:`Verdict` that
names the expectation's file and line and says why it failed.

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
* the run's metrics (``homesim.metrics``): ``metric``.

``absent``/``never="true"`` turns a check around: nothing of the kind may
happen in the window.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from lxml import etree

from ..message import Message
from ..observe import Dispatcher
from ..world.geometry import wrap_angle
from ..world.legs import detect_leg_pairs
from ..world.world import World
from .model import Expectation, Scenario, Target, window_of

SCAN = "/robot/laser/scan"
FACES = "/robot/camera/faces"
SOURCES = "/robot/audio/sources"
SAY = "/robot/speaker/say"
ES_LOG = "/robot/es/log"
ES_STATUS = "/robot/es/status"


@dataclass(frozen=True)
class Verdict:
    expectation: Expectation
    passed: bool
    detail: str
    source: str = ""

    @property
    def name(self) -> str:
        return self.expectation.describe()

    @property
    def where(self) -> str:
        """``file:line`` of the expectation (what a user opens to fix it)."""
        line = self.expectation.line
        if self.source and line:
            return f"{self.source}:{line}"
        return self.source or (f"line {line}" if line else "")

    def line(self) -> str:
        mark = "PASS" if self.passed else "FAIL"
        where = f"{self.where}: " if self.where else ""
        return f"{mark} {where}{self.expectation.describe()}: {self.detail}"

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "where": self.where, "passed": self.passed, "detail": self.detail}


class Check:
    """One streaming expectation. Subclasses set ``channels`` and/or ``steps``."""

    channels: tuple[str, ...] = ()
    steps = False  # call on_step after every world step

    def __init__(self, e: Expectation, scenario: Scenario, world: World) -> None:
        self.e = e
        self.world = world
        self.t0, self.t1 = window_of(e, scenario.duration)
        self.never = bool(e.get("never", False) or e.get("absent", False))

    def on_message(self, msg: Message) -> None:  # pragma: no cover - overridden
        pass

    def on_step(self, world: World) -> None:  # pragma: no cover - overridden
        pass

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        raise NotImplementedError

    def window(self) -> str:
        return f"between {self.t0:g} and {self.t1:g} s"


class EventCheck(Check):
    """Something happens (the first time, with its detail) or, with never=, must not."""

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.first: tuple[float, str] | None = None
        self.count = 0

    def hit(self, t: float, what: str) -> None:
        if self.t0 - 1e-9 <= t <= self.t1 + 1e-9:
            self.count += 1
            if self.first is None:
                self.first = (t, what)

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if self.first is None:
            return self.never, f"no {self.what()} {self.window()}"
        t, what = self.first
        more = f" ({self.count - 1} more)" if self.count > 1 else ""
        if self.never:
            return False, f"{what} at t={t:.2f} s{more}, where none should be"
        return True, f"{what} at t={t:.2f} s"

    def what(self) -> str:
        return "match"


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


# ------------------------------------------------------------- ground truth
def _where(world: World, t: Target) -> tuple[float, float] | None:
    """Where a target is now (None: a person who is not in the flat)."""
    if t.kind == "human":
        h = world.humans[t.name or ""]
        return tuple(h.position) if h.present else None  # type: ignore[return-value]
    x, y, _ = world.target_point(t)
    return x, y


class ReachedCheck(Check):
    """A person came within ``within`` of a target (a moving target where it was at that step)."""

    steps = True

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.who = str(self.e.get("who"))
        self.target: Target = self.e.get("target")  # type: ignore[assignment]
        self.within = float(self.e.get("within"))  # type: ignore[arg-type]
        by = self.e.get("by")
        self.deadline = math.inf if by is None else float(by)  # type: ignore[arg-type]
        self.best = math.inf
        self.done: str | None = None

    def on_step(self, world: World) -> None:
        if self.done is not None or world.time > self.deadline + 1e-9:
            return
        h = world.humans[self.who]
        if not h.present:
            return
        x, y = h.position
        if self.target.kind == "room":
            if world.room_of(x, y) == self.target.name:
                self.done = f"{self.who} was in {self.target.name} at t={world.time:.2f} s"
            return
        goal = _where(world, self.target)
        if goal is None:
            return
        d = math.hypot(x - goal[0], y - goal[1])
        self.best = min(self.best, d)
        if d <= self.within:
            self.done = f"{self.who} came within {d:.2f} m at t={world.time:.2f} s"

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if self.done is not None:
            return True, self.done
        by = f" by {self.deadline:g} s" if math.isfinite(self.deadline) else ""
        if self.target.kind == "room":
            return False, f"{self.who} never entered {self.target.name}{by}"
        return False, f"{self.who} came no closer than {self.best:.2f} m{by}"


class RobotNearCheck(Check):
    """The robot came within ``within`` of a target inside the window."""

    steps = True

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.target: Target = self.e.get("target")  # type: ignore[assignment]
        self.within = float(self.e.get("within"))  # type: ignore[arg-type]
        self.best = math.inf
        self.done: str | None = None

    def on_step(self, world: World) -> None:
        t = world.time
        if self.done is not None or not (self.t0 <= t <= self.t1):
            return
        rx, ry, _ = world.robot.pose
        if self.target.kind == "room":
            if world.room_of(rx, ry) == self.target.name:
                self.done = f"the robot was in {self.target.name} at t={t:.2f} s"
            return
        goal = _where(world, self.target)
        if goal is None:
            return
        d = math.hypot(rx - goal[0], ry - goal[1])
        self.best = min(self.best, d)
        if d <= self.within:
            self.done = f"the robot came within {d:.2f} m at t={t:.2f} s"

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if self.done is not None:
            return (False, f"{self.done}, where it should not") if self.never else (True, self.done)
        if self.target.kind == "room":
            return self.never, f"the robot never entered {self.target.name} {self.window()}"
        closest = f"{self.best:.2f} m" if math.isfinite(self.best) else "(never measured)"
        return self.never, f"the robot came no closer than {closest} {self.window()}"


class NoCollisionCheck(Check):
    """The robot touches nothing (or nothing of one kind, ``with``) in the window: counted as
    contacts begin (:meth:`World.add_contact_listener`), the first one kept for the detail."""

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.what = self.e.get("with")
        self.first: tuple[float, str] | None = None
        self.hits = 0
        self.world.add_contact_listener(self.on_contact)

    def on_contact(self, t: float, what: str) -> None:
        if self.t0 - 1e-9 <= t <= self.t1 + 1e-9 and (self.what is None or what == self.what):
            self.hits += 1
            if self.first is None:
                self.first = (t, what)

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        what = self.what
        if self.first is None:
            return True, f"the robot touched {'nothing' if what is None else f'no {what}'} {self.window()}"
        more = f" (and {self.hits - 1} more contacts)" if self.hits > 1 else ""
        return False, f"the robot touched {self.first[1]} at t={self.first[0]:.2f} s{more}"


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


class StateTracker:
    """The supervisor's current state, from its status and decision log (what the trace shows)."""

    def __init__(self) -> None:
        self.state: str | None = None
        self.since = 0.0

    def update(self, m: Message) -> str | None:
        """Return the new state when ``m`` changes it."""
        if m.channel == ES_LOG:
            if m.xml.get("kind") != "applied":
                return None
            new = m.xml.get("to")
        else:
            new = m.xml.get("state")
        if new is None or new == self.state:
            return None
        self.state, self.since = new, m.created
        return new


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


class LearnedCheck(Check):
    """``object-learned`` / ``place-learned``: the scene model holds a matching document at the end."""

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.kb = "objects" if self.e.kind == "object-learned" else "places"
        self.wanted = {k: str(v) for k, v in self.e.attrs if k not in ("never",) and v is not None}

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        docs = context.get("knowledge", {}).get(self.kb)
        if docs is None:
            return False, f"no scene model answered a query of the {self.kb} base at the end of the run"
        found = [d for d in docs if matches(d, self.wanted)]
        if self.never:
            return not found, f"{len(found)} of {len(docs)} {self.kb} match"
        if found:
            return True, f"the scene model holds {etree.tostring(found[0], encoding='unicode')[:160]}"
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


class MetricCheck(Check):
    """A metric of the run's summary (``following.mean_distance``) lies within [min, max]."""

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        name = str(self.e.get("name"))
        value: Any = context.get("metrics", {})
        for part in name.split("."):
            if not isinstance(value, Mapping) or part not in value:
                return False, f"the run has no metric {name!r}"
            value = value[part]
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            return False, f"metric {name} is {value!r}, not a number"
        lo, hi = self.e.get("min"), self.e.get("max")
        ok = (lo is None or value >= float(lo)) and (hi is None or value <= float(hi))  # type: ignore[arg-type]
        bounds = f"[{'-inf' if lo is None else lo}, {'inf' if hi is None else hi}]"
        return ok, f"{name} = {value:.4g} ({'within' if ok else 'outside'} {bounds})"


CHECKS: dict[str, Callable[..., Check]] = {
    "legs-seen": PerceptCheck,
    "face-seen": PerceptCheck,
    "sound-heard": PerceptCheck,
    "reached": ReachedCheck,
    "robot-near": RobotNearCheck,
    "no-collision": NoCollisionCheck,
    "robot-says": RobotSaysCheck,
    "state-reached": StateReachedCheck,
    "event-rejected": EventRejectedCheck,
    "event-applied": EventAppliedCheck,
    "object-learned": LearnedCheck,
    "place-learned": LearnedCheck,
    "following-distance": FollowingDistanceCheck,
    "metric": MetricCheck,
}

#: Kinds that need the scene model's contents at the end (the runner queries it).
KNOWLEDGE_KINDS = frozenset({"object-learned", "place-learned"})


class Expectations:
    """The streaming checks of one scenario on one run (see the module docstring)."""

    def __init__(self, scenario: Scenario, world: World, dispatcher: Dispatcher) -> None:
        self.scenario = scenario
        self.checks: list[Check] = [CHECKS[e.kind](e, scenario, world) for e in scenario.expectations]
        for c in self.checks:
            if c.channels:
                dispatcher.add(c.channels, c.on_message)
        stepped = [c.on_step for c in self.checks if c.steps]
        if stepped:
            def step(w: World) -> None:
                for fn in stepped:
                    fn(w)

            world.add_listener(step)

    @property
    def needs_knowledge(self) -> bool:
        return any(c.e.kind in KNOWLEDGE_KINDS for c in self.checks)

    def verdicts(self, end: float, context: Mapping[str, Any] | None = None) -> list[Verdict]:
        """One verdict per expectation, in file order. ``context``: ``metrics``, ``knowledge``."""
        ctx = context or {}
        out = []
        for c in self.checks:
            ok, detail = c.verdict(end, ctx)
            out.append(Verdict(c.e, ok, detail, self.scenario.source))
        return out


__all__: Sequence[str] = ("Verdict", "Expectations", "CHECKS", "matches", "window_of")
