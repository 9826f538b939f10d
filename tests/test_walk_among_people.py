"""The simulated people keep clear of each other as real people do.

gen22, cause 2: in generated tour 8800-04 two bystanders stood inside each other and the robot's tracker saw
one blob where there were two people. ``Person.plan`` kept clear only of the robot: people walked through one
another and could stand inside each other. Now the world never lets two bodies overlap (a step that would is
not taken), paths go round whoever stands in the way, two people walking towards each other pass side by side
each on their own right, someone whose way crosses another's lets the one who gets there first pass, and
someone who cannot pass waits (steps back for someone waiting for her) and ends her walk, saying so, only
when people keep her from it for CROWD_GIVE_UP s.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from homesim.scenario.loader import load_scenario_text
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from homesim.world.bodies import HUMAN_RADIUS
from humans.person import CLEAR, CROWD_GIVE_UP
from tests.stage_helpers import PEOPLE

ROOM = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="among_people" seed="1" duration="60">
  <flat>
    <room name="room" points="0,0 W,0 W,H 0,H"/>
    <walls thickness="0.1">
      <wall from="0 0" to="W 0"/>
      <wall from="W 0" to="W H"/>
      <wall from="W H" to="0 H"/>
      <wall from="0 H" to="0 0"/>
    </walls>
    FURNITURE
  </flat>
  <robot x="ROBX" y="0.5" heading="0"/>
  <humans>
    HUMANS
  </humans>
</scenario>
"""

TORSOS = ("red", "green", "blue", "yellow")


def _stage(humans: str, *, w: float = 8.0, h: float = 6.0, furniture: str = "", robot_x: float | None = None,
           seed: int = 1) -> tuple[Stage, list[float]]:
    """A stage with only the people on it; the closest two people came (centre to centre), every world step."""
    text = (ROOM.replace("HUMANS", humans).replace("FURNITURE", furniture).replace("ROBX", f"{w - 0.5 if robot_x is None else robot_x}")
            .replace("W", f"{w}").replace("H", f"{h}"))
    sc = load_scenario_text(text, source="among_people.xml")
    sim = Simulation(seed=seed, scenario=sc.name)
    stage = Stage(sim, sc, actors=PEOPLE)
    closest = [math.inf]

    def watch(world):  # type: ignore[no-untyped-def]
        people = [b.position for b in world.humans.values() if b.present]
        for i in range(len(people)):
            for j in range(i + 1, len(people)):
                d = math.hypot(people[i][0] - people[j][0], people[i][1] - people[j][1])
                closest[0] = min(closest[0], d)

    stage.world.add_listener(watch)
    return stage, closest


def _human(name: str, x: float, y: float, script: str, k: int = 0, heading: float = 0.0, speed: float = 1.0) -> str:
    return (f'<human name="{name}" x="{x}" y="{y}" heading="{heading}" height="1.70" torso="{TORSOS[k % 4]}" speed="{speed}">'
            f"<script>{script}</script></human>")


def _at(stage: Stage, name: str) -> tuple[float, float]:
    return stage.world.humans[name].position


def test_two_people_walking_towards_each_other_pass_side_by_side_each_on_their_right():
    """A hall 1.8 m wide: they meet in the middle, pass at a body width and a little more, never touching."""
    humans = (_human("ann", 0.6, 0.9, '<walk-to point="7.4 0.9"/>', 0) + _human("bob", 7.4, 0.9, '<walk-to point="0.6 0.9"/>', 1, 180))
    stage, closest = _stage(humans, w=10.0, h=1.8, robot_x=9.6)
    seen: list[tuple[float, float, float]] = []
    stage.world.add_listener(lambda w: seen.append((w.humans["ann"].position[0], w.humans["ann"].position[1], w.humans["bob"].position[1])))
    stage.run(20.0)
    assert math.dist(_at(stage, "ann"), (7.4, 0.9)) < 0.1
    assert math.dist(_at(stage, "bob"), (0.6, 0.9)) < 0.1
    assert closest[0] >= 2 * HUMAN_RADIUS + 0.05, "they passed side by side with room between them"
    # where they pass (ann in the middle of the hall) ann (walking +x) is on her right (-y), bob (walking -x) on his (+y)
    ay, by = min(seen, key=lambda s: abs(s[0] - 4.0))[1:]
    assert ay < by


