"""Issue 26 item 5: the partner is never asked to choose between two detections of one thing.

The camera reports each object once per frame, so two objects side by side are seen together in
nearly every frame and one object's detections never are (:func:`robot.objects.resolve.merge`
with ``frames``); one object's detections stand on one surface (:func:`one_surface`)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robot.objects.attention import one_surface
from robot.objects.gestures import CAMERA_HEIGHT, camera_to_map
from robot.objects.resolve import COLOURS, merge

POSE = (1.7, 2.0, 0.0)


def _look(objects, seed, outliers=(), n=12, z=0.8):
    """``n`` frames of the camera seeing ``objects`` (one detection each per frame); ``outliers``:
    (frame, bearing error in degrees) of the first object, the tail of a real camera's noise."""
    rng = np.random.default_rng(seed)
    dets, frames = [], []
    extra = dict(outliers)
    for f in range(n):
        for k, (ox, oy) in enumerate(objects):
            dx, dy = ox - POSE[0], oy - POSE[1]
            err = extra.get(f, None) if k == 0 else None
            b = math.atan2(dy, dx) - POSE[2] + (math.radians(err) if err is not None else rng.normal(0, math.radians(1.0)))
            sl = math.hypot(math.hypot(dx, dy), CAMERA_HEIGHT - z) * (1 + rng.normal(0, 0.06))
            x, y = camera_to_map(POSE, b, sl, z)
            dets.append(("cup", x, y, z, tuple(np.clip(np.array(COLOURS["yellow"]) + rng.normal(0, 0.04, 3), 0, 1))))
            frames.append(0.2 * f)
    return dets, frames


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), dist=st.floats(1.2, 3.0),
       outliers=st.lists(st.tuples(st.integers(0, 11), st.floats(2.0, 4.0) | st.floats(-4.0, -2.0)), max_size=3, unique_by=lambda o: o[0]))
@example(seed=0, dist=2.3, outliers=[(3, 3.5), (6, 1.0), (9, 0.8)])
def test_one_mug_seen_with_stray_bearings_is_one_candidate(seed, dist, outliers):
    dets, frames = _look([(POSE[0] + dist, 2.0)], seed, outliers)
    cands = merge(dets, POSE[:2], min_share=0.0, eye_height=CAMERA_HEIGHT, frames=frames)
    assert len(cands) == 1
    assert cands[0].n == len(dets)


# show_again_walking seed 0 (main b8ffc4b): the camera's twelve detections of ONE yellow mug on a
# counter (map x, y, z as placed), one per frame, seen from (3.8325, 1.7079).
SEED0 = [(6.257, 1.217, 0.95), (6.168, 1.326, 0.95), (6.104, 1.306, 0.95), (6.098, 1.445, 0.05), (5.952, 1.228, 0.95),
         (6.157, 1.282, 0.05), (6.133, 1.341, 0.95), (6.300, 1.276, 0.95), (6.157, 1.255, 0.95), (6.194, 1.292, 0.95),
         (6.135, 1.231, 0.95), (5.956, 1.313, 0.95)]


def test_the_mug_that_was_offered_as_two_is_one():
    dets = [("cup", x, y, z, COLOURS["yellow"]) for x, y, z in SEED0]
    origin = (3.8325, 1.7079)
    # Without the frames (the rule before) the two-group split took three stray bearings for a second mug:
    assert len(merge(dets, origin, eye_height=CAMERA_HEIGHT)) == 2
    # They were never in the same frame: one mug.
    (one,) = merge(dets, origin, eye_height=CAMERA_HEIGHT, frames=[0.2 * k for k in range(len(dets))])
    assert math.hypot(one.x - 6.15, one.y - 1.3) < 0.1


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), sep=st.floats(0.12, 0.5))
def test_two_mugs_side_by_side_seen_together_stay_two(seed, sep):
    cups = [(3.45, 2.0 - sep / 2), (3.45, 2.0 + sep / 2)]
    dets, frames = _look(cups, seed, n=20)
    cands = merge(dets, POSE[:2], eye_height=CAMERA_HEIGHT, frames=frames)
    near = [min(range(2), key=lambda i: abs(c.y - cups[i][1])) for c in cands]
    assert set(near) == {0, 1}
    assert all(abs(c.y - cups[i][1]) < sep * 0.45 for c, i in zip(cands, near))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), low=st.sets(st.integers(0, 11), max_size=4))
def test_one_mugs_detections_stand_on_one_surface(seed, low):
    """A mug on a 0.9 m counter: a few detections placed on the floor (past the counter's edge by
    the range error) are placed again on the counter, where most of its detections stand."""
    rng = np.random.default_rng(seed)
    mug = (4.0, 2.1)
    seen, rays = [], []
    for f in range(12):
        dx, dy = mug[0] - POSE[0], mug[1] - POSE[1]
        b = math.atan2(dy, dx) - POSE[2] + rng.normal(0, math.radians(1.0))
        sl = math.hypot(math.hypot(dx, dy), CAMERA_HEIGHT - 0.95) * (1 + rng.normal(0, 0.06))
        z = 0.05 if f in low else 0.95
        x, y = camera_to_map(POSE, b, sl, z)
        seen.append(("cup", x, y, z, COLOURS["yellow"], None))
        rays.append((POSE, b, sl))
    placed = one_surface(seen, rays)
    assert all(d[3] == 0.95 for d in placed)
    for d, (pose, b, sl) in zip(placed, rays):
        assert (d[1], d[2]) == camera_to_map(pose, b, sl, 0.95)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), near=st.floats(0.9, 2.6), ratio=st.floats(1.25, 1.6), bearing=st.floats(-0.5, 0.5),
       n=st.integers(10, 20))
