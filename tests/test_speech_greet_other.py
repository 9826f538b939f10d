"""A greeting to someone whose name the robot does not know ("Hi Sara, yes it is me", "hello love") is said
to that person (a call on the phone, a visitor): no greeting for the robot, no "say that again" either.
A greeting that names the robot, or calls it "buddy"/"friend", stays the robot's greeting."""

from __future__ import annotations

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.speech.module import shared_understander

GREETS = ["hi", "hello", "hey"]


def understand(words: str):
    return shared_understander().understand(words)


def unknown(word: str) -> bool:
    lex = shared_understander().lexicon
    return lex.tokens(word).unknown == [word]


@pytest.mark.parametrize("words", ["hi sara yes it is me", "hello love", "hey jule how are you", "hi sara",
                                   "hello darling, I am on the bus", "oh hi karin, yes I can talk now"])
def test_greeting_to_an_unknown_name_is_said_to_another(words):
    u = understand(words)
    assert u.frame is None and u.aside


@pytest.mark.parametrize("words", ["hello biron", "hi robot", "hello dear biron", "hello dear robot", "hi there",
                                   "hello again", "hello buddy", "hi little robot", "hey biron how are you",
                                   "oh hello biron", "good morning biron"])
def test_greeting_to_the_robot_stays_a_greeting(words):
    u = understand(words)
    assert u.act == "GREETING" and not u.aside


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(GREETS), st.text(alphabet="bcdfgklmnprstvz", min_size=3, max_size=7).map(lambda w: w + "a"),
       st.sampled_from(["", " yes it is me", " how are you", " I am on my way"]))
def test_a_greeting_naming_someone_unknown_never_greets_the_robot(greet, name, tail):
    assume(unknown(name))
    u = understand(f"{greet} {name}{tail}")
    assert u.act != "GREETING" and u.aside
    # the robot's name anywhere keeps it the robot's greeting
    named = understand(f"{greet} {name} biron{tail}")
    assert not named.aside
