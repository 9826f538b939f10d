"""talk19: requests said in passing (a follow after a suggestion question), polite stops ("you may stop", after an
arrival), whom a thing is for as its owner, "there is <a thing>" as showing it (never a where-question), errands of
closing (a wait, not a teaching), a greeting said again, and the generated user's answer to "Do you want to end the
tour?". Rows and paraphrases of our own (fresh8's kinds; never the checker's sentences)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.scenario.wordpattern import compile_words
from homesim.tour import usergen as U
from robot.speech.grammar import Understander
from robot.speech.module import shared_understander


@pytest.fixture(scope="module")
def u() -> Understander:
    return shared_understander()


ROOMS = ["bedroom", "study", "garage", "bathroom", "kitchen", "dining room", "hall"]


@pytest.mark.parametrize("words", ["shall we go to the bedroom, follow me", "should we go to the garage? come with me",
                                   "so shall we um have a look at the study, this way please",
                                   "how about the hall next, follow me", "why don't we go to the study, come along",
                                   "shall i show you the bathroom? follow me please"])
def test_a_follow_after_a_suggestion_question_is_the_follow_never_a_teaching_or_a_go_to(u: Understander,
                                                                                       words: str) -> None:
    res = u.understand(words)
    assert res.act == "FOLLOW" and not res.partial


@settings(max_examples=30, deadline=None)
@given(room=st.sampled_from(ROOMS), lead=st.sampled_from(["shall we go to", "should we go into", "how about"]),
       follow=st.sampled_from(["follow me", "come with me", "this way please", "follow me please"]))
def test_no_suggested_room_is_taught_where_she_stands_when_she_asks_to_be_followed(u: Understander, room: str,
                                                                                 lead: str, follow: str) -> None:
    res = u.understand(f"{lead} the {room} {follow}")
    assert res.act == "FOLLOW"


@pytest.mark.parametrize("words", ["shall we go to the kitchen", "shall we go to the kitchen, you go first"])
def test_a_suggestion_with_no_follow_after_it_is_never_taken_as_a_follow(u: Understander, words: str) -> None:
    assert u.understand(words).act != "FOLLOW"


@pytest.mark.parametrize("words", ["you may stop", "you may stop here", "we are here now, you may stop",
                                   "there we are, you may stop", "here we are at last, you can stop now"])
def test_a_polite_stop_and_a_stop_after_an_arrival_are_whole_stops(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "STOP" and not res.partial


@pytest.mark.parametrize("words", ["here we are", "we are here stop"])
def test_an_arrival_alone_stays_what_it_was(u: Understander, words: str) -> None:
    assert u.understand(words).act == "PLACE"  # the dialog asks which room this is


@pytest.mark.parametrize(("words", "owner"), [("this cup is for me", "speaker"), ("this mug is for my husband", "husband"),
                                              ("that plate is for my son", "son")])
def test_whom_a_thing_is_for_is_whose_it_is(u: Understander, words: str, owner: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and not res.partial and res.frame.find("OBJECT/OWNER").get("name") == owner


@pytest.mark.parametrize("words", ["there is the kettle", "there's my cup on the table", "there are my glasses on the desk",
                                   "and there is my red book on the shelf"])
def test_there_is_a_thing_shows_it_and_is_never_a_where_question(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and res.frame.find("OBJECT/GESTURE") is not None


def test_a_where_question_is_still_one(u: Understander) -> None:
    assert u.understand("is my cup on the table").act == "WHERE"
    assert u.understand("where is the kettle").act == "WHERE"


@pytest.mark.parametrize("words", ["let me just close the door a bit", "let me just shut the window",
                                   "oh wait, let me just draw the curtains"])
def test_an_errand_of_closing_is_a_wait_never_a_teaching(u: Understander, words: str) -> None:
    assert u.understand(words).act == "WAIT"


@pytest.mark.parametrize("words", ["hi robot hi", "hello biron hello", "hi hi robot"])
def test_a_greeting_said_again_is_one_whole_greeting(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "GREETING" and not res.partial and res.coverage == 1.0


def test_a_greeting_to_a_stranger_said_twice_is_still_not_for_the_robot(u: Understander) -> None:
    assert u.understand("hi anna hi").act != "GREETING"


def test_the_generated_user_says_yes_when_the_robot_asks_whether_to_end_the_tour() -> None:
    answers = U.reactions("goodbye")
    acts = next(a for hears, a in answers if compile_words(hears).search("Do you want to end the tour?"))
    assert acts[0].get("request") == "yes"
    assert not any(compile_words(h).search("Shall I follow you?") for h, _ in answers)


@pytest.mark.parametrize("words", ["down there behind me, that's my alarm clock", "there on the shelf, that is my red book"])
def test_there_setting_the_scene_before_a_whole_teaching_keeps_the_teaching_whole(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and not res.partial


@pytest.mark.parametrize(("words", "owner"), [("the radio over there is ours", "us"), ("the lamp here is mine", "speaker"),
                                              ("the green jug there on the shelf is mine", "speaker")])
def test_the_thing_where_she_points_then_whose_is_a_pointing_teaching_with_its_owner(u: Understander, words: str,
                                                                                    owner: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and not res.partial and res.frame.find("OBJECT/GESTURE") is not None
    assert res.frame.find("OBJECT/OWNER").get("name") == owner


@pytest.mark.parametrize("words", ["let a just close the door a bit", "it me just open the window", "let me just shut the door",
                                   "me just draw the curtains", "let just fold the blanket"])
def test_an_errand_whose_lead_lost_or_misheard_a_word_is_still_a_wait_never_a_teaching(u: Understander, words: str) -> None:
    assert u.understand(words).act == "WAIT"


def test_an_errand_with_a_word_lost_keeps_the_request_after_it_and_let_me_alone_is_no_errand(u: Understander) -> None:
    assert u.understand("let a just close the door, follow me").act == "FOLLOW"
    assert u.understand("let me check, this is my cup").act == "OBJECT"  # no "just", nothing misheard: as before
