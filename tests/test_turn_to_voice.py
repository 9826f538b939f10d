"""The robot turns to whoever talks to it and looks where it is shown (issue 26 items 3, 5, 10, 11; lane turn9).

Fixed cases that fail on main a045923: a greeting from behind, read in front by the two microphones,
turned the robot nowhere ("I can't see you"); a person whose legs a sofa hides from the laser was no
person at all; an object pointed at behind the robot was never looked at. Properties for the two
memories behind the voice search (robot/attention/looking.py), and end-to-end runs of the scenes
written for it (scenarios/turn/, one seed each; the rates over seeds 0-9 are in the branch's report).
Ground truth is read only here, in the tests, never by the robot."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from homesim.tour.runner import RunOptions, run_file
from robot.attention.cues import CueSpec, Hysteresis
from robot.attention.fsm import AttentionFSM
from robot.attention.looking import HeardFrom, LookedAt, angle_between
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import FACE, Tracks, TrackerSpec

SCENES = Path(__file__).resolve().parent.parent / "scenarios" / "turn"
angles = st.floats(-math.pi, math.pi, allow_nan=False)


# ---------------------------------------------------------------- the memories
@settings(max_examples=60, deadline=None)
@given(angles, st.floats(math.radians(10), math.radians(40)), angles)
def test_a_direction_in_the_cameras_field_without_a_face_is_looked_at_and_empty(centre, half, probe):
    looked = LookedAt()
    looked.observe(5.0, centre, half, [], math.radians(10))
    off = angle_between(probe, centre)
    if off <= half - looked.width:
        assert looked.empty_since(probe, 5.0) and not looked.face_since(probe, 0.0)
    elif off >= half + looked.width:
        assert not looked.empty_since(probe, -1e9)
    assert not looked.empty_since(probe, 5.1)  # not looked at since


@settings(max_examples=60, deadline=None)
@given(angles, st.floats(-math.radians(15), math.radians(15)))
def test_a_face_seen_in_a_direction_makes_it_not_empty_until_it_is_looked_at_again_without_one(centre, at):
    looked = LookedAt()
    face = centre + at
    looked.observe(1.0, centre, math.radians(22), [], math.radians(10))
    looked.observe(2.0, centre, math.radians(22), [face], math.radians(10))
    assert looked.face_since(face, 2.0) and not looked.empty_since(face, 0.0)
    looked.observe(3.0, centre, math.radians(22), [], math.radians(10))
    assert looked.empty_since(face, 3.0)


@settings(max_examples=60, deadline=None)
@given(angles, angles, st.floats(0.0, 8.0), st.booleans())
def test_a_person_where_a_voice_came_from_lately_was_its_speaker_unless_in_view_then(front, probe, later, in_view):
    heard = HeardFrom(keep=4.0)
    back = math.pi - front
    heard.add(10.0, front, back, [7] if in_view else [])
    tol, within = math.radians(12), 4.0
    near = min(angle_between(probe, front), angle_between(probe, back)) <= tol
    assert heard.recall(10.0 + later, probe, 7, within, tol) == (near and later <= within and not in_view)
    for k in range(10):  # bounded: a long run keeps only the last keep seconds
        heard.add(11.0 + k, 0.0, math.pi, [])
    assert len(heard) == 5  # 16..20 s


@settings(max_examples=80, deadline=None)
@given(heading=angles, spoke=st.integers(1, 40), others=st.lists(st.tuples(angles, st.integers(1, 3)), max_size=4),
       gap=st.floats(0.0, 4.0), rate=st.sampled_from([10.0, 20.0]))
def test_a_voice_is_recalled_for_its_whole_recall_whatever_was_heard_after_it(heading, spoke, others, gap, rate):
    """review9 item 3: the memory was 32 readings, so a radio talking on after her (10 Hz, 3.2 s) made the
    robot forget her voice before voice_recall (4 s) ended. Now it is kept by age: recalled while within
    the recall, whatever else was heard since; and it stays bounded by what the recall can hold."""
    heard = HeardFrom(keep=4.0)
    t = 0.0
    for _ in range(spoke):
        heard.add(t, heading, math.pi - heading, [])
        t += 1 / rate
    last = t - 1 / rate
    while t <= last + gap:  # other voices from elsewhere, several a frame
        for bearing, n in others:
            for _ in range(n):
                heard.add(t, bearing, math.pi - bearing, [])
        t += 1 / rate
    now = last + gap
    assume(now - last <= 4.0)  # gap 4.0 can come out 4.000000000001 s after her voice in floats: past the recall
    assert heard.recall(now, heading, 7, 4.0, math.radians(12))
    assert len(heard) <= (4.0 * rate + 2) * max(1, sum(n for _, n in others))


# ---------------------------------------------------------------- the attention, fixed cases
def _alone(t: float = 1.0) -> PersonAttention:
    """A person attention looking around (bottom-up), nobody tracked, the robot at the odom origin facing +x."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.cues = CueSpec()
    a.fsm = AttentionFSM()
    a.tracks = Tracks(TrackerSpec())
    a.partner = None
    a._odom = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    a._voice_turn = None
    a.looked, a.heard = LookedAt(), HeardFrom()
    a.facing = Hysteresis(CueSpec().facing_on, CueSpec().facing_off)
    return a


