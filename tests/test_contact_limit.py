"""The contact limit (robot.footprint.contact_speed_limit): the robot never drives into someone walking into its way.

Issue 26's hard line: the robot never touches a person, and yields to anyone in its way. A boy running
out of a side door across a 1.1 m hallway was touched by the follower at 0.45 m/s (fresh7
corr_hallway_crossing seeds 0, 3): it slowed for his distance, not for his walk toward its path.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.footprint import BODY, CONTACT_GAP, CONTACT_GAP_STANDING, CONTACT_REACT, contact_speed_limit, footprint_distance

DECEL = 1.0
TOP = 0.45
DT = 0.1


def _air(rx: float, px: float, py: float) -> float:
    """Air between the footprint (at rx on the x axis, heading 0) and a body centred at (px, py)."""
    return float(footprint_distance(np.array([px - rx]), np.array([py]))[0]) - BODY


@settings(max_examples=80, deadline=None)
@given(x0=st.floats(0.9, 4.0), y0=st.floats(-3.0, 3.0), speed=st.floats(0.3, 1.6),
       heading=st.floats(-math.pi, math.pi), v0=st.floats(0.0, TOP))
def test_someone_walking_into_its_way_is_never_reached(x0, y0, speed, heading, v0):
    """Closed loop at the command rate: a person ahead walking at up to 1.6 m/s in any direction, seen where
    the limit still allows the robot's speed (seen in time), is never touched by the moving robot while
    ahead of its centre, nor come within their personal space while it moves toward them (it stands for
    them); the commands take effect a control period late and the robot brakes no harder than its
    deceleration. (Someone who has passed its centre and walks into its flank from behind is not
    something braking can prevent.)"""
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    assume(_air(0.0, x0, y0) > CONTACT_GAP + 0.05)
    assume(x0 > 0.0)  # ahead of it (someone walking up behind it is not helped by its standing)
    assume(contact_speed_limit(np.array([[x0, y0, vx, vy]]), TOP, decel=DECEL) >= v0)
    rx, v, cmd = 0.0, v0, v0
    px, py = x0, y0
    for _ in range(60):
        nxt = contact_speed_limit(np.array([[px - rx, py, vx, vy]]), TOP, decel=DECEL)
        # the speed moves toward the last command (one period late), at most DECEL per second
        v = max(v - DECEL * DT, min(cmd, v + DECEL * DT)) if cmd < v else min(cmd, v + DECEL * DT)
        cmd = nxt
        for _ in range(10):  # fine steps between commands
            rx += v * DT / 10
            px, py = px + vx * DT / 10, py + vy * DT / 10
            air = _air(rx, px, py)
            if v > 0.05 and px > rx:  # moving toward them (the social metric's "while moving"): their space kept
                assert air > CONTACT_GAP - 0.03, (rx, v, px, py)
            assert v == 0.0 or px <= rx or air > 0.0, (rx, v, px, py)  # (behind its centre: walking into its flank)
            if air <= 0.0:
                return  # they walked into the standing robot (it stood for them: all braking can do)


def test_a_partner_walking_away_ahead_does_not_slow_it():
    """Following at normal distance: the partner 1.0-1.5 m ahead walking on at its speed or faster."""
    for d in (1.0, 1.2, 1.5):
        for walk in (0.45, 0.6, 1.0):
            assert contact_speed_limit(np.array([[d, 0.0, walk, 0.0]]), TOP, decel=DECEL) == TOP


def test_a_child_darting_across_its_lane_stops_it_in_time():
    """corr_hallway_crossing: a boy running across its lane at 1.5 m/s, out of a side door 0.9 m to the right:
    while he is far enough ahead that it can still stand short of his path it drives on (it re-checks every
    command: the closed loop above); once no longer, it stands. Someone walking off to the side, or away
    behind it, does not slow it."""
    assert contact_speed_limit(np.array([[1.0, -0.9, 0.0, 1.5]]), TOP, decel=DECEL) == TOP
    assert contact_speed_limit(np.array([[0.6, -0.9, 0.0, 1.5]]), TOP, decel=DECEL) == 0.0
    assert contact_speed_limit(np.array([[0.6, -0.9, 0.0, 0.0]]), TOP, decel=DECEL) == TOP  # standing in the door: passed
    assert contact_speed_limit(np.array([[1.0, 1.2, 0.0, 1.0]]), TOP, decel=DECEL) == TOP  # walking off to the left
    assert contact_speed_limit(np.array([[-0.8, 0.0, -1.0, 0.0]]), TOP, decel=DECEL) == TOP  # behind, walking away


def test_someone_standing_ahead_is_stopped_short_of():
    """A person standing in the lane: every speed up to the limit stops with the gap left."""
    for d in (0.7, 0.9, 1.2):
        lim = contact_speed_limit(np.array([[d, 0.0, 0.0, 0.0]]), TOP, decel=DECEL)
        stop = lim * CONTACT_REACT + lim * lim / (2 * DECEL)
        assert _air(stop, d, 0.0) >= CONTACT_GAP_STANDING - 0.01
    assert contact_speed_limit(np.array([[0.6, 0.0, 0.0, 0.0]]), TOP, decel=DECEL) == 0.0


def test_nobody_no_limit():
    assert contact_speed_limit(np.zeros((0, 4)), TOP, decel=DECEL) == TOP


def _in_robot(rx: float, ry: float, th: float, px: float, py: float, vx: float, vy: float) -> tuple[float, ...]:
    c, s = math.cos(th), math.sin(th)
    dx, dy = px - rx, py - ry
    return (c * dx + s * dy, -s * dx + c * dy, c * vx + s * vy, -s * vx + c * vy)


@settings(max_examples=80, deadline=None)
@given(x0=st.floats(0.9, 4.0), y0=st.floats(-3.0, 3.0), speed=st.floats(0.3, 1.6),
       heading=st.floats(-math.pi, math.pi), v0=st.floats(0.0, TOP), w=st.floats(-1.0, 1.0))
def test_someone_walking_into_its_way_is_never_reached_on_an_arc(x0, y0, speed, heading, v0, w):
    """review18 F4: the same closed loop with the robot turning at ``w`` (drawn from +-1 rad/s) the whole time,
    the limit reckoned along that arc: someone walking into its way is never touched while ahead of it."""
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    assume(_air(0.0, x0, y0) > CONTACT_GAP + 0.05)
    assume(x0 > 0.0)
    assume(contact_speed_limit(np.array([[x0, y0, vx, vy]]), TOP, decel=DECEL, w=w) >= v0)
    rx = ry = th = 0.0
    v, cmd = v0, v0
    px, py = x0, y0
    for _ in range(60):
        nxt = contact_speed_limit(np.array([_in_robot(rx, ry, th, px, py, vx, vy)]), TOP, decel=DECEL, w=w)
        v = max(v - DECEL * DT, min(cmd, v + DECEL * DT)) if cmd < v else min(cmd, v + DECEL * DT)
        cmd = nxt
        for _ in range(10):
            rx, ry = rx + v * math.cos(th) * DT / 10, ry + v * math.sin(th) * DT / 10
            th += w * DT / 10
            px, py = px + vx * DT / 10, py + vy * DT / 10
            lx, ly, _, _ = _in_robot(rx, ry, th, px, py, vx, vy)
            air = float(footprint_distance(np.array([lx]), np.array([ly]))[0]) - BODY
            assert v == 0.0 or lx <= 0.0 or air > 0.0, (rx, ry, th, v, px, py)
            if air <= 0.0:
                return


@settings(max_examples=80, deadline=None)
@given(x0=st.floats(0.9, 4.0), y0=st.floats(-3.0, 3.0), speed=st.floats(0.3, 1.6), heading=st.floats(-math.pi, math.pi),
       v0=st.floats(0.0, TOP), w0=st.floats(-1.0, 1.0))
def test_a_limit_over_the_reachable_turn_rates_keeps_off_someone_on_any_of_them(x0, y0, speed, heading, v0, w0):
    """review18 F4: the robot changes its turn rate each step by up to ``dw`` (the window), within +-1 rad/s; with
    the limit taken over the rates it can reach in one step, someone walking into its way is never touched
    while ahead of it."""
    dw = 0.5
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    assume(_air(0.0, x0, y0) > CONTACT_GAP + 0.05)
    assume(x0 > 0.0)
    assume(contact_speed_limit(np.array([[x0, y0, vx, vy]]), TOP, decel=DECEL, w=w0, dw=dw) >= v0)
    rx = ry = th = 0.0
    v, cmd, w = v0, v0, w0
    px, py = x0, y0
    for _ in range(60):
        nxt = contact_speed_limit(np.array([_in_robot(rx, ry, th, px, py, vx, vy)]), TOP, decel=DECEL, w=w, dw=dw)
        v = max(v - DECEL * DT, min(cmd, v + DECEL * DT)) if cmd < v else min(cmd, v + DECEL * DT)
        cmd = nxt
        ly_now = _in_robot(rx, ry, th, px, py, vx, vy)[1]
        w = max(-1.0, min(1.0, w + math.copysign(dw, ly_now)))  # the worst reachable pick: turning toward them
        for _ in range(10):
            rx, ry = rx + v * math.cos(th) * DT / 10, ry + v * math.sin(th) * DT / 10
            th += w * DT / 10
            px, py = px + vx * DT / 10, py + vy * DT / 10
            lx, ly, _, _ = _in_robot(rx, ry, th, px, py, vx, vy)
            air = float(footprint_distance(np.array([lx]), np.array([ly]))[0]) - BODY
            assert v == 0.0 or lx <= 0.0 or air > 0.0, (rx, ry, th, v, w, px, py)
            if air <= 0.0:
                return


def test_the_limit_counts_the_turn_the_window_can_take_next():
    """review18 F4's example: someone ahead-left walking across; driving straight the robot may go at 0.45 m/s,
    turning left at 1 rad/s it must stand: with that turn within reach, the limit is the turn's."""
    walker = np.array([[0.54, 1.3, -0.32, -0.61]])
    straight = contact_speed_limit(walker, TOP, decel=DECEL, w=0.0)
    turning = contact_speed_limit(walker, TOP, decel=DECEL, w=1.0)
    assert turning < straight
    assert contact_speed_limit(walker, TOP, decel=DECEL, w=0.0, dw=1.0) <= turning
