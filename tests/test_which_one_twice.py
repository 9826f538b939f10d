"""A which-one question is put at most twice in all (review14 F1): the object attention's second
putting (an answer that picked none of the options) and the dialog's own "say that again" re-ask
are one count, and the robot does not thank her for an answer it then asks again about.

The real supervisor, understanding and dialog (tests.test_dialog_bus.Robot) with the real object
attention's asking (:meth:`ObjectAttention._ask`), not a faked dialog."""

from __future__ import annotations

import pytest
from lxml import etree

from robot.contract import ES_EVENTS
from robot.objects.attention import ObjectAttention
from robot.objects.resolve import COLOURS, Candidate, Wanted, option_texts
from tests.test_dialog_bus import Robot


def _plant(x: float, y: float) -> Candidate:
    c = Candidate(x, y, 0.05)
    for _ in range(10):
        c.add("plant", x, y, 0.05, COLOURS["green"])
    return c


POSE = (0.0, 0.0, 0.0)
PLANTS = [_plant(1.5, -0.4), _plant(2.6, 0.5)]  # one in front on the right, one behind it on the left


class Asking(ObjectAttention):
    """The object attention with its search left out: the test puts the question (its real :meth:`_ask`)."""

    def _on_order(self, msg) -> None:
        if msg.xml.get("name") != "find_object":
            super()._on_order(msg)


@pytest.fixture
def asking():
    """The robot greeted, a plant shown (ObjectTeaching), the object attention asking which one at 7.5 s."""
    robot = Robot()
    robot.greet()
    oa = Asking(robot.sim, ask_timeout=8.0)
    result: list = []

    def teach() -> None:
        frame = etree.fromstring('<event name="object_teaching"><SPEECH><OBJECT type="plant"/></SPEECH></event>')
        robot.sim.bus.get("dialog").publish(ES_EVENTS, frame)

    async def ask() -> None:
        result.append(await oa._ask(PLANTS, Wanted(type="plant"), POSE, "test"))

    robot.sim.call_at(7.0, teach)
    robot.sim.call_at(7.5, lambda: robot.sim.spawn(ask(), name="ask"))
    yield robot, result
    robot.sim.close()


def _question() -> str:
    texts = option_texts(PLANTS, Wanted(type="plant"), POSE)
    return f"{texts[0]} or {texts[1]}"


@pytest.mark.parametrize("second", ["blorp xyzzy", "the one on the sofa"])
def test_a_which_one_question_is_never_put_a_third_time(asking, second) -> None:
    robot, result = asking
    robot.utter("the one on the sofa", 16.0, 17.0)  # picks neither plant, names a place: taken, asked again
    robot.utter(second, 30.0, 30.8)  # not understood / picks neither again
    robot.utter("the one on the sofa", 42.0, 43.0)  # whatever comes next is not answered by a third asking
    robot.sim.run(until=60.0)
    said = robot.sentences()
    asked = [s for s in said if "Do you mean" in s]
    assert len(asked) == 2, said
    assert asked[0].endswith(asked[1][asked[1].index("Do you mean"):]), said  # the same question both times
    assert result == [None], said  # neither plant chosen
    # no "Thank you." for an answer the robot then asks about again
    first, second_q = said.index(asked[0]), said.index(asked[1], said.index(asked[0]) + 1)
    assert "Thank you." not in said[first:second_q], said


def test_a_not_understood_first_answer_then_a_none_answer_is_not_put_again(asking) -> None:
    """The dialog's own re-ask is the second putting: the object attention does not put it a third time."""
    robot, result = asking
    robot.utter("blorp xyzzy", 16.0, 16.8)
    robot.utter("the one on the sofa", 26.0, 27.0)
    robot.utter("blorp xyzzy", 38.0, 38.8)
    robot.sim.run(until=60.0)
    said = robot.sentences()
    assert sum("Do you mean" in s for s in said) == 2, said
    assert result == [None], said


def test_an_answer_that_picks_one_is_thanked_and_taken(asking) -> None:
    robot, result = asking
    robot.utter("the one on the left", 16.0, 17.0)
    robot.sim.run(until=30.0)
    said = robot.sentences()
    assert sum("Do you mean" in s for s in said) == 1 and "Thank you." in said, said
    assert result == [PLANTS[1]], said
