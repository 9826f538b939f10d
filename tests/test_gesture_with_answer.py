"""The gesture that went with a request completed by her answer (look25): "This is my <lost word>" (pointing)
- "What is it?" - "It is a teapot". The event keeps the request's time (the dialog), so the object attention
looks back to the gesture made with the request; when that was long ago, as far as the gesture tracker keeps
its rays, so a gesture made again with the answer is seen too."""

from __future__ import annotations

from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.objects.attention import GESTURE_LEAD, SENTENCE_RECENT, ObjectAttention
from robot.objects.gestures import GestureTracker

POSE = (2.0, 1.0, 0.0)


def _pointed(tracker: GestureTracker, t0: float, duration: float = 1.4) -> None:
    for k in range(int(duration / 0.1)):
        tracker.add(t0 + 0.1 * k, POSE, 0.0, 1.8, 2.0, -14.0, 1.14)


def _start(now: float, said: float) -> float | None:
    return ObjectAttention._gesture_start(SimpleNamespace(now=now), said)  # type: ignore[arg-type]


def test_the_gesture_of_a_request_completed_by_its_answer_is_found():
    # flow/follow_while_looking seed 2: pointed 8.2-9.6 s, "This is my teapot" at 9.7 (noun lost), "It is a
    # teapot" at 14.1; the teaching reaches the object attention at 16.7 with the request's time
    tracker = GestureTracker()
    _pointed(tracker, 8.2)
    assert tracker.pointing(16.7, start=_start(16.7, 9.7)) is not None


def test_a_gesture_made_again_with_a_late_answer_is_found_from_the_requests_time():
    # perceive/cups_across_10 seed 4: pointed with the request at 9 s, again with the answer at 24.5 s; the
    # teaching (the request's time, 10.4) reaches the object attention at 31.8 s, 21 s after the request
    tracker = GestureTracker()
    _pointed(tracker, 9.0)
    _pointed(tracker, 24.5)
    assert tracker.pointing(31.8, start=_start(31.8, 10.4)) is not None


@settings(max_examples=100, deadline=None)
@given(age=st.floats(0.0, 60.0), made=st.floats(0.0, 1.0))
def test_a_gesture_made_after_the_sentence_began_and_within_what_the_tracker_keeps_is_always_found(age, made):
    now = 100.0
    said = now - age
    lo = max(said - GESTURE_LEAD, now - SENTENCE_RECENT) + 0.1
    t0 = lo + made * (now - 1.5 - lo)
    tracker = GestureTracker()
    _pointed(tracker, t0)
    assert tracker.pointing(now, start=_start(now, said)) is not None
