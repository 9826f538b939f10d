"""A teaching said while the robot follows and stands by her (she stopped) ends the walk, as after a pause.

fresh7/corr_fast_walker_goto: a leader at 1.3 m/s stopped in the guest room and said "here, stop" three times
while the robot was still 6 m behind in the hallway; none was heard. The robot came up to him and stood by him
(the follower's status ``waiting``), and "this is the guest room", the sunglasses and the go-to back all got
"I am still following you; say stop first" until the scene ended. Now a place or object teaching begun after the
follower has said ``waiting`` for ``STOOD_FOR`` s (the rule a stop from off her bearing already reads: her walk
is over) is taught: the dialog sends the stop first, as it does in a pause. Said while she walks on (``following``)
or the moment the robot stops beside her, it is refused as before.
"""

from __future__ import annotations

import pytest
from lxml import etree

from robot.contract import FOLLOW_STATUS
from robot.partner_search import STOOD_FOR
from robot.supervisor import ES_EVENTS

from tests.test_dialog_bus import Robot


def _status(robot: Robot, state: str, start: float, end: float) -> None:
    """The follower's status ``state`` every 0.1 s from ``start`` to ``end``."""
    fol = robot.sim.bus.participant("follower")

    def beat(t: float) -> None:
        fol.publish(FOLLOW_STATUS, etree.Element("follow", distance="1.3", speed="0", at_limit="false", state=state))
        if t + 0.1 < end:
            robot.sim.call_at(t + 0.1, lambda: beat(t + 0.1))

    robot.sim.call_at(start, lambda: beat(start))


def _teach_while_following(robot: Robot, state: str, stood: float) -> list[str]:
    """Greeted, "follow me" at 7 s; from 9 s the follower says ``state``; "this is the kitchen" begins
    ``stood`` s after the follower began to say ``state``. Returns what the robot said."""
    robot.greet()
    robot.utter("follow me", 7.0, 7.6)
    _status(robot, state, 9.0, 30.0)
    robot.utter("this is the kitchen", 9.0 + stood, 10.0 + stood)
    robot.sim.run(until=25.0)
    return robot.sentences()


@pytest.mark.parametrize("stood", [STOOD_FOR + 0.5, 6.0])
def test_a_place_named_while_it_stands_by_her_is_taught_after_a_stop(robot, stood):
    said = _teach_while_following(robot, "waiting", stood)
    assert "OK, I am following you." in said
    assert not any("say stop first" in s for s in said)
    assert said[-1] == "OK, this is the kitchen. I will remember it."
    assert robot.es.state == "Interacting"
    names = [r["xml"] for r in robot.records(ES_EVENTS)]
    stop = next(i for i, x in enumerate(names) if 'name="stop"' in x)
    teach = next(i for i, x in enumerate(names) if 'name="place_teaching"' in x)
    assert stop < teach  # the walk ends first, then the place is taught


@pytest.mark.parametrize("state, stood", [("following", 6.0), ("waiting", STOOD_FOR - 1.0), ("searching", 6.0)])
def test_a_place_named_while_she_walks_on_or_the_moment_it_stops_is_refused_as_before(robot, state, stood):
    said = _teach_while_following(robot, state, stood)
    assert any("say stop first" in s for s in said)
    assert robot.es.state == "Following"
    assert not any('name="stop"' in r["xml"] for r in robot.records(ES_EVENTS))


@pytest.mark.parametrize("stood", [STOOD_FOR + 0.5, 6.0])
def test_a_place_named_while_it_is_held_up_on_its_way_to_her_is_refused_as_before(robot, stood):
    # review22 R4: held up (status ``held``: she beyond the band, no way through) is no "she stands by it";
    # the place would be taught where the robot is held, maybe the room before hers
    said = _teach_while_following(robot, "held", stood)
    assert any("say stop first" in s for s in said)
    assert robot.es.state == "Following"
    assert not any('name="stop"' in r["xml"] for r in robot.records(ES_EVENTS))