def test_a_voice_read_in_front_where_the_camera_sees_nobody_is_looked_for_behind():
    """Ines greets 1.2 m behind the robot: the pair reads her voice 10 deg in front, where the camera
    looks and sees no face and the laser no legs. The robot turns round to the mirrored reading
    (on main it did not turn at all: 10 deg is inside the camera's field)."""
    a = _alone()
    a.looked.observe(0.9, 0.0, a.params.camera_hfov / 2, [], a.params.face_look_tolerance)  # ahead: nobody
    b = math.radians(10)
    a._dominant = (1.0, b)
    heading = a._voice_heading(1.0, -1, 0)
    assert heading is not None and angle_between(heading, math.pi - b) < 1e-9
    # the recogniser's beam stays on the direction turned to while the robot turns
    assert abs(math.remainder(a.beam(1.0, None, 0) - (math.pi - b), 2 * math.pi)) < 1e-9


def test_a_voice_from_where_the_camera_has_not_looked_is_looked_at_first():
    a = _alone()
    b = math.radians(-41)  # Ida greets 41 deg off the heading: the camera ahead does not see her
    a._dominant = (1.0, b)
    assert angle_between(a._voice_heading(1.0, -1, 0), b) < 1e-9


def test_a_radio_with_nobody_in_either_direction_does_not_spin_the_robot():
    a = _alone()
    b = math.radians(12)
    a.looked.observe(0.95, 0.0, a.params.camera_hfov / 2, [], a.params.face_look_tolerance)
    a.looked.observe(0.5, math.pi - b, a.params.camera_hfov / 2, [], a.params.face_look_tolerance)  # looked there lately
    a._dominant = (1.0, b)
    assert a._voice_heading(1.0, -1, 0) is None


def test_a_person_turned_away_where_the_voice_is_read_is_someone_there_not_a_voice_from_behind():
    """wlan_reorder: Ben calls "Hello BIRON" from behind a sideboard (legs hidden) before turning to the
    robot. The camera sees his torso at the reading but no frontal face; taken as nobody there, the
    robot turned round to the mirror, its beam left him and the greeting was never recognised
    (wlan_reorder 1/10 on 73edfc7). A torso there is someone: the robot never turns round from him."""
    a = _alone()
    b = math.radians(-16)
    a.looked.observe(0.95, 0.0, a.params.camera_hfov / 2, [], a.params.face_look_tolerance)  # no frontal face ...
    a.looked.bodies(0.95, [math.radians(-17)], a.params.face_look_tolerance)  # ... but his torso
    a._dominant = (1.0, b)
    heading = a._voice_heading(1.0, -1, 0)
    assert heading is None or angle_between(heading, b) < 1e-9  # never round to the mirror behind


def test_a_face_where_the_voice_is_read_ends_the_search_there():
    a = _alone()
    b = math.radians(8)
    a.looked.observe(0.95, 0.0, a.params.camera_hfov / 2, [b], a.params.face_look_tolerance)
    a._dominant = (1.0, b)
    assert a._voice_heading(1.0, -1, 0) is None


