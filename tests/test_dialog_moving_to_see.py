"""When the object attention drives to a viewpoint, the robot says so, once.

gen24 (generated tour 9700-10, -16): after "Let me have a look." the camera could not see where she pointed and the
robot drove 8-10 s to a viewpoint saying nothing; to her that was no answer, and she gave the tour up (10) or said
her request again vaguely (16: the lamp stored with no owner or colour). Now the object attention tells the ES
before its first drive of a search (event ``moving_to_see``) and in ObjectTeaching the dialog says so.
"""

from __future__ import annotations

from lxml import etree

from robot.supervisor import ES_EVENTS, event_xml
from tests.test_dialog_bus import Robot

MOVING = "I cannot see it from here. I will move over to see it."
ROUND = "I do not see it yet. I will look around you for it."


def _teach_with_drives(robot: Robot, drives: tuple[float, ...], learned: float, how: str = "drive") -> list[str]:
    """Greeted, "this is my cup" at 6 s; the object attention reports a drive to see at each of ``drives`` (and
    one leg each), the cup learned at ``learned``. Returns what the robot said."""
    robot.greet()
    robot.utter("this is my cup", 6.0, 7.0)
    objects = robot.sim.bus.participant("object_attention")
    pose = etree.fromstring('<POSE x="1" y="1" theta="0" frame="map" tolerance="0.2" align="true"/>')
    for t in drives:
        robot.sim.call_at(t, lambda: objects.publish(ES_EVENTS, event_xml("moving_to_see", attrs={"how": how})))
        robot.sim.call_at(t + 0.01, lambda: objects.publish(ES_EVENTS, event_xml("view_blocked", children=(pose,))))
    cup = etree.fromstring('<OBJECT type="cup" name="cup" owner="partner" x="1" y="0" z="0.8" frame="map"/>')
    robot.sim.call_at(learned, lambda: objects.publish(ES_EVENTS, event_xml("object_recognized", children=(cup,))))
    robot.sim.run(until=learned + 6.0)
    return robot.sentences()


def test_the_robot_says_it_moves_to_see_between_let_me_have_a_look_and_the_result(robot):
    said = _teach_with_drives(robot, (10.0,), 20.0)
    assert said.count(MOVING) == 1
    look, moving = said.index("Let me have a look."), said.index(MOVING)
    learned = next(i for i, s in enumerate(said) if s.startswith("OK, I have learned"))
    assert look < moving < learned
    assert not any(s.startswith("Now, back to") for s in said)  # no resumption: it never left the teaching
    assert robot.es.state == "Interacting"


def test_a_second_drive_in_the_same_teaching_is_not_announced_again(robot):
    said = _teach_with_drives(robot, (10.0, 16.0), 24.0)
    assert said.count(MOVING) == 1


def test_a_drive_reported_outside_a_teaching_says_nothing(robot):
    # no search of hers under way (the ES in Interacting): the condition never reaches the dialog
    robot.greet()
    objects = robot.sim.bus.participant("object_attention")
    robot.sim.call_at(6.0, lambda: objects.publish(ES_EVENTS, event_xml("moving_to_see", attrs={"how": "drive"})))
    robot.sim.run(until=12.0)
    assert MOVING not in robot.sentences()


def test_a_search_round_her_is_announced_in_its_own_words(robot):
    said = _teach_with_drives(robot, (10.0,), 20.0, how="round")
    assert said.count(ROUND) == 1 and MOVING not in said
    assert said.index("Let me have a look.") < said.index(ROUND)