@example(seed=0, near=1.5, ratio=1.25, bearing=0.0, n=12)
@example(seed=1102, near=1.0, ratio=1.25, bearing=0.0, n=10)
def test_two_mugs_one_behind_the_other_are_never_stored_between_them(seed, near, ratio, bearing, n):
    """Two mugs on one line of sight from the camera, one behind the other, at a depth separation the
    camera resolves (slant ranges 25 % or more apart, about four of its 6 % distance noises, seen in ten frames
    or more): their
    bearings agree, and the range gate once let them run into one candidate at the point between
    them. Now each is a candidate at its own place (the partner can be asked which), never one at a
    midpoint."""
    eye = CAMERA_HEIGHT - 0.8
    slant = math.hypot(near, eye) * ratio
    far = math.sqrt(slant * slant - eye * eye)
    if far > 3.3:  # beyond the camera's object range
        return
    c, s = math.cos(bearing), math.sin(bearing)
    mugs = [(POSE[0] + near * c, POSE[1] + near * s), (POSE[0] + far * c, POSE[1] + far * s)]
    dets, frames = _look(mugs, seed, n=n)
    cands = merge(dets, POSE[:2], eye_height=CAMERA_HEIGHT, frames=frames)
    sep = far - near
    # the midpoint is 0.5 sep from either mug; a candidate is the mean of its own detections (6 % range noise, and
    # now and then one frame's detections in swapped order): CI's draw seed=1102, near=1.0, ratio=1.25 put the far
    # one 0.11 m = 0.33 sep off its mug, nearer its own mug than the midpoint by far. 0.4 sep: that mug's, not between
    for cand in cands:
        assert min(math.hypot(cand.x - mx, cand.y - my) for mx, my in mugs) < 0.4 * sep, "a candidate stored between the two mugs"
    own = {min(range(2), key=lambda i: math.hypot(cand.x - mugs[i][0], cand.y - mugs[i][1])) for cand in cands}
    assert own == {0, 1}


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), near=st.floats(1.0, 2.5), ratio=st.floats(1.0, 1.6), bearing=st.floats(-0.5, 0.5),
       n=st.integers(10, 20))
@example(seed=0, near=2.4, ratio=1.12, bearing=0.0, n=10)
def test_two_mugs_too_close_in_depth_are_never_taken_for_one(seed, near, ratio, bearing, n):
    """Two mugs one behind the other at any depth separation, down to none: a candidate nearer the
    point between them than either mug (and more than 0.1 m from both) is marked ``two``: the camera saw
    two things there (two detections in most frames), and carries its two parts, front and back, each
    the mean of its own detections (the options of the which-one question): the object attention never
    stores the point between them (that is checked through ``find`` in test_object_two_never_stored.py).
    (A part split off by depth whose mean the per-frame ordering pushed past its mug is that mug's, not
    between them.)"""
    eye = CAMERA_HEIGHT - 0.8
    slant = math.hypot(near, eye) * ratio
    far = math.sqrt(slant * slant - eye * eye)
    c, s = math.cos(bearing), math.sin(bearing)
    mugs = [(POSE[0] + near * c, POSE[1] + near * s), (POSE[0] + far * c, POSE[1] + far * s)]
    dets, frames = _look(mugs, seed, n=n)
    cands = merge(dets, POSE[:2], eye_height=CAMERA_HEIGHT, frames=frames)
    mid = ((mugs[0][0] + mugs[1][0]) / 2, (mugs[0][1] + mugs[1][1]) / 2)
    for cand in cands:
        off = min(math.hypot(cand.x - mx, cand.y - my) for mx, my in mugs)
        at_one = off < 0.1 or off < math.hypot(cand.x - mid[0], cand.y - mid[1])
        assert at_one or cand.two, "a candidate between the two mugs, not marked as two"
        if cand.two:
            front, back = cand.parts
            rf, rb = (math.hypot(p.x - POSE[0], p.y - POSE[1]) for p in (front, back))
            assert rf <= rb, "the front part of a two lies behind its back part"


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), dist=st.floats(1.0, 3.0), n=st.integers(8, 20))
def test_one_mug_is_never_marked_two(seed, dist, n):
    """One mug, seen once per frame: never taken for two things the camera could not tell apart (the
    robot would drive round it for nothing)."""
    dets, frames = _look([(POSE[0] + dist, POSE[1])], seed, n=n)
    assert not any(c.two for c in merge(dets, POSE[:2], eye_height=CAMERA_HEIGHT, frames=frames))
