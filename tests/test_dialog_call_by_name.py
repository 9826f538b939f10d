"""A call by name alone before an interaction is her greeting, answered once someone faces the robot.

turn/greet_from_behind seeds 1, 8 (library): Ines says "Hello BIRON" from behind; while the base turns
toward her voice the recogniser hears only "biron" (or "that biron"): not understood, no answer, and her
greeting said again 7 s later came after the scene's 14 s. Someone who calls the robot by its name wants its
attention: the speech module marks such words ``call="true"`` (the name and at most one word more), and
the dialog answers the call as her greeting once a potential partner is reported (at once when one is,
else within ``CALL_WAIT`` s); nobody seen by then (a radio), it says nothing (docs/semantics.md, the call
by name).
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.dialog.module import CALL_WAIT
from robot.speech.module import calls_robot, frame_message, only_calls_robot, shared_understander
from tests.test_dialog_bus import Robot

HELLO = "Hello, I am BIRON. What can I do for you?"


@pytest.mark.parametrize("words, call", [
    ("biron", True), ("that biron", True), ("byron", True), ("hey biron", True), ("biron um", True),
    ("and biron it this the in", False), ("biron go to the kitchen", False), ("the kitchen", False),
    ("that is the", False)])
def test_the_frame_says_when_the_words_are_a_call_by_name_alone(words, call):
    understander = shared_understander()
    lex = understander.lexicon
    u = understander.understand(words)
    el = frame_message(u, 1.0, 2.0, 0.6, calls_robot(words, lex), only_calls_robot(words, lex))
    assert (el.get("call") == "true") == (call and u.frame is None)


def test_a_bare_name_heard_while_turning_is_answered_when_she_is_found(robot):
    robot.utter("biron", 4.7, 6.0, confidence=0.61)  # "Hello BIRON" from behind, heard as the name only
    robot.partner(7.9)  # the base has turned: someone speaking faces the robot
    robot.sim.run(until=7.8)
    assert robot.sentences() == []  # nobody seen yet: no answer into the room
    robot.sim.run(until=10.0)
    assert robot.sentences() == [HELLO]
    assert robot.es.state == "Interacting"


def test_a_bare_name_with_someone_facing_the_robot_is_answered_at_once(robot):
    robot.partner(0.5)
    robot.utter("that biron", 1.0, 1.8, confidence=0.7)
    robot.sim.run(until=4.0)
    assert robot.sentences() == [HELLO]  # not "Sorry, I did not understand you"
    assert robot.es.state == "Interacting"


def test_a_bare_name_with_nobody_there_gets_no_answer(robot):
    robot.utter("biron", 1.0, 1.6)  # a radio: nobody ever faces the robot
    robot.sim.run(until=1.6 + CALL_WAIT + 5.0)
    assert robot.sentences() == []  # no "I can't see you", no "say that again"
    assert robot.es.state == "LookingAround"


@given(late=st.floats(min_value=0.5, max_value=12.0))
@settings(max_examples=10, deadline=None)
def test_a_call_is_answered_only_if_she_is_found_within_the_wait(late):
    robot = Robot()
    try:
        robot.utter("biron", 1.0, 1.6)
        robot.partner(1.6 + late)
        robot.sim.run(until=1.6 + late + 3.0)
        said = robot.sentences()
        if late <= CALL_WAIT - 0.5:
            assert said == [HELLO] and robot.es.state == "Interacting"
        elif late > CALL_WAIT + 1.0:
            assert said == [] and robot.es.state == "PotentialPartner"
    finally:
        robot.sim.close()


def test_a_call_answering_did_you_say_hello_to_me_is_the_yes(robot):
    # sub20_radio_says_the_name seed 4: "hello a" (0.39) -> "Did you say hello to me?"; her "Hello BIRON" again
    # heard as "is biron" got "Sorry, I did not understand you. Did you say hello to me?" (asked a second time)
    robot.partner(0.5)
    robot.utter("hello a", 1.0, 1.8, confidence=0.39)
    robot.sim.run(until=4.0)
    assert robot.sentences() == ["Did you say hello to me?"]
    robot.partner(5.0)
    robot.utter("is biron", 5.5, 6.2, confidence=0.65)
    robot.sim.run(until=9.0)
    assert robot.sentences() == [HELLO]
    assert robot.es.state == "Interacting"


def test_during_an_interaction_a_bare_name_is_no_second_greeting(robot):
    robot.greet()
    robot.sim.run(until=4.0)
    assert robot.sentences() == [HELLO]
    robot.utter("biron", 9.0, 9.5)
    robot.sim.run(until=13.0)
    assert HELLO not in robot.sentences()
    assert robot.es.state == "Interacting"


def test_a_man_who_calls_its_name_from_behind_is_greeted_once_it_faces_him():
    """tests/scenarios/flow/sub20_call_from_behind_kitchen.xml (another flat, another user, the call said on
    purpose): "BIRON?" from 1.4 m behind it gets "Hello, I am BIRON" once the robot has turned to him."""
    from pathlib import Path

    from homesim.tour.runner import RunOptions, run_file

    scene = Path(__file__).resolve().parent / "scenarios" / "flow" / "sub20_call_from_behind_kitchen.xml"
    s = run_file(scene, RunOptions(seed=0))
    failed = [f"{e['name']}: {e['detail']}" for e in s["expectations"] if not e["passed"]]
    assert not failed, failed


# ------------------------------------------------------------------ the call tied to where it came from (turn22)
def _heading(robot, t: float, theta_deg: float) -> None:
    """The localiser's pose from ``t`` on: standing at the origin, heading ``theta_deg`` (every 0.1 s for 1 s)."""
    import math

    from lxml import etree

    loc = robot.sim.bus.participant("localiser") if not hasattr(robot, "_loc") else robot._loc
    robot._loc = loc
    for k in range(10):
        robot.sim.call_at(t + 0.1 * k, lambda: loc.publish("/robot/localisation/pose", etree.Element(
            "pose", time=f"{robot.sim.now:.6f}", x="0", y="0", theta=f"{math.radians(theta_deg):.5f}", cxx="0.01", cyy="0.01",
            ctt="0.01", frame="map")))


