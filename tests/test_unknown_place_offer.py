"""A go-to to a room the robot was never shown: it offers to follow her there (issue 26 item 9, long tours).

fresh9/bay_long_tour, every seed on main 89146ce: her "Now come into the sitting room" was a go-to to a
room it did not know; it said so three times, she walked on alone, "You left", and the sitting room was
stored in the hall. A robot that does not know a room can be shown it: it asks "Shall I follow you
there?" and follows on yes. Frames come from the real understanding, as in test_dialog_confirm.py.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.manager import DialogManager
from tests.test_dialog_confirm import DOC, heard, says, sends
from tests.test_dialog_manager import cond, rejected

OFFER = "Shall I follow you there?"


def unknown(name: str):
    return cond("unknown_place", f'<param name="goal"><PLACE><TITLE name="{name}"/></PLACE></param>')


@pytest.fixture
def dm() -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    return m


@settings(max_examples=30, deadline=None)
@given(st.lists(st.sampled_from(["sitting", "room", "snug", "scullery", "study", "bedroom", "laundry", "den"]),
                min_size=1, max_size=3).map(" ".join))
def test_an_unknown_place_is_named_then_the_robot_offers_to_be_shown_it(name):
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    out = says(m.on_condition(unknown(name)))
    assert out == [f"Sorry, I do not know where the {name} is.", OFFER]
    assert not any("help" in line for line in out)  # nobody can help it there but her


@pytest.mark.parametrize("yes", ["yes", "yes please", "sure", "okay"])
def test_yes_to_the_offer_follows_her(dm, yes):
    dm.on_condition(unknown("sitting room"))
    (s,) = sends(dm.on_frame(heard(yes)))
    assert s.event == "follow"
    dm.es_state = "Following"
    assert says(dm.on_condition(cond("following"))) == ["OK, I am following you."]
    assert dm.stack == []


def test_no_to_the_offer_keeps_the_talk_going_and_sends_nothing(dm):
    dm.on_condition(unknown("sitting room"))
    out = dm.on_frame(heard("no"))
    assert sends(out) == []
    assert says(out) == ["OK. You can show it to me, or send me to another room."]
    assert dm.stack == []


def test_her_own_follow_me_instead_of_an_answer_follows_once_and_the_offer_is_not_put_again(dm):
    dm.on_condition(unknown("study"))
    (s,) = sends(dm.on_frame(heard("okay follow me then")))
    assert s.event == "follow"
    dm.es_state = "Following"
    out = dm.on_condition(cond("following"))
    assert says(out) == ["OK, I am following you."]
    assert OFFER not in says(out)
    assert dm.stack == []


def test_a_refused_follow_after_yes_is_explained_not_left_silent(dm):
    dm.on_condition(unknown("kitchen"))
    dm.on_frame(heard("yes"))
    out = dm.on_rejected(rejected("follow", "inapplicable", "Interacting"))
    assert len(says(out)) == 1
    assert dm.stack == []


def test_a_go_to_heard_as_a_room_it_was_never_shown_ends_with_following_her(dm):
    # the whole exchange: her request, the go-to sent, the plan's failure, the offer, her yes
    (s,) = sends(dm.on_frame(heard("now come into the sitting room")))
    assert s.event == "goto"
    dm.es_state = "Navigating"
    dm.on_condition(cond("navigating", '<param name="goal"><PLACE><TITLE name="sitting room"/></PLACE></param>'))
    dm.es_state = "Interacting"
    assert OFFER in says(dm.on_condition(unknown("sitting room")))
    (f,) = sends(dm.on_frame(heard("yes please do")))
    assert f.event == "follow"


@pytest.mark.parametrize("again", ["now come into the sitting room", "go to the sitting room please",
                                   "could you come to the sitting room"])
def test_the_same_go_to_said_again_while_the_offer_is_open_is_a_yes(dm, again):
    # she still wants it in a room only she knows the way to: no second "Sorry, I do not know where ..."
    dm.on_condition(unknown("sitting room"))
    out = dm.on_frame(heard(again))
    (s,) = sends(out)
    assert s.event == "follow"
    assert not any("do not know" in line for line in says(out))


def test_a_go_to_to_another_place_is_a_go_to_not_a_yes(dm):
    dm.on_condition(unknown("sitting room"))
    out = dm.on_frame(heard("go to the kitchen"))
    assert [s.event for s in sends(out)] == ["goto"]


def test_no_then_the_place_again_is_not_taken_as_following(dm):
    dm.on_condition(unknown("sitting room"))
    out = dm.on_frame(heard("no, go to the sitting room"))
    assert "follow" not in [s.event for s in sends(out)]


def test_her_follow_me_while_another_question_is_open_is_not_taken_for_the_offer(dm):
    # only the offer's own question takes "follow me" as its yes; otherwise the follow dialog decides
    out = dm.on_frame(heard("go to the sitting room", 0.3))
    assert says(out) == ["Shall I go to the sitting room?"]
    out = dm.on_frame(heard("follow me"))
    assert [s.event for s in sends(out)] == ["follow"]
    assert "Shall I follow you there?" not in says(out)


# ------------------------------------------------------------ a room named alone to a question whether to act
# review22 R3: "Shall I follow you there?" - "no, the kitchen" (she corrects the room the recogniser heard in her
# go-to) was taken as "this is the kitchen": the room the robot stood in stored as the kitchen, unasked. A room
# named alone to a question about going somewhere is where to go, never the name of this spot.
ROOMS = ["kitchen", "bathroom", "study", "bedroom", "hall", "dining room", "laundry room", "garage"]


def _room_alone(name: str, lead: str) -> str:
    return f"{lead}the {name}".strip()


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(ROOMS), st.sampled_from(ROOMS), st.sampled_from(["no, ", "no ", "no I meant ", "", "yes, "]),
       st.sampled_from(["offer", "goto"]))
def test_a_room_named_alone_to_a_go_to_question_or_the_offer_is_never_taught_here(asked, named, lead, question):
    """Whatever room she names alone, with or without "no", to "Shall I go to the X?" or to the offer after a
    go-to to a room it does not know: no place is taught; another room is a go-to to it; the same room with
    "no" is a plain no (nothing sent); the same room without it goes where she asked (goto or follow her)."""
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    if question == "offer":
        assert OFFER in says(m.on_condition(unknown(asked)))
    else:
        assert says(m.on_frame(heard(f"go to the {asked}", 0.3))) == [f"Shall I go to the {asked}?"]
    out = m.on_frame(heard(_room_alone(named, lead)))
    events = [s.event for s in sends(out)]
    assert "place_teaching" not in events
    assert not any(d.d.id == "place_teaching" for d in m.stack)
    if named != asked:
        assert events == ["goto"]
        assert sends(out)[0].children[0].find("PLACE/TITLE").get("name") == named
    elif lead.startswith("no"):
        assert events == []
    else:
        assert events == (["follow"] if question == "offer" else ["goto"])


def test_no_the_other_room_to_the_offer_goes_there_and_offers_again_when_it_is_unknown_too(dm):
    dm.on_condition(unknown("sitting room"))
    out = dm.on_frame(heard("no, the kitchen"))
    (s,) = sends(out)
    assert s.event == "goto" and s.children[0].find("PLACE/TITLE").get("name") == "kitchen"
    assert not any("show it to me" in line for line in says(out))  # the no is not said back: it goes
    dm.es_state = "Navigating"
    dm.on_condition(cond("navigating", '<param name="goal"><PLACE><TITLE name="kitchen"/></PLACE></param>'))
    dm.es_state = "Interacting"
    assert says(dm.on_condition(unknown("kitchen"))) == ["Sorry, I do not know where the kitchen is.", OFFER]
    (f,) = sends(dm.on_frame(heard("yes")))
    assert f.event == "follow"


def test_no_this_is_the_kitchen_to_the_offer_still_teaches_the_room(dm):
    # a whole statement with its deixis is a teaching (as to the go-to question): she names where they are
    dm.on_condition(unknown("sitting room"))
    assert [s.event for s in sends(dm.on_frame(heard("no, this is the kitchen")))] == ["place_teaching"]


@pytest.mark.parametrize(("request_", "question"), [("follow me", "Shall I follow you?"),
                                                    ("you are in my way", "Am I in your way?"),
                                                    ("that will be all for the cup", "Do you want to end the tour?")])
def test_no_and_a_room_alone_to_another_question_whether_to_act_is_asked_before_it_is_taught(dm, request_, question):
    # "Shall I follow you?" - "no, the kitchen": "[this is] the kitchen" or "[go to] the kitchen"; the robot
    # does not store the spot it stands in as the kitchen on a guess: it asks first
    assert says(dm.on_frame(heard(request_, 0.3))) == [question]
    out = dm.on_frame(heard("no, the kitchen"))
    assert sends(out) == []
    assert says(out)[-1] == "Is this the kitchen?"
    (s,) = sends(dm.on_frame(heard("yes")))
    assert s.event == "place_teaching"
