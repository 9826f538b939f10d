"""The pan-tilt camera against the world: frontal faces, occlusion, range, pan, objects, gestures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from homesim.world.bodies import HumanBody, Pointing
from homesim.world.raycast import Prisms, sight_lines_clear
from homesim.world.world import Obstacle
from robot.hardware.camera import (
    CameraSpec,
    PanTilt,
    camera_point,
    detect_faces,
    detect_frame,
    detect_gestures,
    detect_objects,
    detect_torsos,
    image_extent,
    image_rise,
    ptu_step,
)
from tests.conftest import examples
from tests.world_helpers import at_bearing, put_person, room

SPEC = CameraSpec()


def _cam(world):
    return camera_point(world.robot.pose, SPEC)[:2]


@settings(max_examples=25)
@given(bearing=st.floats(-22, 22), distance=st.floats(0.8, 3.8), seed=st.integers(0, 2**32 - 1))
def test_face_at_known_bearing_is_detected_within_noise(bearing, distance, seed):
    world = room()
    cam = _cam(world)
    x, y = at_bearing(cam, 0.0, math.radians(bearing), distance)
    put_person(world, "ann", x, y, look_at=cam)
    faces = detect_faces(world, world.robot.pose, PanTilt(), SPEC, np.random.default_rng(seed))
    assert len(faces) == 1
    f = faces[0]
    true_dist = math.hypot(distance, world.humans["ann"].face_z - SPEC.height)
    assert abs(math.degrees(f.bearing) - bearing) < 4 * math.degrees(SPEC.bearing_noise) + 0.5
    assert abs(f.distance - true_dist) < 4 * SPEC.distance_noise * true_dist
    assert abs(f.height - world.humans["ann"].face_z) < 4 * SPEC.height_noise


def test_person_facing_away_gives_no_face_but_a_torso():
    world = room()
    put_person(world, "ann", 3.0, 3.0, heading=0.0)  # back to the robot
    assert detect_faces(world, world.robot.pose, PanTilt(), SPEC, None) == []
    torsos = detect_torsos(world, world.robot.pose, PanTilt(), SPEC, np.random.default_rng(0))
    assert len(torsos) == 1 and torsos[0].bearing == pytest.approx(0.0, abs=0.1)
    assert torsos[0].colour[0] > 0.7 and torsos[0].colour[2] < 0.3  # yellow


@pytest.mark.parametrize("turn,seen", [(0, True), (20, True), (28, True), (35, False), (90, False)])
def test_only_frontal_faces_are_detected(turn, seen):
    world = room()
    cam = _cam(world)
    put_person(world, "ann", 3.0, 3.0, look_at=cam)
    h = world.humans["ann"]
    h.look(h.heading + math.radians(turn))  # turn only the head
    faces = detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)
    assert (len(faces) == 1) is seen


def test_wall_occludes_a_face():
    world = room()
    world.place_robot(3.0, 5.2, 0.0)
    cam = _cam(world)
    put_person(world, "ann", 6.5, 5.2, look_at=cam)  # behind the partition at x = 5
    assert detect_faces(world, world.robot.pose, PanTilt(), SPEC, None) == []
    # Beside the partition, in plain view (the robot turns to her).
    world.place_robot(3.0, 5.2, math.atan2(3.6 - 5.2, 6.0 - 3.0))
    put_person(world, "ann", 6.0, 3.6, look_at=_cam(world))
    assert len(detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)) == 1


def test_faces_only_between_half_a_metre_and_four_metres():
    world = room()
    cam = _cam(world)
    for d, seen in ((0.45, False), (1.0, True), (3.9, True), (4.6, False)):
        put_person(world, "ann", cam[0] + d, cam[1], look_at=cam)
        faces = detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)
        assert (len(faces) == 1) is seen, d


def test_face_outside_the_field_of_view_needs_the_camera_to_pan():
    world = room()
    cam = _cam(world)
    x, y = at_bearing(cam, 0.0, math.radians(50), 2.0)
    put_person(world, "ann", x, y, look_at=cam)
    assert detect_faces(world, world.robot.pose, PanTilt(), SPEC, None) == []
    ptu = PanTilt(target_pan=math.radians(50))
    for _ in range(10):  # 1 s at 80 deg/s is enough for 50 deg
        ptu = ptu_step(ptu, 0.1, SPEC)
    assert ptu.pan == pytest.approx(math.radians(50))
    faces = detect_faces(world, world.robot.pose, ptu, SPEC, None)
    assert len(faces) == 1 and math.degrees(faces[0].bearing) == pytest.approx(50, abs=0.5)


def test_pan_tilt_respects_speed_and_limits():
    ptu = PanTilt(target_pan=math.radians(170), target_tilt=math.radians(-60))
    ptu = ptu_step(ptu, 0.5, SPEC)
    assert math.degrees(ptu.pan) == pytest.approx(40)
    assert math.degrees(ptu.tilt) == pytest.approx(-25)
    for _ in range(10):
        ptu = ptu_step(ptu, 0.5, SPEC)
    assert math.degrees(ptu.pan) == pytest.approx(100)


def test_another_person_hides_a_face_behind_them():
    world = room()
    cam = _cam(world)
    put_person(world, "ann", 4.0, 3.0, look_at=cam)
    bob = HumanBody(world.space, "bob", 2.5, 3.0, 0.0, height=1.9, torso=(0, 0, 0), speed=1.0)
    world.humans["bob"] = bob
    names = [f.truth for f in detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)]
    assert "ann" not in names


def test_objects_are_detected_with_a_configurable_confusion():
    world = room()
    world.humans["ann"].remove()
    world.place_robot(2.2, 2.6, math.atan2(1.0 - 2.6, 3.6 - 2.2))
    ptu = PanTilt(tilt=math.radians(-25))
    found = detect_objects(world, world.robot.pose, ptu, SPEC, np.random.default_rng(1), confusion=0.0)
    cups = [o for o in found if o.truth == "cup"]
    assert len(cups) == 1 and cups[0].type == "cup" and abs(cups[0].bearing) < math.radians(4)
    always = detect_objects(world, world.robot.pose, ptu, SPEC, np.random.default_rng(1), confusion=1.0)
    assert [o.type for o in always if o.truth == "cup"] == ["book"]


def test_pointing_gesture_seen_when_the_hand_is_in_view():
    world = room()
    cam = _cam(world)
    put_person(world, "ann", 2.8, 2.0, look_at=cam)
    h = world.humans["ann"]
    h.pointing = Pointing("cup", world.object_point("cup"), until=5.0)
    ptu = PanTilt(pan=math.atan2(2.0 - 3.0, 2.8 - 1.05), tilt=math.radians(-5))
    g = detect_gestures(world, world.robot.pose, ptu, SPEC, np.random.default_rng(2))
    assert len(g) == 1 and g[0].target == "cup"
    true_dir = math.atan2(1.0 - 2.0, 3.6 - 2.8)
    assert abs(g[0].direction - true_dir) < 4 * SPEC.direction_noise
    h.pointing = None
    assert detect_gestures(world, world.robot.pose, ptu, SPEC, None) == []


# ------------------------------------------------------- occlusion with heights
def _add_person(world, name, x, y, height):
    world.humans[name] = HumanBody(world.space, name, x, y, 0.0, height=height, torso=(0, 0, 0), speed=1.0)


def test_a_child_between_does_not_hide_an_adults_face_a_tall_adult_does():
    """The review's child.py: any person hid faces, whatever their height (2D circles)."""
    for height, hidden in ((0.9, False), (1.3, False), (1.9, True)):
        world = room()
        put_person(world, "ann", 4.0, 3.0, look_at=_cam(world))  # face at 1.58 m
        _add_person(world, "kid", 2.5, 3.0, height)
        names = [f.truth for f in detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)]
        assert ("ann" not in names) is hidden, height


