"""Person attention's turn toward someone beside it is not refused by the sonar hearing their own legs (turn21).

face20 found it in the follower and fixed it there: a flank transducer hears the partner standing beside the robot's
front across its 30 deg cone, and the reading's arc runs on round the flank, where a turn on the spot toward her
swings a corner within the blind half's gap. The person attention's own turn toward her kept the old rule and stopped
at about 65 deg. Both modules now share one rule (:func:`robot.blindside.seen_legs`): laser echoes ahead of the
laser's line within 0.45 m of a tracked person are that person's legs, and a sonar reading whose arc passes within
the floor plan's explaining distance of them is that person, not something unseen; that person's body is kept clear
by the turn's own sweep of the bodies near (:func:`robot.footprint.turn_clear`). A reading far from every seen leg
is judged exactly as before.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.module import AttentionParams, PersonAttention, echo_bodies
from robot.blindside import BLIND_X, EXPLAIN, LEGS_NEAR, blind_clear, blind_points, explained_by_points, seen_legs


def _attention(*, legs: list[tuple[float, float]], people: list[tuple[float, float]], arcs: list[np.ndarray]) -> PersonAttention:
    """A person attention whose laser saw ``legs`` (robot frame) this scan, with confirmed tracks at ``people``."""
    a = PersonAttention.__new__(PersonAttention)
    a.sim = SimpleNamespace(now=5.0)
    a.params = AttentionParams()
    a.legs = SimpleNamespace(offset=0.13)
    a._odom = (5.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    a.sonar = SimpleNamespace(arcs=lambda odom, now: list(arcs))
    a._plan_near, a._scan_pose, a.furniture = None, None, None
    pts = np.array(legs, dtype=float).reshape(-1, 2)
    dx = pts[:, 0] - 0.13
    a._ranges, a._bearings = np.hypot(dx, pts[:, 1]), np.arctan2(pts[:, 1], dx)
    a._people = np.array(people, dtype=float).reshape(-1, 2)
    return a


def _flank_arc(r: float, side: float = 1.0) -> np.ndarray:
    """The arc a flank transducer (at the front corner, facing out to ``side``) gives for a reading of ``r`` m: across
    its 30 deg cone, from ahead of the laser's line round to beside the footprint."""
    a = np.radians(np.linspace(75.0, 105.0, 5))
    return np.column_stack((0.1 + r * np.cos(a), side * (0.22 + r * np.sin(a))))


def test_her_legs_seen_explain_the_flank_reading_so_the_attention_turns_to_her():
    arc = _flank_arc(0.36)  # her near leg heard across the cone: points at x 0.2 .. 0.0, y ~0.58
    legs = [(0.2, 0.57), (0.33, 0.67)]  # the laser sees her legs ahead of its line
    for w in (0.4, 1.0):  # turning toward her, at the slow rate toward a bearing the laser does not see and faster
        assert _attention(legs=legs, people=[(0.3, 0.7)], arcs=[arc])._blind_clear(w)
        # the same reading with nobody seen there (someone out of the laser's view beside it): refused
        assert not _attention(legs=[], people=[(0.3, 0.7)], arcs=[arc])._blind_clear(w)
        # legs seen there, but no track near them (an untracked pair of legs, a chair's): the reading stands
        assert not _attention(legs=legs, people=[(2.0, -1.0)], arcs=[arc])._blind_clear(w)
        assert not _attention(legs=legs, people=[], arcs=[arc])._blind_clear(w)
    # on the right side, mirrored
    arc_r, legs_r = _flank_arc(0.36, -1.0), [(x, -y) for x, y in legs]
    assert _attention(legs=legs_r, people=[(0.3, -0.7)], arcs=[arc_r])._blind_clear(-0.4)
    assert not _attention(legs=[], people=[(0.3, -0.7)], arcs=[arc_r])._blind_clear(-0.4)


def test_someone_else_heard_behind_still_refuses_the_turn():
    """Her legs explain her reading only: another reading behind the robot, near the rear corner the turn swings,
    still refuses it (never a corner turned into anyone)."""
    legs = [(0.2, 0.62), (0.33, 0.72)]
    behind = np.array([(-0.5, -0.05 + 0.03 * k) for k in range(5)])  # someone 0.25 m behind the rear edge
    a = _attention(legs=legs, people=[(0.3, 0.75)], arcs=[_flank_arc(0.42), behind])
    assert not a._blind_clear(0.4) and not a._blind_clear(-0.4)


@settings(max_examples=200, deadline=None)
@given(bx=st.floats(-0.6, BLIND_X - 0.01), by=st.floats(0.3, 0.9), side=st.sampled_from([1.0, -1.0]),
       w=st.sampled_from([0.4, -0.4, 1.0, -1.0]), hx=st.floats(-0.5, 1.5), hy=st.floats(-1.2, 1.2))
