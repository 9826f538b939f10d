"""The sonar rings (robot/hardware/sonar.py) and the blind-half rule every base command keeps (robot/blindside.py).

The robot has no laser behind the laser's line; the people it touched there (contacts9: someone
within 5 cm of its side or back while it backed off or turned) are what the sonar is for. The
closed-loop property below places a person anywhere beside or behind the robot, hears them with the
real sensor model (exact ranges) and checks that any command the rule lets through keeps the
footprint off their body.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
import pytest
from lxml import etree

from robot.blindside import BLIND_X, SonarEchoes, blind_clear, blind_points, explained_by_points, near_arcs
from robot.footprint import BODY, footprint_distance, sweep_poses
from robot.hardware.channels import SCHEMAS
from robot.hardware.sonar import PEOPLEBOT_RING, Sonar, SonarSpec, sonar_element, sonar_readings
from robot.contract import SONAR

LEG_RADIUS, LEG_SPREAD = 0.06, 0.10


class FakeWorld:
    """What the sonar reads of a world: wall segments at its height and people's leg circles."""

    def __init__(self, segments: list[tuple[tuple[float, float], tuple[float, float]]] = (), legs: list[tuple[float, float]] = ()) -> None:
        self._a = np.array([s[0] for s in segments], dtype=float).reshape(-1, 2)
        self._b = np.array([s[1] for s in segments], dtype=float).reshape(-1, 2)
        self._c = np.array(legs, dtype=float).reshape(-1, 2)

    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        return self._a, self._b

    def leg_circles(self) -> tuple[np.ndarray, np.ndarray]:
        return self._c, np.full(len(self._c), LEG_RADIUS)


def person_legs(x: float, y: float, heading: float) -> list[tuple[float, float]]:
    c, s = math.cos(heading), math.sin(heading)
    return [(x - s * LEG_SPREAD, y + c * LEG_SPREAD), (x + s * LEG_SPREAD, y - c * LEG_SPREAD)]


def ring_xml(world: FakeWorld, spec: SonarSpec = SonarSpec()) -> etree._Element:
    """One packet with every transducer's exact reading, the robot at the origin facing +x."""
    which = tuple(range(len(spec.transducers)))
    return sonar_element(0.0, spec, 0, which, sonar_readings(world, (0.0, 0.0, 0.0), spec, which, None))


def test_a_wall_behind_is_read_by_the_rear_ring_at_its_distance():
    spec = SonarSpec()
    world = FakeWorld(segments=[((-1.0, -3.0), (-1.0, 3.0))])  # a wall 1 m behind the centre
    r = sonar_readings(world, (0.0, 0.0, 0.0), spec, tuple(range(16)), None)
    # transducers 11 and 12 face 170 and -170 degrees from x = -0.255: the nearest point in the cone is
    # straight behind (the cone spans the wall's normal)
    assert abs(r[11] - 0.745) < 1e-6 and abs(r[12] - 0.745) < 1e-6
    # the front ring's forward transducers hear nothing
    assert r[3] == spec.max_range and r[4] == spec.max_range


def test_a_person_beside_is_heard_by_the_side_transducer_and_readings_are_clipped():
    spec = SonarSpec()
    world = FakeWorld(legs=person_legs(-0.1, -0.55, 0.0))  # beside the right rear, legs across the beam
    r = sonar_readings(world, (0.0, 0.0, 0.0), spec, (15,), None)
    assert 0.15 < r[0] < 0.30  # transducer 15 at (-0.10, -0.215) facing -90 degrees
    close = FakeWorld(legs=[(-0.1, -0.30)])  # a leg 2.5 cm from the transducer: inside the ring-down
    assert sonar_readings(close, (0.0, 0.0, 0.0), spec, (15,), None)[0] == spec.min_range


