"""Giving way never sweeps the robot's footprint into a tracked body (u_catch_up_slow seed 5: the
follower's step-aside turned at 1.4 rad/s with the partner 0.6-0.9 m away, and a corner touched her).
The dynamic window checks people at six poses over 1.6 s and exempts turns on the spot; the
follower's own check of the command it sends is dense enough for any turn rate."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.navigation.config import Limits
from robot.navigation.follow import SWEEP_TIME, Follower
from robot.navigation.local import BODY, SOCIAL_GAP, TURN_GAP, DWAParams, LatestScan, arcs, footprint_distance, people_sweep_clear
from robot.navigation.people import People


def _gaps(v: float, w: float, bodies: np.ndarray, duration: float) -> np.ndarray:
    """(poses, bodies) air gaps of the footprint swept by (v, w), 2001 poses: a reference far denser than the rule."""
    x, y, th = arcs(np.array([v]), np.array([w]), np.linspace(0.0, duration, 2001))
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = bodies[None, :, 0] - x[0][:, None], bodies[None, :, 1] - y[0][:, None]
    return footprint_distance(c * dx + s * dy, -s * dx + c * dy) - BODY


class _At10(Follower):
    now = 10.0  # the tracks' time (the module's clock, not running here)


def _stepping_aside(her: tuple[float, float], goal: tuple[float, float], v0: float, w0: float,
                    other: tuple[float, float] | None) -> Follower:
    """A follower at the odom origin facing +x, part way along a give-way path to ``goal`` (odom), with
    the partner at ``her`` and maybe someone else at ``other``, driving at (``v0``, ``w0``)."""
    f = Follower.__new__(_At10)
    f.odom = (0.0, 0.0, 0.0)
    f.v, f.w = v0, w0
    f.limits = Limits()
    f.params = DWAParams()
    f.scan = LatestScan()
    f.route = SimpleNamespace(ready=True)
    f._aside = ([(0.0, 0.0), goal], 100.0, False)
    f._leave_aside = False  # a give-way for her standing there (give24b: one for her walking out keeps her in view)
    f._no_spot_until = -math.inf
    f.people = People()
    tracks = etree.Element("tracks", time="10.0", frame="odom")
    etree.SubElement(tracks, "track", id="her", x=str(her[0]), y=str(her[1]), vx="0", vy="0", confirmed="true")
    if other is not None:
        etree.SubElement(tracks, "track", id="him", x=str(other[0]), y=str(other[1]), vx="0", vy="0", confirmed="true")
    f.people.update(tracks)
    return f


polar = st.tuples(st.floats(0.5, 1.1), st.floats(-math.pi, math.pi))


@settings(max_examples=300, deadline=None)
@given(her=st.tuples(st.floats(0.55, 1.0), st.floats(-math.radians(79), math.radians(79))),
       goal=st.tuples(st.floats(0.3, 1.5), st.floats(-math.pi, math.pi)),
       v0=st.floats(0.0, 0.35), w0=st.floats(-math.radians(100), math.radians(100)),
       other=st.none() | polar)
def test_no_step_aside_command_sweeps_the_footprint_into_a_tracked_body(her, goal, v0, w0, other):
    """Whatever the give-way path, the robot's current speed and turn rate: the command it sends keeps
    its swept footprint (over the follower's check horizon) TURN_GAP from every body, her included,
    or no nearer than it is now."""
    hx, hy = her[0] * math.cos(her[1]), her[0] * math.sin(her[1])
    gx, gy = goal[0] * math.cos(goal[1]), goal[0] * math.sin(goal[1])
    ox = None if other is None else (other[0] * math.cos(other[1]), other[0] * math.sin(other[1]))
    f = _stepping_aside((hx, hy), (gx, gy), v0, w0, ox)
    cmd = f._give_way(hx, hy, np.zeros((0, 2)))
    if cmd is None:
        return
    v, w = cmd
    bodies = np.array([(hx, hy)] + ([ox] if ox is not None else []))
    g = _gaps(v, w, bodies, SWEEP_TIME)
    assert np.all(g.min(axis=0) >= np.minimum(g[0], TURN_GAP) - 2e-3), (v, w, g.min(axis=0), g[0])


def test_a_fast_turn_beside_her_is_not_clear_though_its_end_poses_are():
    """The rule itself: a turn on the spot at 1.4 rad/s whose corner passes through her body between
    coarse poses is refused; standing is always clear."""
    her = np.array([(0.0, 0.62)])  # beside it: 0.405 m from its side, a corner sweeps 0.33 m out
    assert not people_sweep_clear(0.0, 1.4, her, duration=SWEEP_TIME, gap=TURN_GAP)
    assert people_sweep_clear(0.0, 0.0, her, duration=SWEEP_TIME)


@given(v=st.floats(-0.3, 0.5), w=st.floats(-2.0, 2.0), p=st.lists(polar, min_size=1, max_size=3),
       gap=st.sampled_from([TURN_GAP, 0.25]))
def test_people_sweep_clear_agrees_with_a_dense_reference(v, w, p, gap):
    """Clear iff, per body, the densely sampled sweep keeps ``gap`` or no nearer than now (2 mm tolerance)."""
    bodies = np.array([(r * math.cos(a), r * math.sin(a)) for r, a in p])
    g = _gaps(v, w, bodies, SWEEP_TIME)
    worst = (g.min(axis=0) - np.minimum(g[0], gap)).min()
    ok = people_sweep_clear(v, w, bodies, duration=SWEEP_TIME, gap=gap)
    if worst < -3e-3:
        assert not ok
    if ok:
        assert worst >= -3e-3


@settings(max_examples=300, deadline=None)
@given(her=st.tuples(st.floats(0.5, 1.0), st.floats(-math.pi, math.pi)), w=st.floats(-math.radians(100), math.radians(100)),
       other=st.none() | polar)
def test_backing_off_while_turning_to_her_never_swings_a_corner_into_a_body(her, w, other):
    """The wait backs off (0.2 m/s) turning to face her: the command kept (u_catch_up_slow seed 5:
    backing at 1.75 rad/s toward her as she walked up touched her) keeps its swept footprint SOCIAL_GAP
    from every body or no nearer than now; a turn alone is left to turn_clear (v 0)."""
    f = _stepping_aside((her[0] * math.cos(her[1]), her[0] * math.sin(her[1])), (1.0, 0.0), 0.0, 0.0, None)
    pts = [(her[0] * math.cos(her[1]), her[0] * math.sin(her[1]))]
    if other is not None:
        pts.append((other[0] * math.cos(other[1]), other[0] * math.sin(other[1])))
    bodies = np.array(pts)
    v, w2 = f._back_off_clear(-0.2, w, bodies, np.zeros((0, 2)))
    if v == 0.0:
        assert w2 == w
        return
    g = _gaps(v, w2, bodies, SWEEP_TIME)
    assert np.all(g.min(axis=0) >= np.minimum(g[0], SOCIAL_GAP) - 2e-3), (v, w2, g.min(axis=0), g[0])
