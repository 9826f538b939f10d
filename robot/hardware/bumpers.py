"""The PeopleBot's bumper rings: contact switches at the front and back of the base.

ActivMedia's PeopleBot (ARIA's ``p2pb`` robot class: ``FrontBumpers`` and ``RearBumpers`` true, five
segments each) carries a bumper ring round the front of its base and another round the back, low
(about :data:`BUMPER_HEIGHT` m above the floor). Each ring is split into five segments that close a
switch when something presses them; the microcontroller reads the switches and reports them in its
server information packets with the odometry, so the :class:`~robot.hardware.base.Base` reports them
here too (``/robot/bumpers``).

Geometry: a ring runs round its end of the footprint's shell (the 0.51 x 0.43 m rectangle and the
body's 0.01 m rounding), from :data:`WRAP` m along one flank, across the end face, to :data:`WRAP` m
along the other flank; its five segments are equal lengths of that path, numbered right to left at
the front and left to right at the back (the sonar's numbering). A segment is pressed when a point of
it lies within :data:`TRAVEL` m (the switch's travel) of what the base can meet at the ring's height:
a wall, a piece of furniture that reaches down to it, a table's leg, or a person's body (the world's
0.25 m collision disc: her shins and feet). A table top the robot's upper body runs under and into is
no bumper contact, as on the real robot; the world's contact solver still stops it there.

A switch has no noise and no dropouts; it is computed from the world's geometry every packet, and
published when a segment's state changes and again with every packet while any segment stays closed
(as the PeopleBot's SIP carries the bumper bits in every packet): a module restarted by the watchdog,
subscribed late or whose message was dropped knows a pressed ring within one packet. A run that
never touches anything carries no bumper message at all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.geometry import distance_points_segments

if TYPE_CHECKING:
    from homesim.world.world import World

__all__ = ["BumperSpec", "BumperSensor", "bumper_element", "BUMPER_HEIGHT", "TRAVEL", "WRAP"]

#: m above the floor: the rings' height (what they meet: walls, low furniture, table legs, shins)
BUMPER_HEIGHT = 0.10
#: m: a switch closes when the shell is this close to something (the bumper's travel; the world holds a
#: walking person 0.02 m off the footprint, so someone who walks up to the robot presses nothing)
TRAVEL = 0.005
#: m: how far a ring wraps round the corners along each flank
WRAP = 0.10
#: m: the spacing of the points each segment is tested at
STEP = 0.01
#: m: the cells of the centre positions known to be clear of every edge (a cache; the flat does not move)
CELL = 0.05
#: m: the world's person collision disc (homesim.world.bodies.HUMAN_RADIUS; the hardware layer may know the world)
_PERSON = 0.25


@dataclass(frozen=True)
class BumperSpec:
    """The rings' geometry (defaults: the PeopleBot's base)."""

    half_length: float = 0.51 / 2
    half_width: float = 0.43 / 2
    shell: float = 0.01  # the body's rounding beyond the rectangle
    segments: int = 5  # per ring
    wrap: float = WRAP
    travel: float = TRAVEL
    height: float = BUMPER_HEIGHT
    #: (ring, segment, x, y) of every tested point, robot frame; made in __post_init__
    points: np.ndarray = field(init=False, repr=False, compare=False, default=None)  # type: ignore[assignment]
    which: tuple[tuple[str, int], ...] = field(init=False, repr=False, compare=False, default=())

    def __post_init__(self) -> None:
        if self.segments < 1 or self.wrap < 0 or self.travel <= 0:
            raise ValueError("a bumper ring needs a segment, a wrap of 0 m or more and a positive travel")
        pts, which = [], []
        for ring, sx in (("front", 1.0), ("rear", -1.0)):
            path = _ring_path(self.half_length + self.shell, self.half_width + self.shell, self.wrap, sx)
            for k, seg in enumerate(_split(path, self.segments)):
                which.append((ring, k))
                pts.extend((len(which) - 1, x, y) for x, y in seg)
        object.__setattr__(self, "points", np.array(pts, dtype=float))
        object.__setattr__(self, "which", tuple(which))


def _ring_path(hl: float, hw: float, wrap: float, sx: float) -> list[tuple[float, float]]:
    """The ring's corners in order (front: right flank to left flank; rear: left flank to right flank)."""
    side = -sx  # the front runs from the right (y < 0), the rear from the left
    return [(sx * (hl - wrap), side * hw), (sx * hl, side * hw), (sx * hl, -side * hw), (sx * (hl - wrap), -side * hw)]


