"""Someone walks past a person who stands (in front of her, as seen from the robot, or behind her): her
track keeps her (robot/attention/tracker.py ``_claimed``).

fresh11/rail_fast_crossing seed 1 as ident23 traced it on session 13's integ (main 5a86edb no longer
reaches that moment): the partner had stopped in a door, his flatmate walked through it past him between
him and the robot; with the contact allowance and the "stopped" hypothesis his track gated her legs nearly
as well as her own track did, took them, and walked off with her. A standing person does not move at
walking speed from one scan to the next."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.legs import PAIR, SINGLE
from robot.attention.tracker import Tracks

DT = 0.1


def _pass(dist, gap, front, speed, angle, seed, lone_from=0.45, hidden_within=0.0, split=0.0):
    """The robot at the origin looking along +x; she stands at (dist, 0); he walks at ``speed`` along a line
    ``gap`` nearer the robot (``front``) or further away than her, tilted ``angle`` (rad) off the
    perpendicular of the line of sight, from 2 m one side of it to 2 m the other. His legs: a pair, or,
    with probability ``split`` per scan while he is within 0.7 m of her, each leg apart as a lone leg (seen
    with probability 0.7: legs crossing hers, half hidden). Her legs: a pair, or the lone leg that shows
    beside him while he is within ``lone_from`` of her line of sight in front of her, nothing while within
    ``hidden_within`` (his body hides both). Yields (t, candidates, kinds, whose) per scan, whose[j] = 'S'
    (hers) or 'W' (his)."""
    rng = np.random.default_rng(seed)
    S = np.array([dist, 0.0])
    c = np.array([dist - gap if front else dist + gap, 0.0])
    u = np.array([math.sin(angle), math.cos(angle)])
    n = np.array([-u[1], u[0]])
    start = c - 2.0 * u / abs(u[1])
    length = 4.0 / abs(u[1])
    k = 0
    while True:
        t = k * DT
        k += 1
        walked = speed * (t - 1.0)
        if walked > length + 1.0:
            return
        W = start + max(walked, 0.0) * u if t >= 1.0 else None
        z, kind, whose = [], [], []

        def seen(p, k, w):
            z.append(p)
            kind.append(k)
            whose.append(w)

        if W is not None:
            if np.hypot(*(W - S)) < 0.7 and rng.random() < split:
                for sg in (1.0, -1.0):
                    if rng.random() < 0.7:
                        seen(W + sg * 0.1 * n + rng.normal(0.0, 0.03, 2), SINGLE, "W")
            else:
                seen(W + rng.normal(0.0, 0.03, 2), PAIR, "W")
        off = abs(math.atan2(W[1], W[0])) * dist if W is not None and front and W[0] < S[0] else math.inf
        if off < hidden_within:
            pass
        elif off < lone_from:
            side = -1.0 if W[1] > 0 else 1.0  # the leg on the side away from him shows
            seen(S + np.array([0.0, side * 0.1]) + rng.normal(0.0, 0.03, 2), SINGLE, "S")
        else:
            seen(S + rng.normal(0.0, 0.03, 2), PAIR, "S")
        yield t, np.array(z).reshape(-1, 2), np.array(kind, dtype=np.int8), whose


def _run(tracks, *args):
    """Her id (the track on her after 0.6 s standing), the scans at which a candidate of his updated it,
    how far it came off her at most, and the tracks at the end."""
    hers = None
    fed: list[float] = []
    off = 0.0
    dist = args[0]
    for t, z, kind, whose in _pass(*args):
        rows = tracks.step(t, z, kind)
        if hers is None and t >= 0.6 and len(tracks):
            S = z[whose.index("S")]
            i = int(np.argmin(np.hypot(tracks.x[:, 0] - S[0], tracks.x[:, 1] - S[1])))
            hers = int(tracks.ids[i])
        if hers is not None:
            r = tracks.row(hers)
            if r >= 0:
                off = max(off, math.hypot(tracks.x[r, 0] - dist, tracks.x[r, 1]))
                if any(rows[j] == r and w == "W" for j, w in enumerate(whose)):
                    fed.append(round(t, 1))
    return hers, fed, off, tracks


def _kept(hers, fed, off, tracks, dist, limit=0.3):
    """Her id stayed hers: never fed his legs two scans running (one lone leg of his beside her once is
    noise, two in a row is her track walking with him), never more than ``limit`` off her (0.3 m: a leg
    spread and noise; a track coasting while she is hidden drifts a little further), and on her (within
    0.2 m) when he has gone."""
    assert hers is not None
    assert not any(b - a <= DT + 1e-6 for a, b in zip(fed, fed[1:])), f"her track took his legs at {fed[:6]}"
    assert off < limit, f"her track came {off:.2f} m off her"
    r = tracks.row(hers)
    assert r >= 0 and math.hypot(tracks.x[r, 0] - dist, tracks.x[r, 1]) < 0.2


@settings(max_examples=60, deadline=None)
@given(
    dist=st.floats(1.5, 4.0), gap=st.floats(0.5, 0.9), front=st.booleans(), speed=st.floats(0.5, 1.5),
    angle=st.floats(-0.6, 0.6), split=st.floats(0.0, 0.7), seed=st.integers(0, 2**16),
)
def test_a_standing_track_is_never_carried_off_by_someone_walking_past_while_her_legs_are_seen(
    dist, gap, front, speed, angle, split, seed,
):
    """He walks past her at walking speed, 0.5-0.9 m in front of her (between her and the robot: only the
    leg of hers beside him shows for a moment) or behind her; near her his legs may show apart as lone
    legs. Her own legs are seen at every scan."""
    _kept(*_run(Tracks(), dist, gap, front, speed, angle, seed, 0.45, 0.0, split), dist)


@settings(max_examples=250, deadline=None)
@given(
    dist=st.floats(1.5, 4.0), gap=st.floats(0.5, 0.9), speed=st.floats(0.5, 1.5), angle=st.floats(-0.6, 0.6),
    hidden=st.floats(0.2, 0.4), split=st.floats(0.0, 0.7), seed=st.integers(0, 2**16),
)
def test_a_standing_track_hidden_a_moment_by_someone_walking_past_in_front_keeps_her(dist, gap, speed, angle, hidden, split, seed):
    """As above, in front of her: his body hides her whole while he is within ``hidden`` of her line of
    sight, then the lone leg of hers beside him shows. Fails on main 5a86edb (her track, coasting while
    hidden, took his legs under the contact allowance and its "stopped" hypothesis and walked off with him)."""
    _kept(*_run(Tracks(), dist, gap, True, speed, angle, seed, 0.45, hidden, split), dist, 0.45)


def test_a_walker_passing_close_in_front_of_someone_standing_keeps_both_tracks():
    """A case that swapped on main: he passes 0.5 m in front of her at 0.6 m/s, hiding her for a moment."""
    hers, fed, off, tracks = _run(Tracks(), 2.0, 0.5, True, 0.6, -0.4, 0, 0.45, 0.4, 0.5)
    _kept(hers, fed, off, tracks, 2.0, 0.45)
    assert len([tk for tk in tracks.tracks if tk.confirmed]) == 2


def test_someone_standing_who_starts_walking_keeps_her_track():
    """The rule is about candidates another walking track explains: a person standing alone who walks off is
    followed by her own track as before."""
    tracks = Tracks()
    for k in range(60):
        t = k * DT
        x = 2.0 + max(0.0, t - 2.0) * 0.9
        tracks.step(t, np.array([[x, 0.3]]), np.array([PAIR], dtype=np.int8))
    assert len(tracks) == 1 and abs(tracks.x[0, 0] - x) < 0.1 and tracks.x[0, 2] > 0.6
