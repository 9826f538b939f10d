"""While "Do you mean the cup on the left or the one on the right?" is open, words lost around a landmark
("the [one on→that] the table") leave an object teaching of the table: taken as the which-one answer "the one
at the table", not as a new teaching that drops the question (perceive/cups_on_table seed 5)."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.module import landmark_answer, unchosen_answer
from robot.speech.grammar import Understander

U = Understander()
THINGS = st.sampled_from(["cup", "mug", "vase", "bottle", "book"])
LANDMARKS = st.sampled_from(["table", "shelf", "counter", "desk", "sideboard"])
#: what the recogniser left of "one on": function words that make no "the one on"
LOST = st.sampled_from(["that", "a", "in the", "to the", "it"])


def _msg(text: str) -> etree._Element:
    r = U.understand(text)
    el = etree.fromstring('<understood start="0" end="1" confidence="0.4"/>')
    if r.partial:
        el.set("partial", "true")
    el.append(r.frame)
    return el


def _options(thing: str) -> list[tuple[int, str]]:
    return [(0, f"the {thing} on the left"), (1, "the one on the right")]


@given(thing=THINGS, landmark=LANDMARKS, lost=LOST)
def test_a_partial_teaching_of_another_thing_is_the_one_at_it(thing, landmark, lost):
    x = _msg(f"the {lost} the {landmark}")
    assert x.get("partial") == "true" and x.find("SPEECH/OBJECT/TITLE").get("name") == landmark
    got = landmark_answer(_options(thing), x)
    assert got is not None
    left = unchosen_answer(got.find("SPEECH/THAT_ONE"))
    assert left.find("POSITION/TITLE").get("name") == landmark  # the asker takes the option standing there


@given(thing=THINGS, landmark=LANDMARKS)
def test_a_teaching_heard_whole_or_of_the_thing_asked_about_stays_a_teaching(thing, landmark):
    assert landmark_answer(_options(thing), _msg(f"this is the {landmark}")) is None  # heard whole
    assert landmark_answer(_options(thing), _msg(f"the that the {thing}")) is None  # the thing asked about
    assert landmark_answer(None, _msg(f"the that the {landmark}")) is None  # no question open
