"""talk17: the users' everyday answers: calling off ("forget it"), praise and non-native yes-forms, "right there"
as a stop, a go-to said after a remark about the way, small talk about who made a thing, and "[can] you go" with a
short word lost."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.cli import main
from robot.speech.grammar import Understander
from robot.speech.module import shared_understander

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


@pytest.fixture(scope="module")
def u() -> Understander:
    return shared_understander()


@pytest.mark.parametrize("words", ["forget it", "oh forget about it", "skip that", "let it be biron"])
def test_calling_it_off_alone_is_a_no(u: Understander, words: str) -> None:
    assert u.understand(words).act == "NO"


def test_calling_it_off_takes_back_the_request_before_and_keeps_the_one_after(u: Understander) -> None:
    assert u.understand("follow me, oh forget it").act == "NO"
    assert u.understand("forget it, follow me").act == "FOLLOW"


@pytest.mark.parametrize("words", ["nicely spotted", "good spotting robot", "yes is correct", "yeah is right"])
def test_praise_and_a_yes_without_its_deixis_answer_yes(u: Understander, words: str) -> None:
    assert u.understand(words).act == "YES"


def test_a_hesitation_word_stays_a_hesitation(u: Understander) -> None:
    # no lexicon phrase starts with "well": "well" inside a room name is still dropped as a hesitation
    assert u.understand("please go to the living well room").frame is not None
    assert u.understand("please go to the living well room").act == "GOTO"
    assert u.understand("please go to the living well room").coverage == 1.0


@pytest.mark.parametrize("words", ["right there", "right here biron", "just right there please"])
def test_right_there_alone_is_the_stop(u: Understander, words: str) -> None:
    assert u.understand(words).act == "STOP"


@pytest.mark.parametrize("words", ["here", "there", "this one right here", "that one over there"])
def test_a_plain_here_or_a_which_one_answer_is_no_stop(u: Understander, words: str) -> None:
    assert u.understand(words).act != "STOP"


ROOMS = ["kitchen", "bedroom", "study", "bathroom", "living room", "office"]
WAYS = ["the hall", "the corridor", "the way", "the passage", "the path"]


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(WAYS), st.sampled_from(["clear", "free", "open"]), st.sampled_from(["", "now ", "again "]),
       st.sampled_from(["go to", "please go to", "can you go to", "drive to"]), st.sampled_from(ROOMS))
def test_a_go_to_after_a_remark_about_the_way_goes_there(way: str, adj: str, when: str, verb: str, room: str) -> None:
    u = shared_understander()
    res = u.understand(f"{way} is {adj} {when}{verb} the {room}")
    assert res.act == "GOTO"
    title = res.frame.find("GOTO/PLACE/TITLE")
    assert title is not None and title.get("name") == room


def test_with_a_deixis_the_remark_names_the_room_she_is_in(u: Understander) -> None:
    res = u.understand("this is the hall now go to the kitchen")
    assert res.act == "PLACE" and res.frame.find("PLACE/TITLE").get("name") == "hall"


@pytest.mark.parametrize("words", ["my grandfather carved that bench", "my wife knitted this blanket herself",
                                   "i painted that picture myself", "this is where the kids play"])
def test_who_made_a_thing_or_what_a_spot_is_for_teaches_nothing(u: Understander, words: str) -> None:
    assert u.understand(words).frame is None


def test_who_made_it_said_after_the_thing_keeps_the_teaching(u: Understander) -> None:
    res = u.understand("this is the mug my daughter painted")
    assert res.act == "OBJECT" and res.frame.find("OBJECT/TITLE").get("name") == "mug"


@pytest.mark.parametrize("words", ["you go", "can go", "you go biron"])
def test_can_you_go_with_a_short_word_lost_asks_where(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "GOTO" and res.frame.find("GOTO/PLACE/TITLE") is None


@pytest.mark.parametrize("words", ["you go first", "you go ahead"])
def test_you_go_with_more_said_is_no_go_to(u: Understander, words: str) -> None:
    assert u.understand(words).act != "GOTO"


def test_lang_silence_seed_10_asks_where_after_a_misheard_can_you_go(capsys) -> None:
    # the recogniser loses "can": "you go" was not understood and "Where shall I go?" never said
    assert main(["run", str(SCENARIOS / "lang_silence.xml"), "--seed", "10", "--quiet"]) == 0, capsys.readouterr().out