def test_furniture_hides_a_face_only_if_the_sight_line_passes_through_it():
    base = room()
    base.humans["ann"].remove()
    cam = camera_point(base.robot.pose, SPEC)
    for top, hidden in ((0.8, False), (1.5, False), (1.6, True)):
        world = room()
        put_person(world, "ann", 4.5, 3.0, look_at=cam[:2])  # face at 1.58 m
        # A sideboard across the sight line at x 3.0-3.4: the line is at about 1.52 m there.
        world.obstacles.append(Obstacle("sideboard", "furniture", np.array([[3.0, 2.6], [3.4, 2.6], [3.4, 3.4], [3.0, 3.4]]), 0.0, top))
        world._prisms = None
        names = [f.truth for f in detect_faces(world, world.robot.pose, PanTilt(), SPEC, None)]
        assert ("ann" not in names) is hidden, top


def test_the_camera_sees_under_a_table_top_but_not_through_it():
    world = room()
    world.humans["ann"].remove()
    obstacles = world.prisms
    cam = (1.0, 1.0, 1.41)  # looking along the table (x 3.0-4.2, top 0.70-0.75 m)
    on_top = (3.6, 1.0, 0.76)  # just above the top: seen from above
    under = (3.6, 1.0, 0.3)  # the line dips under the top's edge (0.56 m there) and stays under
    through = (4.0, 1.0, 0.65)  # the line enters the footprint at 0.9 m: it must cross the top
    inside = (3.6, 1.0, 0.72)  # in the top itself
    clear = sight_lines_clear(cam, np.array([on_top, under, through, inside]), obstacles)
    assert clear.tolist() == [True, True, False, False]
    low_cam = (2.0, 1.0, 0.4)  # a low viewpoint sees under the table to its far side
    assert sight_lines_clear(low_cam, np.array([(5.0, 1.0, 0.4)]), obstacles)[0]