def test_she_walks_round_someone_standing_in_her_way():
    humans = (_human("ann", 1.0, 3.0, '<walk-to point="7.0 3.0"/>', 0)
              + _human("bob", 4.0, 3.0, '<wait for="30"/>', 1))
    stage, closest = _stage(humans)
    stage.run(15.0)
    assert math.dist(_at(stage, "ann"), (7.0, 3.0)) < 0.1
    assert _at(stage, "bob") == (4.0, 3.0)
    assert closest[0] >= CLEAR - 0.05, "round him at a step's distance, not shoulder to shoulder"


def test_a_walk_to_where_someone_stands_ends_beside_them():
    """A walk keeps its meaning: it ends at its place, or as near as the people there allow."""
    humans = (_human("ann", 1.0, 3.0, '<walk-to point="5.0 3.0"/>', 0)
              + _human("bob", 5.0, 3.0, '<wait for="30"/>', 1))
    stage, closest = _stage(humans)
    stage.run(15.0)
    d = math.dist(_at(stage, "ann"), (5.0, 3.0))
    assert 2 * HUMAN_RADIUS <= d <= CLEAR + 0.15
    assert closest[0] >= 2 * HUMAN_RADIUS


def test_who_reaches_a_crossing_second_lets_the_other_pass():
    """Ways crossing at right angles: bob, nearer the crossing, walks on; ann waits for him and walks on after."""
    humans = (_human("ann", 1.0, 3.0, '<walk-to point="7.0 3.0"/>', 0)
              + _human("bob", 4.0, 1.0, '<walk-to point="4.0 5.5"/>', 1, 90))
    stage, closest = _stage(humans)
    order: list[str] = []

    def first_across(world):  # type: ignore[no-untyped-def]
        for name, axis, line in (("ann", 0, 4.0), ("bob", 1, 3.0)):
            if name not in order and world.humans[name].position[axis] > line:
                order.append(name)

    stage.world.add_listener(first_across)
    stage.run(15.0)
    assert order == ["bob", "ann"]
    assert math.dist(_at(stage, "ann"), (7.0, 3.0)) < 0.1
    assert math.dist(_at(stage, "bob"), (4.0, 5.5)) < 0.1
    assert closest[0] >= CLEAR - 0.1


def test_someone_standing_in_the_only_door_makes_her_wait_then_stop_short_saying_why():
    """No way round: she waits at him (never through him) and after CROWD_GIVE_UP s ends her walk there, in her log."""
    wall = '<furniture name="partition" type="shelf" points="3.9,0.0 4.1,0.0 4.1,2.6 3.9,2.6" height="2.0"/>'
    wall += '<furniture name="partition2" type="shelf" points="3.9,3.4 4.1,3.4 4.1,6.0 3.9,6.0" height="2.0"/>'
    humans = (_human("ann", 1.0, 3.0, '<walk-to point="7.0 3.0"/><say text="here I am"/>', 0)
              + _human("bob", 4.0, 3.0, '<wait for="60"/>', 1))
    stage, closest = _stage(humans, furniture=wall)
    stage.run(40.0)
    ann = stage.actors["ann"]
    assert _at(stage, "ann")[0] < 4.0
    assert closest[0] >= 2 * HUMAN_RADIUS
    assert ann.crowd_stops == 1
    assert any("people stand in her way" in line for _, _, line in ann.log)
    assert any("here I am" in line for _, _, line in ann.log), "her script goes on"


