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


@pytest.mark.parametrize("words", ["this is our room", "this is my room", "that is our room"])
def test_a_room_named_only_room_is_a_guess_the_dialog_confirms(words):
    """"this is our room" is also what is left when the recogniser loses the name ("this is our [living]
    room", fresh2/diag_paraphrase_confirm seed 2 stored "room" unasked): half the coverage, so the dialog
    asks before storing it."""
    u = shared_understander().understand(words)
    assert u.frame.find("PLACE/TITLE").get("name") == "room" and u.coverage == 0.5


@pytest.mark.parametrize("words", ["this is my daughter's room", "this is the kids' room", "this is our living room"])
def test_a_room_named_by_whose_or_what_it_is_is_taken_at_once(words):
    assert shared_understander().understand(words).coverage == 1.0


@pytest.mark.parametrize("words", ["oh the bed is not made sorry", "the sofa is new", "the kitchen is a mess",
                                   "the sun is shining today", "my desk is a bit messy"])
def test_something_said_of_a_thing_is_a_remark_not_a_teaching(words):
    """fresh2/galley_long_tour: "Oh the bed is not made sorry" got "Is this bed?" (a noun phrase with its
    predicate left over was taken as the answer "the bed")."""
    u = shared_understander().understand(words)
    assert u.frame is None and u.reason in ("a remark about it", "no parse", "nothing known said about it")


@pytest.mark.parametrize("words", ["the kitchen", "my cup", "the kitchen is", "this is the bed", "the bed is mine"])
def test_a_noun_phrase_alone_or_a_whole_statement_still_counts(words):
    assert shared_understander().understand(words).frame is not None


@pytest.mark.parametrize("words", ["is that the kitchen, no", "is this my cup, no"])
def test_a_question_she_answers_no_herself_asks_nothing_to_confirm(words):
    """review-lang7 item 9: "is that the kitchen, no" was confirmed as "Is this the kitchen?"."""
    assert frame(words) is None


def test_a_question_with_a_yes_tag_is_still_confirmed():
    assert shared_understander().understand("is this the kitchen, right").coverage == 0.5


def test_a_hesitation_before_room_loses_no_name_the_words_give():
    # Hypothesis (test_hesitations_never_change_the_frame) found "this is the children's uh room" taken
    # for a lost name: the children's room is a name, so the hesitation changes nothing; "anna's um room"
    # names only "room", so its name may be what the "um" stands for
    from lxml import etree

    from robot.speech.module import shared_understander

    u = shared_understander()
    assert etree.tostring(u.understand("this is the children's uh room").frame, encoding="unicode") == \
        etree.tostring(u.understand("this is the children's room").frame, encoding="unicode")
    assert etree.tostring(u.understand("here is anna's um room").frame, encoding="unicode") == "<SPEECH><PLACE/></SPEECH>"
