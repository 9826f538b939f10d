"""The attention state machine (the papers' Fig. 3).

Bottom-up states, driven by the tracks alone (while no order holds the
machine top-down):

- ``Sleeping``: nobody tracked (for ``sleep_after`` seconds);
- ``Alertness``: people tracked, the selected one is not speaking;
- ``Listen``: the selected person speaks (category 2 or 3).

Top-down states, entered and left only by the execution supervisor's orders
on ``/robot/es/orders/person_attention``: ``interact`` -> ``Interaction``,
``follow`` -> ``Follow``, ``pause`` -> ``Follow`` paused (a wait said while she leads: the follower
stands facing her until she walks on, then follows again; docs/subsystems.md), ``focus_object`` -> ``Object``; ``look_around``
returns to bottom-up attention, ``look_for_help`` too (the robot asked for help: a voice near
its axis that nobody seen in front explains comes from behind, and it turns round to it, as
when it searches for a lost partner); ``sleep`` holds ``Sleeping`` (the robot
drives autonomously and looks ahead) until ``look_around`` or ``interact``.
Unknown orders are refused with a clear reason (:class:`OrderRefused`).

Per state what the robot does (:data:`CAMERA`, :data:`TURNS`): the camera
on the selected person's face (bottom-up), on the partner's hands
(Interaction), torso (Follow), on the object (Object), straight ahead
(Sleeping); the base turns to the person in Listen, Interaction and Object.
"""

from __future__ import annotations

from dataclasses import dataclass

BOTTOM_UP = ("Sleeping", "Alertness", "Listen")
TOP_DOWN = ("Interaction", "Follow", "Object")
STATES = BOTTOM_UP + TOP_DOWN

ORDERS = {"interact": "Interaction", "follow": "Follow", "pause": "Follow", "focus_object": "Object", "look_around": None,
          "look_for_help": None, "sleep": "Sleeping"}

#: Where the camera looks, per state: a height on the person (m), or a named target.
CAMERA = {"Sleeping": "ahead", "Alertness": "face", "Listen": "face", "Interaction": "hands", "Follow": "torso", "Object": "object"}
#: States in which the base turns on the spot to face the person.
TURNS = frozenset({"Listen", "Interaction", "Object"})


class OrderRefused(ValueError):
    """An order the attention system does not know (names the order and the known ones)."""


@dataclass
class AttentionFSM:
    sleep_after: float = 2.0  # s without tracks before Sleeping
    state: str = "Sleeping"
    held: bool = False  # True while an order holds the state (top-down, or sleep)
    paused: bool = False  # the last order was ``pause`` (Follow, standing until she walks on)
    _empty_since: float | None = None

    @property
    def top_down(self) -> bool:
        return self.state in TOP_DOWN

    def order(self, name: str) -> str:
        """Apply an ES order; returns the new state. Raises OrderRefused for an unknown order."""
        if name not in ORDERS:
            raise OrderRefused(f"person_attention: unknown order {name!r} (known: {', '.join(sorted(ORDERS))})")
        target = ORDERS[name]
        self.paused = name == "pause"
        if target is None:  # look_around, look_for_help: back to bottom-up, the tracks decide
            self.held = False
            self.state = "Alertness"
        else:
            self.held = True
            self.state = target
        return self.state

    def bottom_up(self, now: float, tracked: bool, selected_category: int | None) -> str:
        """Advance the bottom-up states from the tracks (no effect while an order holds the state)."""
        if self.held:
            return self.state
        if not tracked:
            if self._empty_since is None:
                self._empty_since = now
            if now - self._empty_since >= self.sleep_after:
                self.state = "Sleeping"
            return self.state
        self._empty_since = None
        self.state = "Listen" if selected_category is not None and selected_category >= 2 else "Alertness"
        return self.state
