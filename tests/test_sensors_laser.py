"""The laser against the world's geometry: legs, table tops, walls, pymunk agreement."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.world.bodies import LASER_FILTER, LEG_RADIUS
from homesim.world.raycast import FanCaster, RayCaster, cast_rays
from homesim.world.reference_legs import detect_leg_pairs
from robot.hardware.laser import LaserSpec, laser_origin, simulate_scan
from tests.conftest import examples
from tests.world_helpers import at_bearing, put_person, room

SPEC = LaserSpec()


def test_scan_has_361_beams_over_180_degrees():
    b = SPEC.bearings()
    assert b.shape == (361,)
    assert b[0] == pytest.approx(-math.pi / 2) and b[-1] == pytest.approx(math.pi / 2)


@settings(max_examples=25)
@given(bearing=st.floats(-70, 70), distance=st.floats(1.0, 3.5), seed=st.integers(0, 2**32 - 1))
def test_person_at_known_bearing_shows_up_as_a_leg_pair(bearing, distance, seed):
    world = room()
    pose = world.robot.pose
    origin = laser_origin(pose, SPEC)
    x, y = at_bearing(origin, pose[2], math.radians(bearing), distance)
    # Keep the person clear of the table (its legs are leg-like too) and inside the room.
    if not (0.5 < x < 7.5 and 0.5 < y < 5.5) or (2.6 < x < 4.6 and y < 1.9):
        return
    put_person(world, "ann", x, y, look_at=origin)
    ranges = simulate_scan(world, pose, SPEC, np.random.default_rng(seed))
    pairs = [p for p in detect_leg_pairs(ranges, SPEC.bearings()) if not p.single]
    errors = [(abs(math.degrees(p.bearing) - bearing), abs(p.distance - distance)) for p in pairs]
    assert any(db < 2.0 and dd < 0.12 for db, dd in errors), (bearing, distance, pairs)


def test_nobody_there_means_no_leg_pair_in_the_open():
    world = room()
    put_person(world, "ann", 7.0, 5.0, heading=0.0)
    world.humans["ann"].remove()
    ranges = simulate_scan(world, world.robot.pose, SPEC, np.random.default_rng(1))
    pairs = [p for p in detect_leg_pairs(ranges, SPEC.bearings()) if not p.single]
    assert pairs == []


def test_walking_legs_swing_but_stay_a_pair():
    world = room()
    h = world.humans["ann"]
    put_person(world, "ann", 3.5, 3.0, heading=math.pi / 2)
    seps = []
    for _ in range(40):
        h.walk_velocity(0.0, 1.0)  # across the laser's view; the gait follows the distance walked
        world.step()
        legs = h.leg_centres()
        seps.append(float(np.dot(legs[0] - legs[1], (0.0, 1.0))))
    assert max(seps) > 0.15 and min(seps) < -0.15  # alternating gait, stride about 0.6 m


def test_table_top_is_invisible_but_its_legs_and_the_cupboard_are_not():
    world = room()
    world.humans["ann"].remove()
    pose = world.robot.pose
    origin = laser_origin(pose, SPEC)
    b = SPEC.bearings()
    exact = simulate_scan(world, pose, SPEC, None)
    # Beams through the middle of the table (between its legs) pass under the top.
    centre = np.arctan2(1.0 - origin[1], 3.6 - origin[0])
    near = np.argmin(np.abs(b - centre))
    far_edge = math.hypot(4.2 - origin[0], 0.6 - origin[1])
    assert exact[near] > far_edge
    # The cupboard reaches the floor: its front face stops the beam.
    cup = np.arctan2(0.5 - origin[1], 7.0 - origin[0])
    i = np.argmin(np.abs(b - cup))
    assert exact[i] < math.hypot(7.0 - origin[0], 0.5 - origin[1])
    # The table's legs show up as small objects in front of the far wall.
    legs = [p for p in detect_leg_pairs(exact, b) if p.single]
    assert len(legs) >= 2


def test_noise_is_about_one_centimetre_and_seeded():
    world = room()
    pose = world.robot.pose
    exact = simulate_scan(world, pose, SPEC, None)
    a = simulate_scan(world, pose, SPEC, np.random.default_rng(5))
    b = simulate_scan(world, pose, SPEC, np.random.default_rng(5))
    assert np.array_equal(a, b)
    hit = exact < SPEC.max_range
    assert 0.007 < float(np.std(a[hit] - exact[hit])) < 0.013
    assert np.all(a <= SPEC.max_range)


@settings(max_examples=40)
@given(x=st.floats(0.3, 7.7), y=st.floats(0.3, 5.7), heading=st.floats(-math.pi, math.pi))
@example(x=6.5, y=0.5, heading=0.0)  # on a piece of furniture's corner: pymunk says range 0
def test_numpy_laser_matches_pymunk_segment_queries(x, y, heading):
    world = room()
    put_person(world, "ann", 5.5, 2.0, heading=1.0)
    origin = (x, y)
    # Only origins outside every obstacle are meaningful for a laser; one on an
    # obstacle's surface (pymunk reports alpha 0, the kernel culls back faces)
    # is not either, so keep a millimetre clear.
    if world.space.point_query_nearest(origin, 1e-3, LASER_FILTER) is not None:
        return
    angles = SPEC.bearings()[::8] + heading
    ours = world.laser_ranges(origin, angles, SPEC.max_range)
    for ang, r in zip(angles, ours):
        end = (x + SPEC.max_range * math.cos(ang), y + SPEC.max_range * math.sin(ang))
        info = world.space.segment_query_first(origin, end, 0.0, LASER_FILTER)
        theirs = SPEC.max_range if info is None else info.alpha * SPEC.max_range
        assert r == pytest.approx(theirs, abs=1e-6)


@settings(max_examples=40)
@given(
    segs=st.lists(st.tuples(*[st.floats(-5, 5)] * 4), min_size=0, max_size=6),
    circles=st.lists(st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(0.05, 0.5)), min_size=0, max_size=4),
)
def test_raycast_kernel_matches_pymunk_for_random_geometry(segs, circles):
    space = pymunk.Space()
    # A ray along a lone segment's own line is the kernel's documented blind spot
    # (closed polygons catch it with the neighbouring edge): keep lines off the origin.
    segs = [s for s in segs if math.hypot(s[2] - s[0], s[3] - s[1]) > 1e-3 and abs(s[0] * (s[3] - s[1]) - s[1] * (s[2] - s[0])) / math.hypot(s[2] - s[0], s[3] - s[1]) > 1e-3]
    circles = [c for c in circles if math.hypot(c[0], c[1]) > c[2] + 1e-3]
    for ax, ay, bx, by in segs:
        space.add(pymunk.Segment(space.static_body, (ax, ay), (bx, by), 0.0))
    for cx, cy, r in circles:
        space.add(pymunk.Circle(space.static_body, r, (cx, cy)))
    angles = np.linspace(-math.pi, math.pi, 73) + 0.0123  # off the round numbers Hypothesis likes (grazing end points are ties)
    a = np.array([s[:2] for s in segs]).reshape(-1, 2)
    b = np.array([s[2:] for s in segs]).reshape(-1, 2)
    c = np.array([ci[:2] for ci in circles]).reshape(-1, 2)
    r = np.array([ci[2] for ci in circles])
    ours = cast_rays((0.0, 0.0), angles, a, b, c, r, 10.0)
    reused = RayCaster()
    reused.cast((0.0, 0.0), angles[:5], a, b, c, r, 10.0)  # buffers from a smaller call
    again = reused.cast((0.0, 0.0), angles, a, b, c, r, 10.0)
    assert np.array_equal(ours, again)
    for ang, got in zip(angles, ours):
        info = space.segment_query_first((0, 0), (10 * math.cos(ang), 10 * math.sin(ang)), 0.0, pymunk.ShapeFilter())
        want = 10.0 if info is None else info.alpha * 10.0
        assert got == pytest.approx(want, abs=1e-6)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)), min_size=1, max_size=4),
       st.floats(-math.pi, math.pi))
def test_cached_static_ranges_equal_casting_everything_together(moves, heading):
    """The laser keeps its walls-and-furniture ranges per pose; people moving in front of a robot
    standing still must still show exactly as a full cast shows them (bit for bit)."""
    world = room()
    name = next(iter(world.humans))
    spec = LaserSpec()
    origin = laser_origin((*world.robot.pose[:2], heading), spec)
    angles = spec.bearings() + heading
    a, b = world._laser_segments
    for dx, dy in moves:
        put_person(world, name, origin[0] + dx, origin[1] + dy, heading=0.0)
        got = world.laser_ranges(origin, angles, spec.max_range)
        c, r = world.leg_circles()
        want = RayCaster().cast(origin, angles, a, b, c, r, spec.max_range, backfaces=False)
        assert np.array_equal(got, want)


_coord = st.floats(-6.0, 6.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(
    segs=st.lists(st.tuples(_coord, _coord, _coord, _coord), max_size=10),
    circles=st.lists(st.tuples(_coord, _coord, st.floats(0.02, 0.8)), max_size=9),
    origin=st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)),
    start=st.floats(-4.0, 4.0),
    fan=st.sampled_from([(361, math.radians(0.5)), (46, math.radians(4.0)), (7, 0.3), (2, 1.0)]),
    max_range=st.sampled_from([8.19, 2.5, math.inf]),
    backfaces=st.booleans(),
)
@example(segs=[(1.0, -1.0, 1.0, 1.0)], circles=[(0.0, 0.0, 0.5)], origin=(0.0, 0.0), start=-1.5, fan=(361, math.radians(0.5)),
         max_range=8.19, backfaces=True)  # the origin inside a circle: every beam reads 0
@example(segs=[(-1.0, 0.0, 1.0, 0.0), (2.0, -3.0, 2.0, 3.0)], circles=[], origin=(0.0, 0.0), start=-3.0, fan=(361, math.radians(0.5)),
         max_range=2.0, backfaces=True)  # on a segment's line; a wall exactly at max_range
@example(segs=[(-2.0, -1.0, -2.0, 1.0)], circles=[(-1.0, 0.05, 0.1)], origin=(0.0, 0.0), start=-math.pi / 2, fan=(361, math.radians(0.5)),
         max_range=8.19, backfaces=False)  # straight behind the fan's centre
def test_fan_caster_gives_the_dense_kernels_floats(segs, circles, origin, start, fan, max_range, backfaces):
    """The laser's sparse caster meets each obstacle only with the beams inside the angle it
    subtends; every range must still be the dense kernel's float, bit for bit."""
    n, step = fan
    angles = start + step * np.arange(n)
    a = np.array([s[:2] for s in segs]).reshape(-1, 2)
    b = np.array([s[2:] for s in segs]).reshape(-1, 2)
    c = np.array([ci[:2] for ci in circles]).reshape(-1, 2)
    r = np.array([ci[2] for ci in circles])
    want = RayCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces)
    fc = FanCaster()
    assert np.array_equal(fc.cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces), want)
    if not backfaces:
        # scan(): the segments' part kept per origin, circles cast again each time
        assert np.array_equal(fc.scan(origin, angles, a, b, c, r, max_range), want)
        assert np.array_equal(fc.scan(origin, angles.copy(), a.copy(), b.copy(), c, r, max_range), want)
        assert np.array_equal(fc.scan(origin, angles, a, b, c[:0], r[:0], max_range), RayCaster().cast(origin, angles, a, b, max_range=max_range, backfaces=False))


