"""The bare state an object-attention search needs when a test builds it without a bus: the clock at 10 s, a
pointing ray seen, the robot at the origin and its partner 10 m away, nothing asked or found yet."""

from __future__ import annotations

from types import SimpleNamespace

from robot.objects.attention import ObjectAttention
from robot.objects.resolve import Pointing


def bare_search_state(probe: ObjectAttention) -> None:
    """Set the fields ``ObjectAttention.__init__`` would (no bus, no subscriptions) on a test's probe."""
    probe.sim = SimpleNamespace(now=10.0)
    probe.gestures = SimpleNamespace(pointing=lambda *a, **k: Pointing(1.0, 0.0, 1.2, 0.0, -0.3))
    probe.gesture_wait = 0.0
    probe.pose = (0.0, 0.0, 0.0)
    probe._partner = (10.0, 0.0, 1.5)
    probe._asked_where = None
    probe._finds = 0
    probe._looking = False
    probe._subs = []