def test_an_echo_far_from_seen_legs_is_kept_clear_of_as_before(bx, by, side, w, hx, hy):
    """A tracked person's legs explain only a reading whose arc passes within EXPLAIN of the laser's echoes near them
    (ahead of the laser's line): any other reading refuses a turn exactly as with nobody there."""
    arc = np.array([(bx + 0.02 * k, side * by) for k in range(-2, 3)])
    legs = [(hx - 0.1, hy), (hx + 0.1, hy)]
    seen = [p for p in legs if p[0] >= BLIND_X and math.hypot(p[0] - hx, p[1] - hy) <= LEGS_NEAR]
    if seen and min(math.hypot(p[0] - a[0], p[1] - a[1]) for p in seen for a in arc) <= EXPLAIN + 1e-6:
        return
    with_her = _attention(legs=legs, people=[(hx, hy)], arcs=[arc])
    alone = _attention(legs=[], people=[], arcs=[arc])
    assert with_her._blind_clear(w) == alone._blind_clear(w)
    # and the shared function agrees with the follower's use: the same points are left to keep clear of
    echoes = np.array(legs)
    explains = explained_by_points(seen_legs(echoes, np.array([(hx, hy)])))
    assert blind_clear(0.0, w, blind_points([arc], explains), duration=0.5) == blind_clear(0.0, w, blind_points([arc]), duration=0.5)


@settings(max_examples=200, deadline=None)
@given(ex=st.floats(-1.0, 1.5), ey=st.floats(-1.5, 1.5), hx=st.floats(-1.0, 1.5), hy=st.floats(-1.5, 1.5))
def test_seen_legs_are_ahead_of_the_line_and_near_a_person(ex, ey, hx, hy):
    out = seen_legs(np.array([(ex, ey)]), np.array([(hx, hy)]))
    expect = ex >= BLIND_X and math.hypot(ex - hx, ey - hy) <= LEGS_NEAR - 1e-9
    if expect or not (ex >= BLIND_X and math.hypot(ex - hx, ey - hy) <= LEGS_NEAR + 1e-9):
        assert (len(out) == 1) == expect
    assert not len(seen_legs(np.array([(ex, ey)]), np.zeros((0, 2))))


# Making room (generated tour 8900-3): she walked past the robot's side and stood at its back, 0.36 m behind it. Either
# way round a turn on the spot swings a rear corner nearer to her, so the sonar refused every turn toward her, "You
# left", and her greetings from there got "I can't see you". A turn only the sonar refuses is now preceded by a creep
# ahead, away from her, while everything ahead is clear; at most room_max m.

def _plan_ahead(points: np.ndarray) -> np.ndarray:
    """The floor plan explains what lies more than 0.3 m ahead of the centre (a wall there), nothing else."""
    return points[:, 0] > 0.3 if len(points) else np.zeros(0, dtype=bool)


class _Bus:
    def __init__(self) -> None:
        self.sent: list[tuple[float, float]] = []

    def publish(self, channel, el, transfer=False) -> None:
        self.sent.append((float(el.get("v")), float(el.get("w"))))


def _turning(*, ahead: list[tuple[float, float]], moved: float = 0.0) -> _Bus:
    behind = np.array([(-0.45, -0.1 + 0.05 * k) for k in range(5)])  # someone 0.2 m behind the rear edge
    a = _attention(legs=ahead, people=[], arcs=[behind])
    a._explained = _plan_ahead
    a._near = np.zeros((0, 2))
    a.furniture = None
    a.bumpers = SimpleNamespace(command=lambda v, w, now, *rest: (v, w))
    a.bus = _Bus()
    a._room = None if not moved else (-moved, 0.0, 5.0)
    a._turn(math.radians(175.0))
    return a.bus


def test_someone_close_behind_the_robot_makes_room_then_turns():
    sent = _turning(ahead=[])
    assert len(sent.sent) == 1
    v, w = sent.sent[0]
    assert v > 0.0  # ahead, away from her
    assert not blind_clear(0.0, 0.4, np.array([(-0.45, -0.1 + 0.05 * k) for k in range(5)]), duration=0.5)


def test_no_room_is_made_toward_a_wall_ahead_nor_beyond_the_allowance():
    wall = [(0.42, y) for y in np.linspace(-0.6, 0.6, 13)]  # the laser sees a wall 0.17 m ahead of the front
    assert _turning(ahead=wall).sent == [(0.0, 0.0)]
    # the wall itself leaves the turn free (only the sonar refuses it): it is the creep toward it that is refused
    a = _attention(legs=wall, people=[], arcs=[])
    e = a._echoes()
    assert a.turn_rate(math.radians(175.0), echo_bodies(e, _plan_ahead(e), 0.13)) != 0.0 and a._flat_clear(0.4, e)
    params = AttentionParams()
    assert _turning(ahead=[], moved=params.room_max + 0.01).sent == [(0.0, 0.0)]