def test_fan_caster_falls_back_to_the_dense_kernel_off_an_even_fan():
    world = room()
    origin = laser_origin(world.robot.pose, SPEC)
    a, b = world._laser_segments
    c, r = world.leg_circles()
    for angles in (np.sort(np.random.default_rng(3).uniform(-3, 3, 50)), np.linspace(-math.pi, math.pi, 73)):
        want = RayCaster().cast(origin, angles, a, b, c, r, SPEC.max_range, backfaces=False)
        assert FanCaster().fan(angles) is None
        assert np.array_equal(FanCaster().scan(origin, angles, a, b, c, r, SPEC.max_range), want)


_wide = st.floats(-20.0, 20.0, allow_nan=False)


@settings(max_examples=examples(40, 300), deadline=None)
@given(
    segs=st.lists(st.tuples(_wide, _wide, _wide, _wide), max_size=8),
    circles=st.lists(st.tuples(_wide, _wide, st.floats(0.0, 30.0)), max_size=5),
    origin=st.tuples(st.sampled_from([0.0, 0.5]) | _wide, st.sampled_from([0.0, 0.5]) | _wide),
    start=st.floats(-10.0, 10.0),
    n=st.integers(2, 400),
    span=st.floats(1e-5, 2 * math.pi),
    max_range=st.sampled_from([8.19, 2.5, 30.0, math.inf]),
    backfaces=st.booleans(),
    snap=st.sampled_from(["none", "end at origin", "origin on line", "tangent to first beam", "tangent to last beam"]),
)
def test_fan_caster_matches_the_dense_kernel_on_any_fan_and_geometry(segs, circles, origin, start, n, span, max_range, backfaces, snap):
    """Any evenly spaced fan (up to a whole turn, any start: across the +-pi wrap), segments
    that end at the laser or lie on a line through it, circles from a point to 30 m across,
    around the laser or tangent to the fan's edge beams: the sparse caster's ranges are the
    dense kernel's floats."""
    step = span / (n - 1)
    angles = start + step * np.arange(n)
    ox, oy = origin
    rows = []
    for ax, ay, bx, by in segs:
        if snap == "end at origin":
            ax, ay = ox, oy
        elif snap == "origin on line":
            bx, by = 2 * ox - ax, 2 * oy - ay
        rows.append((ax, ay, bx, by))
    circ = []
    for cx, cy, r in circles:
        if snap.startswith("tangent"):
            edge = angles[0] if snap.endswith("first beam") else angles[-1]
            r = abs(math.sin(math.atan2(cy - oy, cx - ox) - edge)) * math.hypot(cx - ox, cy - oy)
        circ.append((cx, cy, r))
    a = np.array([s[:2] for s in rows]).reshape(-1, 2)
    b = np.array([s[2:] for s in rows]).reshape(-1, 2)
    c = np.array([ci[:2] for ci in circ]).reshape(-1, 2)
    r = np.array([ci[2] for ci in circ])
    want = RayCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces)
    fc = FanCaster()
    assert np.array_equal(fc.cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces), want)
    if not backfaces:
        assert np.array_equal(fc.scan(origin, angles, a, b, c, r, max_range), want)


