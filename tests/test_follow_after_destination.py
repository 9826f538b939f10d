"""A whole follow said after a noun phrase alone naming where they go next is the follow (long20: "now the
study, follow me please" was taken as a teaching of the study where she stood; "and now the last room, follow
me" was not understood, fresh7 corr_long_tour). The lead is no teaching, which-one answer or go-to."""

from __future__ import annotations

import pytest

from robot.speech.grammar import Understander

U = Understander()


@pytest.mark.parametrize("words", [
    "now the kitchen, follow me",
    "so the next room, follow me please",
    "and now our bedroom, come with me",
    "okay then my office, follow me",
    "next the bathroom, follow me",
])
def test_a_destination_then_a_follow_is_the_follow(words):
    r = U.understand(words)
    assert r.act == "FOLLOW" and not r.partial


@pytest.mark.parametrize("words, act", [
    ("this is the kitchen", "PLACE"),  # a teaching stays one
    ("the kitchen", "PLACE"),  # a room named alone: no follow
    ("the red cup on the table is mine", "OBJECT"),
])
def test_without_a_whole_follow_after_it_a_noun_phrase_keeps_its_meaning(words, act):
    assert U.understand(words).act == act


def test_a_clause_before_the_follow_is_not_set_aside_as_a_destination():
    # "is" makes the lead a clause: not this rule's (what it means is the other rules' business), and a lead
    # with a verb of its own is never dropped by it
    r = U.understand("the kitchen is not here, follow me")
    assert U._follow_after_destination("the kitchen is not here, follow me", ["the", "kitchen", "is", "not", "here", "follow", "me"]) is None
    assert r.act != "PLACE" or r.partial
