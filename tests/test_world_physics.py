"""The pymunk world: the robot drives, stops at walls and people; legs swing; time is a step count."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from homesim.errors import ScenarioError
from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.world.bodies import HUMAN_RADIUS, ROBOT_LENGTH
from homesim.geometry import polygon_edges, segments_intersect, split_wall, wrap_angle
from homesim.tour.stage import Stage
from homesim.world.world import World
from tests.conftest import examples
from tests.world_helpers import EXAMPLE, ROOM, put_person, room, scenario
from tests.stage_helpers import PEOPLE


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


def test_a_long_run_keeps_its_latest_contacts_and_counts_them_all(monkeypatch):
    """Bumping into the wall again and again: every contact is counted and seen by the
    listeners, only the latest CONTACT_LOG are kept (memory does not grow with the run)."""
    import homesim.world.world as world_mod

    monkeypatch.setattr(world_mod, "CONTACT_LOG", 2)
    world = room()
    world.humans["ann"].remove()
    seen = []
    world.add_contact_listener(lambda t, what: seen.append((t, what)))
    for _ in range(4):
        world.place_robot(7.2, 3.0, 0.0)  # 0.5 m from the east wall, facing it
        _drive(world, 0.5, 0.0, 2.0)
    assert len(seen) == world.contact_count >= 4 and {w for _, w in seen} == {"wall"}
    assert world.contacts == seen[-2:]
    assert [t for t, _ in seen] == sorted(t for t, _ in seen)


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


# ------------------------------------------------- people never push the robot
def _static_penetration(world) -> float:
    """How deep (m) the robot overlaps walls or furniture (0 when clear)."""
    deepest = 0.0
    for info in world.space.shape_query(world.robot.shape):
        if info.shape.sensor or info.shape.body.body_type != pymunk.Body.STATIC:
            continue
        deepest = max(deepest, max((abs(p.distance) for p in info.contact_point_set.points), default=0.0))
    return deepest


def test_a_person_walking_at_the_robot_by_a_wall_stops_instead_of_pushing_it_through():
    """The review's push.py: the person used to shove the robot 1.9 m through the south wall."""
    world = room()
    world.place_robot(2.0, 0.4, 0.0)
    put_person(world, "ann", 2.0, 2.0, heading=-math.pi / 2)
    h = world.humans["ann"]
    h.walk_velocity(0.0, -1.0)
    for _ in range(150):
        world.step()
    assert world.robot.pose == pytest.approx((2.0, 0.4, 0.0))
    assert world.contacts == []
    gap = world.robot.shape.point_query(h.position).distance - HUMAN_RADIUS
    assert 0.0 < gap <= 0.03 and h.held
    h.walk_velocity(0.0, 1.0)  # and walks away again
    world.step()
    assert h.position[1] > 0.9 and not h.held


def test_squeezed_between_a_person_and_a_wall_the_wall_wins():
    """Even if a person ends up overlapping a robot at a wall, the robot never goes into the wall."""
    world = room()
    reach = ROBOT_LENGTH / 2 + 0.01  # half-length plus the shape's rounding
    world.place_robot(2.0, 0.06 + reach, math.pi / 2)  # 1 cm from the wall's inner face (0.05)
    put_person(world, "ann", 2.0, 0.06 + 2 * reach + HUMAN_RADIUS - 0.1, heading=-math.pi / 2)  # 10 cm into the robot
    world.step()
    assert _static_penetration(world) < 0.005
    assert world.robot.pose[1] == pytest.approx(0.06 + reach, abs=0.011)
    x, y = world.humans["ann"].position
    assert y >= world.robot.pose[1] + reach + HUMAN_RADIUS - 0.005  # the person was moved back