def _sampled_clear(origin, target, box, cyl):
    """Brute force: sample the line finely; blocked if a sample is inside the box or the cylinder."""
    t = np.linspace(0.0, 1.0, 4001)[:-1]
    p = np.asarray(origin)[None, :] + t[:, None] * (np.asarray(target) - np.asarray(origin))[None, :]
    (x0, y0, x1, y1, b, top), (cx, cy, r, h) = box, cyl
    in_box = (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1) & (p[:, 2] >= b) & (p[:, 2] <= top)
    in_cyl = ((p[:, 0] - cx) ** 2 + (p[:, 1] - cy) ** 2 <= r * r) & (p[:, 2] <= h)
    return not (in_box.any() or in_cyl.any())


_xy = st.floats(0.0, 6.0)
_z = st.floats(0.0, 2.5)


@settings(max_examples=examples(200, 1000))
@given(
    origin=st.tuples(_xy, _xy, _z),
    target=st.tuples(_xy, _xy, _z),
    box=st.tuples(_xy, _xy, st.floats(0.1, 2.0), st.floats(0.1, 2.0), _z, st.floats(0.05, 2.0)),
    cyl=st.tuples(_xy, _xy, st.floats(0.05, 0.5), _z),
)
def test_sight_lines_agree_with_sampling_the_line(origin, target, box, cyl):
    x0, y0, w, d, bottom, tall = box
    inflate = lambda e: ((x0 - e, y0 - e, x0 + w + e, y0 + d + e, bottom - e, bottom + tall + e), (cyl[0], cyl[1], cyl[2] + e, cyl[3] + e))  # noqa: E731
    inner, outer = _sampled_clear(origin, target, *inflate(-0.01)), _sampled_clear(origin, target, *inflate(0.01))
    assume(inner == outer)  # not a grazing line
    assume(math.dist(origin[:2], (cyl[0], cyl[1])) > cyl[2] + 0.01)  # the viewpoint is not inside the person
    prism = Prisms([np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + d], [x0, y0 + d]])], [bottom], [bottom + tall])
    got = sight_lines_clear(origin, np.array([target]), prism, np.array([cyl[:2]]), np.array([cyl[2]]), np.array([cyl[3]]), margin=0.0)
    assert bool(got[0]) == inner


def _uncull(prisms):
    """The same prisms with boxes that can cull nothing (the kernel then tests every prism)."""
    out = prisms.subset(np.arange(len(prisms)))
    out.lo = np.full_like(out.lo, -np.inf)
    out.hi = np.full_like(out.hi, np.inf)
    out.bottom, out.top = prisms.bottom.copy(), prisms.top.copy()
    return out


@settings(max_examples=examples(100, 400))
@given(
    origin=st.tuples(_xy, _xy, _z),
    targets=st.lists(st.tuples(_xy, _xy, _z), min_size=1, max_size=6),
    boxes=st.lists(st.tuples(_xy, _xy, st.floats(0.1, 2.0), st.floats(0.1, 2.0), _z, st.floats(0.05, 2.0)), min_size=1, max_size=5),
    cyls=st.lists(st.tuples(_xy, _xy, st.floats(0.05, 0.5), _z), max_size=4),
)
def test_sight_lines_are_per_line_and_culling_changes_nothing(origin, targets, boxes, cyls):
    """Each line's answer is the same asked alone or with others, and with or without box culling."""
    prisms = Prisms([np.array([[x, y], [x + w, y], [x + w, y + d], [x, y + d]]) for x, y, w, d, _, _ in boxes],
                    [b for *_, b, _ in boxes], [b + t for *_, b, t in boxes])
    c = np.array([k[:2] for k in cyls]).reshape(-1, 2)
    r, top = np.array([k[2] for k in cyls]), np.array([k[3] for k in cyls])
    tg = np.array(targets)
    skip = np.zeros((len(targets), len(cyls)), dtype=bool)
    if len(cyls):
        skip[0, 0] = True
    together = sight_lines_clear(origin, tg, prisms, c, r, top, skip=skip)
    alone = [bool(sight_lines_clear(origin, tg[i:i + 1], prisms, c, r, top, skip=skip[i:i + 1])[0]) for i in range(len(tg))]
    assert together.tolist() == alone
    # (Culled cylinders are checked against brute-force sampling above.)
    assert together.tolist() == sight_lines_clear(origin, tg, _uncull(prisms), c, r, top, skip=skip).tolist()