# Places inside an 8 x 6 m room with a table in its middle, a metre apart, off the walls and the table; each
# drawn place is moved by up to 0.2 m.
TABLE = '<furniture name="table" type="table" points="3.4,2.6 4.6,2.6 4.6,3.4 3.4,3.4" height="0.75"/>'
PLACES = [(0.8 + i, 0.8 + j) for i in range(7) for j in range(5) if not (2.9 < 0.8 + i < 5.1 and 2.1 < 0.8 + j < 3.9)]
_JIT = st.floats(-0.2, 0.2)


def _place(draw, k: int) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    x, y = PLACES[k]
    return round(x + draw(_JIT), 2), round(y + draw(_JIT), 2)


@st.composite
def _scenes(draw):  # type: ignore[no-untyped-def]
    n = draw(st.integers(2, 4))
    idx = draw(st.lists(st.integers(0, len(PLACES) - 1), min_size=n, max_size=n, unique=True))
    starts = [_place(draw, k) for k in idx]
    goals = [[_place(draw, k) for k in draw(st.lists(st.integers(0, len(PLACES) - 1), min_size=1, max_size=2))] for _ in range(n)]
    speeds = [draw(st.sampled_from((0.5, 0.9, 1.3))) for _ in range(n)]
    return starts, goals, speeds


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_scenes())
# found by random runs: three people sent to one spot, the last twice; one sent next to where another then stands
@example(([(0.8, 0.8), (0.8, 1.8), (0.8, 2.8)], [[(0.8, 0.8)], [(0.8, 0.8)], [(0.8, 0.8), (0.8, 0.8)]], [0.5, 0.5, 0.5]))
@example(([(0.8, 0.8), (0.8, 1.8)], [[(0.8, 0.8), (0.93, 0.99)], [(0.8, 0.8)]], [0.5, 0.5]))
@example(([(5.8, 0.8), (6.8, 0.84), (5.8, 4.74)], [[(0.8, 0.8), (3.8, 1.8)], [(0.8, 0.8), (0.8, 0.8)], [(3.8, 1.6), (0.8, 0.8)]],
          [1.3, 0.5, 0.5]))
@example(([(5.77, 0.94), (6.6, 0.84), (5.8, 4.74)], [[(0.8, 0.8)], [(0.8, 0.8)], [(0.8, 0.8)]], [0.5, 0.5, 0.5]))
def test_no_two_people_ever_overlap_and_every_walk_ends_at_its_place_or_says_why(scene):
    starts, goals, speeds = scene
    humans = ""
    for k, ((x, y), walks, v) in enumerate(zip(starts, goals, speeds)):
        script = "".join(f'<walk-to point="{gx:.2f} {gy:.2f}"/>' for gx, gy in walks) + '<say text="done"/>'
        humans += _human(f"p{k}", round(x, 2), round(y, 2), script, k, speed=v)
    stage, closest = _stage(humans, furniture=TABLE, robot_x=7.55)
    # every walk's end is checked, not only the last one's (review23 N5): a walk's line enters her log the step it
    # ends; then where she stands, where the others stand, and whether this walk was given up for people in her way
    ends: dict[tuple[int, int], tuple[tuple[float, float], list[tuple[float, float]], bool]] = {}
    seen = [0] * len(goals)
    walked = [0] * len(goals)
    gave_up = [False] * len(goals)

    def mark(world):  # type: ignore[no-untyped-def]
        for k in range(len(goals)):
            lines = [line for _, _, line in stage.actors[f"p{k}"].log]
            for line in lines[seen[k]:]:
                if "people stand in her way" in line:
                    gave_up[k] = True
                elif line.startswith("walkto"):
                    others = [world.humans[f"p{i}"].position for i in range(len(goals)) if i != k]
                    ends[(k, walked[k])] = (world.humans[f"p{k}"].position, others, gave_up[k])
                    walked[k] += 1
                    gave_up[k] = False
            seen[k] = len(lines)

    stage.world.add_listener(mark)
    # time for every walk: a walk held by people ends after CROWD_GIVE_UP s, plus the way there
    stage.run(15.0 + (CROWD_GIVE_UP + 15.0) * max(len(walks) for walks in goals))
    assert closest[0] >= 2 * HUMAN_RADIUS, "two bodies overlapped"
    for k, walks in enumerate(goals):
        for j, (gx, gy) in enumerate(walks):
            assert (k, j) in ends, f"p{k} never finished walk {j}: {[ln for _, _, ln in stage.actors[f'p{k}'].log][-3:]}"
            here, others, excused = ends[(k, j)]
            d = math.dist(here, (gx, gy))
            near = [math.dist(o, (gx, gy)) for o in others]
            # at her place; or as near as someone standing on or by it allows (a body whose clearance covers her
            # place); or she said, on this walk, why she stopped short
            assert d < 0.15 or (any(o < CLEAR + 0.05 for o in near) and d <= CLEAR + 0.35) or excused, (k, j, d, near)


