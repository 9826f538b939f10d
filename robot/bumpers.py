"""The bumper reflex: what the base may still do while a bumper is pressed, the last check of every command.

Every other rule the modules keep (the dynamic window, the floor-plan sweeps, the people rules, the
sonar's blind half) works on what the robot believes is round it; a bumper is the one sensor that
says the base is touching something now (``/robot/bumpers``, :mod:`robot.hardware.bumpers`). So each
module that sends ``/robot/base/cmd`` with a forward speed (the follower, the player) or a turn
(person attention) holds a :class:`BumperReflex` and passes every command through
:meth:`BumperReflex.command` before its other last checks; the rule, as the Pioneer's own bumper
behaviours have it (stop into what you touch, back away from it):

- a pressed front ring allows no forward speed and no turn on the spot: a segment of the ring may be
  pressed by something at the face or at a corner's flank, and a turn swings a corner into one or the
  other; backing straight away (or backing and turning) is what frees it. The one turn allowed is the
  reverse of a turn on the spot that pressed the segment: it sweeps the footprint back through the poses
  it held untouched (person attention only turns, and a turn into a wall would otherwise trap it: it can
  never turn again and never sends a reverse speed). The rear ring likewise.
- both rings pressed (wedged between a desk and a chair): no speed at all; turning on the spot is
  the only way out, and the modules' own floor-plan checks decide whether a turn is free.
- a new press while the module drove into that ring starts a back-off: for :data:`BACKOFF_TIME` s, while
  the module asks to move at all, the command becomes :data:`BACKOFF_SPEED` straight away from it,
  held to the module's own checks of that motion (the ``may_back`` it passes: the floor plan's sweep,
  nobody tracked behind, the laser's echoes ahead; then its sonar check of the blind half), then the
  module's own command again, held to the rule above while anything stays pressed. The back-off is the
  reflex's only motion of its own, so it never causes a contact of its own: it starts only from a press
  the module drove into (never from one made during a back-off), ends when its own checks refuse it or
  the ring it backs toward is pressed, and the robot stands whenever the module asks it to.

Pure code and one small state (the pressed segments and the back-off's end); no world, no ground
truth: the robot sees only the base's bumper messages.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cached_property

from lxml import etree

#: m/s: the back-off's speed (slow: it drives where the laser does not look, or where it just touched)
BACKOFF_SPEED = 0.1
#: s: how long the back-off lasts after a new press (10 cm at BACKOFF_SPEED)
BACKOFF_TIME = 1.0


class BumperReflex:
    """The pressed segments and the back-off under way (see the module docstring)."""

    __slots__ = ("pressed", "_backoff", "_last_v", "_last_w", "_turned")

    def __init__(self) -> None:
        self.pressed: frozenset[tuple[str, int]] = frozenset()
        self._backoff: tuple[float, float] | None = None  # (until, speed): backing away after a new press
        self._last_v = 0.0  # the module's last forward speed sent (which ring a new press was driven into)
        self._last_w = 0.0  # the module's last turn sent (the turn a segment was pressed in: its reverse frees it)
        self._turned: dict[tuple[str, int], float] = {}  # pressed segment -> the turn it was pressed in (0: none)

    def update(self, xml: etree._Element, now: float) -> None:
        """Take a ``<bumpers>`` message (sent on every change and repeated while anything is pressed): a new
        press of the ring the module drove into starts a back-off; a press during a back-off starts none,
        and one of the ring the back-off drives toward ends it."""
        pressed = frozenset((p.get("ring", ""), int(p.get("id", "0"))) for p in xml.iter("pressed"))
        fresh = pressed - self.pressed
        new = {ring for ring, _ in fresh}
        self.pressed = pressed
        turning = self._last_w if self._last_v == 0.0 else 0.0  # a turn on the spot, not an arc
        self._turned = {seg: self._turned.get(seg, turning if seg in fresh else 0.0) for seg in pressed}
        front, rear = self.rings()
        if self._backoff is not None and now < self._backoff[0]:
            if (rear if self._backoff[1] < 0.0 else front):
                self._backoff = None  # backed into something: stop (never a back-off the other way)
            return
        if front and rear:
            self._backoff = None
        elif "front" in new and self._last_v > 0.0:
            self._backoff = (now + BACKOFF_TIME, -BACKOFF_SPEED)
        elif "rear" in new and self._last_v < 0.0:
            self._backoff = (now + BACKOFF_TIME, BACKOFF_SPEED)

    def rings(self) -> tuple[bool, bool]:
        """(front pressed, rear pressed)."""
        rings = {ring for ring, _ in self.pressed}
        return "front" in rings, "rear" in rings

    def backing_off(self, now: float) -> bool:
        """Whether a back-off is under way."""
        return self._backoff is not None and now < self._backoff[0]

    def _frees(self, w: float) -> bool:
        """Whether turning on the spot at ``w`` undoes the turn every pressed segment was pressed in
        (the footprint sweeps back through poses it held untouched); a segment pressed while not
        turning (driven or walked into) allows no turn."""
        return all(t * w < 0.0 for t in self._turned.values())

    def command(self, v: float, w: float, now: float,
                may_back: Callable[[float], bool] | None = None) -> tuple[float, float]:
        """The command the base may have instead of (``v``, ``w``): the back-off while it lasts and the
        module moves at all (held to ``may_back``, the module's own checks of backing straight at a speed:
        refused, the back-off ends), else the command held to the pressed rings (unchanged when nothing is
        pressed). Asked to stand, it stands."""
        if not (math.isfinite(v) and math.isfinite(w)):
            v, w = (v if math.isfinite(v) else 0.0), (w if math.isfinite(w) else 0.0)
        if v == 0.0 and w == 0.0:
            self._last_v = self._last_w = 0.0
            return 0.0, 0.0
        if self._backoff is not None:
            until, speed = self._backoff
            front, rear = self.rings()
            if now < until and not (rear if speed < 0.0 else front) and (may_back is None or may_back(speed)):
                self._last_v = self._last_w = 0.0  # the module drove nothing into what a press meets now
                return speed, 0.0
            self._backoff = None
        front, rear = self.rings()
        if front and rear:
            v = 0.0
        elif front:
            v = min(v, 0.0)
            if v == 0.0 and not self._frees(w):
                w = 0.0
        elif rear:
            v = max(v, 0.0)
            if v == 0.0 and not self._frees(w):
                w = 0.0
        self._last_v, self._last_w = v, w
        return v, w


def own_reflex() -> cached_property[BumperReflex]:
    """A class attribute that gives each module instance its own :class:`BumperReflex` the first time it is
    read (nothing pressed, never told otherwise: a module built without ``__init__``, as the rules' unit
    tests build them); one instance shared by the class would carry one test's back-off into the next."""
    return cached_property(_new_reflex)


def _new_reflex(_module: object) -> BumperReflex:
    return BumperReflex()
