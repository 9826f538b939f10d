"""Backing out of her way from a door frame the robot stands in, turned toward her, never ends in a standstill
that blocks her only way out (long22's cause B: fresh7/corr_long_tour seed 0 on integ stood there from 168.8 s
for the rest of the run, "giving_way" at speed 0; tests/scenarios/follow/laundry_stop_in_door.xml is the scene).

The geometry is that run's, read from the follower at 168.8 s (robot frame): a rear corner 9 cm from a jamb with
the wall running on behind its left side, the door's other jamb and wall ahead on the right, her body 0.5 m off
its front-left corner, the back-out path's next point behind on the right. Every step at the back-out's speed
dipped under the sweep's margin at the jamb, every turn toward clearer ground swung a front corner toward her.
Here the follower's own back-out (Follower._back_out) is run closed loop: the robot's pose follows each command
for a tenth of a second, the floor plan and her body are seen from the new pose."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.config import Limits
from robot.navigation.follow import SWEEP_TIME, Follower, sweep_allowed
from robot.navigation.local import SOCIAL_GAP, TURN_GAP, footprint_distance, people_sweep_clear

#: corr_long_tour seed 0 at 168.8 s, robot frame (the floor plan's points within 0.8 m of its centre)
JAMBS = np.array([
    [0.542, -0.583], [0.504, -0.551], [0.44, -0.627], [0.465, -0.519], [0.401, -0.595], [0.427, -0.487],
    [0.363, -0.563], [0.388, -0.455], [0.356, -0.493], [0.324, -0.531], [-0.341, 0.154], [-0.373, 0.115],
    [-0.405, 0.077], [-0.379, 0.186], [-0.444, 0.109], [-0.418, 0.218], [-0.482, 0.141], [-0.456, 0.25],
    [-0.52, 0.173], [-0.495, 0.282], [-0.559, 0.205], [-0.533, 0.314], [-0.597, 0.237], [-0.571, 0.346],
    [-0.636, 0.269], [-0.61, 0.378], [-0.674, 0.301], [-0.648, 0.41], [-0.712, 0.333]])
HER = (0.441, 0.256)
#: the back-out path's pure-pursuit point at 168.8 s, carried on along its direction
OUT = (-0.244 * 3, -0.251 * 3)


class _Scan:
    def points(self) -> np.ndarray:
        return np.zeros((0, 2))


class _Nobody:
    def around(self, *_: object, **__: object) -> np.ndarray:
        return np.zeros((0, 2))


def _follower() -> Follower:
    f = Follower.__new__(Follower)
    f.limits = Limits()
    f.scan = _Scan()  # type: ignore[assignment]
    f.people = _Nobody()  # type: ignore[assignment]
    f.odom = (0.0, 0.0, 0.0)
    f.sim = SimpleNamespace(now=0.0)  # type: ignore[assignment]
    f._backout_refused = None
    return f


def _to_robot(p: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    d = np.atleast_2d(p) - (x, y)
    return np.stack((c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]), axis=1)


def _clearance(pts: np.ndarray) -> float:
    return float(footprint_distance(pts[:, 0], pts[:, 1]).min())


def test_turned_in_the_door_with_her_in_front_it_makes_room_instead_of_standing_for_ever():
    f = _follower()
    pose = (0.0, 0.0, 0.0)
    moved_at = None
    closest = _clearance(JAMBS)
    for k in range(100):  # 10 s
        f.sim.now = k * 0.1
        mapped = _to_robot(JAMBS, pose)
        goal = _to_robot(np.array(OUT), pose)[0]
        d_goal = math.hypot(*goal)
        if d_goal > 0.35:
            goal = goal * 0.35 / d_goal
        her = _to_robot(np.array(HER), pose)[0]
        v, w = f._back_out((float(goal[0]), float(goal[1])), (float(her[0]), float(her[1])), mapped)
        x, y, th = pose
        pose = (x + v * 0.1 * math.cos(th), y + v * 0.1 * math.sin(th), th + w * 0.1)
        closest = min(closest, _clearance(_to_robot(JAMBS, pose)))
        if moved_at is None and (math.hypot(pose[0], pose[1]) > 0.05 or abs(pose[2]) > math.radians(10)):
            moved_at = f.sim.now
    assert moved_at is not None, f"still standing in the door at {pose}"
    assert moved_at <= 3.0  # a second of refusals, then slower steps
    assert closest > 0.0  # never touching the jambs
    # and it made room for her: its footprint further from her body than it was
    assert _clearance(_to_robot(np.array(HER), pose)) > _clearance(np.array([HER])) + 0.03


@settings(max_examples=60, deadline=None)
@given(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2), st.floats(-0.6, 0.6), st.floats(0.3, 0.9), st.floats(-0.6, 0.6))
def test_the_freeing_step_keeps_the_floor_plan_and_her_as_every_back_out_step(dx, dy, turn, hx, hy):
    """Whatever it picks once the back-out has been refused a while, its sweep keeps off the floor plan's
    points (no nearer than now when already within the margin) and off her body (the social gap, or no
    nearer than now; the turn gap turning on the spot): it never buys its way out with a touch."""
    c, s = math.cos(turn), math.sin(turn)
    pts = JAMBS @ np.array([[c, s], [-s, c]]) + (dx, dy)
    here = _clearance(pts)
    if here <= 0.0:
        return
    f = _follower()
    her = np.array([(hx, hy)])
    v, w = f._free_turn(-0.14, her, pts, here)
    if (v, w) == (0.0, 0.0):
        return
    assert v <= 0.0
    assert sweep_allowed(v, w, pts, here)
    assert people_sweep_clear(v, w, her, duration=SWEEP_TIME, gap=TURN_GAP if v == 0.0 else SOCIAL_GAP)


def _stepping(poses: list[tuple[float, float, float]], dt: float = 0.1) -> list[bool]:
    f = _follower()
    f._aside_moving = None
    out = []
    for k, pose in enumerate(poses):
        f.sim.now = k * dt
        f.odom = pose
        out.append(f._aside_stuck())
    return out


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(-0.015, 0.015), st.floats(-0.015, 0.015), st.floats(-0.12, 0.12)), min_size=30, max_size=30))
def test_a_forward_give_way_that_only_turns_to_and_fro_in_place_counts_as_stalled_after_two_seconds(jitter):
    # tests/scenarios/follow/laundry_stop_in_door.xml seed 3 on integ: in the door, her 0.5 m in front, the dynamic
    # window's command never quite zero, a few degrees to and fro: the back-out that frees her way never began
    stuck = _stepping([(3.0 + dx, 1.0 + dy, 0.5 + dth) for dx, dy, dth in jitter])
    assert not any(stuck[:20])
    assert all(stuck[21:])


def test_a_forward_give_way_that_gets_somewhere_is_never_stalled():
    assert not any(_stepping([(0.03 * k, 0.0, 0.0) for k in range(60)]))  # 0.3 m/s along
    assert not any(_stepping([(0.0, 0.0, 0.05 * k) for k in range(60)]))  # turning on the spot, 0.5 rad/s
