"""A person waiting for her answer waits while the robot visibly acts on her request, and after it tells her it will.

gen24 (generated tour 9700-10): after "Let me have a look." the robot drove 9 s to a place from which it could see
her vase; her wait (8 s) ran out during the drive and she gave the tour up, 4 s before "I have learned the blue
vase" (9700-16: she said her request again, vaguely). A person who repairs the way people do (a profile, or
``repairs``/``patience``/``give-up``) now waits for her answer anew while she sees the robot drive or turn, and from
a sentence of the robot's saying it moves; never more than ``ACTING_WAIT_MAX`` s beyond her timeout.
"""

from __future__ import annotations

import pytest

from humans.script import ACTING_WAIT_MAX
from tests.test_users_reactive import _robot, _said, _stage

ASK = '<say text="Look at this"/>\n<wait-for hears="learned" timeout="4" {how}/>\n<say text="next"/>'
REPAIRING = 'repairs="none" patience="0" give-up="skip"'


def _turn(st, start: float, end: float, w: float = 0.5) -> None:  # type: ignore[no-untyped-def]
    """The robot's base turns on the spot from ``start`` to ``end``."""
    def go(v: float) -> None:
        st.world.robot.cmd_w = v
    st.sim.call_at(start, lambda: go(w))
    st.sim.call_at(end, lambda: go(0.0))


def _next_at(st) -> float:  # type: ignore[no-untyped-def]
    return next(t for t, text in _said(st) if text == "next")


def test_she_waits_while_she_sees_the_robot_turn_and_hears_the_answer_after_it():
    st = _stage(ASK.format(how=REPAIRING), duration=40)
    _turn(st, 2.0, 12.0)
    _robot(st, 14.0, "OK, I have learned the vase.")
    st.run(30)
    answer = st.world.sound.by("robot")[0]
    assert _next_at(st) >= answer.end  # answered: she went on after it, never gave up
    assert st.actors["ann"].gave_up == 0


def test_she_still_gives_up_when_the_robot_acts_but_never_answers():
    st = _stage(ASK.format(how=REPAIRING), duration=90)
    _turn(st, 2.0, 80.0)
    st.run(80)
    t = _next_at(st)
    assert 4.0 + ACTING_WAIT_MAX - 1.0 <= t <= 4.0 + ACTING_WAIT_MAX + 3.0  # bounded: a long silence
    assert st.actors["ann"].gave_up == 1


def test_she_waits_anew_after_the_robot_says_it_will_move():
    st = _stage(ASK.format(how=REPAIRING), duration=40)
    _robot(st, 3.0, "I cannot see it from here. I will move over to see it.")
    _robot(st, 9.5, "OK, I have learned the vase.")
    st.run(30)
    assert _next_at(st) >= st.world.sound.by("robot")[1].end
    assert st.actors["ann"].gave_up == 0


@pytest.mark.parametrize("said", ["Sorry, I did not see it.", "Let me think."])
def test_other_words_of_the_robot_do_not_stretch_her_wait(said):
    st = _stage(ASK.format(how=REPAIRING), duration=40)
    _robot(st, 2.0, said)
    _robot(st, 9.5, "OK, I have learned the vase.")
    st.run(30)
    assert _next_at(st) < 9.5  # she gave up before the answer came
    assert st.actors["ann"].gave_up == 1


def test_a_person_with_no_repair_strategy_keeps_her_plain_timeout():
    st = _stage(ASK.format(how=""), duration=40)
    _turn(st, 2.0, 12.0)
    _robot(st, 14.0, "OK, I have learned the vase.")
    st.run(30)
    assert _next_at(st) < 6.0
