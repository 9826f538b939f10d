"""Out of the camera's view is not "you are standing in front of it" (issue 26 items 5 and 11; fresh3
open_sofa_guest and angle_point_far): from the pointing ray, the camera's range and where the partner
stands, the object attention tells a spot too far to see (it comes closer) from one she hides (it asks
her to step aside), and a sight line that passes over her head from one she blocks."""

from __future__ import annotations

import math
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.floorplan import FloorPlan, MapObstacle, MapRoom, MapWall
from robot.objects.attention import PERSON_TOP, ObjectAttention
from robot.objects.gestures import CAMERA_HEIGHT
from robot.objects.resolve import Pointing
from robot.objects.viewpoint import CAMERA_RANGE


def _box(x0: float, y0: float, x1: float, y1: float, top: float) -> MapObstacle:
    return MapObstacle("furniture", "shelf", ((x0, y0), (x1, y0), (x1, y1), (x0, y1)), 0.0, top)


def _attention(*obstacles: MapObstacle, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> ObjectAttention:
    oa = ObjectAttention.__new__(ObjectAttention)  # the geometry only: no bus
    walls = (MapWall(-1, -3, 12, -3, 0.1), MapWall(12, -3, 12, 3, 0.1), MapWall(12, 3, -1, 3, 0.1), MapWall(-1, 3, -1, -3, 0.1))
    oa.plan = FloorPlan(walls, tuple(obstacles), (MapRoom("room", ((-1, -3), (12, -3), (12, 3), (-1, 3))),), (0.0, 0.0, 0.0))
    oa.pose = pose
    return oa


def _pointing_at(hand: tuple[float, float, float], target: tuple[float, float, float]) -> Pointing:
    d = math.hypot(target[0] - hand[0], target[1] - hand[1])
    return Pointing(hand[0], hand[1], hand[2], math.atan2(target[1] - hand[1], target[0] - hand[0]), math.atan2(target[2] - hand[2], d))


def test_a_book_on_a_tall_shelf_four_metres_away_is_out_of_range_not_hidden_by_her():
    shelf = _box(3.7, -0.5, 4.2, 0.5, 1.9)
    oa = _attention(shelf)
    p = _pointing_at((2.5, 0.1, 1.6), (3.9, 0.0, 2.02))  # she stands 2.6 m out, between the robot and the shelf
    assert oa._out_of_range(p)  # the robot comes closer: asking her to step aside would not help


def test_a_sight_line_that_passes_over_her_head_is_not_hidden_by_her():
    # a clock on a 2.3 m cabinet 2.9 m away, she stands just in front of the cabinet: the camera
    # (1.41 m) looks up past her head to the clock
    oa = _attention(_box(2.7, -0.4, 3.1, 0.4, 2.3))
    p = _pointing_at((2.3, 0.2, 1.6), (2.9, 0.0, 2.4))
    assert not oa._out_of_range(p)
    assert not oa._in_the_way(0.0, 2.6, p)
    assert oa._in_the_way(0.0, 1.0, p)  # standing nearer the robot she would hide it


def test_a_cup_on_a_low_table_behind_her_is_hidden_by_her_and_in_range():
    table = _box(1.8, -0.4, 2.4, 0.4, 0.75)
    oa = _attention(table)
    p = _pointing_at((1.3, 0.25, 1.1), (2.1, 0.0, 0.8))
    assert not oa._out_of_range(p)
    assert oa._in_the_way(0.0, 1.2, p)  # straight between the camera and the cup
    assert not oa._in_the_way(math.radians(30.0), 1.2, p)  # beside the line: she hides nothing


@settings(max_examples=150, deadline=None)
@given(dist=st.floats(0.8, 5.0), top=st.floats(0.4, 2.2), her=st.floats(0.4, 4.5))
def test_she_hides_a_spot_only_below_a_tall_persons_head_and_nearer_than_it(dist, top, her):
    oa = _attention(_box(dist - 0.2, -0.3, dist + 0.2, 0.3, top))
    p = _pointing_at((max(0.2, dist - 1.0), 0.2, 1.3), (dist, 0.0, top + 0.1))
    target = oa._landing(p)
    if target is None:
        return
    t_dist = math.hypot(target[0], target[1])
    line = CAMERA_HEIGHT + (target[2] - CAMERA_HEIGHT) * her / t_dist
    hidden = oa._in_the_way(math.atan2(target[1], target[0]), her, p)
    assert hidden == (her < t_dist - 0.1 and line <= PERSON_TOP)
    cam = (0.05, 0.0, CAMERA_HEIGHT)
    assert oa._out_of_range(p) == (math.dist(cam, target) > CAMERA_RANGE[1])


def test_a_vase_on_a_sideboard_she_stands_in_front_of_is_hidden_not_out_of_range():
    # scenarios/perceive/occluded_vase seed 8: her ray passes just over the sideboard's far edge and its
    # last low stretch is the floor by the wall 3.6 m from the robot; she still hides the vase where the
    # ray first comes down, 2.9 m away: ask her to step aside (as on main), do not drive off
    oa = _attention(_box(4.6 - 2.2, -0.9, 5.1 - 2.2, 0.9, 0.8))
    p = Pointing(4.80 - 2.2, -0.1, 1.0, math.radians(-4.5), math.radians(-35.6))
    assert not oa._out_of_range(p)
    assert oa._in_the_way(math.radians(-1.0), 2.1, p)


def test_a_teapot_on_a_dresser_against_the_wall_behind_her_is_hidden_by_her_not_out_of_range():
    # scenarios/flow/follow_while_looking seeds 2, 4 (look25): Ines 1.3 m in front of the robot points back
    # over the dresser behind her (its top 0.95 m, against the wall); her ray runs low over the dresser into the
    # wall. Where it would come down on the floor lies 4.6 m out, beyond the wall: judged there, the teapot was
    # "out of range" and the robot drove to see it instead of asking her to step aside
    oa = _attention(_box(11.5, -1.0, 11.95, 1.0, 0.95), pose=(9.4, 0.0, 0.0))
    p = Pointing(11.25, 0.0, 1.14, 0.0, math.radians(-14.0))
    assert not oa._out_of_range(p)
    assert oa._in_the_way(0.0, 1.3, p)  # she stands on the sight line: ask her to step aside


@settings(max_examples=60, deadline=None)
@given(x=st.floats(0.0, 11.0), y=st.floats(-2.5, 2.5), z=st.floats(0.9, 1.5), direction=st.floats(-math.pi, math.pi),
       elevation=st.floats(math.radians(-60.0), math.radians(-4.0)))
def test_where_a_ray_lands_is_never_beyond_a_wall_it_meets(x, y, z, direction, elevation):
    # a ray that shows something (its last low stretch before it ends, pointed_spot) is judged there: the
    # camera's range and who hides it are never taken from the floor beyond a wall (look25)
    from robot.objects.viewpoint import pointed_spot, wall_before
    oa = _attention(_box(11.5, -1.0, 11.95, 1.0, 0.95), _box(3.0, 2.5, 5.0, 2.95, 0.8))
    p = Pointing(x, y, z, direction, elevation)
    land = oa._landing(p)
    assert land is not None
    if pointed_spot(oa.plan, (x, y, z), direction, elevation) is not None:
        assert not wall_before(oa.plan, (x, y), (land[0], land[1]))