def test_noise_and_dropouts_come_from_the_generator_handed_in():
    spec = SonarSpec()
    world = FakeWorld(segments=[((-1.0, -3.0), (-1.0, 3.0))])
    which = tuple(range(16)) * 50
    a = sonar_readings(world, (0.0, 0.0, 0.0), spec, which, np.random.default_rng(7))
    b = sonar_readings(world, (0.0, 0.0, 0.0), spec, which, np.random.default_rng(7))
    assert np.array_equal(a, b)
    exact = sonar_readings(world, (0.0, 0.0, 0.0), spec, which, None)
    lost = (a == spec.max_range) & (exact < spec.max_range)
    assert 0.005 < lost.mean() < 0.08  # the dropout rate, about spec.dropout
    kept = (exact < spec.max_range) & ~lost
    assert 0.0 < np.abs(a[kept] - exact[kept]).mean() < 0.05


def test_each_ring_fires_every_transducer_once_a_cycle_and_packets_keep_its_clock():
    spec = SonarSpec()
    fired = [i for k in range(spec.per_ring) for i in spec.firing(k)]
    assert sorted(fired) == list(range(len(PEOPLEBOT_RING)))
    sonar = Sonar.__new__(Sonar)
    sonar.spec = spec
    assert sum(sonar.due(seq) for seq in range(100)) == round(100 / spec.rate / spec.fire_interval)
    assert all(sonar.due(seq) in (2, 3) for seq in range(100))


def test_the_packet_satisfies_its_schema():
    spec = SonarSpec()
    el = ring_xml(FakeWorld(segments=[((-1.0, -3.0), (-1.0, 3.0))]), spec)
    schema = etree.XMLSchema(etree.parse(str(SCHEMAS[SONAR])))
    assert schema.validate(el), schema.error_log
    bad = etree.fromstring(etree.tostring(el))
    bad[0].set("range", "-1")
    assert not schema.validate(bad)


def test_echoes_are_kept_in_odometry_and_forgotten_when_old():
    world = FakeWorld(legs=person_legs(-0.7, 0.0, math.pi / 2))  # behind the robot
    echoes = SonarEchoes()
    echoes.update(ring_xml(world), (0.0, 0.0, 0.0), 0.0)
    arcs = echoes.arcs((0.0, 0.0, 0.0), 0.1)
    assert arcs and min(float(a[:, 0].min()) for a in arcs) < -0.4
    # the robot turned half round in place: what was behind is now ahead
    turned = echoes.arcs((0.0, 0.0, math.pi), 0.2)
    assert max(float(a[:, 0].max()) for a in turned) > 0.4
    assert echoes.arcs((0.0, 0.0, 0.0), 1.0) == []  # older than ECHO_AGE


def test_an_echo_the_floor_plan_explains_is_not_a_body():
    world = FakeWorld(segments=[((-0.45, -3.0), (-0.45, 3.0))])  # a wall 0.2 m behind the rear
    echoes = SonarEchoes()
    echoes.update(ring_xml(world), (0.0, 0.0, 0.0), 0.0)
    arcs = echoes.arcs((0.0, 0.0, 0.0), 0.0)
    wall = np.column_stack((np.full(121, -0.45), np.linspace(-3.0, 3.0, 121)))
    assert len(blind_points(arcs)) and not len(blind_points(arcs, explained_by_points(wall)))


def test_backing_into_someone_heard_behind_is_refused_and_driving_away_allowed():
    world = FakeWorld(legs=person_legs(-0.62, 0.0, math.pi / 2))
    echoes = SonarEchoes()
    echoes.update(ring_xml(world), (0.0, 0.0, 0.0), 0.0)
    pts = blind_points(echoes.arcs((0.0, 0.0, 0.0), 0.0))
    assert len(pts) and (pts[:, 0] < BLIND_X).all()
    assert not blind_clear(-0.2, 0.0, pts, duration=0.5)
    assert blind_clear(0.3, 0.0, pts, duration=0.5)
    assert blind_clear(0.0, 0.0, pts, duration=0.5)


@settings(max_examples=300, deadline=None)
@given(bearing=st.floats(math.radians(75), math.radians(285)), air=st.floats(0.0, 0.6), heading=st.floats(0, 2 * math.pi),
       v=st.floats(-0.3, 0.0), w=st.floats(-0.8, 0.8))