def _split(path: list[tuple[float, float]], n: int) -> list[list[tuple[float, float]]]:
    """Points every :data:`STEP` m along ``path``, cut into ``n`` equal lengths."""
    p = np.array(path, dtype=float)
    legs = np.hypot(*np.diff(p, axis=0).T)
    total = float(legs.sum())
    cum = np.concatenate(([0.0], np.cumsum(legs)))
    out = []
    for k in range(n):
        a, b = total * k / n, total * (k + 1) / n
        ts = np.linspace(a, b, max(2, int(math.ceil((b - a) / STEP)) + 1))
        out.append([(float(np.interp(t, cum, p[:, 0])), float(np.interp(t, cum, p[:, 1]))) for t in ts])
    return out


class BumperSensor:
    """Which segments are pressed, from the world's geometry (see the module docstring)."""

    def __init__(self, world: World, spec: BumperSpec | None = None) -> None:
        self.world = world
        self.spec = spec or BumperSpec()
        a, b = world.segments_at(self.spec.height)
        self._a, self._b = a, b
        self._lo, self._hi = np.minimum(a, b), np.maximum(a, b)  # each edge's box (the flat does not move)
        self._reach = math.hypot(self.spec.half_length, self.spec.half_width) + self.spec.shell + self.spec.travel
        self._clear: dict[tuple[int, int], bool] = {}  # CELL cells of the robot's centre no edge comes within reach of
        self.pressed: tuple[tuple[str, int], ...] = ()

    def _clear_of_edges(self, x: float, y: float) -> bool:
        """Whether no edge can be within reach of a centre in (x, y)'s cell (asked once per cell: the flat
        does not move, and most of a run the robot is nowhere near a wall)."""
        key = (math.floor(x / CELL), math.floor(y / CELL))
        got = self._clear.get(key)
        if got is None:
            cx, cy = (key[0] + 0.5) * CELL, (key[1] + 0.5) * CELL
            r = self._reach + CELL  # any centre in the cell is within CELL * 0.71 of its middle
            near = (self._lo[:, 0] <= cx + r) & (self._hi[:, 0] >= cx - r) & (self._lo[:, 1] <= cy + r) & (self._hi[:, 1] >= cy - r)
            got = not near.any() or bool(distance_points_segments(np.array([[cx, cy]]), self._a[near], self._b[near]).min() > r)
            self._clear[key] = got
        return got

    def read(self) -> tuple[tuple[str, int], ...]:
        """The pressed segments now, in the spec's order (front 0-4, then rear 0-4)."""
        spec = self.spec
        x, y, th = self.world.robot.pose
        reach = self._reach
        people = [h.position for h in self.world.humans.values() if h.present]
        people = [(hx, hy) for hx, hy in people if math.hypot(hx - x, hy - y) <= reach + _PERSON]
        if not people and (not len(self._a) or self._clear_of_edges(x, y)):
            self.pressed = ()
            return self.pressed
        c, s = math.cos(th), math.sin(th)
        hits = np.zeros(len(spec.which), dtype=bool)
        lx, ly = spec.points[:, 1], spec.points[:, 2]
        wx, wy = x + c * lx - s * ly, y + s * lx + c * ly
        seg = spec.points[:, 0].astype(int)
        a, b = self._a, self._b
        if len(a) and not self._clear_of_edges(x, y):
            # the edges near the robot only: those whose box meets the box round the footprint's bounding circle
            lo, hi = self._lo, self._hi
            near = (lo[:, 0] <= x + reach) & (hi[:, 0] >= x - reach) & (lo[:, 1] <= y + reach) & (hi[:, 1] >= y - reach)
            if near.any():
                d = distance_points_segments(np.column_stack((wx, wy)), a[near], b[near]).min(axis=1)
                np.logical_or.at(hits, seg[d <= spec.travel], True)
        for hx, hy in people:
            d = np.hypot(wx - hx, wy - hy) - _PERSON
            np.logical_or.at(hits, seg[d <= spec.travel], True)
        self.pressed = tuple(w for w, hit in zip(spec.which, hits.tolist()) if hit)
        return self.pressed


def bumper_element(time: float, pressed: tuple[tuple[str, int], ...]) -> etree._Element:
    """``<bumpers time><pressed ring id/>...</bumpers>``: the segments pressed now (none: all released)."""
    el = etree.Element("bumpers", time=f"{time:.3f}")
    for ring, k in pressed:
        etree.SubElement(el, "pressed", ring=ring, id=str(k))
    return el