def test_leaving_she_waits_at_the_door_for_whoever_stands_in_it_and_never_vanishes_mid_room():
    """A leave blocked by someone in the exit is not ended short after CROWD_GIVE_UP s: she waits, then goes out."""
    sc = ROOM.replace('<wall from="0 H" to="0 0"/>', '<wall from="0 H" to="0 0"><door name="exit" at="3" width="0.9" exit="true"/></wall>')
    humans = (_human("ann", 4.0, 3.0, '<leave/>', 0)
              + _human("bob", 0.45, 3.0, '<wait for="30"/><walk-to point="2.0 5.0"/><wait for="30"/>', 1))
    text = (sc.replace("HUMANS", humans).replace("FURNITURE", "").replace("ROBX", "7.5").replace("W", "8.0").replace("H", "6.0"))
    stage = Stage(Simulation(seed=1, scenario="among_people"), load_scenario_text(text, source="among_people.xml"), actors=PEOPLE)
    stage.run(28.0)
    assert stage.world.humans["ann"].present, "still waiting for bob to clear the door"
    assert math.dist(_at(stage, "ann"), _at(stage, "bob")) >= 2 * HUMAN_RADIUS
    stage.run(50.0)
    assert not stage.world.humans["ann"].present, "out once he had gone"
    assert stage.actors["ann"].crowd_stops == 0


@pytest.mark.parametrize("listed", [("zoe", "bob"), ("bob", "zoe")])
def test_a_tie_at_a_crossing_goes_to_whoever_the_scenario_lists_first_not_by_name(listed):
    """Two reach a right-angle crossing at the same moment (each 2.5 m from it, the same speed): the one the scenario
    lists first walks on, the other lets them pass, whatever their names (review23 N6: by name spelling a rename
    changed who waits)."""
    walks = {"zoe": (1.5, 3.0, '<walk-to point="7.0 3.0"/>', 0.0), "bob": (4.0, 0.5, '<walk-to point="4.0 5.5"/>', 90.0)}
    humans = "".join(_human(n, walks[n][0], walks[n][1], walks[n][2], k, walks[n][3]) for k, n in enumerate(listed))
    stage, closest = _stage(humans)
    order: list[str] = []

    def first_across(world):  # type: ignore[no-untyped-def]
        for name, axis, line in (("zoe", 0, 4.0), ("bob", 1, 3.0)):
            if name not in order and world.humans[name].position[axis] > line:
                order.append(name)

    stage.world.add_listener(first_across)
    stage.run(15.0)
    assert order == list(listed)
    assert math.dist(_at(stage, "zoe"), (7.0, 3.0)) < 0.1
    assert math.dist(_at(stage, "bob"), (4.0, 5.5)) < 0.1
    assert closest[0] >= 2 * HUMAN_RADIUS
