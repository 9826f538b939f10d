"""Someone who stops dead in front of the robot and walks on (the contact limit's prediction, people.People.stopped).

cross_child_stops_twins seed 4 (main 9561a5d): Emma runs across the robot's way at 2 m/s, stops dead 1 m ahead-left
of it for 0.7 s and runs on. The contact limit reckoned her standing (the tracker's stopped gate reports her velocity
0), the follower drove on at 0.5 m/s, and she ran on across its front with 0.014 m of air. Someone who stopped dead a
moment ago is reckoned with twice: standing, and walking on as they last walked.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.footprint import BODY, contact_speed_limit, footprint_distance
from robot.navigation.people import RESUME_FOR, People, in_the_way

DECEL = 1.0
TOP = 0.5
DT = 0.1


def _tracks(x: float, y: float, vx: float, vy: float, time: float) -> etree._Element:
    el = etree.Element("tracks", time=f"{time:.3f}", frame="odom")
    etree.SubElement(el, "track", id="t1", x=f"{x:.4f}", y=f"{y:.4f}", vx=f"{vx:.4f}", vy=f"{vy:.4f}",
                     cxx="0.002", cxy="0", cyy="0.002", confirmed="true")
    return el


def _air(rx: float, px: float, py: float) -> float:
    return float(footprint_distance(np.array([px - rx]), np.array([py]))[0]) - BODY


def _drive(x0: float, y0: float, speed: float, heading: float, walk: float, pause: float, steps: int = 80,
           people: People | None = None) -> float:
    """Closed loop at 10 Hz: the robot drives along +x at the contact limit over the tracks (a tracker that reports
    her velocity at once, 0 while she stands); she walks ``walk`` s, stands ``pause`` s, walks on as before.
    The least air between the moving robot's footprint and her body while she is ahead of its centre."""
    people = people if people is not None else People()
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    rx, v, cmd = 0.0, TOP, TOP
    px, py = x0, y0
    least = math.inf
    for k in range(steps):
        t = k * DT
        standing = walk <= t < walk + pause
        ux, uy = (0.0, 0.0) if standing else (vx, vy)
        people.update(_tracks(px, py, ux, uy, t))
        nxt = contact_speed_limit(in_the_way(people, (rx, 0.0, 0.0), t), TOP, decel=DECEL)
        v = max(v - DECEL * DT, cmd) if cmd < v else min(cmd, v + DECEL * DT)
        cmd = nxt
        for _ in range(10):
            rx += v * DT / 10
            px, py = px + ux * DT / 10, py + uy * DT / 10
            if v > 0.0 and px > rx:
                least = min(least, _air(rx, px, py))
    return least


@settings(max_examples=60, deadline=None)
@given(x0=st.floats(1.2, 3.5), side=st.sampled_from([-1.0, 1.0]), y_far=st.floats(1.2, 2.5), speed=st.floats(0.6, 2.0),
       angle=st.floats(-0.6, 0.6), walk=st.floats(0.1, 1.0), pause=st.floats(0.2, RESUME_FOR - 0.3))
def test_someone_who_stops_dead_and_walks_on_across_its_way_is_never_reached(x0, side, y_far, speed, angle, walk, pause):
    """Anyone walking across the robot's way who stops dead for a moment (within RESUME_FOR s) and walks on as they
    walked is never touched by the moving robot while ahead of it."""
    heading = -side * math.pi / 2 + angle  # toward its lane, from the side she starts on
    y0 = side * y_far
    # she stops beside its lane, not in it (someone standing in its way is waited for by other rules)
    stop_y = y0 + speed * math.sin(heading) * walk
    assume(side * stop_y > 0.5)
    assume(_air(0.0, x0, y0) > 0.6)
    assert _drive(x0, y0, speed, heading, walk, pause) > 0.0


def test_cross_child_stops_twins_geometry_needs_the_rule():
    """The scene's geometry (she runs at 2 m/s from 2 m left of its lane, stands 0.8 s 1 m beside it, runs on): touched
    at full speed without the rule (People.stopped empty), clear with it."""
    args = (1.9, 2.0, 2.0, -math.pi / 2 - 0.3, 0.5, 0.8)

    class Forgetful(People):
        def stopped(self, odom, now, *, reach=4.0, exclude=None):  # noqa: ARG002 - the rule taken out
            return np.zeros((0, 4))

    assert _drive(*args, people=Forgetful()) <= 0.0
    assert _drive(*args) > 0.25


def test_someone_who_stands_on_is_forgotten_as_a_walker():
    """RESUME_FOR s after she last walked, someone standing is only someone standing."""
    people = People()
    people.update(_tracks(1.5, 1.0, 0.0, -1.5, 0.0))
    people.update(_tracks(1.5, 0.9, 0.0, 0.0, 0.1))
    assert len(people.stopped((0.0, 0.0, 0.0), 0.1)) == 1
    people.update(_tracks(1.5, 0.9, 0.0, 0.0, RESUME_FOR + 0.2))
    assert len(people.stopped((0.0, 0.0, 0.0), RESUME_FOR + 0.2)) == 0
    people.update(_tracks(1.5, 0.9, 0.0, -1.5, RESUME_FOR + 0.3))
    assert len(people.stopped((0.0, 0.0, 0.0), RESUME_FOR + 0.3)) == 0  # walking: the tracks' own row