# A person: bearing from where the camera looks (rad), distance (m), gaze away from the camera (rad), height (m).
_spot = st.tuples(st.floats(-0.5, 0.5), st.floats(0.6, 4.5), st.floats(-0.8, 0.8), st.floats(0.9, 2.0))


@settings(max_examples=examples(30, 150), deadline=None)
@given(
    people=st.lists(_spot, min_size=0, max_size=4),
    pointing=st.lists(st.booleans(), min_size=4, max_size=4),
    robot=st.tuples(st.floats(0.8, 2.5), st.floats(0.8, 5.0), st.floats(-math.pi, math.pi)),
    ptu=st.tuples(st.floats(-1.7, 1.7), st.floats(-0.4, 0.4)),
    seed=st.integers(0, 2**32 - 1),
)
def test_one_frame_equals_each_kind_detected_in_turn(people, pointing, robot, ptu, seed):
    """detect_frame asks every kind's sight lines in one pass; the detections and the random
    numbers drawn must be exactly those of the four per-kind detectors called in turn."""
    world = room()
    world.place_robot(*robot)
    cam = camera_point(world.robot.pose, SPEC)
    for i, (bearing, distance, gaze, height) in enumerate(people):
        x, y = at_bearing(cam[:2], robot[2] + ptu[0], bearing, distance)
        _add_person(world, f"p{i}", x, y, height)
        world.humans[f"p{i}"].turn_to(math.atan2(cam[1] - y, cam[0] - x) + gaze)
        if pointing[i]:
            world.humans[f"p{i}"].pointing = Pointing("cup", world.object_point("cup"), until=5.0)
    pose, pt = world.robot.pose, PanTilt(pan=ptu[0], tilt=ptu[1])
    one, each = np.random.default_rng(seed), np.random.default_rng(seed)
    frame = detect_frame(world, pose, pt, SPEC, one, confusion=0.3)
    assert frame.faces == detect_faces(world, pose, pt, SPEC, each)
    assert frame.torsos == detect_torsos(world, pose, pt, SPEC, each)
    assert frame.gestures == detect_gestures(world, pose, pt, SPEC, each)
    assert frame.objects == detect_objects(world, pose, pt, SPEC, each, confusion=0.3)
    assert one.random() == each.random()  # the same numbers drawn, no more, no fewer