@pytest.mark.parametrize("max_range", [8.19, math.inf])
@pytest.mark.parametrize(
    "origin, legs, radii",
    [
        ((0.0, 0.0), [[math.nan, 0.0], [1.0, 0.2]], [0.1, 0.1]),  # a leg whose position went NaN
        ((0.0, 0.0), [[1.0, math.inf]], [0.1]),
        ((math.nan, 0.0), [[1.0, 0.2]], [0.1]),  # the laser's own pose went NaN
        ((0.0, math.inf), [[1.0, 0.2]], [0.1]),
        ((0.0, 0.0), [[1.0, 0.2]], [math.nan]),
    ],
)
def test_fan_caster_agrees_with_the_dense_kernel_on_non_finite_geometry(origin, legs, radii, max_range):
    """The dense kernel reads a NaN leg or wall as no echo; the sparse caster must not raise
    instead (math.floor of a NaN subtended angle, a NaN beam count cast to an integer) nor
    read anything else."""
    angles = SPEC.bearings()
    a, b = np.array([[2.0, -1.0], [2.0, 1.0], [math.nan, 0.0]]), np.array([[2.0, 1.0], [-2.0, 1.0], [1.0, -1.0]])
    c, r = np.array(legs), np.array(radii)
    with np.errstate(invalid="ignore", over="ignore"):
        want = RayCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=False)
        assert np.array_equal(FanCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=False), want, equal_nan=True)
        assert np.array_equal(FanCaster().scan(origin, angles, a, b, c, r, max_range), want, equal_nan=True)


