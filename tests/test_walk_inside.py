"""People walk inside the flat and leave it only by ``<leave/>`` (gen12, tour-3000-03: the user model walked out).

The people's walk grid reaches 1.5 m beyond the outer walls (for leaving through an exit). A walk whose
goal is not free (the robot's disc over it, the goal in a wall) ends at the free cell nearest the goal;
by an outer wall that cell lay outside, and the user walked up to the robot round the flat, out through
the front door. Now every walk but leaving ends inside the flat (Grid.plan(inside=)); a script whose walk
names a point outside the flat was already refused with its file and line (the kernel's checks).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.errors import ScenarioError
from homesim.geometry import point_in_polygon
from homesim.scenario.loader import load_scenario_text
from homesim.scenario.pathplan import Grid

FLAT = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="by_the_wall" seed="1" duration="30">
  <flat>
    <room name="room" points="0,0 4,0 4,3 0,3"/>
    <room name="hall" points="4,0 6,0 6,3 4,3"/>
    <walls thickness="0.1">
      <wall from="0 0" to="6 0"/>
      <wall from="6 0" to="6 3"><door name="front door" at="1.5" width="1.0" exit="true"/></wall>
      <wall from="6 3" to="0 3"/>
      <wall from="0 3" to="0 0"/>
      <wall from="4 0" to="4 3"><door name="hall door" at="1.5" width="1.0"/></wall>
    </walls>
  </flat>
  <robot x="0.4" y="1.5" heading="90"/>
  <humans>
    <human name="ann" x="2" y="1.5" heading="180" height="1.7" torso="red">
      <script>WALK</script>
    </human>
  </humans>
</scenario>
"""

ROBOT_DISC = 0.34  # the footprint's bounding circle (humans.person plans round it)


def _flat(walk: str = "<wait for=\"1\"/>"):
    return load_scenario_text(FLAT.replace("WALK", walk), source="by_the_wall.xml")


def _inside(sc, p) -> bool:
    return any(point_in_polygon(p, np.array(r.polygon, dtype=float)) for r in sc.rooms)


def test_a_walk_up_to_the_robot_by_the_outer_wall_ends_inside_not_beyond_the_wall():
    sc = _flat()
    grid = Grid.for_scenario(sc)
    goal = (0.0, 1.5)  # where the robot stands by the west wall, the approach point in the wall
    old = grid.plan((2.0, 1.5), goal, avoid=[(0.4, 1.5, ROBOT_DISC)], inside=False)
    assert not _inside(sc, old[-1])  # the nearest free cell is outside: she walked out through the front door
    path = grid.plan((2.0, 1.5), goal, avoid=[(0.4, 1.5, ROBOT_DISC)], inside=True)
    assert all(_inside(sc, p) for p in path)
    assert math.dist(path[-1], goal) < 1.0


def test_leaving_still_ends_outside_by_the_exit():
    sc = _flat()
    grid = Grid.for_scenario(sc)
    path = grid.plan((2.0, 1.5), (6.7, 1.5), inside=False)  # the front door's outside point, as <leave/> walks
    assert not _inside(sc, path[-1]) and path[-1][0] > 6.0


@settings(max_examples=60, deadline=None)
@given(gx=st.floats(-0.05, 6.05), gy=st.floats(-0.05, 3.05), rx=st.floats(0.3, 5.7), ry=st.floats(0.3, 2.7))
def test_every_walk_but_leaving_ends_inside_the_flat(gx, gy, rx, ry):
    """Whatever the goal (in a wall, by one, under the robot) and wherever the robot stands, a walk from the
    room's middle ends inside the flat, or is refused (NoPathError), never beyond an outer wall."""
    sc = _flat()
    grid = Grid.for_scenario(sc)
    try:
        path = grid.plan((2.0, 1.5), (gx, gy), avoid=[(rx, ry, ROBOT_DISC)], inside=True)
    except ValueError:
        return
    assert _inside(sc, path[-1])


def test_a_script_that_walks_to_a_point_outside_the_flat_is_refused_with_its_line():
    with pytest.raises(ScenarioError) as err:
        _flat('<walk-to point="7.5 1.5"/>')
    text = str(err.value)
    assert "by_the_wall.xml:17" in text and "not inside any room" in text  # the kernel's check (homesim.scenario.checks)
    _flat('<walk-to point="5.5 1.5"/>')  # in the hall: fine
