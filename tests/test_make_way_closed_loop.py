"""review12 items 1, 6 and 7: the make-way back-off, closed loop with the real sonar model.

"You are in my way" makes the robot back off half a metre straight back, into the half the laser does
not see. The back-off is held, like every other base command, to the sonar's blind-half rule
(robot/blindside.py): here the player runs step by step, the robot's pose follows the commands it
sends, and every step the rings' readings are computed by the real sensor model
(robot.hardware.sonar.sonar_readings) from a world with a person's legs behind the robot. Nobody is
tracked (the laser never saw him), so the sonar alone must stop it. It waits for the first sonar packet
and person tracks after the order; in an open room (no floor plan within reach) it backs off all the way.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.blindside import SonarEchoes
from robot.footprint import HALF_LENGTH, footprint_distance
from robot.hardware.sonar import SonarSpec, sonar_packet, sonar_readings
from robot.navigation import player as player_mod
from robot.navigation.player import MAKE_WAY_BACK, MAKE_WAY_WAIT, Player

LEG_RADIUS, LEG_SPREAD = 0.06, 0.10


class _World:
    """What the sonar reads: wall segments and people's leg circles."""

    def __init__(self, legs: list[tuple[float, float]], segments: list[tuple[tuple[float, float], tuple[float, float]]] = ()) -> None:
        self._a = np.array([s[0] for s in segments], dtype=float).reshape(-1, 2)
        self._b = np.array([s[1] for s in segments], dtype=float).reshape(-1, 2)
        self._c = np.array(legs, dtype=float).reshape(-1, 2)

    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        return self._a, self._b

    def leg_circles(self) -> tuple[np.ndarray, np.ndarray]:
        return self._c, np.full(len(self._c), LEG_RADIUS)


class _Bus:
    def __init__(self) -> None:
        self.sent: list[tuple[str, etree._Element]] = []

    def publish(self, channel: str, el: etree._Element, **_: object) -> None:
        self.sent.append((channel, el))


def _player(mapped: np.ndarray) -> Player:
    """A player that has just been ordered to make way, its floor plan ``mapped`` round it (robot frame
    = world frame: it starts at the origin facing +x), with the real sonar buffer and blind-half check."""
    p = Player.__new__(Player)
    p.sim = SimpleNamespace(now=0.0)
    p.bus = _Bus()
    p.goal = None
    p.period = 0.1
    p.limits = player_mod.limits_from_config({})
    p._map_asked = True
    p._tracks_sub = None
    p._sonar_at = p._tracks_at = None
    p.outline = object()
    p.odo = SimpleNamespace(pose=(0.0, 0.0, 0.0))
    p.pose = lambda: p.odo.pose  # type: ignore[method-assign]
    p.mapped = lambda pose: mapped  # type: ignore[method-assign]
    p._behind_clear = lambda reach: True  # type: ignore[method-assign]  # nobody tracked: the laser never saw him
    p._listen_to_people = lambda on: None  # type: ignore[method-assign]
    p.sonar = SonarEchoes()
    p._make_way = MAKE_WAY_BACK
    p._make_way_at = 0.0
    return p


def _hear(p: Player, world: _World, seq: int) -> None:
    """One sonar packet of every transducer's exact reading at the robot's pose, and an (empty) tracks packet."""
    spec = SonarSpec()
    which = tuple(range(len(spec.transducers)))
    packet = sonar_packet(p.now, spec, seq, which, sonar_readings(world, p.odo.pose, spec, which, None))
    p._on_sonar(SimpleNamespace(data=packet, xml=packet.to_xml()))  # as the sonar sends it: a typed record
    p._tracks_at = p.now