def test_fan_caster_recasts_the_walls_when_a_read_only_view_changes_underneath():
    """Segments are recognised by identity only when nobody can change them: a read-only view
    of a writeable array changes with it, and the kept static ranges must not outlive that."""
    angles = SPEC.bearings()
    base_a, base_b = np.array([[2.0, 1.0]]), np.array([[2.0, -1.0]])  # facing the origin
    a, b = base_a.view(), base_b.view()
    a.flags.writeable = b.flags.writeable = False
    fc, no_c, no_r = FanCaster(), np.zeros((0, 2)), np.zeros(0)
    fc.scan((0.0, 0.0), angles, a, b, no_c, no_r, SPEC.max_range)
    base_a[0], base_b[0] = (1.0, 1.0), (1.0, -1.0)  # the wall moves nearer
    want = RayCaster().cast((0.0, 0.0), angles, a, b, max_range=SPEC.max_range, backfaces=False)
    assert want[180] == pytest.approx(1.0)
    assert np.array_equal(fc.scan((0.0, 0.0), angles, a, b, no_c, no_r, SPEC.max_range), want)


@settings(max_examples=examples(20, 100), deadline=None)
@given(st.floats(0.5, 7.5), st.floats(0.5, 5.5), st.floats(-math.pi, math.pi), st.floats(0.0, 3.0), st.booleans())
def test_leg_circles_are_each_persons_leg_centres(x, y, heading, walked, present):
    """The laser's legs, gathered in plain floats, are the people's own leg centres bit for bit
    (mid-stride too), and nobody absent is cast."""
    world = room()
    h = world.humans["ann"]
    put_person(world, "ann", x, y, heading=heading)
    h.walk_velocity(math.cos(heading), math.sin(heading))
    h.advance(walked)
    if not present:
        h.remove()
    c, r = world.leg_circles()
    if present:
        assert c.tobytes() == h.leg_centres().tobytes()
        assert r.tolist() == [LEG_RADIUS, LEG_RADIUS]
    else:
        assert c.shape == (0, 2) and r.shape == (0,)
