"""obj17: answers to "which one?" and confirmations that a user cares about.

- a teaching said again with pointing while "Do you mean the book on the left or the one on the right?" is open
  is answered by the pointing, never by the noun the first option happens to say (fresh7 corr_nonnative_books:
  the left book stored while he pointed at the right one);
- "Is this your alarm clock?" - "yes, my clock" confirms (a shorter name of the same thing), it does not
  replace the request (which lost its gesture and its place: "could not find your clock").
"""
from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.manager import _same, _same_name
from robot.dialog.module import choose, unchosen_answer

WORDS = st.sampled_from(["alarm", "clock", "coffee", "mug", "red", "book", "desk", "lamp", "flower", "vase"])


def _object(xml: str) -> etree._Element:
    return etree.fromstring(xml)


def test_a_teaching_said_again_with_pointing_is_answered_by_the_pointing() -> None:
    options = [(0, "the book on the left"), (1, "the one on the right")]
    again = _object('<OBJECT type="book"><GESTURE val="probably_pointing"/><TITLE name="book"/><COLOUR name="red"/>'
                    '<OWNER name="speaker"/></OBJECT>')
    assert choose(options, again) is None
    assert unchosen_answer(again).get("deixis") == "true"


def test_an_object_named_without_pointing_still_picks_by_its_words() -> None:
    options = [(0, "the red cup on the left"), (1, "the blue cup on the right")]
    said = _object('<OBJECT type="cup"><TITLE name="cup"/><COLOUR name="blue"/></OBJECT>')
    assert choose(options, said) == 1


@given(st.lists(WORDS, min_size=1, max_size=3), st.integers(min_value=1, max_value=3))
def test_a_shorter_name_of_the_same_thing_is_the_same(words: list[str], keep: int) -> None:
    full = " ".join(words)
    short = " ".join(words[-min(keep, len(words)):])
    assert _same_name(full, short) and _same_name(short, full)
    old = _object(f'<OBJECT type="clock"><GESTURE val="probably_pointing"/><TITLE name="{full}"/></OBJECT>')
    new = _object(f'<OBJECT type="clock"><TITLE name="{short}"/></OBJECT>')
    assert _same(old, new)


@given(WORDS, WORDS)
def test_another_head_noun_is_another_thing(a: str, b: str) -> None:
    if a != b:
        assert not _same_name(f"alarm {a}", b) or a == b
        assert not _same_name(a, b)