@example(bearing=2.03125, air=0.0, heading=0.0, v=0.0, w=-0.125)  # pressed against the flank at 116 degrees: 3 mm in with a 0.30 m gap
def test_a_command_the_rule_lets_through_never_touches_someone_beside_or_behind(bearing, air, heading, v, w):
    """Someone stands anywhere beside or behind the robot, both legs behind the laser's line (``air`` m of air
    between body and footprint), heard by the real sensor model; a back-off or turn the rule clears
    never brings the footprint into their body (0.25 m round their centre) while the modules hold it, one
    control period, before they decide again. It fails without the rule (backing at 0.2 m/s into
    someone 1 cm behind is a touch within 0.1 s). Held open loop for the whole 0.5 s the rule looks
    ahead, a turn past someone pressed against the flank can end a few millimetres into them: a
    reading's arc stands for the leg it heard, not for the body round it (stated in robot/blindside.py)."""
    # the body centre at the given air off the footprint, along the bearing
    ux, uy = math.cos(bearing), math.sin(bearing)
    lo, hi = 0.0, 3.0
    for _ in range(50):
        mid = (lo + hi) / 2
        if float(footprint_distance(np.array([mid * ux]), np.array([mid * uy]))[0]) - BODY < air:
            lo = mid
        else:
            hi = mid
    cx, cy = hi * ux, hi * uy
    legs = person_legs(cx, cy, heading)
    assume(all(x < BLIND_X for x, _ in legs))  # a leg ahead of the laser's line is the laser's (the modules' people rules)
    packet = ring_xml(FakeWorld(legs=legs))
    # heard: the ring's cones have gaps (between the 90 and 130 degree transducers a leg pressed
    # against the flank can fall in none): the rule can only keep off someone the sonar hears
    assume(any(float(e.get("range")) < SonarSpec().max_range for e in packet))
    echoes = SonarEchoes()
    echoes.update(packet, (0.0, 0.0, 0.0), 0.0)
    pts = blind_points(echoes.arcs((0.0, 0.0, 0.0), 0.0))
    if not blind_clear(v, w, pts, duration=0.5):
        return
    # the modules hold a command one control period (0.1 s) and decide again on the next readings
    x, y, th = sweep_poses(v, w, 0.1)
    c, s = np.cos(th), np.sin(th)
    dx, dy = cx - x, cy - y
    gaps = footprint_distance(c * dx + s * dy, -s * dx + c * dy) - BODY
    assert gaps.min() >= min(0.0, float(gaps[0])) - 1e-3, (cx, cy, gaps.min())


def test_a_packet_in_one_pass_reads_what_ray_by_ray_casting_reads_float_for_float():
    """The module casts a packet's rays in one pass (cast_from); RayCaster, one transducer at a time, is the
    reference: the same floats, so traces do not depend on which is used."""
    from homesim.world.raycast import RayCaster

    rng = np.random.default_rng(3)
    spec = SonarSpec()
    for _ in range(300):
        segs = [((rng.uniform(-4, 4), rng.uniform(-4, 4)), (rng.uniform(-4, 4), rng.uniform(-4, 4))) for _ in range(rng.integers(0, 30))]
        legs = [(rng.uniform(-2, 2), rng.uniform(-2, 2)) for _ in range(rng.integers(0, 6))]
        world = FakeWorld(segments=segs, legs=legs)
        pose = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-math.pi, math.pi))
        which = tuple(int(i) for i in rng.choice(16, size=5, replace=False))
        assert np.array_equal(sonar_readings(world, pose, spec, which, None), sonar_readings(world, pose, spec, which, None, caster=RayCaster()))


