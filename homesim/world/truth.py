"""Ground truth: who was where, who spoke, who faced whom, what was pointed at.

:class:`GroundTruth` is a world listener (it observes, never changes): after
every ``every``-th physics step it appends one :class:`Frame`. It exists for
evaluation (expectations, plots, tests). Robot modules never see it: it
travels on no bus channel and hardware models do not read it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry import wrap_angle
from .world import World

FACING = math.radians(30)  # "faces the robot": gaze within this of the robot's direction


@dataclass(frozen=True)
class PersonState:
    name: str
    x: float
    y: float
    heading: float
    gaze: float
    speaking: str | None
    facing_robot: bool
    pointing_at: str | None
    room: str | None
    present: bool


@dataclass(frozen=True)
class Frame:
    t: float
    robot: tuple[float, float, float]
    people: tuple[PersonState, ...]
    sounds: tuple[tuple[str, str], ...]  # (source, text) active at t


class GroundTruth:
    """Records a :class:`Frame` every ``every`` world steps."""

    def __init__(self, world: World, *, every: int = 5) -> None:
        self.world = world
        self.every = max(1, every)
        self.frames: list[Frame] = []
        world.add_listener(self._on_step)
        self.capture()

    def _on_step(self, world: World) -> None:
        if world.steps % self.every == 0:
            self.capture()

    def capture(self) -> Frame:
        """Record the world as it is now (also callable by hand)."""
        w = self.world
        t = w.time
        rx, ry, rth = w.robot.pose
        people = []
        for name, h in w.humans.items():
            x, y = h.position
            u = w.sound.speaking(name, t)
            to_robot = math.atan2(ry - y, rx - x)
            facing = h.present and abs(float(wrap_angle(h.gaze - to_robot))) <= FACING
            people.append(PersonState(name, x, y, h.heading, h.gaze, u.text if u else None, bool(facing), h.pointing.target_name if h.pointing else None, w.room_of(x, y),
                h.present))
        sounds = tuple((u.source, u.text) for u in w.sound.active(t))
        frame = Frame(t, (rx, ry, rth), tuple(people), sounds)
        self.frames.append(frame)
        return frame

    def track(self, name: str) -> np.ndarray:
        """(T, 3) array of (t, x, y) for a person ("robot" for the robot), present frames only."""
        rows = []
        for f in self.frames:
            if name == "robot":
                rows.append((f.t, f.robot[0], f.robot[1]))
                continue
            for p in f.people:
                if p.name == name and p.present:
                    rows.append((f.t, p.x, p.y))
        return np.array(rows, dtype=float).reshape(-1, 3)

    def at(self, t: float) -> Frame:
        """The last frame recorded at or before ``t``."""
        best = self.frames[0]
        for f in self.frames:
            if f.t <= t + 1e-9:
                best = f
            else:
                break
        return best
