"""Before "could not find", the object attention brings the whole search area into view (beside24): what lies
beyond the pan-tilt's reach (the base turns) and what lies too close under the camera (it backs off), planned from
its own pose, floor plan and camera model, never driving at a person (generated tour 9100-00: a bag 0.7 m
beside-behind the robot was never seen, "could not find" in 9 of 10 runs)."""

from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.floorplan import FloorPlan, MapObstacle, MapRoom, MapWall
from robot.objects.viewpoint import COVER_BEARINGS, LEG_LEAVE, PERSON_CLEARANCE, cover_leg_ok, cover_places, cover_views, search_area, sees

CAM, OFF = 1.41, 0.05
PAN = math.radians(100.0)


def _plan(w: float, h: float, *obstacles: MapObstacle) -> FloorPlan:
    walls = [MapWall(0, 0, w, 0, 0.1), MapWall(w, 0, w, h, 0.1), MapWall(w, h, 0, h, 0.1), MapWall(0, h, 0, 0, 0.1)]
    return FloorPlan(tuple(walls), tuple(obstacles), (MapRoom("room", ((0, 0), (w, 0), (w, h), (0, h))),), (1.0, 1.0, 0.0))


def _box(x0: float, y0: float, x1: float, y1: float, top: float) -> MapObstacle:
    return MapObstacle("box", "table", ((x0, y0), (x1, y0), (x1, y1), (x0, y1)), 0.0, top)


def _cam(x: float, y: float, b: float) -> tuple[float, float, float]:
    return x + OFF * math.cos(b), y + OFF * math.sin(b), CAM


def test_a_bag_beside_behind_the_robot_is_out_of_every_pan_and_comes_into_view_from_a_pose_no_nearer_to_her():
    plan = _plan(5.0, 4.0)
    robot = (2.5, 2.0, 0.0)
    her = (3.3, 2.2)
    bag = (2.0, 2.45, 0.15)  # 0.67 m away, 138 deg off the heading
    # from where it stands, no pan of the camera (nor a turn of the base) has it in view: too close under the camera
    assert not any(sees(plan, _cam(2.5, 2.0, b), b, bag) for b in [2 * math.pi * k / 72 for k in range(72)])
    views = cover_views(plan, robot, [bag], [her], camera_height=CAM, camera_offset=OFF)
    assert len(views) == 1 and views[0][3] == [0]
    x, y, b, _ = views[0]
    assert sees(plan, _cam(x, y, b), b, bag)
    assert math.hypot(x - her[0], y - her[1]) >= math.hypot(robot[0] - her[0], robot[1] - her[1]) - 1e-9


def test_a_thing_beyond_the_pan_range_but_in_range_is_viewed_by_turning_on_the_spot():
    plan = _plan(6.0, 5.0)
    robot = (3.0, 2.5, 0.0)
    cup = (1.5, 2.6, 0.8)  # 1.5 m behind the robot on a table top
    plan = _plan(6.0, 5.0, _box(1.3, 2.3, 1.8, 2.9, 0.75))
    assert not sees(plan, _cam(3.0, 2.5, PAN), PAN, cup) and not sees(plan, _cam(3.0, 2.5, -PAN), -PAN, cup)
    views = cover_views(plan, robot, [cup], [(3.9, 2.5)], camera_height=CAM, camera_offset=OFF)
    assert len(views) == 1 and (views[0][0], views[0][1]) == (3.0, 2.5)  # turned, not moved


def test_nothing_behind_a_wall_is_planned_for():
    plan = _plan(3.0, 3.0)
    views = cover_views(plan, (1.5, 1.5, 0.0), [(4.0, 1.5, 0.05)], [], camera_height=CAM, camera_offset=OFF)
    assert views == []


def test_the_search_area_holds_table_tops_and_floor_and_no_wall_or_tall_furniture():
    plan = _plan(4.0, 4.0, _box(0.5, 0.5, 1.0, 1.0, 0.75), MapObstacle("wardrobe", "shelf", ((3.0, 3.0), (3.9, 3.0), (3.9, 3.9), (3.0, 3.9)), 0.0, 1.9))
    area = search_area(plan, (2.0, 2.0), 2.0)
    assert area and all(0.0 < x < 4.0 and 0.0 < y < 4.0 for x, y, _ in area)
    assert any(abs(z - 0.8) < 1e-9 for _, _, z in area) and any(abs(z - 0.05) < 1e-9 for _, _, z in area)
    assert not any(3.0 < x < 3.9 and 3.0 < y < 3.9 for x, y, _ in area)


@settings(max_examples=25, deadline=None)
@given(w=st.floats(3.0, 6.0), h=st.floats(3.0, 6.0), rx=st.floats(0.2, 0.8), ry=st.floats(0.2, 0.8), th=st.floats(-math.pi, math.pi),
       hb=st.floats(-math.pi, math.pi), hd=st.floats(0.7, 1.6), table=st.booleans(), spots=st.lists(st.tuples(st.floats(0, 1), st.floats(0, 1)), min_size=1, max_size=12))
