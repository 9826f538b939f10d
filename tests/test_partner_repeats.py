"""pass12: a partner turned aside who says her request again is heard (issue 26, fresh12 defect 0).

The addressee rule drops words said with her back to the robot 1.2 m or further off (talking to
herself) unless she names it, shows something, or has talked with it since she turned aside. Nothing
she said turned aside could start that exchange, so after "Stop" and one exchange she was deaf to it
for the rest of the run: "where is my cup" three times, "good bye" three times, all dropped (fresh3
open_two_cups_rooms seeds 0, 1 on 25b2ff0). One repeats a request that got no answer, not one's
muttering: the same act said again within ``REPEAT_WINDOW`` s is meant for the robot. Properties over
the dialog module's frame handling (no simulation)."""

from __future__ import annotations

import math
from collections import deque

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import BIRON_DIALOGS, load
from robot.dialog.manager import DialogManager
from robot.dialog.module import ASIDE, REPEAT_WINDOW, Dialog, said_act
from robot.speech.module import frame_message, shared_understander

DOC = load(BIRON_DIALOGS)
REQUESTS = ["where is my cup", "good bye", "this is the study", "follow me", "what is this"]


def _dialog() -> tuple[Dialog, list[str]]:
    """A dialog whose partner has stood turned aside (her back to it, 1.3 m off) since t = 10 s, with
    no exchange since; what it takes up is recorded instead of handled."""
    d = Dialog.__new__(Dialog)
    d.manager = DialogManager(DOC)
    d.manager.es_state = "Interacting"
    d._partner_cues = deque([(10.0 + 0.1 * i, ASIDE, 0, 0.0) for i in range(3000)], maxlen=3000)
    d._sources = deque(maxlen=300)
    d.barge_in_width = 9.0
    d._addressed_at = -math.inf
    d._aside_since = 10.0
    d._unanswered = None
    d.not_addressed = 0
    taken: list[str] = []
    d._on_addressed = lambda msg: taken.append(msg.xml.findtext("words") or msg.xml.text)  # type: ignore[method-assign]
    return d, taken


class _Msg:
    def __init__(self, xml: etree._Element) -> None:
        self.xml = xml


def _frame(words: str, start: float) -> _Msg:
    return _Msg(frame_message(shared_understander().understand(words), start, start + 1.5, 0.8, False))


@settings(max_examples=100, deadline=None)
@given(words=st.sampled_from(REQUESTS), gap=st.floats(2.0, REPEAT_WINDOW - 0.1))
def test_a_request_said_again_turned_aside_is_heard(words, gap):
    d, taken = _dialog()
    d._on_frame(_frame(words, 20.0))
    assert taken == []  # said once with her back turned: talking to herself (the rule as it was)
    d._on_frame(_frame(words, 20.0 + gap))
    assert taken == [words]  # b8a52de: dropped again, and every later one too
    assert d.not_addressed == 1


@settings(max_examples=100, deadline=None)
@given(first=st.sampled_from(REQUESTS), second=st.sampled_from(REQUESTS), gap=st.floats(2.0, 60.0))
def test_only_the_same_act_soon_after_is_a_repeat(first, second, gap):
    d, taken = _dialog()
    d._on_frame(_frame(first, 20.0))
    d._on_frame(_frame(second, 20.0 + gap))
    same = said_act(_frame(first, 0.0).xml) == said_act(_frame(second, 0.0).xml)
    assert (taken == [second]) == (same and gap <= REPEAT_WINDOW)


@settings(max_examples=50, deadline=None)
@given(seq=st.lists(st.sampled_from(REQUESTS), min_size=2, max_size=8), gap=st.floats(3.0, 12.0))
def test_a_partner_is_never_deaf_after_one_exchange(seq, gap):
    """Whatever she says turned aside, once a request of hers has been said twice in a row it is heard,
    and from then on (the exchange since she turned aside) every later request is heard."""
    d, taken = _dialog()
    seq = [seq[0]] + seq  # she says her first request again, unanswered
    for i, words in enumerate(seq):
        d._on_frame(_frame(words, 20.0 + i * gap))
    assert taken == seq[1:]


def test_muttering_once_is_still_her_own():
    d, taken = _dialog()
    d._on_frame(_frame("where did I put that novel", 20.0))
    d._on_frame(_frame("this is the study", 28.0))
    assert taken == []


@pytest.mark.parametrize("a,b", [("where is my cup", "where uh my cup")])
def test_a_misheard_repeat_is_the_same_act(a, b):
    assert said_act(_frame(a, 1.0).xml) == said_act(_frame(b, 9.0).xml)