def _someone(robot, t: float, bearing: float, distance: float = 1.0) -> None:
    """A potential partner reported at ``bearing`` degrees (robot frame), ``distance`` m."""
    from lxml import etree

    from robot.supervisor import ES_EVENTS, event_xml

    person = etree.Element("PERSON", id="t1", bearing=f"{bearing}", distance=f"{distance}", speaking="true", facing="true")
    robot.sim.call_at(t, lambda: robot.attention.publish(ES_EVENTS, event_xml("potential_partner", children=(person,))))


def _call_from(robot, heard: float, start: float = 1.0, end: float = 1.6) -> None:
    """The name alone, its sound frames heard at ``heard`` degrees (the pair's reading, a few tenths of a degree of
    noise: no frame repeats the one before, as the detector's hangover does) every 0.1 s."""
    for k in range(int(round((end - start) / 0.1)) + 1):
        robot.sound(start + 0.1 * k, heard + 0.2 * (k % 3 - 1), 60.0)
    robot.utter("biron", start, end)


def test_a_radio_saying_the_name_then_someone_else_facing_the_robot_gets_no_greeting(robot):
    """review20 F2: the radio 40 degrees to the left says "Byron!"; then a flatmate 30 degrees to the right speaks
    facing the robot (a mutter, not understood): she did not call it, and is not greeted."""
    _heading(robot, 0.0, 0.0)
    _call_from(robot, 40.0)
    _someone(robot, 3.0, -30.0)
    robot.sim.run(until=1.6 + CALL_WAIT + 2.0)
    assert robot.sentences() == []
    assert robot.es.state == "PotentialPartner"


def test_the_one_who_called_is_greeted_though_the_robot_turned_to_her_between():
    """She called from behind its left (150 degrees: the pair hears 30); the robot turned to her, and the potential
    partner is reported straight ahead: it is she (a robot-frame bearing would say 0 against 30). Someone straight
    ahead of where the robot faced at the call (not turned) did not call it."""
    for turned, greeted in ((150.0, True), (0.0, False)):
        robot = Robot()
        try:
            _heading(robot, 0.0, 0.0)
            _call_from(robot, 30.0)
            _heading(robot, 2.0, turned)
            _someone(robot, 3.0, 0.0, 1.2)
            robot.sim.run(until=6.0)
            assert (robot.sentences() == [HELLO]) == greeted, turned
        finally:
            robot.sim.close()


@given(caller=st.floats(-180.0, 180.0), turn=st.floats(-180.0, 180.0), d=st.floats(1.0, 3.0), other=st.floats(-180.0, 180.0))
@settings(max_examples=12, deadline=None)
def test_the_call_is_answered_for_the_caller_whatever_the_turn_and_never_for_one_heard_elsewhere(caller, turn, d, other):
    """The caller at ``caller`` degrees (robot frame at the call), the robot turned by ``turn`` before she is reported:
    she is greeted. Someone else whom the pair would have heard at least 40 degrees away from her at the call (front
    and back look alike to it, and beside the robot its readings crowd together: 40 covers both), reported instead,
    is not."""
    import math

    from robot.dialog.module import front_bearing, heard_bearing

    far = abs(front_bearing(other) - front_bearing(caller)) >= 40.0
    for who, want in ((caller, [HELLO]),) + (((other, []),) if far else ()):
        robot = Robot()
        try:
            _heading(robot, 0.0, 0.0)
            _call_from(robot, heard_bearing(caller, d))
            _heading(robot, 2.0, turn)
            b = math.degrees(math.atan2(math.sin(math.radians(who - turn)), math.cos(math.radians(who - turn))))
            _someone(robot, 3.0, b, d)
            robot.sim.run(until=6.0)
            assert robot.sentences() == want, (who, turn)
        finally:
            robot.sim.close()