def test_a_person_found_facing_the_robot_where_the_voice_came_from_is_the_speaker():
    """After the turn her track is confirmed and faces the robot, but she is silent (she waits for
    its answer): she counts as having spoken, so her greeting meets a potential partner. Someone in
    view while the voice was heard is not taken as its speaker by this rule."""
    a = _alone()
    a.heard.add(1.0, math.radians(20), math.radians(160), in_view=[9])
    a.tracks._birth(2.0, np.array([(-1.2 * math.cos(math.radians(20)), 1.2 * math.sin(math.radians(20)))]), np.full(1, 0.01))
    her = a.tracks.tracks[0]
    assert a._spoke_before(3.0, her, 0.0, 0.0)
    assert not a._spoke_before(6.0, her, 0.0, 0.0)  # too long ago
    her.id = 9
    assert not a._spoke_before(3.0, her, 0.0, 0.0)  # was in view: her own voice would have matched her track


# ---------------------------------------------------------------- the tracker: faces whose legs are hidden
@settings(max_examples=40, deadline=None)
@given(st.floats(0.8, 3.5), angles, st.integers(0, 10_000))
def test_a_face_whose_legs_are_hidden_starts_and_confirms_a_track_where_it_is(r, bearing, seed):
    rng = np.random.default_rng(seed)
    x, y = r * math.cos(bearing), r * math.sin(bearing)
    tracks = Tracks(TrackerSpec())
    for k in range(4):
        zx, zy = rng.normal((x, y), 0.1)
        tracks.step(0.1 * k, [(zx, zy)], [FACE])
    (tk,) = tracks.tracks
    assert tk.confirmed and math.hypot(tk.x[0] - x, tk.x[1] - y) < 0.45


def test_face_candidates_are_only_where_the_laser_cannot_see_and_nobody_it_sees_stands():
    a = _alone()
    a._loose_faces = (1.0, [(2.0, 0.0), (0.0, 2.0)])
    assert a._face_candidates(1.05, lambda pts: [p[0] > 1.0 for p in pts]) == [(2.0, 0.0)]
    assert a._face_candidates(1.5, lambda pts: [True] * len(pts)) == []  # the frame is too old
    a.tracks._birth(1.0, np.array([(0.1, 2.3)]), np.full(1, 0.01))  # someone the laser sees in that direction
    assert a._face_candidates(1.05, lambda pts: [p[0] > 1.0 or abs(p[1] - 2.0) < 0.01 for p in pts]) == [(2.0, 0.0)]


# ---------------------------------------------------------------- end to end (one seed each)
def _said(summary: dict) -> list[str]:
    return [u["text"].lower() for u in summary["utterances"] if u.get("speaker") == "robot"]


def test_a_greeting_from_behind_is_turned_to_and_answered():
    s = run_file(SCENES / "greet_from_behind.xml", RunOptions(seed=0, until=12))
    said = _said(s)
    assert any("i am biron" in t for t in said) and not any("can't see you" in t for t in said)


def test_an_object_pointed_at_behind_the_robot_is_looked_at_and_learned():
    s = run_file(SCENES / "point_behind_robot.xml", RunOptions(seed=0, until=20))
    (obj,) = s["learned"]["objects"]
    assert obj["type"] == "bin" and math.hypot(float(obj["x"]) - 2.5, float(obj["y"]) - 1.6) < 0.15


def test_a_track_fed_only_by_faces_says_its_legs_are_hidden_and_one_fed_by_legs_does_not():
    """The camera keeps the face of a partner whose legs the laser cannot see in view (in Interaction
    it looks at her hands otherwise, loses her face, and her track starves: greet_over_sofa seed 7,
    her good-bye unheard). It reads ``last_legs``: only leg candidates renew it."""
    from robot.attention.legs import PAIR

    faces, legs = Tracks(TrackerSpec()), Tracks(TrackerSpec())
    for k in range(5):
        faces.step(0.1 * k, [(2.0, 0.5)], [FACE])
        legs.step(0.1 * k, [(2.0, 0.5)], [PAIR])
    assert faces.tracks[0].confirmed and faces.tracks[0].last_legs == -math.inf
    assert legs.tracks[0].confirmed and legs.tracks[0].last_legs == 0.4
