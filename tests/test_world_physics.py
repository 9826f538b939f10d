"""The pymunk world: the robot drives, stops at walls and people; legs swing; time is a step count."""

from __future__ import annotations

import math

import numpy as np
import pytest

from homesim.world.bodies import ROBOT_LENGTH
from homesim.world.geometry import split_wall, wrap_angle
from tests.world_helpers import put_person, room


def _drive(world, v, w, seconds):
    world.robot.command(v, w)
    for _ in range(int(round(seconds / world.dt))):
        world.step()


def test_robot_stops_at_a_wall():
    world = room()
    world.humans["ann"].remove()
    world.place_robot(6.0, 3.0, 0.0)  # 2 m from the east wall, facing it
    _drive(world, 0.5, 0.0, 10.0)
    x, y, th = world.robot.pose
    inner_face = 8.0 - 0.05
    assert x + ROBOT_LENGTH / 2 <= inner_face + 0.02
    assert x + ROBOT_LENGTH / 2 > inner_face - 0.05  # it did get there
    assert abs(y - 3.0) < 0.02 and abs(th) < 0.01
    assert [what for _, what in world.contacts] == ["wall"]


def test_robot_cannot_pass_through_a_person():
    world = room()
    put_person(world, "ann", 4.0, 3.0, heading=math.pi)
    world.place_robot(2.0, 3.0, 0.0)
    _drive(world, 0.5, 0.0, 8.0)
    x, _, _ = world.robot.pose
    assert x + ROBOT_LENGTH / 2 < 4.0 - 0.2
    assert ("ann" in [what for _, what in world.contacts])


def test_speed_and_turn_rate_are_limited():
    world = room()
    world.humans["ann"].remove()
    world.place_robot(2.0, 3.0, 0.0)
    _drive(world, 5.0, 0.0, 2.0)  # asks for 5 m/s
    assert world.robot.v == pytest.approx(0.5)
    x0 = world.robot.pose[0]
    _drive(world, 5.0, 0.0, 1.0)
    assert world.robot.pose[0] - x0 == pytest.approx(0.5, abs=0.01)
    _drive(world, 0.0, 10.0, 3.0)  # asks for 573 deg/s
    assert math.degrees(world.robot.w) == pytest.approx(100.0)
    th0 = world.robot.pose[2]
    _drive(world, 0.0, 10.0, 1.0)
    assert math.degrees(abs(wrap_angle(world.robot.pose[2] - th0))) == pytest.approx(100.0, abs=1.0)


def test_time_is_a_step_count_and_runs_are_reproducible():
    def run():
        world = room()
        world.robot.command(0.4, 0.3)
        h = world.humans["ann"]
        for _ in range(250):
            h.walk_velocity(0.0, 0.5)
            world.step()
        return world.time, world.robot.pose, h.leg_centres().tolist()

    a, b = run(), run()
    assert a == b
    assert a[0] == 250 * (1 / 50)


def test_standing_legs_are_side_by_side_walking_legs_alternate():
    world = room()
    h = world.humans["ann"]
    put_person(world, "ann", 4.0, 3.0, heading=0.0)
    legs = h.leg_centres()
    assert legs[0][0] == pytest.approx(legs[1][0])  # no fore/aft offset
    assert abs(legs[0][1] - legs[1][1]) == pytest.approx(0.2)
    fore = []
    for _ in range(75):  # 1.5 s at 1 m/s: 2.5 strides
        h.walk_velocity(1.0, 0.0)
        world.step()
        l0, l1 = h.leg_centres()
        fore.append(l0[0] - l1[0])
    signs = np.sign(np.array(fore[10:]))
    assert (np.diff(signs) != 0).sum() >= 3  # the legs overtake each other again and again


def test_door_gaps_split_walls_and_bad_gaps_are_refused():
    pieces = split_wall((0, 0), (5, 0), [(2.0, 1.0)])
    assert pieces == [((0.0, 0.0), (1.5, 0.0)), ((2.5, 0.0), (5.0, 0.0))]
    with pytest.raises(ValueError, match="outside the wall"):
        split_wall((0, 0), (5, 0), [(4.8, 1.0)])
    with pytest.raises(ValueError, match="overlap"):
        split_wall((0, 0), (5, 0), [(2.0, 1.0), (2.5, 1.0)])


def test_robot_drives_through_a_door_gap():
    world = room()
    world.humans["ann"].remove()
    world.place_robot(1.0, 3.0, math.pi)  # the exit door is at y = 3 in the west wall
    _drive(world, 0.5, 0.0, 6.0)
    assert world.robot.pose[0] < -0.5
    assert world.contacts == []


def test_laser_segments_at_30cm_exclude_table_tops():
    world = room()
    a, _ = world.segments_at(0.30)
    kinds = {o.kind for o in world.obstacles if o.bottom <= 0.30 <= o.top}
    assert kinds == {"wall", "furniture", "leg"}
    names = {o.name for o in world.obstacles if o.bottom <= 0.30 <= o.top}
    assert "table" not in names and "cupboard" in names
    assert a.shape[0] == sum(len(o.polygon) for o in world.obstacles if o.bottom <= 0.30 <= o.top)