def test_the_detectors_hangover_is_no_evidence_of_where_the_call_came_from(robot):
    """A radio's name ahead, its readings drifting toward the axis; its last reading repeated word for word after the
    voice ended (the detector's hangover), where the pair would hear someone right behind the robot: the repeats
    are not counted as frames from the person then behind it (review20's radio_then_mutter seeds 1, 8: 3 of 7
    frames hers with the repeats, 3 of 6 without)."""
    _heading(robot, 0.0, 0.0)
    for k, b in enumerate((8.3, 6.0, 6.0 + 0.01, 0.6, -1.3, -1.4, -1.4, -1.4, -1.4)):
        robot.sound(1.0 + 0.1 * k, b, 60.0)
    robot.utter("biron", 1.0, 1.8)
    _someone(robot, 3.0, 180.0 + 1.0, 1.0)  # right behind it, where the pair hears about -1 degree
    robot.sim.run(until=1.8 + CALL_WAIT + 2.0)
    assert robot.sentences() == []


def test_a_tvs_call_by_name_is_not_taken_for_the_greeting_of_a_man_who_grumbles_facing_the_robot():
    """tests/scenarios/flow/turn22_tv_name_then_grumble.xml (review20 F2 in another flat): the TV says "BIRON!", a man
    behind the robot's right grumbles facing it: nothing said to him (main: "Hello, I am BIRON", seeds 0-8); his own
    greeting later is answered."""
    from pathlib import Path

    from homesim.tour.runner import RunOptions, run_file

    scene = Path(__file__).resolve().parent / "scenarios" / "flow" / "turn22_tv_name_then_grumble.xml"
    s = run_file(scene, RunOptions(seed=0))
    failed = [f"{e['name']}: {e['detail']}" for e in s["expectations"] if not e["passed"]]
    assert not failed, failed


# ------------------------------------------------------------------ the robot turning during the call (review22 R7, R8)
TURN_RATE = 0.8  # rad/s: the base turning to a voice (the figure CALL_WIDTH's budget assumes)
DOCUMENTED_CALL_WIDTH = 6.0  # degrees (docs/semantics.md: more than half the frames within CALL_WIDTH = 6 degrees)


def _wrap(deg: float) -> float:
    import math

    return math.degrees(math.remainder(math.radians(deg), 2 * math.pi))


def _sweep(loc, robot, t0: float, t1: float, theta0: float, rate: float, phase: float = 0.0) -> None:
    """The localiser's pose every 0.1 s from ``t0 + phase`` to ``t1``: at the origin, heading ``theta0`` degrees
    plus ``rate`` rad/s since ``t0`` (``loc``: the participant that publishes it)."""
    import math

    from lxml import etree

    def pose(t: float) -> None:
        th = math.radians(theta0) + rate * (t - t0)
        loc.publish("/robot/localisation/pose", etree.Element(
            "pose", time=f"{robot.sim.now:.6f}", x="0", y="0", theta=f"{th:.5f}", cxx="0.01", cyy="0.01", ctt="0.01",
            frame="map"))

    k = 0
    while t0 + phase + 0.1 * k <= t1 + 1e-9:
        t = t0 + phase + 0.1 * k
        robot.sim.call_at(t, lambda t=t: pose(t))
        k += 1


def _turning_call(robot, caller: float, d: float, rate: float, phase: float, start: float = 1.0, end: float = 1.6) -> None:
    """She calls from ``caller`` degrees (map frame; the robot at the origin facing 0 until ``start``) while the base
    turns at ``rate`` rad/s from ``start`` on; each sound frame is where the pair hears her from the robot's heading
    at that instant (a few tenths of a degree of noise), the poses come every 0.1 s ``phase`` s off the frames."""
    import math

    from robot.dialog.module import heard_bearing

    loc = robot.sim.bus.participant("localiser")
    robot._loc = loc
    _sweep(loc, robot, 0.0, start - 0.1, 0.0, 0.0)
    _sweep(loc, robot, start, 2.9, 0.0, rate, phase)
    for k in range(int(round((end - start) / 0.1)) + 1):
        t = start + 0.1 * k
        robot.sound(t, heard_bearing(_wrap(caller - math.degrees(rate * (t - start))), d) + 0.2 * (k % 3 - 1), 60.0)
    robot.utter("biron", start, end)


