"""The pan-tilt camera against the world: frontal faces, occlusion, range, pan, objects, gestures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.world.bodies import HumanBody, Pointing
from robot.hardware.camera import (
    CameraSpec,
    PanTilt,
    camera_point,
    detect_faces,
    detect_gestures,
    detect_objects,
    detect_torsos,
    ptu_step,
)
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
