"""A stop said with its spot first ("here, stop") is the same request as "stop here".

A fast leader who has just stopped says it over her shoulder; the recogniser hears the words
right, and before follow19 the grammar found no parse for them, so the robot answered "Sorry, I
did not understand you" three times and stayed in Following (fresh8 terr_fast_walker_passage).
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.speech.grammar import Understander


@pytest.fixture(scope="module")
def u() -> Understander:
    return Understander()


def _frame(u: Understander, words: str) -> str | None:
    r = u.understand(words)
    return None if r.frame is None else etree.tostring(r.frame).decode()


@pytest.mark.parametrize("words", ["here stop", "here, stop", "there, stop", "right here, stop",
                                   "biron, here stop", "okay, here, stop", "here stop please"])
def test_spot_before_the_stop_is_a_stop(u: Understander, words: str) -> None:
    assert _frame(u, words) == "<SPEECH><STOP/></SPEECH>"


@pytest.mark.parametrize("words", ["here is the kitchen", "here we are in the bedroom", "here is my cup",
                                   "there is my red book", "here i am"])
def test_here_before_anything_else_is_unchanged(u: Understander, words: str) -> None:
    """Only a spot directly before the stop's word moves: "here is ..." teaches, "here I am" greets."""
    assert _frame(u, words) != "<SPEECH><STOP/></SPEECH>"


@settings(max_examples=40, deadline=None)
@given(spot=st.sampled_from(["here", "there", "right here", "right there"]),
       tail=st.sampled_from(["", "please", "now", "biron"]))
def test_spot_first_means_what_spot_after_means(u: Understander, spot: str, tail: str) -> None:
    """"<spot>, stop <tail>" gives the frame "stop <spot> <tail>" gives."""
    assert _frame(u, f"{spot} stop {tail}".strip()) == _frame(u, f"stop {spot} {tail}".strip())
