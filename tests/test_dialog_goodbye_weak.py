"""A good-bye read from words the robot mostly did not use is asked before the tour ends (issue 26 item 7).

On main a045923 the goodbye dialog's fill was always sure: "that will be all for the cup" (a good-bye at a
quarter of the words) or "the goodbye song is on the radio" ended the tour at once. Now a partial good-bye
heard below confirm-below is asked ("Do you want to end the tour?"); a clear one still ends it.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.manager import Say, Send
from tests.test_speech_review_lang7 import said


def acts(steps: list[list[object]]) -> list[list[str]]:
    return [[o.text if isinstance(o, Say) else o.event for o in step if isinstance(o, (Say, Send))] for step in steps]


QUESTION = "Do you want to end the tour?"


@pytest.mark.parametrize("words", ["that will be all for the cup", "the goodbye song is on the radio",
                                   "i will say goodbye to grandma later"])
def test_a_weak_good_bye_is_asked(words):
    assert acts(said("Interacting", words)) == [[QUESTION]]


@pytest.mark.parametrize("answer", ["yes", "goodbye", "yes bye", "right"])
def test_yes_or_a_good_bye_said_again_ends_the_tour(answer):
    assert acts(said("Interacting", "that will be all for the cup", answer))[-1] == ["goodbye"]


def test_no_keeps_the_tour_going():
    assert acts(said("Interacting", "that will be all for the cup", "no")) == [[QUESTION], ["OK, let us go on."]]


@given(words=st.sampled_from(["goodbye", "bye", "good bye biron", "see you later", "thanks a lot, bye bye",
                              "that's it for today, goodbye", "thank you that's all see you later"]),
       confidence=st.floats(0.2, 1.0))
@settings(max_examples=40, deadline=None)
def test_a_clear_good_bye_ends_the_tour_at_any_confidence(words, confidence):
    assert acts(said("Interacting", words, confidence=confidence)) == [["goodbye"]]


def test_the_question_is_never_asked_more_than_twice():
    steps = acts(said("Interacting", "that will be all for the cup", "la la la", "la la la", "la la la"))
    assert sum(s.count(QUESTION) for s in steps) <= 2
