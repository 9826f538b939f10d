"""talk22: another request said while a confirmation of a request is open is that request, never a yes.

On integ b49cba5, "Do you want to end the tour?" - "follow me" sent the follow but left the good-bye question open
below it: her next "yes" or "okay" (to anything) ended the tour ("Good-bye!"; fresh10 open_fast_crossing: a follow
said with a reason, asked about as a good-bye, then her follow again). Only a yes-word, the asked request again or
its paraphrase confirm; another request answers the question no (silently: its own answer follows) and is carried
out. Confirmations of what she teaches ("Is this the kitchen?") still wait below a request (she may answer later).
Language rows and paraphrases are our own (fresh10's kinds; never the checker's sentences)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.manager import Say, Send
from robot.speech.grammar import Understander
from robot.speech.module import shared_understander
from robot.dialog.loader import load
from robot.dialog.manager import DialogManager
from robot.speech.module import frame_message
from tests.test_speech_review_lang7 import said, understood


def heard(state: str, *turns: tuple[str, float]) -> list[list[object]]:
    """What the dialog does with each (words, confidence) turn, starting in the supervisor state ``state``."""
    dm = DialogManager(load())
    dm.es_state = state
    out, t = [], 1.0
    for words, confidence in turns:
        out.append(dm.on_frame(frame_message(understood(words), t, t + 1.0, confidence)))
        t += 3.0
    return out


def acts(steps: list[list[object]]) -> list[list[str]]:
    return [[o.text if isinstance(o, Say) else o.event for o in step if isinstance(o, (Say, Send))] for step in steps]


def flat(steps: list[list[str]]) -> list[str]:
    return [a for s in steps for a in s]


WEAK_BYE = "that will be all for the cup"  # a good-bye read from a partial turn: "Do you want to end the tour?"
OTHER = {"follow me": "follow", "go to the kitchen": "goto", "stop": "stop", "come with me please": "follow",
         "this is the kitchen": "place_teaching", "please let me pass": "make_way"}


@settings(max_examples=30, deadline=None)
@given(ask=st.sampled_from(sorted(OTHER)), answer=st.sampled_from(["yes", "okay", "yes please", "right"]))
def test_another_request_after_the_good_bye_question_is_that_request_and_no_later_yes_ends_the_tour(ask, answer):
    steps = acts(said("Interacting", WEAK_BYE, ask, answer))
    assert steps[0] == ["Do you want to end the tour?"]
    assert OTHER[ask] in steps[1] and "goodbye" not in steps[1]
    assert "goodbye" not in steps[2]


@pytest.mark.parametrize("answer", ["yes", "goodbye", "yes bye"])
def test_yes_or_the_good_bye_again_still_ends_the_tour(answer):
    assert acts(said("Interacting", WEAK_BYE, answer))[-1] == ["goodbye"]


@pytest.mark.parametrize(("first", "other", "event"), [
    ("follow me", "go to the kitchen", "goto"),
    ("follow me", "stop", "stop"),
    ("go to the kitchen", "follow me", "follow"),
])
def test_another_request_after_a_follow_or_go_to_question_is_that_request(first, other, event):
    """Heard below confirm-below, "follow me" is asked ("Shall I follow you?"); her go-to instead is the go-to,
    and a later yes confirms nothing she did not ask for (nor is "OK, I will stay here." said to it)."""
    steps = acts(heard("Interacting", (first, 0.2), (other, 0.9), ("yes", 0.9)))
    assert steps[0] and steps[0][0].startswith("Shall I")
    assert event in steps[1]
    first_event = "follow" if first.startswith("follow") else "goto"
    assert first_event not in flat(steps[1:]) or first_event == event
    assert not any(s.startswith("OK, I will stay here") for s in flat(steps[1:]))


def test_the_asked_request_said_again_in_other_words_still_confirms():
    steps = acts(heard("Interacting", ("follow me", 0.2), ("could you follow me please", 0.9)))
    assert "follow" in steps[1]
