"""Scripted people on a stage: walking around obstacles, reacting to the robot, leaving."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lxml import etree

from homesim.errors import ScenarioError, TaskFailedError
from homesim.scenario.loader import load_scenario_text
from homesim.scenario.model import Door, Face, Leave, Repeat, Say, Target, WalkTo, Wall
from homesim.sim import Simulation
from homesim.world.acoustics import SoundField, first_words, speech_duration, words_spoken
from homesim.geometry import split_wall, wall_rectangle
from homesim.scenario.pathplan import MIN_DOOR_WIDTH, Grid, door_frame, door_sides
from homesim.tour.stage import Stage
from humans.script import ScriptError
from tests.conftest import examples
from tests.world_helpers import ROOM, drive_base
from tests.stage_helpers import ACTORS, PEOPLE

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _stage(script: str, *, start: str = 'x="3" y="3"', hardware: bool = False, duration: float = 20) -> Stage:
    text = ROOM_TEXT.replace('torso="yellow"/>', f'torso="yellow">\n<script>\n{script}\n</script>\n</human>')
    text = text.replace('x="3" y="3" heading="180"', f'{start} heading="180"').replace('duration="10"', f'duration="{duration}"')
    sc = load_scenario_text(text, source="humans.xml")
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    actors = ACTORS if hardware else PEOPLE
    return Stage(sim, sc, actors=actors, keep_messages=hardware)


def test_walk_to_goes_around_furniture_and_never_through_it():
    # From below-left of the table to below-right of it: the straight line crosses the table.
    st = _stage('<walk-to point="5.2 1.0"/>', start='x="2.2" y="1.0"')
    st.run(12)
    x, y = st.world.humans["ann"].position
    assert math.hypot(x - 5.2, y - 1.0) < 0.1
    track = st.truth.track("ann")
    inside = [(px, py) for _, px, py in track if 3.0 - 0.2 < px < 4.2 + 0.2 and 0.6 - 0.2 < py < 1.4 + 0.2]
    assert inside == []


def test_say_puts_words_in_the_air_for_as_long_as_they_take():
    st = _stage('<wait for="1"/>\n<say text="one two three four"/>')
    st.run(5)
    (u,) = st.world.sound.all()
    assert (u.source, u.start) == ("ann", 1.0)
    assert u.end - u.start == pytest.approx(0.3 + 4 * 0.4)


def test_wait_for_reacts_to_what_the_robot_says():
    st = _stage('<wait-for robot-says="hello" timeout="10"/>\n<say text="hi robot"/>', hardware=True)
    speaker = st.sim.bus.participant("dialog", host="robot")
    st.sim.call_at(2.0, lambda: speaker.publish("/robot/speaker/say", etree.Element("say", text="Hello, I am BIRON")))
    st.run(8)
    said = [(u.source, round(u.start, 2)) for u in st.world.sound.all()]
    assert said[0][0] == "robot"
    robot_end = st.world.sound.by("robot")[0].end
    ann = st.world.sound.by("ann")
    assert len(ann) == 1 and robot_end <= ann[0].start <= robot_end + 0.15


def test_wait_for_times_out_when_the_robot_stays_silent():
    st = _stage('<wait-for robot-says="hello" timeout="3"/>\n<say text="hm"/>')
    st.run(6)
    assert [round(u.start, 6) for u in st.world.sound.by("ann")] == [3.0]


def test_wait_for_robot_within_a_distance():
    st = _stage('<wait-for robot-within="1.5" timeout="15"/>\n<say text="there you are"/>', start='x="5" y="3"', hardware=True)
    drive_base(st, 0.5, 0.0)
    st.run(12)
    (u,) = st.world.sound.by("ann")
    # The robot starts 4 m away at 0.5 m/s: within 1.5 m after about 5 s (plus acceleration).
    assert 4.5 < u.start < 6.5


def test_face_point_and_leave():
    st = _stage('<face robot="true"/>\n<point object="cup" duration="2"/>\n<leave/>', start='x="3" y="2.5"')
    st.run(0.5)
    h = st.world.humans["ann"]
    to_robot = math.atan2(3.0 - 2.5, 1.0 - 3.0)
    assert abs(math.remainder(h.gaze - to_robot, 2 * math.pi)) < 1e-6
    assert h.pointing is not None and h.pointing.target_name == "cup"
    st.run(20)
    assert not h.present and h.pointing is None
    assert st.truth.frames[-1].people[0].present is False


def test_walk_to_the_robot_stops_short_of_it():
    st = _stage('<walk-to robot="true" stop-at="1.0"/>', start='x="6" y="4"')
    st.run(10)
    x, y = st.world.humans["ann"].position
    rx, ry, _ = st.world.robot.pose
    assert 0.9 < math.hypot(x - rx, y - ry) <= 1.05
    assert st.world.contacts == []


# ---------------------------------------------------------------- repeat never hangs
@pytest.mark.timeout(60)
@pytest.mark.parametrize(
    "body",
    [
        '<walk-to place="middle"/>',  # already there after the first pass
        '<wait-for robot-within="5"/>',  # the robot is within 5 m from the start
        '<face robot="true"/><wait for="0"/><walk-to place="middle"/>',
    ],
)
def test_a_repeat_whose_passes_take_no_time_lets_the_world_run(body):
    st = _stage(f"<repeat>{body}</repeat>", duration=5)
    st.run(5)  # used to spin for ever at one instant
    assert st.world.time == pytest.approx(5.0, abs=st.world.dt + 1e-9)
    passes = [(a, b) for a, b, d in st.actors["ann"].log if d != "repeat"]
    assert len(passes) > 10
    # After the first pass (the walk), a pass takes no time: one world step apart.
    starts = sorted({a for a, _ in passes if a > 2.5})
    assert min(np.diff(starts)) == pytest.approx(st.world.dt)


@pytest.mark.timeout(60)
def test_run_time_guards_cover_scripts_built_without_the_loader():
    """The loader refuses these; a scenario built in code still never hangs the run."""
    sc = load_scenario_text(ROOM_TEXT, source="humans.xml")
    ann = sc.human("ann")
    forever_face = Repeat((Face(Target("robot")),), times=10**9)
    leave_again = Repeat((WalkTo(Target("place", name="middle")), Leave()), times=None)
    for script in ((forever_face, Say("done")), (leave_again,)):
        scn = dataclasses.replace(sc, humans=(dataclasses.replace(ann, script=script),), duration=12.0)
        sim = Simulation(seed=1, scenario=scn.name)
        st = Stage(sim, scn, actors=PEOPLE)
        st.run(12)
        assert st.world.time == pytest.approx(12.0, abs=st.world.dt + 1e-9)
        sim.close()
    assert not st.world.humans["ann"].present and st.actors["ann"].done  # left once, then the repeat ended


# ------------------------------------------------------- paths, doors, no wall walking
def _crossings(track: np.ndarray, x_wall: float) -> list[float]:
    """The y where a track crosses the vertical line x = x_wall (either way)."""
    out = []
    for (_, x0, y0), (_, x1, y1) in zip(track, track[1:]):
        if (x0 - x_wall) * (x1 - x_wall) < 0:
            out.append(y0 + (y1 - y0) * (x_wall - x0) / (x1 - x0))
    return out


def test_people_go_through_a_narrow_inner_door_never_through_its_wall():
    """The review's leave2.py: a 0.6 m door used to be impassable on the 10 cm grid, and
    the failed plan was silent, so the walk and then <leave> went straight through walls."""
    text = ROOM_TEXT.replace('<wall from="5 4.5" to="5 5.9"/>', '<wall from="5 0" to="5 6"><door name="inner" at="3" width="0.6"/></wall>')
    text = text.replace('<object name="book" type="book" colour="blue" x="4.0" y="3.0"/>', "")
    text = text.replace('<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>',
        '<human name="ann" x="6.5" y="4.5" heading="180" height="1.70" torso="yellow"><script><walk-to point="2 4.5"/><leave/></script></human>')
    sc = load_scenario_text(text, source="leave2.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE, truth_every=1)
    st.run(15)
    track = st.truth.track("ann")
    inner, west = _crossings(track, 5.0), _crossings(track, 0.0)
    assert len(inner) == 1 and 2.7 + 0.2 <= inner[0] <= 3.3 - 0.2  # through the gap, body clear of its edges
    assert len(west) == 1 and 2.55 + 0.2 <= west[0] <= 3.45 - 0.2
    assert not st.world.humans["ann"].present
    sim.close()


@settings(max_examples=examples(40, 300))
@given(width=st.floats(MIN_DOOR_WIDTH, 1.2), at=st.floats(1.0, 5.0), angle=st.floats(0.0, math.pi), thickness=st.sampled_from([0.05, 0.1, 0.2]))
def test_a_door_a_person_fits_through_is_passable_wherever_it_lies(width, at, angle, thickness):
    """Passability used to depend on how the gap fell on the 10 cm grid (0.65 m at y=3.00 no, at 3.04 yes)."""
    c, s = math.cos(angle), math.sin(angle)
    wall = Wall((1.0, 1.0), (1.0 + 6 * c, 1.0 + 6 * s), thickness, (Door(at, width),))
    polys = [wall_rectangle(a, b, thickness) for a, b in split_wall(wall.start, wall.end, [(at, width)])]
    grid = Grid(polys, (1.0 - 6, 1.0 - 6, 1.0 + 6, 1.0 + 6))
    assert grid.passable(wall, wall.doors[0])
    inside, outside = door_sides(wall, wall.doors[0])
    path = [inside] + grid.plan(inside, outside)
    # Straight through: every waypoint stays within the gap's width of the door's centre line.
    (cx, cy), (ux, uy) = door_frame(wall, wall.doors[0])
    assert all(abs((x - cx) * ux + (y - cy) * uy) <= width / 2 for x, y in path)


@pytest.mark.parametrize(
    "old,new,message",
    [
        ('at="3" width="0.9" exit="true"', 'at="3" width="0.55" exit="true"', "door 'exit' is 0.55 m wide: a person"),
        ('<place name="middle"', '<furniture name="chest" type="chest" points="0.1,2.5 0.5,2.5 0.5,3.5 0.1,3.5" height="0.8"/>\n    <place name="middle"',
            "door 'exit' cannot be walked through"),
    ],
)
def test_doors_a_person_cannot_use_are_refused_naming_the_door(old, new, message):
    text = ROOM_TEXT.replace(old, new)
    with pytest.raises(ScenarioError, match=message) as exc:
        load_scenario_text(text, source="doors.xml")
    assert exc.value.line == text[: text.index("<door ")].count("\n") + 1


def test_a_walk_to_a_closed_off_place_is_refused_naming_the_action():
    # A closed box around the place 'middle': nobody can get in.
    box = '<wall from="3 2" to="5 2"/><wall from="5 2" to="5 4"/><wall from="5 4" to="3 4"/><wall from="3 4" to="3 2"/>'
    text = ROOM_TEXT.replace('<wall from="5 4.5" to="5 5.9"/>', box).replace('<object name="book" type="book" colour="blue" x="4.0" y="3.0"/>', "")
    text = text.replace('x="3" y="3" heading="180"', 'x="2" y="5" heading="180"').replace('torso="yellow"/>',
        'torso="yellow"><script>\n<wait for="1"/>\n<walk-to place="middle"/></script></human>')
    with pytest.raises(ScenarioError, match="'ann' cannot reach place 'middle'") as exc:
        load_scenario_text(text, source="box.xml")
    assert exc.value.line == text[: text.index("<walk-to")].count("\n") + 1


def test_a_failed_plan_at_run_time_fails_the_run_naming_the_action_never_walks_through_a_wall():
    """Built in code (the loader would refuse it): the walk fails loudly and ann stays put."""
    sc = load_scenario_text(ROOM_TEXT, source="humans.xml")
    corners = [(3.0, 2.0), (5.0, 2.0), (5.0, 4.0), (3.0, 4.0)]
    box = tuple(Wall(corners[i], corners[(i + 1) % 4], 0.1) for i in range(4))
    walk = WalkTo(Target("point", x=4.0, y=3.0), line=42)  # inside the closed box
    ann = dataclasses.replace(sc.human("ann"), x=2.0, y=5.0, script=(walk,))
    scn = dataclasses.replace(sc, walls=sc.walls + box, humans=(ann,), objects=())
    sim = Simulation(seed=1, scenario=scn.name)
    st = Stage(sim, scn, actors=PEOPLE)
    with pytest.raises(TaskFailedError) as exc:
        st.run(5)
    cause = exc.value.__cause__
    assert isinstance(cause, ScriptError) and cause.line == 42 and cause.element == "walk-to"
    assert "humans.xml:42" in str(exc.value)
    assert st.world.humans["ann"].position == pytest.approx((2.0, 5.0))
    sim.close()


# ------------------------------------------------------------- speech in the air
def test_a_cut_short_utterance_keeps_only_the_words_said_before_the_cut():
    """The review's cut.py: cut after 0.3 s, 'now please follow me to the kitchen' kept its
    whole text, so ann heard 'follow me' and the recogniser returned every word."""
    st = _stage('<wait-for robot-says="follow me" timeout="8"/>\n<say text="ok I follow"/>', hardware=True)
    dialog = st.sim.bus.participant("dialog", host="robot")
    st.sim.call_at(1.0, lambda: dialog.publish("/robot/speaker/say", etree.Element("say", text="now please follow me to the kitchen")))
    st.sim.call_at(1.3, lambda: dialog.publish("/robot/speaker/say", etree.Element("say", text="sorry")))
    st.run(10)
    first, second = st.world.sound.by("robot")
    assert (first.text, first.cut) == ("", True) and first.end == second.start < 1.5
    assert (second.text, second.cut) == ("sorry", False)
    assert [u.start for u in st.world.sound.by("ann")] == [pytest.approx(8.0)]  # timed out: never heard "follow me"
    # The robot's own voice is cancelled (its speaker announced it): never recognised.
    assert [m for m in st.messages if m.channel == "/robot/audio/speech"] == []


def test_words_said_before_a_cut_follow_the_speech_timing():
    field = SoundField()
    u = field.say("robot", "One, two three four!", 10.0)  # 0.15 s onset, 0.4 s a word, 0.15 s offset
    assert u.end == pytest.approx(10.0 + 0.3 + 1.6)
    cut = field.say("robot", "stop", 10.0 + 0.15 + 2 * 0.4 + 0.01)
    first = field.all()[0]
    assert (first.text, first.cut, first.end) == ("One, two", True, cut.start)


@given(words=st.integers(1, 12), explicit=st.one_of(st.none(), st.floats(0.05, 10.0)), a=st.floats(0, 1), b=st.floats(0, 1))
def test_the_words_kept_at_a_cut_are_a_prefix_that_grows_with_time(words, explicit, a, b):
    text = " ".join(f"w{i}" for i in range(words))
    dur = speech_duration(text) if explicit is None else explicit
    ka, kb = (words_spoken(text, dur, x * dur) for x in sorted((a, b)))
    assert 0 <= ka <= kb <= words
    assert words_spoken(text, dur, dur) == words and words_spoken(text, dur, 0.0) == 0
    assert first_words(text, ka) == " ".join(text.split()[:ka])


def test_wait_for_hears_a_robot_sentence_that_began_before_the_wait():
    """The review's waitfor.py: the robot said 'please follow me' from 1.5 to 3.0 s; ann began
    waiting at 2.0 s (after her walk) and, ignoring it, timed out at 10 s."""
    st = _stage('<walk-to point="5 3"/>\n<wait-for robot-says="follow" timeout="8"/>\n<say text="ok"/>', hardware=True)
    dialog = st.sim.bus.participant("dialog", host="robot")
    st.sim.call_at(1.5, lambda: dialog.publish("/robot/speaker/say", etree.Element("say", text="please follow me")))
    st.run(12)
    robot = st.world.sound.by("robot")[0]
    walk_end = st.actors["ann"].log[0][1]
    assert robot.start < walk_end < robot.end  # the wait began in the middle of the sentence
    (ok,) = st.world.sound.by("ann")
    assert robot.end <= ok.start <= robot.end + 0.15


def test_walking_up_to_a_person_stops_at_a_conversational_distance_by_default():
    """Without stop-at, walk-to human= used to end on top of the other person."""
    text = ROOM_TEXT.replace('<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>',
        '<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>\n    <human name="bob" x="6" y="4"><script><walk-to human="ann"/></script></human>')
    sc = load_scenario_text(text, source="meet.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE)
    st.run(8)
    d = math.dist(st.world.humans["bob"].position, st.world.humans["ann"].position)
    assert 0.7 <= d <= 0.85
    sim.close()


# ------------------------------------------------------- a user who repeats herself
def _robot_says(st: Stage, *said: tuple[float, str]) -> None:
    dialog = st.sim.bus.participant("dialog", host="robot")
    for t, text in said:
        st.sim.call_at(t, lambda text=text: dialog.publish("/robot/speaker/say", etree.Element("say", text=text)))


@pytest.mark.parametrize("repair", ["Sorry, I did not understand you. Could you say that again?", "Did you say hello to me?", "Is this hello?"])
def test_a_user_asked_for_a_repair_says_it_again_after_a_turn_gap(repair):
    st = _stage('<say text="hello robot"/>\n<wait-for robot-says="hello|hi" timeout="10" retries="2"/>\n<say text="done"/>', hardware=True)
    _robot_says(st, (2.5, repair), (9.0, "Hi, I am BIRON."))
    st.run(16)
    repair = st.world.sound.by("robot")[0]
    ann = st.world.sound.by("ann")
    assert [u.text for u in ann] == ["hello robot", "hello robot", "done"]
    assert ann[1].start == pytest.approx(repair.end + 0.5, abs=0.11)  # polled every 0.1 s, then a 0.5 s gap
    hello = st.world.sound.by("robot")[1]
    assert hello.end <= ann[2].start <= hello.end + 0.15  # answered: she goes on


def test_a_user_who_gets_no_answer_repeats_her_turn_then_gives_up():
    script = '<point object="cup" duration="1"/>\n<say text="this is a cup"/>\n<wait-for robot-says="cup" timeout="3" retries="2"/>\n<say text="oh well"/>'
    st = _stage(script, duration=30)
    st.run(25)
    ann = st.world.sound.by("ann")
    assert [u.text for u in ann] == ["this is a cup"] * 3 + ["oh well"]
    # Each try is her whole turn (the pointing too), 3 s of waiting and a 0.5 s gap apart.
    points = [e for e in st.actors["ann"].log if e[2].startswith("pointat")]
    assert len(points) == 3
    gaps = [b.start - a.end for a, b in zip(ann, ann[1:3])]
    assert gaps == [pytest.approx(3.0 + 0.5 + 1.0, abs=1e-6)] * 2  # wait, gap, then the 1 s point


def test_a_repeated_turn_leaves_out_the_pause_before_it():
    """A person who waited 4 s before greeting does not wait 4 s again before saying it again."""
    st = _stage('<wait for="4"/>\n<say text="hello robot"/>\n<wait-for robot-says="hello" timeout="10" retries="1"/>', hardware=True)
    _robot_says(st, (5.8, "Sorry, I did not understand you. Could you say that again?"))
    st.run(16)
    repair = st.world.sound.by("robot")[0]
    ann = st.world.sound.by("ann")
    assert [u.text for u in ann] == ["hello robot", "hello robot"]
    assert ann[1].start == pytest.approx(repair.end + 0.5, abs=0.11)


def test_without_retries_a_user_does_not_repeat_herself():
    st = _stage('<say text="hello robot"/>\n<wait-for robot-says="hello" timeout="4"/>\n<say text="done"/>', hardware=True)
    _robot_says(st, (2.5, "Sorry, I did not understand you. Could you say that again?"))
    st.run(16)
    assert [u.text for u in st.world.sound.by("ann")] == ["hello robot", "done"]


def test_nobody_gives_up_on_an_answer_while_the_robot_is_still_talking():
    """A 5 s timeout ran out in the middle of the robot's long answer, and the
    person repeated her request over it."""
    st = _stage('<wait-for robot-says="following you" timeout="2" retries="1"/>\n<say text="ok"/>', hardware=True)
    _robot_says(st, (1.0, "OK, I am following you. Now, back to your object. What is it?"))
    st.run(12)
    robot = st.world.sound.by("robot")[0]
    assert robot.end > 3.0  # it was still talking when the 2 s ran out
    (ok,) = st.world.sound.by("ann")
    assert robot.end <= ok.start <= robot.end + 0.15


def test_a_person_held_by_the_robot_in_the_only_doorway_walks_on_when_it_leaves():
    """The robot parked in the only door: no way round it, so ann walks up and is held back
    (re-asking the planner from the same spot, answered from its kept refusals); once the
    robot has gone, the question is a new one and she walks through."""
    text = ROOM_TEXT.replace('<wall from="5 4.5" to="5 5.9"/>', '<wall from="5 0" to="5 6"><door name="inner" at="3" width="1.0"/></wall>')
    text = text.replace('<object name="book" type="book" colour="blue" x="4.0" y="3.0"/>', "")
    text = text.replace('<human name="ann" x="3" y="3" heading="180" height="1.70" torso="yellow"/>',
                        '<human name="ann" x="7" y="3" heading="180" height="1.70" torso="yellow"><script><walk-to point="2 3"/></script></human>')
    sc = load_scenario_text(text.replace('duration="10"', 'duration="30"'), source="doorway.xml")
    sim = Simulation(seed=1, scenario=sc.name)
    st = Stage(sim, sc, actors=PEOPLE, truth_every=None)
    ann = st.world.humans["ann"]
    st.world.place_robot(5.0, 3.0, 0.0)  # in the doorway
    st.run(8)
    held = ann.held_time
    assert ann.held and held > 4.0 and ann.position[0] > 5.0  # waiting at the robot, still on her side
    st.world.place_robot(5.0, 5.2, 0.0)  # out of the way
    st.run(20)
    sim.close()
    assert math.hypot(ann.position[0] - 2.0, ann.position[1] - 3.0) < 0.1 and ann.held_time == held


@settings(max_examples=examples(40, 200), deadline=None)
@given(width=st.floats(0.2, 1.2), at=st.floats(1.0, 5.0), angle=st.floats(0.0, math.pi), thickness=st.sampled_from([0.05, 0.1, 0.2]),
       block=st.lists(st.tuples(st.floats(-1.2, 1.2), st.floats(-1.0, 1.0), st.floats(0.05, 0.6)), max_size=4))
def test_door_passability_is_the_breadth_first_search(width, at, angle, thickness, block):
    """passable() (one labelling of the box around the gap) answers as the walk from cell to cell it
    replaced, for doors too narrow, wide ones, and furniture (squares) next to or inside the gap."""
    c, s = math.cos(angle), math.sin(angle)
    wall = Wall((1.0, 1.0), (1.0 + 6 * c, 1.0 + 6 * s), thickness, (Door(at, width),))
    polys = [wall_rectangle(a, b, thickness) for a, b in split_wall(wall.start, wall.end, [(at, width)])]
    (cx, cy), (ux, uy) = door_frame(wall, wall.doors[0])
    for along, across, half in block:  # a square piece of furniture placed in the door's frame
        x, y = cx + along * ux - across * uy, cy + along * uy + across * ux
        polys.append([(x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half)])
    grid = Grid(polys, (1.0 - 6, 1.0 - 6, 1.0 + 6, 1.0 + 6))
    assert grid.passable(wall, wall.doors[0]) == grid._passable_search(wall, wall.doors[0])