def _run(p: Player, world: _World, *, heard_from: int = 0, steps: int = 60) -> float:
    """Run the back-off closed loop; the robot's pose follows what it sends. Returns the least gap (m)
    between the footprint and any leg over the run."""
    legs, _ = world.leg_circles()
    least = math.inf
    for k in range(steps):
        if k >= heard_from:
            _hear(p, world, k)
        out = p.control_step()
        v = out[0] if out else 0.0
        x, y, th = p.odo.pose
        p.odo.pose = (x + v * p.period * math.cos(th), y + v * p.period * math.sin(th), th)
        p.sim.now += p.period
        if len(legs):
            gap = float((footprint_distance(legs[:, 0] - p.odo.pose[0], legs[:, 1] - p.odo.pose[1]) - LEG_RADIUS).min())
            least = min(least, gap)
        if p._make_way <= 0.0:
            break
    return least


OPEN = np.zeros((0, 2))  # no floor plan within reach: an open room


def test_in_an_open_room_it_backs_off_the_half_metre_it_promised():
    p = _player(OPEN)
    _run(p, _World([]))
    assert p.odo.pose[0] == pytest.approx(-MAKE_WAY_BACK, abs=0.03)


@settings(max_examples=30, deadline=None)
@given(gap=st.floats(0.05, 0.45), side=st.floats(-0.2, 0.2), heading=st.floats(0.0, math.pi))
def test_it_never_backs_into_a_person_standing_behind_it_whom_the_laser_never_saw(gap, side, heading):
    # a person standing still ``gap`` m behind the back bumper (legs on either side of that point)
    cx = -HALF_LENGTH - gap - LEG_RADIUS
    c, s = math.cos(heading), math.sin(heading)
    world = _World([(cx - s * LEG_SPREAD, side + c * LEG_SPREAD), (cx + s * LEG_SPREAD, side - c * LEG_SPREAD)])
    p = _player(OPEN)
    before = float((footprint_distance(world._c[:, 0], world._c[:, 1]) - LEG_RADIUS).min())
    least = _run(p, world)
    assert least >= min(before, 0.05)  # it keeps off his body (never closer than 5 cm, or than he stood)
    assert p._make_way == 0.0  # and it ends the back-off instead of waiting there


def test_a_person_behind_in_a_mapped_hall_stops_it_too():
    # walls 1 m to either side (on the plan and heard by the side transducers), a person 0.15 m behind
    walls = [((-3.0, 1.0), (3.0, 1.0)), ((-3.0, -1.0), (3.0, -1.0))]
    mapped = np.array([[x, y] for x in np.arange(-1.5, 1.5, 0.05) for y in (-1.0, 1.0)])
    cx = -HALF_LENGTH - 0.15 - LEG_RADIUS
    p = _player(mapped)
    least = _run(p, _World([(cx, 0.1), (cx, -0.1)], walls))
    assert least >= 0.05 and p.odo.pose[0] > -0.1


def test_it_does_not_start_before_the_sonar_has_been_heard_and_stays_if_it_never_is():
    p = _player(OPEN)
    for _ in range(5):
        assert p.control_step() is None  # ordered, nothing heard yet: nothing sent
        p.sim.now += p.period
    assert not p.bus.sent and p._make_way == MAKE_WAY_BACK
    p.sim.now = MAKE_WAY_WAIT + 0.1
    assert p.control_step() == (0.0, 0.0) and p._make_way == 0.0  # never heard behind it: it stays
    assert all(float(el.get("v")) == 0.0 for _, el in p.bus.sent)


def test_once_heard_late_it_backs_off():
    p = _player(OPEN)
    _run(p, _World([]), heard_from=5)
    assert p.odo.pose[0] == pytest.approx(-MAKE_WAY_BACK, abs=0.03)


def test_a_pressed_rear_bumper_stops_the_make_way_back_off():
    """review13 item 5: make-way's backing was published without the bumper reflex (every other command goes
    through it): with the rear ring pressed it backed on into what pressed it."""
    from robot.contract import BASE_CMD
    from robot.hardware.bumpers import bumper_element

    p = _player(OPEN)
    p.bumpers.update(bumper_element(0.0, (("rear", 2),)), 0.0)
    _run(p, _World([]), steps=20)
    assert p.odo.pose[0] == 0.0
    assert all(float(el.get("v")) >= 0.0 for ch, el in p.bus.sent if ch == BASE_CMD)
