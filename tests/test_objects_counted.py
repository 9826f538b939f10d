"""Three or more like objects close together are as many candidates (fresh11/rail_three_books).

Three like books 0.25 m apart on a sideboard, seen at a slant from 2 m, were two candidates: the
cuts by bearing and by depth each cut two at a time, and neither axis alone told the middle book
from its neighbours, so the robot asked "the book on the left or the one on the right?".
The camera reports each object once per frame: a group whose frames hold k detections holds k
objects (:func:`robot.objects.resolve._split_counted`), and k like objects the camera can resolve
are k candidates, each at its own object, never at a point between two."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robot.objects.gestures import CAMERA_HEIGHT, camera_to_map
from robot.objects.resolve import BEARING_NOISE, COLOURS, RANGE_NOISE, merge, option_texts, Wanted

POSE = (0.0, 0.0, 0.0)
Z = 0.9  # a sideboard's top
#: the camera's resolvable spacing: neighbours this many of its own noises apart (bearing and log slant range)
RESOLVABLE = 2.5


def _look(objects, seed, n=15, z=Z, pose=POSE):
    """``n`` frames of the camera at ``pose`` seeing every object once (bearing noise 1 deg, distance 6 %)."""
    rng = np.random.default_rng(seed)
    dets, frames = [], []
    for f in range(n):
        for ox, oy in objects:
            dx, dy = ox - pose[0], oy - pose[1]
            b = math.atan2(dy, dx) - pose[2] + rng.normal(0, BEARING_NOISE)
            sl = math.hypot(math.hypot(dx, dy), CAMERA_HEIGHT - z) * (1 + rng.normal(0, RANGE_NOISE))
            x, y = camera_to_map(pose, b, sl, z)
            dets.append(("book", x, y, z, tuple(np.clip(np.array(COLOURS["blue"]) + rng.normal(0, 0.04, 3), 0, 1))))
            frames.append(0.1 * f)
    return dets, frames


def _apart(a, b, z=Z):
    """Two spots' distance in the camera's own noises (bearing, log slant range), seen from POSE."""
    def polar(p):
        return math.atan2(p[1], p[0]), math.log(math.hypot(math.hypot(p[0], p[1]), CAMERA_HEIGHT - z))
    (ba, ra), (bb, rb) = polar(a), polar(b)
    return math.hypot(math.remainder(ba - bb, 2 * math.pi) / BEARING_NOISE, (ra - rb) / RANGE_NOISE)


def _row(k, dist, spacing, slant):
    """``k`` objects in a row ``spacing`` apart, its middle ``dist`` ahead, the row ``slant`` off
    square to the line of sight (0: side by side across it; near 90 deg: one behind the other)."""
    c, s = math.cos(math.radians(slant)), math.sin(math.radians(slant))
    ux, uy = s, c  # the row's direction: across the line of sight (y) turned towards it (x)
    return [(dist + (i - (k - 1) / 2) * spacing * ux, (i - (k - 1) / 2) * spacing * uy) for i in range(k)]


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), k=st.integers(3, 4), dist=st.floats(1.2, 3.0), spacing=st.floats(0.12, 0.4),
       slant=st.floats(0.0, 75.0), n=st.integers(10, 25))
@example(seed=0, k=3, dist=2.5, spacing=0.2, slant=0.0, n=15)  # side by side, 4.6 deg apart
def test_k_like_objects_the_camera_can_resolve_are_k_candidates_each_at_its_own(seed, k, dist, spacing, slant, n):
    objects = _row(k, dist, spacing, slant)
    gaps = [_apart(a, b) for a, b in zip(objects, objects[1:])]
    if min(gaps) < RESOLVABLE:
        return  # closer than the camera resolves: the rule promises nothing here (fewer candidates, and one between two
        #        objects does occur: review25 F-H found it in 10 of 53 such rows, as on main before obj24)
    dets, frames = _look(objects, seed, n)
    cands = merge(dets, POSE[:2], eye_height=CAMERA_HEIGHT, frames=frames)
    assert len(cands) == k
    # one candidate at each object, measured in the camera's own noises (its range is 6 % of the
    # distance, its bearing 1 deg), each at most half as far from its own object as from any other:
    # a point between two objects is as far from both
    near = []
    for c in cands:
        d = sorted((_apart((c.x, c.y), o), i) for i, o in enumerate(objects))
        assert d[0][0] < 0.5 * d[1][0]
        near.append(d[0][1])
    assert sorted(near) == list(range(k))


def test_the_three_books_seen_at_a_slant_are_three_and_the_question_names_the_middle_one():
    # fresh11/rail_three_books: the robot at (7.4, 1.0) facing the sideboard's three books at
    # x 5.1, 5.35, 5.6 (y 0.33): 1.5 bearing noises and 2 range noises apart.
    pose = (7.4, 1.0, math.pi)
    books = [(5.1, 0.33), (5.35, 0.33), (5.6, 0.33)]
    right = 0
    for seed in range(20):
        dets, frames = _look(books, seed, 20, pose=pose)
        cands = merge(dets, pose[:2], eye_height=CAMERA_HEIGHT, frames=frames)
        for c in cands:  # never a point between two books
            assert min(abs(c.x - bx) for bx, _ in books) < 0.125
        if len(cands) == 3:
            right += 1
            texts = option_texts(cands, Wanted(type="book"), pose)
            middle = min(range(3), key=lambda i: abs(cands[i].x - 5.35))
            assert "in the middle" in texts[middle]
            assert sum("in the middle" in t for t in texts) == 1
    assert right >= 16  # on main: 4 of 20 (two candidates, "left or right")