def _plain_frame(world, pose, ptu, spec, rng, confusion):
    """The frame computed the plain way: each kind in turn, each point's direction on its own
    (:func:`_look`), each sight line asked alone, then that kind's noise: the reference the
    batched :func:`detect_frame` must reproduce float for float."""
    from homesim.geometry import wrap_angle
    from robot.hardware.camera import (FaceDetection, GestureDetection, ObjectDetection, TorsoDetection, _in_view, _look,
                                       confuse, visible)

    cam, th = camera_point(pose, spec), pose[2]
    people = [h for h in world.humans.values() if h.present]

    def seen(point, who):
        return bool(visible(world, cam, np.array([point]), exclude=[who])[0])

    def colour(rgb):
        if rng is None:
            return tuple(float(c) for c in rgb)
        return tuple(float(c) for c in np.clip(np.array(rgb, dtype=float) + rng.normal(0.0, spec.colour_noise, 3), 0.0, 1.0))

    faces = []
    for h, (b, e, d) in [(h, _look(cam, th, h.face_point())) for h in people]:
        f = h.face_point()
        frontal = abs(wrap_angle(h.gaze - math.atan2(cam[1] - f[1], cam[0] - f[0]))) <= spec.frontal
        if frontal and _in_view(b, e, ptu, spec) and spec.face_range[0] <= d <= spec.face_range[1] and seen(f, h.name):
            z = float(f[2])
            if rng is not None:
                b += float(rng.normal(0.0, spec.bearing_noise))
                d *= float(1.0 + rng.normal(0.0, spec.distance_noise))
                z += float(rng.normal(0.0, spec.height_noise))
            faces.append(FaceDetection(float(wrap_angle(b)), max(0.1, d), z, h.name))
    torsos = []
    for h in people:
        p = (*h.position, h.torso_z)
        b, e, d = _look(cam, th, p)
        if _in_view(b, e, ptu, spec) and spec.torso_range[0] <= d <= spec.torso_range[1] and seen(p, h.name):
            if rng is not None:
                b += float(rng.normal(0.0, spec.bearing_noise * 2))
            torsos.append(TorsoDetection(float(wrap_angle(b)), colour(h.torso), h.name))
    gestures = []
    for h in people:
        hand = h.hand_point()
        if hand is None or h.pointing is None:
            continue
        b, e, d = _look(cam, th, hand)
        if _in_view(b, e, ptu, spec) and d <= spec.gesture_range and seen(hand, h.name):
            arm = np.array(hand) - np.array([*h.position, h.shoulder_z])
            direction = math.atan2(arm[1], arm[0]) - th
            arm_elev = math.atan2(arm[2], math.hypot(arm[0], arm[1]))
            if rng is not None:
                direction += float(rng.normal(0.0, spec.direction_noise))
                arm_elev += float(rng.normal(0.0, spec.direction_noise))
                b += float(rng.normal(0.0, spec.bearing_noise))
            gestures.append(GestureDetection(float(wrap_angle(b)), d, float(wrap_angle(direction)), arm_elev, float(hand[2]), h.name,
                                             h.pointing.target_name))
    objects = []
    types = sorted({o.type for o in world.objects.values()})
    for n, o in world.objects.items():
        p = world.object_point(n)
        b, e, d = _look(cam, th, p)
        if _in_view(b, e, ptu, spec) and spec.object_range[0] <= d <= spec.object_range[1] and seen((p[0], p[1], p[2] + o.height / 2), None):
            d0 = d
            if rng is not None:
                b += float(rng.normal(0.0, spec.bearing_noise))
                d *= float(1.0 + rng.normal(0.0, spec.distance_noise))
            rgb = colour(o.colour)
            objects.append(ObjectDetection(confuse(o.type, types, confusion, rng), rgb, float(wrap_angle(b)), max(0.05, d), o.name, image_extent(o.size, d0, spec),
                                           image_rise(cam, (p[0], p[1], p[2] + o.height / 2), o.height, spec)))
    return faces, torsos, gestures, objects


_anyone = st.tuples(st.floats(0.3, 5.7), st.floats(0.3, 5.7), st.floats(-1.2, 1.2), st.floats(0.8, 2.1), st.booleans(),
                    st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)))


@settings(max_examples=examples(30, 150), deadline=None)
@given(
    people=st.lists(_anyone, max_size=5),
    robot=st.tuples(st.floats(0.5, 5.5), st.floats(0.5, 5.5), st.floats(-4.0, 4.0)),
    target=st.tuples(st.sampled_from([-2.0, 2.0, 0.0]) | st.floats(-2.0, 2.0), st.sampled_from([-0.6, 0.6]) | st.floats(-0.5, 0.5)),
    first_at_edge=st.booleans(),
    noisy=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
def test_one_frame_equals_the_plain_per_point_computation(people, robot, target, first_at_edge, noisy, seed):
    """detect_frame batches directions and sight lines over every kind; anywhere in the room
    (people behind the robot, at the field of view's edge, hiding each other; the pan-tilt
    driven to its limits) it must give the plain per-point computation's detections, float for
    float, with the same random numbers drawn."""
    world = room()
    world.place_robot(*robot)
    pose = world.robot.pose
    cam = camera_point(pose, SPEC)
    ptu = ptu_step(PanTilt(target_pan=target[0], target_tilt=target[1]), 100.0, SPEC)  # at the limits when beyond them
    for i, (x, y, gaze, height, pointing, torso) in enumerate(people):
        if first_at_edge and i == 0:  # exactly on the image's left edge, 2 m away
            edge = pose[2] + ptu.pan + SPEC.hfov / 2
            x, y = cam[0] + 2.0 * math.cos(edge), cam[1] + 2.0 * math.sin(edge)
        world.humans[f"p{i}"] = HumanBody(world.space, f"p{i}", x, y, 0.0, height=height, torso=torso, speed=1.0)
        world.humans[f"p{i}"].turn_to(math.atan2(cam[1] - y, cam[0] - x) + gaze)
        if pointing:
            world.humans[f"p{i}"].pointing = Pointing("cup", world.object_point("cup"), until=5.0)
    one, each = (np.random.default_rng(seed), np.random.default_rng(seed)) if noisy else (None, None)
    frame = detect_frame(world, pose, ptu, SPEC, one, confusion=0.3, occluders=world.person_cylinders())
    assert (frame.faces, frame.torsos, frame.gestures, frame.objects) == _plain_frame(world, pose, ptu, SPEC, each, 0.3)
    if noisy:
        assert one.random() == each.random()
