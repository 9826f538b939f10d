"""lang12 (issue 26 item 8): telling the robot it is in someone's way, and words said to someone else.

"Excuse me, you are in my way" is an act of its own (MAKE_WAY): the dialog sends it at once (never confirmed:
getting out of someone's way is what a polite robot does first), the supervisor, standing with the partner,
orders the player to back off and the dialog says so; in other states the rejection says why not. The player
backs off only where the floor plan leaves room and nobody tracked stands behind it. Words that call someone
else ("Tom, can you put the kettle on", "yes dear") are neither requests nor answered with "say that again".
"""

from __future__ import annotations

import pytest
from lxml import etree

from robot.dialog.loader import load
from robot.dialog.manager import DialogManager, Say, Send
from robot.navigation import player as player_mod
from robot.navigation.player import MAKE_WAY_BACK, Player
from robot.speech.module import frame_message, shared_understander

DOC = load()


def heard(words: str, confidence: float = 0.9) -> etree._Element:
    return frame_message(shared_understander().understand(words), 1.0, 2.0, confidence)


def frame(words: str) -> str:
    f = shared_understander().understand(words).frame
    return "NOT_UNDERSTOOD" if f is None else etree.tostring(f, encoding="unicode")


@pytest.mark.parametrize("words", ["excuse me, you're in my way", "you are blocking the door biron", "let me through",
                                   "could you please move out of the way", "can I get past", "I can't get past you",
                                   "mind out", "sorry BIRON, you are standing in my way", "make way please"])
def test_telling_it_it_blocks_someone_is_make_way(words):
    assert frame(words) == "<SPEECH><MAKE_WAY/></SPEECH>"


@pytest.mark.parametrize("words, act", [("make your way to the kitchen", "GOTO"), ("you are in the kitchen", "PLACE"),
                                        ("move to the bedroom", "GOTO"), ("step back", None), ("this way please", "FOLLOW")])
def test_way_words_in_other_requests_stay_those_requests(words, act):
    u = shared_understander().understand(words)
    assert u.act == act


def _dm(state: str = "Interacting") -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = state
    return m


def test_make_way_is_sent_at_once_even_heard_badly_and_the_robot_says_what_it_does():
    dm = _dm()
    out = dm.on_frame(heard("excuse me you are in my way", 0.2))
    (s,) = [o for o in out if isinstance(o, Send)]
    assert s.event == "make_way" and not [o for o in out if isinstance(o, Say)]
    out = dm.on_condition(etree.Element("condition", name="making_way"))
    assert [o.text for o in out if isinstance(o, Say)] == ["Sorry, I am in your way. I will back off if there is room behind me."]


@pytest.mark.parametrize("state, says", [("Following", "I am following you; I will keep my distance"),
                                         ("Navigating", "will pass you as soon as I can")])
def test_make_way_where_it_cannot_back_off_says_why(state, says):
    dm = _dm(state)
    dm.on_frame(heard("you are in my way"))
    out = dm.on_rejected(etree.Element("rejected", name="make_way", reason="inapplicable", state=state))
    (text,) = [o.text for o in out if isinstance(o, Say)]
    assert says in text


@pytest.mark.parametrize("words", ["Tom can you put the kettle on", "yes dear I am coming in a minute", "darling, get the door",
                                   "mum come and look at this", "no not you BIRON, I was talking to Peter",
                                   "look, the robot is listening", "anna follow me into the kitchen"])
def test_words_said_to_someone_else_are_no_request_and_get_no_say_that_again(words):
    msg = heard(words)
    assert msg.tag == "not_understood" and msg.get("addressee") == "other"


@pytest.mark.parametrize("words, act", [("this is tom's cup", "OBJECT"), ("this cup belongs to anna", "OBJECT"),
                                        ("bye tom", "GOODBYE"), ("tara love", "GOODBYE"), ("hello anna", "GREETING"),
                                        ("this is my cup which I really love", "OBJECT"), ("follow me biron", "FOLLOW")])
def test_a_name_as_owner_or_in_a_greeting_keeps_the_request(words, act):
    assert shared_understander().understand(words).act == act


class _Bus:
    def __init__(self) -> None:
        self.sent: list[tuple[str, etree._Element]] = []

    def publish(self, channel: str, el: etree._Element) -> None:
        self.sent.append((channel, el))


def _player(*, mapped: bool = True, behind_clear: bool = True, sweep_ok: bool = True) -> Player:
    import numpy as np
    p = Player.__new__(Player)
    p.bus = _Bus()
    p.goal = None
    p.period = 0.1
    p.limits = player_mod.limits_from_config({})
    p._make_way = MAKE_WAY_BACK
    p._map_asked = True
    p._tracks_sub = None
    p.outline = object() if mapped else None
    p.pose = lambda: (0.0, 0.0, 0.0)  # type: ignore[method-assign]
    p.mapped = lambda pose: np.array([[-3.0, 0.0]]) if mapped else np.zeros((0, 2))  # type: ignore[method-assign]
    p._sweep_ok = lambda v, w, m: sweep_ok  # type: ignore[method-assign]
    p._behind_clear = lambda reach: behind_clear  # type: ignore[method-assign]
    p._listen_to_people = lambda on: None  # type: ignore[method-assign]
    return p


def test_the_player_backs_off_half_a_metre_where_there_is_room_then_stops():
    p = _player()
    steps = []
    while p._make_way > 0.0 and len(steps) < 200:
        steps.append(p.control_step())
    backed = -sum(v for v, _ in steps) * p.period
    assert MAKE_WAY_BACK - 0.02 <= backed <= MAKE_WAY_BACK + 0.02 and all(w == 0.0 for _, w in steps)
    assert p.control_step() is None  # done: nothing more sent


@pytest.mark.parametrize("why", [dict(behind_clear=False), dict(sweep_ok=False), dict(mapped=False)])
def test_the_player_does_not_back_into_a_person_the_furniture_or_without_a_floor_plan(why):
    p = _player(**why)
    out = p.control_step()
    assert out in (None, (0.0, 0.0)) and p._make_way == 0.0
    assert all(float(el.get("v", "0")) == 0.0 for _, el in p.bus.sent)
