"""The "which one?" question about two objects one behind the other (issue 26 item 5), asked through the
ES as the object attention asks it, answered the way people answer: by depth ("the one at the back",
"the one closer to you"), and after an answer the robot did not understand, in the time the question
asked again gives her."""

from __future__ import annotations

import pytest
from lxml import etree

from robot.contract import ES_EVENTS
from tests.test_dialog_bus import Robot


def _ask(robot: Robot, options: list[str], timeout: float = 8.0, at: float = 7.0, on_order=None) -> list:
    """Teach, then the object attention's clarification with these option texts; the orders it gets
    (``on_order(participant, msg)``: called with each, as the asker would act on it)."""
    robot.greet()
    obj = robot.sim.bus.participant("object_attention")
    orders: list = []
    obj.subscribe("/robot/es/orders/object_attention", lambda m: (orders.append(m), on_order(obj, m) if on_order else None))

    def teach_and_ask() -> None:
        frame = etree.fromstring('<event name="object_teaching"><SPEECH><OBJECT type="plant"/></SPEECH></event>')
        robot.sim.bus.get("dialog").publish(ES_EVENTS, frame)
        ev = etree.Element("event", name="clarification")
        opts = etree.SubElement(ev, "OPTIONS", timeout=f"{timeout:g}")
        for i, t in enumerate(options):
            etree.SubElement(opts, "option", index=str(i), text=t)
        robot.sim.call_at(at + 0.5, obj.publish, ES_EVENTS, ev)

    robot.sim.call_at(at, teach_and_ask)
    return orders


def _answer(orders: list) -> etree._Element | None:
    got = [o for o in orders if o.xml.get("name") == "clarified"]
    return got[0].xml.find("param/ANSWER") if got else None


@pytest.mark.parametrize("options, words, index", [
    (["the plant in front on the right", "the one behind it on the left"], "the one at the back", "1"),
    (["the plant in front on the right", "the one behind it on the left"], "the nearer one", "0"),
    (["the plant in front on the right", "the one behind it on the left"], "the one on the left", "1"),
    (["the plant nearer to you", "the one nearer to me"], "the one closer to you", "1"),  # nearer the robot
    (["the plant nearer to you", "the one nearer to me"], "the one closer to me", "0"),  # nearer her
])
def test_a_depth_answer_picks_the_option_standing_there(robot, options, words, index) -> None:
    orders = _ask(robot, options)
    robot.utter(words, 16.0, 17.0)
    robot.sim.run(until=22.0)
    assert any(s.startswith("Do you mean the plant") for s in robot.sentences())
    ans = _answer(orders)
    assert ans is not None and ans.get("index") == index, etree.tostring(ans) if ans is not None else None


def test_the_time_to_answer_runs_from_the_question_asked_again(robot) -> None:
    """She answers, the robot does not understand and asks again; her answer to the second asking comes
    more than the 8 s after the first question's end, but within 8 s of the second's: it is taken (on
    2e607e0 the first question's time ran out under her answer and the robot gave up, "unclear")."""
    def put_again(obj, msg) -> None:  # the asker (the object attention) puts the question again itself
        ans = msg.xml.find("param/ANSWER")
        if msg.xml.get("name") == "clarified" and ans is not None and ans.get("asked") == "1":
            ev = etree.Element("event", name="clarification")
            opts = etree.SubElement(ev, "OPTIONS", timeout="8", again="true")
            for i, t in enumerate(["the plant in front", "the one behind it"]):
                etree.SubElement(opts, "option", index=str(i), text=t)
            obj.publish(ES_EVENTS, ev)

    orders = _ask(robot, ["the plant in front", "the one behind it"], on_order=put_again)
    robot.utter("blorp xyzzy", 15.0, 15.8)  # nothing understood: handed back to the asker, which asks again
    robot.utter("the one at the back", 25.0, 26.0)
    robot.sim.run(until=32.0)
    said = robot.sentences()
    assert sum("Do you mean the plant in front or the one behind it?" in s for s in said) == 2
    answers = [o.xml.find("param/ANSWER") for o in orders if o.xml.get("name") == "clarified"]
    assert answers[0].get("none") == "true" and answers[0].get("asked") == "1"  # the misheard answer, handed back
    assert answers[-1].get("index") == "1"


def test_nearer_to_whom_is_not_guessed(robot) -> None:
    """Asked "the plant nearer to you or the one nearer to me?", a plain "the nearer one" (or one whose
    "to you" the recogniser lost) says nearer to nobody in particular: no option is taken (the robot
    did not store the wrong one, perceive bottles_across_island seed 7 before this rule). Nor is it taken
    for the choice of neither: the question is asked again (libperc14), and with no answer to that, none."""
    orders = _ask(robot, ["the plant nearer to you", "the one nearer to me"])
    robot.utter("the closer one", 16.0, 17.0)
    robot.sim.run(until=45.0)
    assert sum("Do you mean the plant nearer to you" in s for s in robot.sentences()) == 2
    ans = _answer(orders)
    assert ans is not None and ans.get("index") is None and ans.get("none") == "true"


def test_a_distance_answer_that_picks_neither_option_is_asked_again_and_the_next_answer_counts(robot) -> None:
    """bottles_across_island seeds 2 and 7: "the one closer to you" heard as "the is closer is you" ("closer", to
    whom not said) to "the bottle nearer to you or the one nearer to me?" picks neither option. It was taken
    as the choice ("Thank you.") and the robot gave up on the bottle; now it is an answer the robot did not
    get: the question is asked again, and her answer to that picks the option."""
    orders = _ask(robot, ["the bottle nearer to you on the right", "the one nearer to me on the left"], timeout=10.0)
    robot.utter("the is closer is you", 16.0, 17.5)
    robot.utter("the one closer to you", 30.0, 31.5)
    robot.sim.run(until=36.0)
    said = robot.sentences()
    asked = [s for s in said if "Do you mean the bottle nearer to you" in s]
    assert len(asked) == 2 and asked[1].startswith("Sorry"), said
    ans = _answer(orders)
    assert ans is not None and ans.get("index") == "1", etree.tostring(ans) if ans is not None else None


def test_an_answer_that_picks_an_option_is_taken_at_once(robot) -> None:
    """The same question answered by a side it worded: no second asking."""
    orders = _ask(robot, ["the bottle nearer to you on the right", "the one nearer to me on the left"], timeout=10.0)
    robot.utter("the one on the left", 16.0, 17.0)
    robot.sim.run(until=24.0)
    assert sum("Do you mean" in s for s in robot.sentences()) == 1
    ans = _answer(orders)
    assert ans is not None and ans.get("index") == "1"


@pytest.mark.parametrize("words", ["this is mine", "that one belongs to my son"])
def test_whose_said_without_what_is_asked_what_it_is(robot, words) -> None:
    """bottles_across_island seed 1: "this bottle is mine" heard as "this is mine" was not understood ("Could you
    say that again?"). Said pointing, it says whose and not what: the robot asks what it is."""
    robot.greet()
    robot.utter(words, 7.0, 8.2)
    robot.sim.run(until=14.0)
    assert robot.sentences()[-1] == "What is it?", robot.sentences()


def test_yes_that_is_mine_confirms_the_object(robot) -> None:
    """"Is this your cup?" - "yes, that is mine": the yes (whose, said again, is nothing new to show)."""
    robot.greet()
    robot.utter("this is my cup", 7.0, 8.2, confidence=0.3)
    robot.utter("yes that is mine", 12.0, 13.2)
    robot.sim.run(until=18.0)
    said = robot.sentences()
    assert "Is this your cup?" in said and "What is it?" not in said, said