def test_a_scripted_person_walks_around_the_robot_not_through_it():
    """The review's push2.py: ann's straight path ran through the robot standing by the wall."""
    text = ROOM.read_text(encoding="utf-8").replace('<robot x="1" y="3" heading="0"/>', '<robot x="1.2" y="1.0" heading="90"/>')
    text = text.replace('<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>',
        '<human name="ann" x="1.2" y="3" heading="270" height="1.70" torso="yellow"><script><walk-to point="1.2 0.4"/></script></human>')
    sc = load_scenario_text(text, source="push2.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE)
    st.run(8)
    assert st.world.robot.pose == pytest.approx((1.2, 1.0, math.pi / 2))
    assert st.world.contacts == []
    assert math.dist(st.world.humans["ann"].position, (1.2, 0.4)) < 0.06
    sim.close()


@settings(max_examples=examples(30, 300))
@given(
    robot=st.tuples(st.floats(0.35, 7.65), st.floats(0.35, 5.65), st.floats(-math.pi, math.pi)),
    person=st.tuples(st.floats(0.3, 7.7), st.floats(0.3, 5.7)),
    walks=st.lists(st.tuples(st.floats(0.0, 1.5), st.floats(-0.6, 0.6)), min_size=1, max_size=8),
    drive=st.tuples(st.floats(-0.5, 0.5), st.floats(-1.7, 1.7)),
)
def test_people_never_push_the_robot_into_walls_or_out_of_the_flat(robot, person, walks, drive):
    """People walk (roughly) at the robot, which drives about; it never ends in a wall, and it
    leaves the room only through the door (its centre never crosses a wall)."""
    world = room()
    world.place_robot(*robot)
    assume(_static_penetration(world) == 0.0)
    put_person(world, "ann", *person)
    assume(world.robot.shape.point_query(person).distance > HUMAN_RADIUS + 0.05)
    world.robot.command(*drive)
    walls = [polygon_edges(o.polygon) for o in world.obstacles if o.kind == "wall"]
    wall_a, wall_b = np.concatenate([a for a, _ in walls]), np.concatenate([b for _, b in walls])
    h = world.humans["ann"]
    for speed, off in walks:
        rx, ry, _ = world.robot.pose
        a = math.atan2(ry - h.position[1], rx - h.position[0]) + off
        h.walk_velocity(speed * math.cos(a), speed * math.sin(a))
        for _ in range(15):
            before = world.robot.pose[:2]
            world.step()
            assert _static_penetration(world) < 0.01
            assert not segments_intersect(np.array([before]), np.array([world.robot.pose[:2]]), wall_a, wall_b).any()


# ------------------------------------------------------------ no tunnelling
@pytest.mark.parametrize("speed,rate", [(0.5, 1), (2.0, 1), (3.0, 1), (3.0, 50), (0.5, 50)])
def test_a_fast_robot_or_a_slow_world_rate_never_carries_the_robot_through_a_wall(speed, rate):
    """The review's tunnel2.py: 2 m/s at 1 Hz ended at x=39.5, through the wall at x=8."""
    text = ROOM.read_text(encoding="utf-8").replace('<robot x="1" y="3" heading="0"/>', f'<robot x="0.5" y="2" heading="0" max-speed="{speed}"/>')
    world = World(load_scenario_text(text.replace('duration="10"', f'duration="10" world-rate="{rate}"')))
    world.humans["ann"].remove()
    world.robot.command(speed, 0.0)
    for _ in range(max(1, int(20 * rate))):
        world.step()
    x = world.robot.pose[0]
    assert 7.0 < x + ROBOT_LENGTH / 2 <= 7.95 + 0.02
    assert _static_penetration(world) < 0.01


@pytest.mark.parametrize("attr", ['max-speed="8"', 'max-turn="1000"'])
def test_robot_limits_beyond_the_physics_are_refused_with_the_line(attr):
    text = ROOM.read_text(encoding="utf-8").replace('<robot x="1" y="3" heading="0"/>', f'<robot x="1" y="3" heading="0" {attr}/>')
    with pytest.raises(ScenarioError, match="scenario.xsd") as exc:
        load_scenario_text(text, source="fast.xml")
    assert exc.value.line == text[: text.index("<robot ")].count("\n") + 1


def test_default_rates_take_one_sub_step():
    world = World(scenario(EXAMPLE))
    assert world.substeps(world.dt) == 1


def test_the_robot_cannot_turn_through_a_wall_in_a_tight_spot():
    """Between the south wall and the table (0.55 m apart) the 0.69 m-wide turning circle does
    not fit: the base's imposed turn rate used to rotate the robot's corners into the wall."""
    world = room()
    world.humans["ann"].remove()
    world.place_robot(3.0, 0.375, 0.0)
    world.robot.command(0.0, 1.0)
    for _ in range(100):
        world.step()
        assert _static_penetration(world) < 0.005
    x, y, th = world.robot.pose
    assert abs(th) < math.radians(20) and math.hypot(x - 3.0, y - 0.375) < 0.05
