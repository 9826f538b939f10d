"""Language defects the outside checkers' fresh5 scenes found (issue 26 items 7, 8; session 8 lane talk14).

Each example fails on main 0b9766c: an owner said after the noun with a position "next to it" was lost
("the blue book next to it is my husband's" -> a blue book, no owner); "that one on the coffee table is my
teapot" kept only "that one on the table"; words that say where the thing is, said before the teaching,
sank it ("behind me on the sideboard, that is my blue vase" -> a which-one answer nobody asked for); "come
on, the living room is next door" was a place to teach here (or the object "door").
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from robot.speech.module import shared_understander


def understand(words: str):
    return shared_understander().understand(words)


@pytest.mark.parametrize("words, thing, owner", [
    ("the red mug next to it is my son's", "mug", "son"),
    ("the lamp behind it is mine", "lamp", "speaker"),
    ("that old chair beside it is my grandfather's", "chair", "grandfather"),
])
def test_an_owner_after_a_position_by_it_is_kept(words, thing, owner):
    u = understand(words)
    obj = u.frame.find("OBJECT")
    assert obj.find("TITLE").get("name") == thing and obj.find("OWNER").get("name") == owner
    assert obj.find("POSITION") is None  # "it" is no landmark to look for by name
    assert u.coverage == 1.0


@pytest.mark.parametrize("words, thing, landmark", [
    ("that one on the coffee table is my teapot", "teapot", "table"),
    ("this one on the shelf is my red book", "book", "shelf"),
])
def test_the_one_she_points_at_where_it_stands_then_what_it_is(words, thing, landmark):
    u = understand(words)
    obj = u.frame.find("OBJECT")
    assert obj.find("TITLE").get("name") == thing and obj.find("POSITION/TITLE").get("name") == landmark
    assert obj.find("GESTURE") is not None and u.coverage == 1.0


@given(where=st.sampled_from(["behind me on the sideboard", "on the shelf", "over there on the left",
                              "behind you on the table", "on the right"]),
       said=st.sampled_from([("this is my blue vase", "vase", "speaker"), ("that is our old clock", "clock", "us"),
                             ("that is my husband's lamp", "lamp", "husband")]))
def test_where_said_before_a_teaching_does_not_sink_it(where, said):
    words, thing, owner = said
    u = understand(f"{where} {words}")
    obj = u.frame.find("OBJECT")
    assert obj is not None and obj.find("TITLE").get("name") == thing
    assert obj.find("OWNER").get("name") == owner and u.coverage == 1.0


@pytest.mark.parametrize("words", ["the one on the table please follow me", "on the table follow me",
                                   "the red one on the left", "on the left"])
def test_a_which_one_answer_or_a_place_before_another_request_stays_as_it_was(words):
    assert understand(words).act == "THAT_ONE"


@pytest.mark.parametrize("words", ["come on the living room is next door", "come on the kitchen is through here",
                                   "come on biron the office is down the hall"])
def test_come_on_and_where_the_room_is_from_here_is_a_follow(words):
    u = understand(words)
    assert u.act == "FOLLOW" and u.frame.find(".//PLACE") is None and u.frame.find(".//OBJECT") is None


@pytest.mark.parametrize("words, act", [("come on this is the kitchen", "PLACE"), ("come on the kitchen is here", "PLACE"),
                                        ("come on the bedroom is lovely", None)])
def test_come_on_before_a_teaching_or_a_remark_is_no_follow(words, act):
    assert understand(words).act == act


@pytest.mark.parametrize("words, thing, owner, lost", [
    ("the green vase to the window is mine", "vase", "speaker", ["to", "the", "window"]),
    ("the old clock the next to it is my grandmother's", "clock", "grandmother", ["the"]),
])
def test_an_owner_said_after_a_misheard_word_is_kept_and_confirmed(words, thing, owner, lost):
    """fresh5 stair_three_on_shelf seed 0: "the red book [to] the shelf is mine" was learned as "the red book"."""
    u = understand(words)
    obj = u.frame.find("OBJECT")
    assert obj.find("TITLE").get("name") == thing and obj.find("OWNER").get("name") == owner
    assert u.ignored == lost and u.partial and u.coverage < 1.0  # words lost: the dialog asks first


def test_a_misheard_word_never_makes_another_thing_the_one_owned():
    u = understand("the red cup to the shelf is mine")
    assert u.frame.find("OBJECT/TITLE").get("name") == "cup"


@pytest.mark.parametrize("owner, said", [("husband", "your husband's blue book"), ("kids", "your kids' blue book"),
                                         ("tom", "Tom's blue book"), ("speaker", "your blue book")])
def test_a_kin_owner_is_said_back_as_hers(owner, said):
    from lxml import etree

    from robot.dialog.model import noun_phrase
    el = etree.fromstring(f'<OBJECT type="book"><TITLE name="book"/><OWNER name="{owner}"/><COLOUR name="blue"/></OBJECT>')
    assert noun_phrase(el) == said


@pytest.mark.parametrize("words", ["come on the in is next door", "this is next door", "we are going next door",
                                   "it is next door"])
def test_next_door_is_no_door(words):
    """fresh5 row_hidden_step_aside seed 4: "come on the in is next door" (misheard) became "Is this the door?"."""
    u = understand(words)
    assert u.frame is None or u.frame.find(".//OBJECT[@type='door']") is None


def test_a_door_she_shows_is_still_a_door():
    assert understand("this is the door to the garden").frame.find("OBJECT").get("type") == "door"


@pytest.mark.parametrize("words", ["here we are stop", "here we are stop here", "okay here we are stop please"])
def test_an_arrival_then_stop_is_a_stop(words):
    """fresh5 stair_wait_walks_on: "Here we are, stop" was "Which room is this?" and the stop was lost, so every
    teaching after it got "say stop first"."""
    assert understand(words).act == "STOP"


@pytest.mark.parametrize("words, act", [("here we are", "PLACE"), ("here we are in the kitchen", "PLACE")])
def test_an_arrival_alone_or_with_its_room_is_still_a_place(words, act):
    assert understand(words).act == act


@pytest.mark.parametrize("words, owner", [("the green lamp by the window a mine", "speaker"),
                                          ("the old radio on the desk the my father's", "father")])
def test_a_misheard_copula_before_the_owner_keeps_the_owner(words, owner):
    """fresh5 stair_three_on_shelf seeds 5, 6: "the red book on the shelf [is→a] mine" was learned without her."""
    u = understand(words)
    assert u.frame.find("OBJECT/OWNER").get("name") == owner and u.partial and u.coverage < 1.0