@given(caller=st.floats(-180.0, 180.0), d=st.floats(0.8, 3.0), rate=st.sampled_from([-TURN_RATE, -0.4, 0.4, TURN_RATE]),
       phase=st.floats(0.0, 0.05),
       other=st.one_of(st.floats(-180.0, 180.0), st.floats(-45.0, 45.0).map(lambda x: ("near", x))),
       d_other=st.floats(0.8, 3.0))
@settings(max_examples=36, deadline=None)
def test_the_call_is_answered_for_the_caller_though_the_robot_turns_during_it_and_never_for_one_heard_apart(
        caller, d, rate, phase, other, d_other):
    """review22 R7: the robot turns at up to 0.8 rad/s *during* the call (the per-frame poses are what the rule is
    for), the poses 0-0.05 s off the sound frames; she is reported 1.4 s later, still turning: she is greeted.
    Someone else (anywhere, or within 45 degrees of her: the 6-40 degrees the old property left out) is reported
    instead: when at least half the frames, each against where the pair would have heard *him* from the robot's
    heading at that frame, lie further off than CALL_WIDTH plus the 0.05 s of turn between a frame and its nearest
    pose plus the noise and 0.5 degrees, he is not greeted (the rule takes a call as hers only when more than half its
    frames lie within CALL_WIDTH)."""
    import math

    from robot.dialog.module import CALL_FRAMES_HERS, heard_bearing, heard_span, span_off

    if isinstance(other, tuple):
        other = _wrap(caller + other[1])
    # the width the docs promise (docs/semantics.md, the call by name: 6 degrees), not the code's constant: a wider
    # CALL_WIDTH would greet someone 10 degrees off the call and fail here
    margin = DOCUMENTED_CALL_WIDTH + math.degrees(abs(rate) * 0.05) + 0.2 + 0.5
    frames = [1.0 + 0.1 * k for k in range(7)]
    heard = [heard_bearing(_wrap(caller - math.degrees(rate * (t - 1.0))), d) + 0.2 * (k % 3 - 1)
             for k, t in enumerate(frames)]
    apart = sum(span_off(b, heard_span(_wrap(other - math.degrees(rate * (t - 1.0))), d_other)) > margin
                for b, t in zip(heard, frames))
    report = 2.4  # s: the base still turning
    cases = [(caller, d, [HELLO])]
    if apart >= (1.0 - CALL_FRAMES_HERS) * len(frames):
        cases.append((other, d_other, []))
    for who, dist, want in cases:
        robot = Robot()
        try:
            _turning_call(robot, caller, d, rate, phase)
            _someone(robot, report, _wrap(who - math.degrees(rate * (report - 1.0))), dist)
            robot.sim.run(until=5.0)
            assert robot.sentences() == want, (who, apart)
        finally:
            robot.sim.close()


def test_her_place_is_put_in_the_map_with_the_pose_of_her_report_not_the_latest():
    """review22 R8: the report of the potential partner reaches the dialog (a laptop on the WLAN) 0.3 s after the
    supervisor sent it, while the localiser's poses, which the dialog hears at once here, show the base turned on
    by 14 degrees: placed with the latest pose she stood 14 degrees off where she called from, and her call was
    not answered. Placed with the pose of when she was reported, it is."""
    import math

    from homesim.network import LinkModel

    from robot.dialog.module import heard_bearing

    robot = Robot(host="laptop")
    try:
        net = robot.sim.network
        net.set_link(LinkModel("slow_wlan", 0.3, 0.3))
        net.set_link(LinkModel("same_box", 0.0, 0.0))
        net.add_host("laptop", link="same_box")
        net.set_route("robot", "laptop", "slow_wlan")
        loc = robot.sim.bus.participant("localiser_on_laptop", host="laptop")
        _sweep(loc, robot, 0.0, 0.9, 0.0, 0.0)
        _sweep(loc, robot, 1.0, 4.0, 0.0, TURN_RATE)
        for k in range(7):  # she calls from 60 degrees left while the base turns to her
            t = 1.0 + 0.1 * k
            robot.sound(t, heard_bearing(60.0 - math.degrees(TURN_RATE * (t - 1.0)), 1.5) + 0.2 * (k % 3 - 1), 60.0)
        robot.utter("biron", 1.0, 1.6)
        _someone(robot, 2.0, 60.0 - math.degrees(TURN_RATE * 1.0), 1.5)
        robot.sim.run(until=5.0)
        assert robot.sentences() == [HELLO]
    finally:
        robot.sim.close()
