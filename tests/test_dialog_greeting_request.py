"""A greeting that opens a request ("hello BIRON, follow me"): the robot greets and does what she asked.

On main a045923 the request was lost: the frame was the greeting alone, so she had to say "follow me"
again. Now the understanding sends the request as a frame of its own after the greeting, and the dialog
handles it once the supervisor has taken the greeting (docs/semantics.md §4).
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.speech.module import shared_understander
from tests.test_dialog_bus import Robot


def frames(robot: Robot) -> list[str]:
    return [r["xml"] for r in robot.records("/robot/speech/frames")]


def test_hello_biron_follow_me_greets_and_follows(robot):
    robot.utter("hello biron, follow me", 0.3, 1.6)
    robot.partner(1.7)
    robot.sim.run(until=8.0)
    assert robot.sentences() == ["Hello, I am BIRON. What can I do for you?", "OK, I am following you."]
    assert robot.es.state == "Following"
    greeting, request = frames(robot)
    assert 'opens="true"' in greeting and "<GREETING" in greeting
    assert 'after="greeting"' in request and "<FOLLOW/>" in request


def test_hi_biron_this_is_the_kitchen_greets_and_teaches_the_kitchen(robot):
    robot.utter("hi biron this is the kitchen", 0.3, 2.0)
    robot.partner(2.1)
    robot.sim.run(until=8.0)
    said = robot.sentences()
    assert said[0] == "Hello, I am BIRON. What can I do for you?"
    assert any("kitchen" in s for s in said[1:])


def test_a_greeting_nobody_takes_takes_its_request_with_it(robot):
    robot.utter("hello biron, follow me", 0.3, 1.6)  # a radio: nobody faces the robot
    robot.sim.run(until=25.0)
    assert robot.sentences() == ["I can't see you. Please look at me."]
    assert robot.es.state == "LookingAround"
    assert not [r for r in robot.records("/robot/es/events") if 'name="follow"' in r["xml"]]


def test_during_the_interaction_the_greeting_is_left_out_and_the_request_done(robot):
    robot.greet()
    robot.sim.run(until=6.0)
    robot.sentences()
    robot.utter("hello biron, follow me", 6.3, 7.6)
    robot.sim.run(until=12.0)
    assert robot.sentences() == ["OK, I am following you."]  # no "We are already talking"
    assert robot.es.state == "Following"


def test_a_greeting_alone_is_one_frame(robot):
    robot.greet()
    robot.sim.run(until=4.0)
    (greeting,) = frames(robot)
    assert "opens" not in greeting


@given(hello=st.sampled_from(["hello", "hi", "hey", "good morning", "hello there"]),
       name=st.sampled_from(["", " biron", " robot"]),
       request=st.sampled_from(["follow me", "come with me", "this is the kitchen", "go to the kitchen",
                                "what can you do", "stop"]))
@settings(max_examples=60, deadline=None)
def test_a_greeting_before_a_whole_request_keeps_the_request(hello, name, request):
    """Whatever greeting opens it, a whole request after it is understood as that request alone."""
    u = shared_understander()
    said = u.understand(f"{hello}{name}, {request}")
    alone = u.understand(request)
    assert said.act == "GREETING"
    assert said.rest
    assert u.understand(" ".join(said.rest)).act == alone.act


def test_during_the_interaction_a_greeting_with_words_not_understood_asks_to_hear_it_again(robot):
    """lang_greet_request seed 2: "Hello again, this is the kitchen", misheard, got "Did you say hello to
    me?" in Interacting, and then "We are already talking": the turn was not understood."""
    robot.greet()
    robot.sim.run(until=6.0)
    robot.sentences()
    robot.utter("hello again uh is the the", 6.3, 7.6)
    robot.sim.run(until=12.0)
    assert robot.sentences() == ["Sorry, I did not understand you. Could you say that again?"]
    assert robot.es.state == "Interacting"
