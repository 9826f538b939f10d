"""Whom a person walks up to, she stops in sight of, never on the other side of a wall at her distance.

fresh10/hall_goto_music_room (fresh22, defect D): after a go-to the robot stood in the music room just inside
its wall; its user came back along the hall, and his ``<walk-to robot="true" stop-at="1.2"/>`` ended in the hall,
1.2 m from the robot in a straight line but behind the wall. He greeted it through the wall for the rest of the
run ("I can't see you. Please look at me.", 10/10): no robot can see through a wall. A walk up to the robot or to
a person (and a profile's approach, which stands in front of the robot on the line between them) now ends only
where nothing tall stands between them: she goes on round through the door.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from homesim.world.raycast import line_of_sight
from humans.person import SIGHT_HEIGHT
from tests.stage_helpers import PEOPLE

# A room with a hall along its north wall; the door between them is 2 m east of the robot, which stands by
# that wall inside the room. The straight line from the hall to the robot crosses the wall.
FLAT = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="behind_the_wall" seed="1" duration="40">
  <flat>
    <room name="room" points="0,0 5,0 5,3 0,3"/>
    <room name="hall" points="0,3 8,3 8,4.2 0,4.2"/>
    <walls thickness="0.1">
      <wall from="0 0" to="5 0"/>
      <wall from="5 0" to="5 3"/>
      <wall from="5 3" to="8 3"/>
      <wall from="8 3" to="8 4.2"/>
      <wall from="8 4.2" to="0 4.2"/>
      <wall from="0 4.2" to="0 0"/>
      <wall from="0 3" to="5 3"><door name="room door" at="3.2" width="0.9"/></wall>
    </walls>
  </flat>
  <robot x="1.2" y="2.5" heading="90"/>
  <humans>
    HUMANS
  </humans>
</scenario>
"""


def _run(humans: str, seconds: float = 30.0) -> Stage:
    sc = load_scenario_text(FLAT.replace("HUMANS", humans), source="behind_the_wall.xml")
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE)
    st.run(seconds)
    return st


def _in_sight(st: Stage, a: tuple[float, float], b: tuple[float, float]) -> bool:
    sa, sb = st.world.segments_at(SIGHT_HEIGHT)
    return bool(line_of_sight(a, np.array([b]), sa, sb)[0])


@pytest.mark.parametrize("walk, near", [
    ('<walk-to robot="true" stop-at="1.2"/>', 1.2),  # a scripted person's stop-at
    ('<walk-to robot="true"/>', 1.0),  # a profile's approach: in front of the robot at her distance
])
def test_a_walk_up_to_the_robot_behind_a_wall_goes_round_through_the_door(walk, near):
    extra = ' distance="1.0"' if 'stop-at' not in walk else ""
    st = _run(f'<human name="ann" x="6.5" y="3.6" heading="180" height="1.70" torso="red"{extra}>'
              f'<script><walk-to point="1.4 3.6"/>{walk}<wait for="1"/></script></human>')
    x, y = st.world.humans["ann"].position
    rx, ry, _ = st.world.robot.pose
    assert y < 3.0  # in the room with the robot, not in the hall behind its wall
    assert _in_sight(st, (x, y), (rx, ry))
    assert math.hypot(x - rx, y - ry) <= near + 0.1
    assert st.world.contacts == []


def test_a_walk_up_to_the_robot_in_sight_still_stops_at_her_distance():
    """Nothing between them: the walk ends where it did before, at the distance asked for."""
    st = _run('<human name="ann" x="4.2" y="1.0" heading="180" height="1.70" torso="red">'
              '<script><walk-to robot="true" stop-at="1.2"/></script></human>')
    x, y = st.world.humans["ann"].position
    rx, ry, _ = st.world.robot.pose
    assert 1.0 <= math.hypot(x - rx, y - ry) <= 1.25


def test_a_walk_up_to_a_person_behind_a_wall_goes_round_too():
    st = _run('<human name="ann" x="0.6" y="2.2" heading="180" height="1.70" torso="red"/>\n'
              '<human name="bob" x="6.5" y="3.6" heading="180" height="1.80" torso="blue">'
              '<script><walk-to point="1.4 3.6"/><walk-to human="ann" stop-at="1.8"/></script></human>')
    bob, ann = st.world.humans["bob"].position, st.world.humans["ann"].position
    assert bob[1] < 3.0 and _in_sight(st, bob, ann)
    assert math.dist(bob, ann) <= 1.9
