"""After asking her to step aside the search waits for her step, her track moving and then standing, before the
time it looks counts; bounded (fresh12 kink_long_tour, defect J: "Could you step aside, please?" then "Sorry, I could
not find your small teapot" while she stepped aside)."""

from __future__ import annotations

import asyncio
from types import SimpleNamespace
from unittest import mock

from hypothesis import given, settings
from hypothesis import strategies as st

import robot.objects.attention as attention
from robot.objects.attention import STILL_WAIT, ObjectAttention


class _Walker(ObjectAttention):
    """Only her track: she stands ``delay`` s, walks ``length`` m at ``speed`` m/s, then stands."""

    def __init__(self, delay: float, length: float, speed: float) -> None:  # noqa: D107 (no bus)
        self.clock, self.delay, self.length, self.speed = 0.0, delay, length, speed

    def _partner_map(self):  # type: ignore[no-untyped-def]
        walked = min(self.length, max(0.0, self.clock - self.delay) * self.speed)
        return (1.0 + walked, 0.0)

    def stops(self) -> float:
        return self.delay + self.length / self.speed


def _until_still(w: _Walker, stood: tuple[float, float] | None) -> float:
    async def sleep(dt: float) -> None:
        w.clock += dt

    with mock.patch.object(attention, "asyncio", SimpleNamespace(sleep=sleep)):
        coro = w._until_still(stood)
        try:
            coro.send(None)
        except StopIteration:
            pass
    return w.clock


@settings(max_examples=60, deadline=None)
@given(delay=st.floats(0.0, 2.5), length=st.floats(0.4, 2.0), speed=st.floats(0.4, 1.0))
def test_the_look_waits_until_she_has_stepped_and_stands_and_no_longer_than_still_wait(delay, length, speed):
    w = _Walker(delay, length, speed)
    t = _until_still(w, (1.0, 0.0))
    assert t <= STILL_WAIT + 1e-9  # bounded
    if w.stops() + 1.0 <= STILL_WAIT:
        assert t >= w.stops() - 1e-9  # not while she still walks, nor before she began
        assert t <= w.stops() + 1.0 + 1e-9  # and soon once she stands


def test_she_who_has_not_begun_to_move_is_waited_for_until_she_has_stepped():
    w = _Walker(2.0, 1.0, 0.5)  # stands 2 s listening, then steps 1 m
    assert _until_still(w, (1.0, 0.0)) >= 4.0
    w = _Walker(2.0, 1.0, 0.5)
    assert _until_still(w, None) == 0.5  # without where she stood: the first still moment (as before)

