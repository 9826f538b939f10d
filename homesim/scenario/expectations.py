"""Expectations: what a scenario says must happen, checked *as the run goes*.

Each expectation of a scenario becomes one streaming check that sees the
messages sent on the channels it names (through one
:class:`~homesim.observe.Dispatcher`) and, if it needs ground truth, the
world after each physics step; it keeps a few numbers, never the messages,
so a run's memory does not grow with its length. At the end
:meth:`Expectations.verdicts` turns each check into a :class:`Verdict` that
names the expectation's file and line and says why it failed.

This module holds the mechanism and the kinds that need nothing but the
world and the run's numbers: ``reached``, ``robot-near`` and ``robot-inside`` (ground truth,
step by step), ``no-collision`` (the world's contact log) and ``metric``
(the run's metrics). Kinds that read a robot's messages or knowledge are
added by the run package with :func:`register_check` (``homesim.tour.expect``).
The world is handed in (duck-typed: ``time``, ``humans``, ``robot``,
``room_of``, ``target_point``, ``add_listener``, ``add_contact_listener``);
this module does not import it, so the scenario package stays below the world.

``absent``/``never="true"`` turns a check around: nothing of the kind may
happen in the window.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import ScenarioError
from ..message import Message
from ..observe import Dispatcher
from ..suggest import closest
from .model import Expectation, Scenario, Target, window_of


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
    knowledge = False  # its verdict needs the robot's knowledge at the end (the runner queries it)

    def __init__(self, e: Expectation, scenario: Scenario, world: Any) -> None:
        self.e = e
        self.world = world
        self.t0, self.t1 = window_of(e, scenario.duration)
        self.never = bool(e.get("never", False) or e.get("absent", False))

    def on_message(self, msg: Message) -> None:  # pragma: no cover - overridden
        pass

    def on_step(self, world: Any) -> None:  # pragma: no cover - overridden
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


# ------------------------------------------------------------- ground truth
def _where(world: Any, t: Target) -> tuple[float, float] | None:
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

    def on_step(self, world: Any) -> None:
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

    def on_step(self, world: Any) -> None:
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


class RobotInsideCheck(Check):
    """The robot's centre stays in a room of the flat (ground truth, step by step) inside the window:
    a robot that drives out through an exit door after someone who left fails it."""

    steps = True

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.out: tuple[float, float, float] | None = None  # first time and place outside
        self.longest = 0.0  # s: the longest stretch outside
        self._since: float | None = None

    def on_step(self, world: Any) -> None:
        t = world.time
        if not (self.t0 <= t <= self.t1):
            return
        rx, ry, _ = world.robot.pose
        if world.room_of(rx, ry) is not None:
            self._since = None
            return
        if self.out is None:
            self.out = (t, rx, ry)
        if self._since is None:
            self._since = t
        self.longest = max(self.longest, t - self._since)

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        if self.out is None:
            return True, f"the robot stayed inside the flat {self.window()}"
        t, x, y = self.out
        return False, (f"the robot left the flat at t={t:.2f} s ({x:.2f}, {y:.2f}); "
                       f"longest time outside {self.longest:.1f} s")


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


class MetricCheck(Check):
    """A metric of the run's summary (``following.mean_distance``) lies within [min, max]."""

    def verdict(self, end: float, context: Mapping[str, Any]) -> tuple[bool, str]:
        name = str(self.e.get("name"))
        value: Any = context.get("metrics", {})
        parts = name.split(".")
        for k, part in enumerate(parts):
            if not isinstance(value, Mapping) or part not in value:
                near = closest(part, [str(key) for key in value]) if isinstance(value, Mapping) else None
                hint = f" (did you mean {'.'.join([*parts[:k], near])!r}?)" if near is not None else ""
                return False, f"the run has no metric {name!r}{hint}"
            value = value[part]
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            return False, f"metric {name} is {value!r}, not a number"
        lo, hi = self.e.get("min"), self.e.get("max")
        ok = (lo is None or value >= float(lo)) and (hi is None or value <= float(hi))  # type: ignore[arg-type]
        bounds = f"[{'-inf' if lo is None else lo}, {'inf' if hi is None else hi}]"
        return ok, f"{name} = {value:.4g} ({'within' if ok else 'outside'} {bounds})"


#: Expectation kind -> its check (``check(expectation, scenario, world)``); see :func:`register_check`.
CHECKS: dict[str, Callable[..., Check]] = {
    "reached": ReachedCheck,
    "robot-near": RobotNearCheck,
    "no-collision": NoCollisionCheck,
    "robot-inside": RobotInsideCheck,
    "metric": MetricCheck,
}


def register_check(kind: str, check: Callable[..., Check]) -> None:
    """Add (or replace) the streaming check of an expectation kind (the run package adds the robot's)."""
    CHECKS[kind] = check


class Expectations:
    """The streaming checks of one scenario on one run (see the module docstring)."""

    def __init__(self, scenario: Scenario, world: Any, dispatcher: Dispatcher) -> None:
        self.scenario = scenario
        missing = [e for e in scenario.expectations if e.kind not in CHECKS]
        if missing:
            e = missing[0]
            raise ScenarioError(f"<{e.kind}>: no check is registered for this kind of expectation "
                                f"(known: {', '.join(sorted(CHECKS))})", source=scenario.source, line=e.line, element=e.kind)
        self.checks: list[Check] = [CHECKS[e.kind](e, scenario, world) for e in scenario.expectations]
        for c in self.checks:
            if c.channels:
                dispatcher.add(c.channels, c.on_message)
        stepped = [c.on_step for c in self.checks if c.steps]
        if stepped:
            def step(w: Any) -> None:
                for fn in stepped:
                    fn(w)

            world.add_listener(step)

    @property
    def needs_knowledge(self) -> bool:
        return any(c.knowledge for c in self.checks)

    def verdicts(self, end: float, context: Mapping[str, Any] | None = None) -> list[Verdict]:
        """One verdict per expectation, in file order. ``context``: ``metrics``, ``knowledge``."""
        ctx = context or {}
        out = []
        for c in self.checks:
            ok, detail = c.verdict(end, ctx)
            out.append(Verdict(c.e, ok, detail, self.scenario.source))
        return out


__all__: Sequence[str] = ("Verdict", "Check", "EventCheck", "Expectations", "CHECKS", "register_check", "window_of")
