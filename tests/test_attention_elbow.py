"""attn18: a person at the robot's elbow (half a metre beside it) is found by the camera and matched.

The microphone pair reads a mouth above it and close by nearer the axis than it stands; the camera
must look further round than the reading, the voice memory must recall the reading for her track, and
her face must match her track kept by one leg beside it."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.cues import NEAREST_SPEAKER, CueSpec, match_faces, sound_bearings_from, voice_reach
from robot.attention.looking import HeardFrom


@settings(max_examples=60, deadline=None)
@given(az=st.floats(min_value=5.0, max_value=90.0), dist=st.floats(min_value=NEAREST_SPEAKER, max_value=4.0),
       mouth=st.floats(min_value=1.15, max_value=1.85))
def test_a_voice_never_comes_from_beyond_its_reach(az, dist, mouth):
    """Wherever a person stands (at least NEAREST_SPEAKER away, any mouth height the robot allows), her true
    direction lies between her voice's reading and voice_reach of that reading."""
    spec = CueSpec()
    a = math.radians(az)
    b = sound_bearings_from([(dist * math.cos(a), dist * math.sin(a))], CueSpec(mouth_height=mouth))[0]
    assert voice_reach(b, spec) >= a - math.radians(0.5)


def test_far_voices_reach_little_further_than_read():
    """A reading near the axis does not send the camera round: 5 degrees reaches at most ~10."""
    assert voice_reach(math.radians(5.0), CueSpec()) < math.radians(12.0)


def test_a_voice_read_at_45_deg_is_recalled_for_the_person_standing_at_88():
    heard = HeardFrom(keep=4.0)
    heard.add(2.0, math.radians(45.0), math.radians(135.0), [])
    # by her planar bearing (88 deg) the voice is not hers; by the span of readings she may give, it is
    assert not heard.recall(3.0, math.radians(88.0), 7, 4.0, math.radians(12.0))
    assert heard.recall_span(3.0, math.radians(40.0), math.radians(60.0), 7, 4.0, math.radians(12.0))
    assert not heard.recall_span(3.0, math.radians(70.0), math.radians(89.0), 7, 4.0, math.radians(12.0))
    assert not heard.recall_span(7.5, math.radians(40.0), math.radians(60.0), 7, 4.0, math.radians(12.0))  # too old


def test_a_near_face_matches_a_track_kept_by_one_leg_beside_it_but_a_far_one_does_not():
    spec = CueSpec()
    # face at 93 deg, 0.6 m from the camera; the track 0.13 m beside her (one leg): 13 deg off
    track = [(0.15, 0.565)]
    assert match_faces(track, [(math.radians(93.0), 0.6)], spec) == [0]
    # the same 13 degrees at 3 m is another person's place: no match
    far = [(spec.camera_offset + 3.0 * math.cos(math.radians(80.0)), 3.0 * math.sin(math.radians(80.0)))]
    assert match_faces(far, [(math.radians(93.0), 3.0)], spec) == []
