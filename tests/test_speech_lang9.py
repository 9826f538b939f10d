"""Everyday phrases the language review (reports/review-lang7.md items 10, 13, 14) found misread.

Each example fails on main a045923: "bear with me" was a toy bear to teach, "my friend's cup" was owned by
"my friend" (the robot's address word) while "my sister's cup" is the sister's, "a picture of my
daughter" was the daughter's, and "is this biron's cup" asked the robot to learn its own cup.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.speech.module import shared_understander


def frame(words: str) -> str | None:
    f = shared_understander().understand(words).frame
    return None if f is None else etree.tostring(f, encoding="unicode")


@pytest.mark.parametrize("words", ["bear with me", "bear with me a second", "uh bear with me"])
def test_bear_with_me_asks_for_patience_and_teaches_nothing(words):
    assert frame(words) is None  # was OBJECT toy "bear" ("Is this bear?")


def test_bear_with_me_before_a_teaching_leaves_the_teaching():
    assert frame("bear with me, this is my cup") == (
        '<SPEECH><OBJECT type="cup"><GESTURE val="probably_pointing"/><TITLE name="cup"/>'
        '<OWNER name="speaker"/></OBJECT></SPEECH>')


def test_a_bear_shown_is_still_a_toy():
    assert frame("this is my teddy bear") == (
        '<SPEECH><OBJECT type="toy"><GESTURE val="probably_pointing"/><TITLE name="teddy bear"/>'
        '<OWNER name="speaker"/></OBJECT></SPEECH>')


@given(owner=st.sampled_from(["friend", "sister", "brother", "daughter", "neighbour"]),
       thing=st.sampled_from(["cup", "mug", "book", "lamp"]),
       opening=st.sampled_from(["that's", "this is", "here is"]))
@settings(max_examples=40, deadline=None)
def test_my_x_s_thing_is_owned_by_x_whatever_x_is(owner, thing, opening):
    """"my friend's cup" is owned as "my sister's cup" is: by the word after "my" (was "my friend",
    because "my friend" is also a way to address the robot)."""
    f = shared_understander().understand(f"{opening} my {owner}'s {thing}").frame
    assert f is not None
    assert [o.get("name") for o in f.iter("OWNER")] == [owner]


def test_calling_the_robot_my_friend_still_addresses_it():
    assert frame("my friend, follow me") == "<SPEECH><FOLLOW/></SPEECH>"


@pytest.mark.parametrize("words", ["this is a picture of my daughter", "that is a photo of me",
                                   "this is a painting of anna"])
def test_a_picture_of_someone_is_not_theirs(words):
    f = shared_understander().understand(words).frame
    assert f is not None and f.find("OBJECT") is not None
    assert f.find(".//OWNER") is None


def test_a_picture_that_is_hers_keeps_its_owner():
    f = shared_understander().understand("this is my daughter's picture").frame
    assert [o.get("name") for o in f.iter("OWNER")] == ["daughter"]


@pytest.mark.parametrize("words", ["is this biron's cup", "is this the robot's charger", "is that biron's lamp"])
def test_a_question_about_the_robots_own_things_teaches_nothing(words):
    assert frame(words) is None


def test_a_question_about_someone_elses_thing_is_still_confirmed():
    u = shared_understander().understand("is this anna's cup")
    assert u.frame is not None and u.frame.find(".//OWNER").get("name") == "anna" and u.coverage == 0.5


@pytest.mark.parametrize("words", ["this is our the room", "this is our uh room", "this is my a room",
                                   "this is the uh room", "here is anna's um room"])
def test_a_word_misheard_where_the_rooms_name_goes_leaves_the_place_unnamed(words):
    """"this is our [the→living] room" (fresh2/diag_paraphrase_confirm seed 0) stored a room called "room"
    unasked; the name was lost, so the place has none and the dialog asks which room this is."""
    u = shared_understander().understand(words)
    assert frame(words) == "<SPEECH><PLACE/></SPEECH>" and u.partial


@pytest.mark.parametrize("words", ["this is our room", "uh this is my room", "this is uh our room"])
def test_our_room_said_whole_is_still_our_room(words):
    f = shared_understander().understand(words).frame
    assert f is not None and f.find("PLACE/TITLE").get("name") == "room"


def test_the_dialog_asks_which_room_and_takes_her_correction():
    from robot.dialog.manager import Say, Send
    from tests.test_speech_review_lang7 import said

    out = said("Interacting", "this is our the room", "No, I said the living room")
    assert [o.text for o in out[0] if isinstance(o, Say)] == ["Which room is this?"]
    (send,) = [o for o in out[1] if isinstance(o, Send)]
    assert send.event == "place_teaching" and send.children[0].find(".//TITLE").get("name") == "living room"
