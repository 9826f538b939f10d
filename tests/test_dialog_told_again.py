"""A request repeated over the robot's word that it was done ("OK, I have learned your cup." while she says
"this is my cup" again, her retry): the robot says its word again and does not begin anew; the same words
begun after it was said to its end are a new request (lib25: perceive/study_far_behind_user seed 5 began a
second look and her good-bye came in ObjectTeaching)."""

from __future__ import annotations

import pytest
from lxml import etree

from robot.supervisor import ES_EVENTS, event_xml
from tests.test_dialog_bus import Robot

LEARNED = "OK, I have learned your cup."


def _teach_and_repeat(again_at: float) -> tuple[Robot, list[str], int]:
    r = Robot()
    try:
        r.greet()
        r.utter("this is my cup", 6.0, 7.0)
        objects = r.sim.bus.participant("object_attention")
        cup = etree.fromstring('<OBJECT type="cup" name="cup" owner="partner" x="1" y="0" z="0.8" frame="map"/>')
        r.sim.call_at(12.0, lambda: objects.publish(ES_EVENTS, event_xml("object_recognized", children=(cup,))))
        r.utter("this is my cup", again_at, again_at + 0.8)
        r.sim.run(until=again_at + 8.0)
        teach = [x for x in r.records(ES_EVENTS) if 'name="object_teaching"' in x["xml"]]
        return r, r.sentences(), len(teach)
    finally:
        r.sim.close()


def test_her_request_repeated_over_the_word_that_it_is_done_gets_that_word_again():
    r, said, teachings = _teach_and_repeat(12.6)  # "OK, I have learned your cup." is said from about 12.2 to 14.9
    assert said.count(LEARNED) == 2
    assert said.count("Let me have a look.") == 1 and teachings == 1
    assert r.es.state == "Interacting"
    assert r.dialog.summary()["told_again"] == 1


@pytest.mark.parametrize("again_at", [16.0, 20.0])
def test_the_same_request_after_the_word_was_heard_is_a_new_one(again_at):
    _, said, teachings = _teach_and_repeat(again_at)
    assert teachings == 2 and said.count("Let me have a look.") == 2


def test_in_a_flat_her_retry_over_i_have_learned_is_told_again_and_her_good_bye_comes_in_interacting():
    # tests/scenarios/perceive/bedroom_clock_retry.xml seed 0: her retry begins 1 s into "OK, I have learned your
    # clock." (before lib25: a second look, and her good-bye in ObjectTeaching)
    from pathlib import Path

    from homesim.tour.runner import RunOptions, run_file

    s = run_file(Path(__file__).resolve().parent / "scenarios" / "perceive" / "bedroom_clock_retry.xml", RunOptions(seed=0))
    said = [u["text"] for u in s["utterances"] if u.get("speaker") == "robot"]
    assert s["verdict"] == "PASS"
    assert s["metrics"]["dialog"]["subdialogs"]["told_again"] == 1
    assert said.count("Let me have a look.") == 1  # one look: the retry began none
