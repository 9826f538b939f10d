"""A drive to a viewpoint is given up for a blockage only while the robot stands blocked, not while the player
works its own way out.

perceive/view_round_corner seeds 8, 9 (library): on a leg round a bookcase's end the player stopped at the
corner ("blocked"), stood 1 s, backed off 0.3 m (3 s) and drove on; the object attention counted the 4 s from
"blocked" and gave the leg up just as the robot drove on again ("Sorry, I could not find your box"). Now
``MOVE_BLOCKED`` s count only while the localised position moves less than ``MOVE_STILL`` m.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.sim import Simulation
from robot.contract import PLAYER_STATUS, POSE
from robot.objects.attention import MOVE_BLOCKED, MOVE_STILL, ObjectAttention


class Leg:
    """The object attention driving one leg; the player's status and the localised pose played by the test."""

    def __init__(self) -> None:
        self.sim = Simulation(seed=1, scenario="leg")
        self.oa = ObjectAttention(self.sim)
        self.player = self.sim.bus.participant("player")
        self.localiser = self.sim.bus.participant("localiser")
        self.result: list[str] = []
        self.sim.start()
        self.oa._listen(True)

    def status(self, t: float, state: str) -> None:
        self.sim.call_at(t, lambda: self.player.publish(PLAYER_STATUS, etree.Element("player", state=state)))

    def poses(self, t0: float, t1: float, x0: float, speed: float) -> None:
        """The localised pose every 0.1 s from t0 to t1, moving along x at ``speed`` m/s (negative: backing)."""
        n = int(round((t1 - t0) / 0.1))
        for i in range(n + 1):
            t = t0 + 0.1 * i
            x = x0 + speed * (t - t0)
            self.sim.call_at(t, lambda t=t, x=x: self.localiser.publish(
                POSE, etree.Element("pose", time=f"{t:.6f}", x=f"{x:.4f}", y="0", theta="0", frame="map")))

    def drive(self, at: float) -> None:
        async def go() -> None:
            self.result.append(await self.oa._drive_leg((3.0, 0.0, 0.0), False, "test"))
        self.sim.call_at(at, lambda: self.sim.spawn(go(), name="leg"))


@pytest.fixture
def leg():
    lg = Leg()
    yield lg
    lg.sim.close()


def test_standing_blocked_gives_the_leg_up(leg):
    leg.drive(1.0)
    leg.status(1.2, "moving")
    leg.poses(1.0, 12.0, 0.0, 0.0)  # it never moves
    leg.status(2.0, "blocked")
    leg.sim.run(until=2.0 + MOVE_BLOCKED + 0.6)
    assert leg.result == ["failed"]


def test_a_back_off_and_on_again_while_blocked_is_no_blockage(leg):
    leg.drive(1.0)
    leg.status(1.2, "moving")
    leg.poses(1.0, 3.0, 0.0, 0.0)
    leg.status(2.0, "blocked")  # stopped at the corner
    leg.poses(3.1, 6.0, 0.0, -0.1)  # backs off 0.3 m (the player's BACK_OFF)
    leg.poses(6.1, 9.0, -0.3, 0.2)  # and drives on, still "blocked" until 0.3 m of progress
    leg.status(8.8, "reached")
    leg.sim.run(until=10.0)
    assert leg.result == ["reached"]


@given(still=st.floats(min_value=0.0, max_value=3.0), moving=st.floats(min_value=0.5, max_value=6.0))
@settings(max_examples=15, deadline=None)
def test_the_leg_fails_only_after_standing_blocked_for_the_whole_time(still, moving):
    lg = Leg()
    try:
        lg.drive(1.0)
        lg.status(1.2, "blocked")
        lg.poses(1.0, 1.2 + still, 0.0, 0.0)  # stands blocked for `still` s (less than MOVE_BLOCKED)
        lg.poses(1.3 + still, 1.2 + still + moving, 0.0, -0.1)  # then backs off
        end = 1.2 + still + moving
        lg.poses(end + 0.1, end + 12.0, -0.1 * moving, 0.0)  # and stands again, blocked
        lg.sim.run(until=end - 0.3)
        if moving * 0.1 >= MOVE_STILL + 0.02:  # it backed off far enough to count as moving
            assert lg.result == []
        lg.sim.run(until=end + MOVE_BLOCKED + 1.0)
        assert lg.result == ["failed"]  # standing blocked again: given up within MOVE_BLOCKED s (and the poll)
    finally:
        lg.sim.close()
