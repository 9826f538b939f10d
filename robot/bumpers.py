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
  other; backing straight away (or backing and turning) is what frees it. The rear ring likewise.
- both rings pressed (wedged between a desk and a chair): no speed at all; turning on the spot is
  the only way out, and the modules' own floor-plan checks decide whether a turn is free.
- a new press while the module drove into that ring starts a back-off: for :data:`BACKOFF_TIME` s the
  command becomes :data:`BACKOFF_SPEED` straight away from it (when the other ring is free; still
  through the module's sonar check of the blind half, so it never backs into someone), then the
  module's own command again, held to the rule above while anything stays pressed.

Pure code and one small state (the pressed segments and the back-off's end); no world, no ground
truth: the robot sees only the base's bumper messages.
"""

from __future__ import annotations

import math

from lxml import etree

#: m/s: the back-off's speed (slow: it drives where the laser does not look, or where it just touched)
BACKOFF_SPEED = 0.1
#: s: how long the back-off lasts after a new press (10 cm at BACKOFF_SPEED)
BACKOFF_TIME = 1.0


class BumperReflex:
    """The pressed segments and the back-off under way (see the module docstring)."""

    __slots__ = ("pressed", "_backoff", "_last_v")

    def __init__(self) -> None:
        self.pressed: frozenset[tuple[str, int]] = frozenset()
        self._backoff: tuple[float, float] | None = None  # (until, speed): backing away after a new press
        self._last_v = 0.0  # the last forward speed commanded (which ring a new press was driven into)

    def update(self, xml: etree._Element, now: float) -> None:
        """Take a ``<bumpers>`` message; a new press of the ring the robot drove into starts a back-off."""
        pressed = frozenset((p.get("ring", ""), int(p.get("id", "0"))) for p in xml.iter("pressed"))
        new = {ring for ring, _ in pressed - self.pressed}
        self.pressed = pressed
        front, rear = self.rings()
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

    def command(self, v: float, w: float, now: float) -> tuple[float, float]:
        """The command the base may have instead of (``v``, ``w``): the back-off while it lasts, else the
        command held to the pressed rings (unchanged when nothing is pressed)."""
        if self._backoff is not None:
            until, speed = self._backoff
            if now < until:
                self._last_v = speed
                return speed, 0.0
            self._backoff = None
        front, rear = self.rings()
        if front and rear:
            v = 0.0
        elif front:
            v = min(v, 0.0)
            if v == 0.0:
                w = 0.0
        elif rear:
            v = max(v, 0.0)
            if v == 0.0:
                w = 0.0
        if not math.isfinite(v):
            v = 0.0
        self._last_v = v
        return v, w
