"""talk21: a follow said with a lead-in ("let's go over to the study, follow me") or with its destination repaired
("follow me into the study, er, no, into the bedroom") is the follow; greetings with words said of the robot or of
the home; "one's" is "one is" (no owner "one"); a contrasting clause about another thing is set aside; a stop said
twice in other words is one stop. Rows and paraphrases of our own (fresh9's kinds; never the checker's sentences)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.speech.grammar import Understander
from robot.speech.module import shared_understander


@pytest.fixture(scope="module")
def u() -> Understander:
    return shared_understander()


ROOMS = ["bedroom", "study", "garage", "bathroom", "dining room", "hall", "guest room"]
FOLLOWS = ["follow me", "come with me", "this way please", "follow me please"]


@settings(max_examples=40, deadline=None)
@given(room=st.sampled_from(ROOMS), lead=st.sampled_from(["let's go to", "let's go over to", "let us go into",
                                                            "we are going to", "ok we'll go to", "so let's head to"]),
       follow=st.sampled_from(FOLLOWS))
def test_going_together_then_a_follow_is_the_follow_never_a_go_to(u: Understander, room: str, lead: str,
                                                                   follow: str) -> None:
    res = u.understand(f"{lead} the {room}, {follow}")
    assert res.act == "FOLLOW"


@settings(max_examples=40, deadline=None)
@given(first=st.sampled_from(ROOMS), second=st.sampled_from(ROOMS),
       verb=st.sampled_from(["follow me", "come with me"]), prep=st.sampled_from(["to", "into"]),
       edit=st.sampled_from(["no", "um, no", "er no"]))
def test_a_follow_whose_destination_is_repaired_stays_the_follow(u: Understander, first: str, second: str, verb: str,
                                                                  prep: str, edit: str) -> None:
    res = u.understand(f"{verb} {prep} the {first}, {edit}, {prep} the {second}")
    assert res.act == "FOLLOW" and not res.partial


@pytest.mark.parametrize("words", ["go to the study, no, go to the bedroom", "follow me, no, go to the bedroom",
                                   "go to the study, no, to the bedroom", "let's go to the garage",
                                   "follow me, no wait, stop"])
def test_a_go_to_with_its_own_verb_or_without_a_follow_stays_what_it_was(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == ("STOP" if words.endswith("stop") else "GOTO")


@pytest.mark.parametrize("words", ["good evening, you must be biron", "hi there, welcome to our home",
                                   "hello, so you're the robot", "morning, you must be the new robot",
                                   "hello biron, welcome to my flat"])
def test_a_greeting_with_words_said_of_the_robot_or_the_home_is_a_whole_greeting(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "GREETING" and not res.partial and not res.aside


def test_the_robot_spoken_of_to_someone_else_is_still_not_for_it(u: Understander) -> None:
    assert u.understand("look, the robot is listening").act is None


@pytest.mark.parametrize("words,owner", [("this one's our kettle", "us"), ("that one's mine", "speaker"),
                                         ("the red one's my bag", "speaker")])
def test_ones_is_one_is_never_an_owner_called_one(u: Understander, words: str, owner: str) -> None:
    res = u.understand(words)
    assert res.frame is not None
    owners = [o.get("name") for o in res.frame.iter("OWNER")]
    assert "one" not in owners


@pytest.mark.parametrize("words", ["this pen is mine, the other one is my son's", "this cup is mine, that one is anna's",
                                   "this is my mug, the other cup is his"])
def test_a_contrasting_clause_about_another_thing_keeps_the_teachings_own_owner(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and not res.partial
    assert [o.get("name") for o in res.frame.iter("OWNER")] == ["speaker"]


def test_a_remark_about_another_thing_that_is_no_owner_is_not_set_aside(u: Understander) -> None:
    assert u.understand("this is my mug, the other one is broken").partial


@pytest.mark.parametrize("words", ["alright, stop, that is far enough", "that will do, stop", "stop, far enough"])
def test_a_stop_said_twice_in_other_words_is_one_whole_stop(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "STOP" and not res.partial


@pytest.mark.parametrize("words", ["the biron follow me", "the you follow me please"])
def test_a_misheard_word_before_a_follow_is_no_destination_and_stays_a_word_lost(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "FOLLOW" and res.partial


@pytest.mark.parametrize("words", ["this is my pen, the other one belongs to my son",
                                   "this one's my bag, the other belongs to my daughter"])
def test_whom_the_other_thing_belongs_to_is_never_the_shown_things_owner(u: Understander, words: str) -> None:
    res = u.understand(words)
    assert res.act == "OBJECT" and not res.partial
    assert [o.get("name") for o in res.frame.iter("OWNER")] == ["speaker"]


@pytest.mark.parametrize("who", ["we", "i"])
@pytest.mark.parametrize("verb", ["put", "leave"])
def test_where_did_we_put_a_thing_is_the_where_question_never_a_teaching(u: Understander, who: str,
                                                                                verb: str) -> None:
    res = u.understand(f"where did {who} {verb} the green vase again")
    assert res.act == "WHERE" and not res.partial


def test_the_other_things_owner_never_becomes_the_shown_things_when_her_own_whose_was_lost(u: Understander) -> None:
    res = u.understand("this pen here the other one is my son's")
    assert res.act == "OBJECT" and res.partial
    assert [o.get("name") for o in res.frame.iter("OWNER")] == []


def test_the_other_things_owner_is_set_aside_when_her_copula_was_lost(u: Understander) -> None:
    res = u.understand("this pen here mine the other one is my son's")
    assert res.act == "OBJECT" and res.partial
    assert "son" not in [o.get("name") for o in res.frame.iter("OWNER")]
