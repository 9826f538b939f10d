"""Expectations: what a scenario says must have happened, checked after a run.

Two kinds of evidence, never mixed up: ground truth (where people were,
from :class:`~homesim.world.truth.GroundTruth`, frame by frame: a moving
target is where it was in the same frame) for ``reached`` and
``robot-near``, and the world's contact log for ``no-collision``; the
robot's own sensor messages as they went over the bus for ``legs-seen`` (a
leg pair found in a laser scan by the reference detector), ``face-seen``
(a face detection) and ``sound-heard`` (a sound direction); with ``absent="true"`` a percept must *not* be there (no face
while the person looks away). So "the laser saw legs at -18 deg" is checked
on what the laser published, not on where the person was.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..message import Message
from ..world.geometry import wrap_angle
from ..world.legs import detect_leg_pairs
from ..world.truth import GroundTruth
from ..world.world import World
from .model import Expectation, Scenario, Target

SCAN = "/robot/laser/scan"
FACES = "/robot/camera/faces"
SOURCES = "/robot/audio/sources"


@dataclass(frozen=True)
class Verdict:
    expectation: Expectation
    passed: bool
    detail: str

    def line(self) -> str:
        mark = "PASS" if self.passed else "FAIL"
        where = f"line {self.expectation.line}: " if self.expectation.line else ""
        return f"{mark} {where}{self.expectation.describe()}: {self.detail}"


def evaluate(scenario: Scenario, world: World, truth: GroundTruth, messages: Iterable[Message]) -> list[Verdict]:
    """Check every expectation of ``scenario``; one verdict each, in file order."""
    msgs = list(messages)
    return [_check(e, scenario, world, truth, msgs) for e in scenario.expectations]


def _window(e: Expectation, scenario: Scenario) -> tuple[float, float]:
    w = e.get("between")
    return (0.0, scenario.duration) if w is None else (float(w[0]), float(w[1]))  # type: ignore[index]


def _in(msgs: list[Message], channel: str, t0: float, t1: float) -> list[Message]:
    return [m for m in msgs if m.channel == channel and t0 <= m.created <= t1]


def _check(e: Expectation, sc: Scenario, world: World, truth: GroundTruth, msgs: list[Message]) -> Verdict:
    if e.kind == "reached":
        return _reached(e, world, truth)
    if e.kind == "robot-near":
        return _robot_near(e, sc, world, truth)
    if e.kind == "no-collision":
        return _no_collision(e, sc, world)
    t0, t1 = _window(e, sc)
    want = float(e.get("bearing"))  # type: ignore[arg-type]
    tol = float(e.get("tolerance"))  # type: ignore[arg-type]
    seen: list[float] = []
    if e.kind == "legs-seen":
        for m in _in(msgs, SCAN, t0, t1):
            ranges = np.asarray(m.attachments["ranges"])
            start = math.radians(float(m.xml.get("min_angle")))
            step = math.radians(float(m.xml.get("resolution")))
            bearings = start + step * np.arange(ranges.shape[0])
            seen += [p.bearing for p in detect_leg_pairs(ranges, bearings, max_range=float(m.xml.get("max_range"))) if not p.single]
        what = "leg pairs"
    elif e.kind == "face-seen":
        seen = [math.radians(float(f.get("bearing"))) for m in _in(msgs, FACES, t0, t1) for f in m.xml.iterfind("face")]
        what = "faces"
    elif e.kind == "sound-heard":
        seen = [math.radians(float(s.get("bearing"))) for m in _in(msgs, SOURCES, t0, t1) for s in m.xml.iterfind("source")]
        what = "sound directions"
    else:
        return Verdict(e, False, f"unknown expectation kind {e.kind!r}")
    absent = bool(e.get("absent", False))
    if not seen:
        return Verdict(e, absent, f"no {what} at all between {t0:g} and {t1:g} s")
    errs = [abs(float(wrap_angle(b - want))) for b in seen]
    best = int(np.argmin(errs))
    near = errs[best] <= tol
    closest = f"closest of {len(seen)} {what} at {math.degrees(seen[best]):.1f} deg"
    wanted = f"{math.degrees(want):.1f} +- {math.degrees(tol):.1f}"
    if absent:
        return Verdict(e, not near, f"{closest} ({'inside' if near else 'outside'} {wanted}, where none should be)")
    return Verdict(e, near, f"{closest} (wanted {wanted})")


def _no_collision(e: Expectation, sc: Scenario, world: World) -> Verdict:
    t0, t1 = _window(e, sc)
    what = e.get("with")
    hits = [(t, w) for t, w in world.contacts if t0 - 1e-9 <= t <= t1 + 1e-9 and (what is None or w == what)]
    if not hits:
        return Verdict(e, True, f"the robot touched {'nothing' if what is None else f'no {what}'} between {t0:g} and {t1:g} s")
    more = f" (and {len(hits) - 1} more contacts)" if len(hits) > 1 else ""
    return Verdict(e, False, f"the robot touched {hits[0][1]} at t={hits[0][0]:.2f} s{more}")


def _target_xy(world: World, t: Target) -> tuple[float, float] | None:
    if t.kind == "room":
        return None  # a room is reached by being in it
    x, y, _ = world.target_point(t)
    return x, y


def _reached(e: Expectation, world: World, truth: GroundTruth) -> Verdict:
    who = str(e.get("who"))
    target: Target = e.get("target")  # type: ignore[assignment]
    within = float(e.get("within"))  # type: ignore[arg-type]
    by = e.get("by")
    deadline = math.inf if by is None else float(by)  # type: ignore[arg-type]
    fixed = _target_xy(world, target) if target.kind not in ("human", "robot") else None
    best = math.inf
    for f in truth.frames:
        if f.t > deadline + 1e-9:
            break
        # A person or the robot is a moving target: where it was in this very frame.
        goal = fixed
        if target.kind == "robot":
            goal = f.robot[:2]
        elif target.kind == "human":
            there = [p for p in f.people if p.name == target.name and p.present]
            if not there:
                continue
            goal = (there[0].x, there[0].y)
        for p in f.people:
            if p.name != who or not p.present:
                continue
            if target.kind == "room":
                if p.room == target.name:
                    return Verdict(e, True, f"{who} was in {target.name} at t={f.t:.2f} s")
                continue
            d = math.hypot(p.x - goal[0], p.y - goal[1])
            best = min(best, d)
            if d <= within:
                return Verdict(e, True, f"{who} came within {d:.2f} m at t={f.t:.2f} s")
    if target.kind == "room":
        return Verdict(e, False, f"{who} never entered {target.name}" + (f" by {deadline:g} s" if by is not None else ""))
    return Verdict(e, False, f"{who} came no closer than {best:.2f} m" + (f" by {deadline:g} s" if by is not None else ""))


def _robot_near(e: Expectation, sc: Scenario, world: World, truth: GroundTruth) -> Verdict:
    target: Target = e.get("target")  # type: ignore[assignment]
    within = float(e.get("within"))  # type: ignore[arg-type]
    t0, t1 = _window(e, sc)
    best = math.inf
    for f in truth.frames:
        if not (t0 <= f.t <= t1):
            continue
        if target.kind == "human":
            ps = [p for p in f.people if p.name == target.name and p.present]
            if not ps:
                continue
            gx, gy = ps[0].x, ps[0].y
        elif target.kind == "room":
            if world.room_of(f.robot[0], f.robot[1]) == target.name:
                return Verdict(e, True, f"the robot was in {target.name} at t={f.t:.2f} s")
            continue
        else:
            gx, gy, _ = world.target_point(target)
        d = math.hypot(f.robot[0] - gx, f.robot[1] - gy)
        best = min(best, d)
        if d <= within:
            return Verdict(e, True, f"the robot came within {d:.2f} m at t={f.t:.2f} s")
    return Verdict(e, False, f"the robot came no closer than {best:.2f} m")