def test_every_spot_of_the_search_area_that_a_pose_in_reach_sees_is_brought_into_view(w, h, rx, ry, th, hb, hd, table, spots):
    """Any point of the search area that is reachable to view (some place the robot may take, looking some way,
    sees it) is in one of the planned views; every view is from such a place (no nearer to her than now)."""
    obstacles = (_box(0.3, 0.3, 1.0, 0.9, 0.75),) if table else ()
    plan = _plan(w, h, *obstacles)
    robot = (0.5 + rx * (w - 1.0), 0.5 + ry * (h - 1.0), th)
    her = (robot[0] + hd * math.cos(hb), robot[1] + hd * math.sin(hb))
    unseen = [(0.2 + u * (w - 0.4), 0.2 + v * (h - 0.4), 0.05) for u, v in spots]
    views = cover_views(plan, robot, unseen, [her], camera_height=CAM, camera_offset=OFF)
    places = cover_places(plan, (robot[0], robot[1]), [her])
    covered = {i for *_, got in views for i in got}
    for i, s in enumerate(unseen):
        reachable = any(sees(plan, _cam(q[0], q[1], b), b, s, [her]) for _d, q in places
                        for b in [math.remainder(2 * math.pi * k / COVER_BEARINGS, 2 * math.pi) for k in range(COVER_BEARINGS)])
        assert (i in covered) == reachable
    for x, y, b, got in views:
        assert any(abs(q[0] - x) < 1e-9 and abs(q[1] - y) < 1e-9 for _d, q in places)
        assert math.hypot(x - her[0], y - her[1]) >= min(hd, 1.3) - 1e-9
        assert all(sees(plan, _cam(x, y, b), b, unseen[i], [her]) for i in got)


def _walk(plan, robot, unseen, her, *, check: bool = True):
    """The cover search's walk as :meth:`ObjectAttention._cover_area` drives it: the first plan's views in order, each
    leg checked against her before it is driven (:func:`cover_leg_ok`) and the rest planned afresh from where the
    robot stands when one fails; at most as many views as the first plan had (``check=False``: the first plan's views
    in order, unchecked, as before review25 F-D). The legs driven."""
    pose, left = robot, list(unseen)
    views = cover_views(plan, pose, left, [her], camera_height=CAM, camera_offset=OFF)
    legs, budget, done = [], len(views), []
    while views and budget > 0:
        budget -= 1
        x, y, b, got = views[0]
        if check and not cover_leg_ok(plan, pose[:2], (x, y), [her]):
            left = [s for s in left if not any(sees(plan, _cam(*v), v[2], s, [her]) for v in done)]
            views = cover_views(plan, pose, left, [her], camera_height=CAM, camera_offset=OFF)
            if not views:
                break
            x, y, b, got = views[0]
        views = views[1:]
        legs.append(((pose[0], pose[1]), (x, y)))
        pose = (x, y, b)
        done.append((x, y, b))
    return legs


def _legs_keep_away(legs, her) -> bool:
    """Every leg keeps PERSON_CLEARANCE from her after its first LEG_LEAVE m (where it starts) and ends no nearer to
    her than it began (nor within PERSON_CLEARANCE + 0.5 m when farther)."""
    for a, b in legs:
        n = max(1, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.02))
        along = [(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) for k in range(n + 1)]
        if any(math.hypot(q[0] - a[0], q[1] - a[1]) >= LEG_LEAVE and math.hypot(q[0] - her[0], q[1] - her[1]) < PERSON_CLEARANCE - 1e-9
               for q in along):
            return False
        if math.hypot(b[0] - her[0], b[1] - her[1]) < min(math.hypot(a[0] - her[0], a[1] - her[1]), PERSON_CLEARANCE + 0.5) - 1e-9:
            return False
    return True


def test_the_review_case_no_leg_of_the_cover_walk_comes_within_the_clearance_of_her():
    """review25 F-D: only the first leg was checked against the people; the leg from one view's place to the next
    passed 0.73 m from her, who stood 1.06 m away (room 4.62 m x 5.82 m), inside the 0.815 m every leg keeps from a
    person. Each leg now checked from where it begins (the rest planned afresh when one fails), none comes within
    that clearance nor ends nearer to her than it began."""
    plan = _plan(4.62, 5.82)
    robot, her = (1.95, 1.71, 0.4), (0.92, 1.52)
    unseen = search_area(plan, her, 1.5)
    assert not _legs_keep_away(_walk(plan, robot, unseen, her, check=False), her)  # (the first plan's legs, in order)
    legs = _walk(plan, robot, unseen, her)
    assert legs and _legs_keep_away(legs, her)


@settings(max_examples=6, deadline=None)
@given(w=st.floats(3.0, 6.0), h=st.floats(3.0, 6.0), rx=st.floats(0.15, 0.85), ry=st.floats(0.15, 0.85), th=st.floats(-math.pi, math.pi),
       hb=st.floats(-math.pi, math.pi), hd=st.floats(0.9, 1.6))
def test_no_leg_of_the_cover_walk_comes_within_the_clearance_of_her_or_ends_nearer(w, h, rx, ry, th, hb, hd):
    plan = _plan(w, h)
    robot = (0.5 + rx * (w - 1.0), 0.5 + ry * (h - 1.0), th)
    her = (robot[0] + hd * math.cos(hb), robot[1] + hd * math.sin(hb))
    assume(0.3 < her[0] < w - 0.3 and 0.3 < her[1] < h - 0.3)
    assert _legs_keep_away(_walk(plan, robot, search_area(plan, her, 1.5), her), her)
