"""What the outside review of session 9 (reports/review9.md items 1, 5, 6) found the understanding got wrong.

Each example fails on 99d6fcd: "the study is this room" and "the keys are on the table" were remarks (no
frame), "this is the kitchen, no" taught the kitchen at full coverage, "hello, is this the kitchen" lost its
question and "hello biron, don't follow me" lost its greeting.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.speech.module import shared_understander


def understand(words: str):
    return shared_understander().understand(words)


@pytest.mark.parametrize("words, room", [("the study is this room", "study"), ("my office is this room", "office"),
                                         ("the kitchen is this one", "kitchen")])
def test_a_room_named_first_and_shown_after_is_taught(words, room):
    u = understand(words)
    assert u.frame.find("PLACE/TITLE").get("name") == room and u.coverage == 1.0


@pytest.mark.parametrize("words, thing, where", [("my cup is this one", "cup", None),
                                                 ("the keys are on the table", "keys", "table"),
                                                 ("my glasses are on the shelf", "glasses", "shelf"),
                                                 ("my keys are in the drawer", "keys", "drawer")])
def test_a_thing_named_first_and_shown_or_placed_after_is_taught(words, thing, where):
    u = understand(words)
    obj = u.frame.find("OBJECT")
    assert obj.find("TITLE").get("name") == thing and u.coverage == 1.0
    assert (obj.find("POSITION/TITLE").get("name") if where else None) == where


@pytest.mark.parametrize("words", ["my cup is the left one", "my cup is the red one", "the bathroom is next door"])
def test_which_or_where_after_the_copula_keeps_the_noun_phrase(words):
    assert understand(words).frame is not None  # an answer to "which one?" / "which room?", as at a045923


@given(thing=st.sampled_from(["the sofa", "the bed", "my lamp", "the kitchen", "the window"]),
       said=st.sampled_from(["is new", "is not made", "is a mess", "is clean now", "is open again"]))
def test_what_a_thing_is_like_is_a_remark(thing, said):
    assert understand(f"{thing} {said}").frame is None


@pytest.mark.parametrize("words", ["this is the kitchen, no", "this is the kitchen, no no", "this is my cup no"])
def test_a_statement_she_ends_with_no_teaches_nothing(words):
    """review9 item 5: "this is the kitchen, no" taught the kitchen at full coverage, unasked."""
    assert understand(words).frame is None


@pytest.mark.parametrize("words", ["no, this is the kitchen", "this is the kitchen", "no no", "no"])
def test_a_no_before_the_statement_or_alone_still_counts(words):
    assert understand(words).frame is not None


def test_a_greeting_before_a_question_keeps_the_question():
    """review9 item 6: "hello, is this the kitchen" was a greeting only."""
    u = understand("hello, is this the kitchen")
    assert u.frame.find("GREETING") is not None
    rest = understand(" ".join(u.rest))
    assert rest.frame.find("PLACE/TITLE").get("name") == "kitchen" and rest.coverage == 0.5  # asked first


@pytest.mark.parametrize("words", ["hello biron, don't follow me", "hi, please do not follow me"])
def test_a_greeting_before_a_negated_request_still_greets(words):
    """review9 item 6: the whole turn was "a request said negated", so the robot did not greet back."""
    u = understand(words)
    assert etree.tostring(u.frame[0]).startswith(b"<GREETING") and u.rest == []


def test_a_negated_request_alone_is_still_nothing():
    assert understand("don't follow me").frame is None
