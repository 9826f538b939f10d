"""lang12 (issue 26 item 8): telling the robot it is in someone's way, and words said to someone else.

"Excuse me, you are in my way" is an act of its own (MAKE_WAY): heard clearly, the dialog sends it at once
(getting out of someone's way is what a polite robot does first; heard below confirm-below it asks "Am I in your
way?" first, as for every act that moves the robot: talk13), the supervisor, standing with the partner,
orders the player to back off and the dialog says so; in other states the rejection says why not. The player
backs off only where the floor plan leaves room and nobody tracked stands behind it. Words that call someone
else ("Tom, can you put the kettle on", "yes dear") are neither requests nor answered with "say that again".
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
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
                                   "mind out", "sorry BIRON, you are standing in my way", "make way please",
                                   "i cannot get past", "can i get past you", "you are blocking me"])
def test_telling_it_it_blocks_someone_is_make_way(words):
    assert frame(words) == "<SPEECH><MAKE_WAY/></SPEECH>"


@pytest.mark.parametrize("words", ["you are not in my way", "you're not in the way", "you are not in the way anymore",
                                   "you aren't in my way", "you're not blocking anything", "you are not in my way, are you",
                                   "i can get past", "i can get past you now", "it's ok, i can get past",
                                   "you are blocking my view", "never mind, you're not in my way"])
def test_saying_it_is_not_in_the_way_or_that_she_can_pass_never_makes_way(words):
    # review12 item 2: a negation or "I can get past" turned into a blind reverse
    assert shared_understander().understand(words).act != "MAKE_WAY"


@pytest.mark.parametrize("words, act", [("make your way to the kitchen", "GOTO"), ("you are in the kitchen", "PLACE"),
                                        ("move to the bedroom", "GOTO"), ("step back", None), ("this way please", "FOLLOW")])
def test_way_words_in_other_requests_stay_those_requests(words, act):
    u = shared_understander().understand(words)
    assert u.act == act


def _dm(state: str = "Interacting") -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = state
    return m


def test_make_way_heard_clearly_is_sent_at_once_and_the_robot_says_what_it_does():
    dm = _dm()
    out = dm.on_frame(heard("excuse me you are in my way", 0.9))
    (s,) = [o for o in out if isinstance(o, Send)]
    assert s.event == "make_way" and not [o for o in out if isinstance(o, Say)]
    out = dm.on_condition(etree.Element("condition", name="making_way"))
    assert [o.text for o in out if isinstance(o, Say)] == ["Sorry, I am in your way. I will back off if there is room behind me."]


@pytest.mark.parametrize("answer, sent", [("yes", True), ("no", False)])
def test_make_way_heard_badly_is_asked_first_as_every_act_that_moves_the_robot(answer, sent):
    # talk13: a misheard "you are in my way" (below confirm-below) made the robot back off unasked
    dm = _dm()
    out = dm.on_frame(heard("excuse me you are in my way", 0.3))
    assert not [o for o in out if isinstance(o, Send)]
    assert [o.text for o in out if isinstance(o, Say)] == ["Am I in your way?"]
    out = dm.on_frame(heard(answer))
    assert bool([o for o in out if isinstance(o, Send) and o.event == "make_way"]) == sent
    if not sent:
        assert [o.text for o in out if isinstance(o, Say)] == ["OK, I will stay here."]


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


@pytest.mark.parametrize("words", ["go to the kitchen, peter", "follow me, kids", "follow me tom", "come on tom, follow me",
                                   "stop, tom", "stop it tom", "wait for me anna", "and this is the kitchen, tom",
                                   "hey tom, look at this", "please tom, follow me", "i'm coming, dear"])
def test_a_call_to_someone_else_is_heard_wherever_the_name_stands(words):
    # review12 item 3: only a name said first was a call; said last, the robot drove off on words for Peter
    msg = heard(words)
    assert msg.tag == "not_understood" and msg.get("addressee") == "other"


@pytest.mark.parametrize("words, act", [("mark this as the kitchen", "PLACE"), ("no love, the kitchen", "PLACE"),
                                        ("follow me please dear", "FOLLOW"), ("this is the kitchen, dear", "PLACE"),
                                        ("goodbye my little friend", "GOODBYE")])
def test_a_name_or_endearment_that_calls_nobody_else_keeps_the_request(words, act):
    # review12 item 4: "mark" is a verb, a correction with "love" answers the robot, people call a robot "dear"
    assert shared_understander().understand(words).act == act


@pytest.mark.parametrize("words", ["peter is my husband", "guests bedroom", "partner mode", "thank you dear",
                                   "no, the cup dear", "this is peter", "tom and i live here"])
def test_a_statement_naming_someone_is_not_said_to_them(words):
    assert heard(words).get("addressee") != "other"


@pytest.mark.parametrize("words, act", [("this is tom's cup", "OBJECT"), ("this cup belongs to anna", "OBJECT"),
                                        ("tara love", "GOODBYE"), ("bye biron", "GOODBYE"), ("bye friend", "GOODBYE"),
                                        ("goodbye my little friend", "GOODBYE"), ("hello robot", "GREETING"),
                                        ("this is my cup which I really love", "OBJECT"), ("follow me biron", "FOLLOW")])
def test_a_name_as_owner_or_a_greeting_for_the_robot_keeps_the_request(words, act):
    assert shared_understander().understand(words).act == act


@pytest.mark.parametrize("words", ["bye tom", "hello anna", "see you tomorrow julia", "good bye grandma",
                                   "bye bye peter see you later"])
def test_a_greeting_or_good_bye_naming_someone_else_is_said_to_them(words):
    # talk13 (fresh4 ring_visitor_leaves): a visitor's "See you tomorrow Julia" ended Julia's tour
    msg = heard(words)
    assert msg.tag == "not_understood" and msg.get("addressee") == "other"


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
    from types import SimpleNamespace
    from robot.blindside import SonarEchoes
    p.sim = SimpleNamespace(now=0.0)
    p.odo = SimpleNamespace(pose=(0.0, 0.0, 0.0))
    p.sonar = SonarEchoes()  # a packet came, nothing heard behind (closed loop: test_make_way_closed_loop.py)
    p._make_way_at = p._sonar_at = p._tracks_at = 0.0
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


_REQUESTS = ["follow me", "go to the kitchen", "can you put the kettle on", "where are my keys", "this is my cup",
             "come and look at this", "stop", "wait here"]
_CALLED = ["tom", "anna", "mum", "dad", "peter", "darling", "honey", "sweetie", "kids"]


@given(st.sampled_from(_CALLED), st.sampled_from(_REQUESTS), st.sampled_from(["", "yes ", "no ", "oh "]))
def test_a_turn_that_calls_someone_else_first_is_theirs_and_one_that_calls_the_robot_is_its(who, request, answer):
    """The rule's invariant: the same words after another person's name or an endearment are said to that
    person (no frame, addressee other); after BIRON's name they are the robot's (the aside rule never fires)."""
    u = shared_understander().understand(f"{answer}{who} {request}")
    assert u.frame is None and u.aside
    mine = shared_understander().understand(f"{answer}biron {request}")
    assert not mine.aside