def test_readings_kept_at_a_pose_are_the_floats_of_casting_anew():
    """The module keeps the walls' part of each transducer's readings while the robot stands still
    (SegmentRanges) and its rays per pose: with people moving, walls swapped and the robot now still, now
    moving, every packet reads bit for bit what a fresh cast reads (traces must not depend on the cache)."""
    from robot.hardware.sonar import SegmentRanges

    rng = np.random.default_rng(5)
    spec, kept = SonarSpec(), SegmentRanges()
    world = None
    pose = (0.0, 0.0, 0.0)
    for step in range(400):
        if world is None or rng.random() < 0.05:  # new walls (read-only, as the world's)
            segs = [((rng.uniform(-5, 5), rng.uniform(-5, 5)), (rng.uniform(-5, 5), rng.uniform(-5, 5))) for _ in range(rng.integers(0, 30))]
            world = FakeWorld(segments=segs)
            world._a.flags.writeable = world._b.flags.writeable = False
        world._c = np.array([(rng.uniform(-2, 2), rng.uniform(-2, 2)) for _ in range(rng.integers(0, 6))]).reshape(-1, 2)
        if rng.random() < 0.3:  # the robot moves now and then, and stands still in between
            pose = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-math.pi, math.pi))
        which = spec.firing(step) + spec.firing(step + 1) + (spec.firing(step + 2) if step % 2 else ())
        got = sonar_readings(world, pose, spec, which, None, kept=kept)
        want = sonar_readings(world, pose, spec, which, None)
        assert got.tobytes() == want.tobytes(), (step, which)


@given(exact=st.lists(st.floats(0.0, 6.0) | st.sampled_from([0.0, -0.0, 0.1, 5.0]), max_size=12), seed=st.integers(0, 2**16))
@settings(max_examples=200, deadline=None)
def test_the_noise_step_in_floats_gives_the_array_expressions_floats(exact, seed):
    """The readings' noise and dropouts are added in Python floats (``noisy``); the array expressions
    they replace are the reference: the same bytes for any readings and draws."""
    from robot.hardware.sonar import noisy

    spec = SonarSpec()
    rng = np.random.default_rng(seed)
    out = np.array(exact, dtype=float)
    noise = rng.normal(0.0, 3.0, len(exact))
    lost = rng.random(len(exact)) < 0.2
    want = np.where(out < spec.max_range, out + noise * (spec.noise + spec.noise_per_m * out), out)
    want = np.clip(np.where(lost, spec.max_range, want), spec.min_range, spec.max_range)
    got = np.array(noisy(out.tolist(), noise.tolist(), lost.tolist(), spec), dtype=float)
    assert got.tobytes() == want.tobytes()


@given(seed=st.integers(0, 2**16), odom=st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-4, 4)))
@settings(max_examples=60, deadline=None)
def test_the_typed_packet_says_what_its_xml_says(seed, odom):
    """The sonar sends its packet as a typed record (robot.sonar_packet): a receiver keeping echoes from the
    record keeps the floats one reading its XML keeps (the trace's document), the record's size is its XML's,
    and no receiver can change it for the others."""
    from robot.hardware.sonar import sonar_packet
    from robot.sonar_packet import echoes_of

    rng = np.random.default_rng(seed)
    spec = SonarSpec()
    legs = [(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)) for _ in range(rng.integers(0, 5))]
    world = FakeWorld(segments=[((-0.8, -3.0), (-0.8, 3.0)), ((-3.0, 0.9), (3.0, 0.9))], legs=legs)
    which = spec.firing(seed) + spec.firing(seed + 1) + spec.firing(seed + 2)
    packet = sonar_packet(seed * 0.1, spec, seed, which, sonar_readings(world, odom, spec, which, rng))
    xml = packet.to_xml()
    assert packet.echoes() == echoes_of(xml) and packet.size() == len(etree.tostring(xml))
    assert [packet.get(k) for k in ("seq", "time", "min_range", "max_range", "cone", "height")] == \
        [xml.get(k) for k in ("seq", "time", "min_range", "max_range", "cone", "height")]
    typed, plain = SonarEchoes(), SonarEchoes()
    for _ in range(2):  # the second time from the arcs kept for the packet's other receivers
        typed.update(packet, odom, 1.0)
        plain.update(etree.fromstring(etree.tostring(xml)), odom, 1.0)
        got, want = typed.arcs(odom, 1.0), plain.arcs(odom, 1.0)
        assert len(got) == len(want) and all(g.tobytes() == w.tobytes() for g, w in zip(got, want))
    with pytest.raises(AttributeError):
        packet.rows = ()
    for _, px, py, _r, _b in near_arcs(packet):  # shared by every receiver: read-only
        with pytest.raises(ValueError):
            px[0] = 0.0
