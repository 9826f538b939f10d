"""talk16: greetings said with the words that go with them, a word before "room", remarks about a room, "not X, I
said Y", a that-one teaching whose noun was lost, and what a simulated user does again when the robot missed her."""

from __future__ import annotations

import pytest
from lxml import etree

from homesim.scenario.model import Face, PointAt, Say, Target, Wait, WalkTo
from humans.script import _said_part
from robot.speech.grammar import Understander


@pytest.fixture(scope="module")
def u() -> Understander:
    return Understander()


def frame(u: Understander, words: str) -> str | None:
    f = u.understand(words).frame
    return None if f is None else etree.tostring(f, encoding="unicode").replace("<SPEECH>", "").replace("</SPEECH>", "")


@pytest.mark.parametrize("words", [
    "what's up", "wassup biron", "yo robot what is up", "nice to meet you", "hi there, pleased to meet you, biron",
    "good evening biron, it is a pleasure to meet you", "how are you doing", "how is it going biron",
])
def test_the_words_that_go_with_a_greeting_greet(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "GREETING"
    assert res.coverage == 1.0  # a whole greeting: not "Did you say hello to me?"


def test_a_misheard_opening_before_the_name_leaves_the_greeting_sure(u: Understander) -> None:
    res = u.understand("good to biron, lovely to meet you")
    assert res.act == "GREETING" and res.coverage == 1.0
    # without a greeting word after the name the misheard words still count against it
    assert u.understand("go to biron").act != "GREETING"


def test_a_greeting_word_after_a_request_keeps_the_request(u: Understander) -> None:
    assert frame(u, "follow me please, how are you") == "<FOLLOW/>"


@pytest.mark.parametrize("words,name", [
    ("this little room is the snug", "snug"), ("this small room here is our den", "den"),
    ("this cosy room is the conservatory", "conservatory"),
])
def test_a_word_for_the_room_before_room_names_no_room(u: Understander, words: str, name: str) -> None:
    f = u.understand(words).frame
    assert f is not None and f.find("PLACE/TITLE").get("name") == name


@pytest.mark.parametrize("words", ["this room is so boring", "this room is nice", "this little room is very cosy"])
def test_a_remark_about_the_room_asks_no_room_name(u: Understander, words: str) -> None:
    assert u.understand(words).frame is None


def test_a_room_whose_name_was_lost_is_still_asked_about(u: Understander) -> None:
    # "this room is my <lost>": her owner word says a name followed
    assert frame(u, "this room is my") == '<PLACE><OWNER name="speaker"/></PLACE>'


@pytest.mark.parametrize("words,name", [
    ("not the kitchen, I said the bathroom", "bathroom"), ("no, not the den, I said the snug", "snug"),
    ("not my study, I said the box room", "box room"),
])
def test_not_x_i_said_y_is_y(u: Understander, words: str, name: str) -> None:
    f = u.understand(words).frame
    assert f is not None and f.find("PLACE/TITLE").get("name") == name


def test_that_one_with_a_copula_and_its_noun_lost_is_a_teaching_to_ask_about(u: Understander) -> None:
    f = u.understand("that one on the coffee table is my that").frame
    assert f is not None and f[0].tag == "OBJECT" and f.find("OBJECT/OWNER").get("name") == "speaker"
    assert f.find("OBJECT/TITLE") is None  # the noun was lost: the dialog asks what it is
    assert frame(u, "that one on the left") == '<THAT_ONE side="left"><GESTURE val="probably_pointing"/></THAT_ONE>'


def test_a_repeated_turn_is_her_words_not_what_she_did_before_them() -> None:
    robot, other = Target("robot"), Target("human", "wim")
    say, point = Say("What can you do"), PointAt(Target("object", "cup"))
    turn = (Wait(1.0), WalkTo(Target("point", x=4.6, y=4.0)), Face(other), Wait(8.0), WalkTo(Target("point", x=4.0, y=2.5)),
            Face(robot), say)
    assert _said_part(turn) == (Face(robot), say)
    assert _said_part((Wait(1.0), point, say, WalkTo(robot))) == (point, say, WalkTo(robot))
    walk = WalkTo(Target("point", x=1.0, y=1.0))
    assert _said_part((Wait(1.0), walk, Wait(2.0))) == (walk, Wait(2.0))  # no words: all but the opening pause


@pytest.mark.parametrize("words,act", [
    ("do you mind waiting here", "<WAIT/>"), ("would you mind holding on a second", "<WAIT/>"),
    ("if you could just wait there", "<WAIT/>"), ("this way to the utility room", "<FOLLOW/>"),
    ("with me to my study", "<FOLLOW/>"), ("walk with me to the mudroom", "<FOLLOW/>"),
])
def test_polite_and_indirect_requests_and_a_follow_with_where_to(u: Understander, words: str, act: str) -> None:
    res = u.understand(words)
    assert frame(u, words) == act and res.coverage == 1.0


def test_a_verbless_go_to_after_follow_words_is_the_follow_confirmed(u: Understander) -> None:
    res = u.understand("come with the to my study")  # "me" misheard
    assert frame(u, "come with the to my study") == "<FOLLOW/>" and res.partial
    # said alone, or after words of no follow, it stays the go-to
    assert u.understand("to my study").act == "GOTO"
    assert u.understand("go to my study").act == "GOTO"


@pytest.mark.parametrize("words", ["good day biron, it is is pleasure to meet you", "hello biron, the the nice to meet you"])
def test_words_not_placed_after_a_whole_greeting_by_name_take_nothing_from_it(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "GREETING" and res.coverage == 1.0
