"""After a go-to ("I have arrived at the kitchen") the partner who sent the robot there goes on with the tour.

Generated tours 1000-011 and 059 (issue 26): her "bye for now" and her next requests after the arrival got
"Please say hello to me first." or nothing, the robot having gone back to looking around. Now a whole request
or a good-bye said within ``ARRIVAL_RESUME`` s of the arrival is taken as said with a greeting (as "hello BIRON,
follow me"): synchronised with a potential partner like any greeting, so with nobody facing the robot (a
radio) nothing starts, and the robot asks to be looked at (docs/semantics.md §2).
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.module import ARRIVAL_RESUME
from robot.supervisor import ES_EVENTS, event_xml
from tests.test_dialog_bus import Robot


def arrive(robot: Robot) -> float:
    """Greet, send it to the kitchen, and let the sequencer report the arrival; returns the arrival time."""
    robot.greet()
    robot.utter("go to the kitchen", 3.0, 4.0)
    sequencer = robot.sim.bus.participant("sequencer")
    place = etree.Element("PLACE", name="kitchen")
    robot.sim.call_at(10.0, lambda: sequencer.publish(ES_EVENTS, event_xml("goal_reached", children=(place,))))
    robot.sim.run(until=12.0)
    assert robot.es.state == "LookingAround"
    said = robot.sentences()
    assert said[-1].startswith("I have arrived at the")
    return 10.0


def test_follow_me_after_the_arrival_is_obeyed_without_a_new_greeting(robot):
    t = arrive(robot)
    robot.utter("follow me", t + 8.0, t + 9.0)
    robot.partner(t + 9.1)
    robot.sim.run(until=t + 16.0)
    assert robot.sentences() == ["OK, I am following you."]  # no "Hello, I am BIRON", no "say hello first"
    assert robot.es.state == "Following"


def test_a_good_bye_after_the_arrival_is_answered(robot):
    t = arrive(robot)
    robot.utter("thank you, bye", t + 20.0, t + 21.0)
    robot.partner(t + 21.1)
    robot.sim.run(until=t + 28.0)
    assert robot.sentences() == ["Good-bye! It was nice talking to you."]
    assert robot.es.state == "LookingAround"


def test_with_nobody_facing_the_robot_a_request_after_the_arrival_starts_nothing(robot):
    t = arrive(robot)
    robot.utter("follow me", t + 5.0, t + 6.0)  # a radio: nobody speaks facing the robot
    robot.sim.run(until=t + 25.0)
    assert robot.sentences() == ["I can't see you. Please look at me."]
    assert robot.es.state == "LookingAround"
    follows = [r for r in robot.records("/robot/es/events") if 'name="follow"' in r["xml"]]
    assert not follows  # the request went with the greeting nobody took


def test_long_after_the_arrival_a_request_needs_a_greeting_again(robot):
    t = arrive(robot)
    later = t + ARRIVAL_RESUME + 5.0
    robot.utter("follow me", later, later + 1.0)
    robot.partner(later + 1.1)
    robot.sim.run(until=later + 8.0)
    assert robot.sentences() == ["Please say hello to me first."]
    assert robot.es.state == "PotentialPartner"


@given(after=st.floats(min_value=1.0, max_value=ARRIVAL_RESUME - 2.0))
@settings(max_examples=8, deadline=None)
def test_a_greeting_after_the_arrival_is_answered_as_a_greeting(after):
    robot = Robot()
    try:
        t = arrive(robot)
        robot.utter("hello biron", t + after, t + after + 0.7)
        robot.partner(t + after + 0.8)
        robot.sim.run(until=t + after + 6.0)
        assert robot.sentences() == ["Hello, I am BIRON. What can I do for you?"]
        assert robot.es.state == "Interacting"
    finally:
        robot.sim.close()
