"""Discourse around a request: an errand announced before it, "never mind" before it, "don't mind me".

review13 (the outside review of session 7): an announced errand swallowed the request said after it (item 1),
"never mind the X, <request about Y>" built the frame on X (item 2), "never mind, this is my cup" lost the
teaching (item 8), "don't mind me" was a no (item 11)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.speech.module import shared_understander

U = shared_understander()


def frame(words: str) -> str | None:
    f = U.understand(words).frame
    return None if f is None else etree.tostring(f, encoding="unicode")


ERRANDS = ["I will just grab my phone", "I will just open the door", "let me just see", "let me just check",
           "sorry, I need to find my keys", "oh wait, I'll just get my cup", "let me just put the cup on the table",
           "hang on, I'll just get my glasses", "sorry, I have to get the door", "I'll just quickly fetch the post"]
REQUESTS = ["follow me please", "where is my cup", "is this the kitchen", "where are my keys", "go to the kitchen",
            "this is my cup", "this is the living room", "stop", "take me to the bedroom", "then follow me"]


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(ERRANDS), st.sampled_from(REQUESTS))
def test_a_request_said_after_an_errand_is_the_request(errand, request):
    # the errand is discourse; the whole request said after it is what she asks (it was a bare WAIT)
    assert frame(f"{errand}, {request}") == frame(request) is not None


@given(st.sampled_from(ERRANDS[:2] + ERRANDS[5:]))
def test_an_errand_that_ends_the_turn_is_a_wait(errand):
    assert frame(errand) == "<SPEECH><WAIT/></SPEECH>"
