"""Scripted people on a stage: walking around obstacles, reacting to the robot, leaving."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from lxml import etree

from homesim.scenario.loader import load_scenario_text
from homesim.scenario.model import Face, Leave, Repeat, Say, Target, WalkTo
from homesim.sim import Simulation
from homesim.world.stage import Stage
from tests.world_helpers import ROOM

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _stage(script: str, *, start: str = 'x="3" y="3"', hardware: bool = False, duration: float = 20) -> Stage:
    text = ROOM_TEXT.replace('torso="yellow"/>', f'torso="yellow">\n<script>\n{script}\n</script>\n</human>')
    text = text.replace('x="3" y="3" heading="180"', f'{start} heading="180"').replace('duration="10"', f'duration="{duration}"')
    sc = load_scenario_text(text, source="humans.xml")
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    actors = ("humans.install", "robot.hardware.install") if hardware else ("humans.install",)
    return Stage(sim, sc, actors=actors)


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
    driver = st.sim.bus.participant("driver", host="robot")

    async def drive():
        import asyncio

        while True:
            driver.publish("/robot/base/cmd", etree.Element("velocity", v="0.5", w="0"))
            await asyncio.sleep(0.2)

    st.sim.spawn(drive(), name="driver")
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
        st = Stage(sim, scn, actors=("humans.install",))
        st.run(12)
        assert st.world.time == pytest.approx(12.0, abs=st.world.dt + 1e-9)
        sim.close()
    assert not st.world.humans["ann"].present and st.actors["ann"].done  # left once, then the repeat ended
