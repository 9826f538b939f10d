"""A go-to standing at a passage's end with the side of the stairs at its back (fresh5/stair_goto_passage_person
seeds 1, 9): its first leg lies 40-80 deg to one side (through the living room's door, or back up the passage). The
turn on the spot toward it would swing a rear corner into the stairs, and the dynamic window, which admits any turn
on the spot that brings no corner nearer the floor plan than it is, offered a creeping turn the other way instead
(braking from the turn it had); the player took that for a turn, never arced round, and dithered (turn, back up, arc,
turn) for a minute with the way clear until it asked for help. Now a turn on the spot counts only when it turns
toward the leg (``turns_to``); else it arcs round, every rule of driving kept."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.scenario.loader import load_scenario
from robot.hardware.map_server import floor_plan, map_element
from robot.navigation.grid import parse_map
from robot.navigation.local import sweep_clearance
from robot.navigation.outline import FloorOutline
from robot.navigation.player import SWEEP_TIME, TURN_EITHER, TURN_PROGRESS, turns_to
from tests.player_helpers import player_standing_at

SCENE = Path(__file__).resolve().parent / "scenarios" / "fresh5" / "stair_goto_passage_person.xml"
#: the town house's floor plan, as the map server sends it
OUTLINE = FloorOutline(parse_map(map_element(floor_plan(load_scenario(SCENE)))))
#: the two legs it had from there: through the living room's door (south-west), and north up the passage
THROUGH_DOOR, UP_PASSAGE = (3.925, 1.275), (4.608, 7.307)


def _at(x: float, y: float, th: float, goal: tuple[float, float], w0: float):  # noqa: ANN202
    p = player_standing_at(x, y, th, goal, w0)
    p.outline = OUTLINE  # type: ignore[assignment]
    return p


@settings(max_examples=40, deadline=None)
@given(st.floats(4.64, 4.70), st.floats(2.07, 2.13), st.floats(math.radians(160), math.radians(200)), st.booleans(),
       st.floats(-0.5, 0.5))
@example(4.669, 2.107, -2.978 % (2 * math.pi), True, 0.3)  # seed 1, 108.7 s: it had turned the other way at 0.3 rad/s
@example(4.683, 2.095, 2.957, False, -0.3)  # seed 1, 122 s, after "The way is clear now"
def test_at_the_passage_end_with_the_stairs_at_its_back_it_gets_going_toward_its_leg(x, y, th, door, w0):
    goal = THROUGH_DOOR if door else UP_PASSAGE
    p = _at(x, y, th, goal, w0)
    bearing = math.remainder(math.atan2(goal[1] - y, goal[0] - x) - th, 2 * math.pi)
    cmd = p.control_step()
    assert cmd is not None
    v, w = cmd
    # it drives forward, out of the passage's end, or turns on the spot toward its leg: never a creeping turn away
    assert v > 0.02 or turns_to(w, bearing), (v, w, bearing)
    # never backing into the stairs, and held half a second the command keeps the footprint off the floor plan (the
    # window's own margin applies to the part of the arc it could not brake from)
    assert v >= 0.0
    assert sweep_clearance(v, w, OUTLINE.around((x, y, th)), SWEEP_TIME) > 0.0


@given(st.floats(-math.pi, math.pi), st.floats(-2.0, 2.0))
def test_a_turn_counts_only_toward_the_leg_or_either_way_to_a_leg_behind(bearing, w):
    if abs(w) < TURN_PROGRESS:
        assert not turns_to(w, bearing)
    elif abs(bearing) > TURN_EITHER:
        assert turns_to(w, bearing)
    else:
        assert turns_to(w, bearing) == (w * bearing > 0.0)


@pytest.mark.parametrize("w0", [0.0, 0.3, -0.3])
def test_with_nothing_at_its_back_it_still_turns_on_the_spot_to_a_first_leg(w0):
    """In the open (the hall's middle) a first leg 70 deg off is turned to on the spot, as before: no arc."""
    p = _at(4.6, 1.0, 0.0, (4.6 + math.cos(1.2), 1.0 + math.sin(1.2)), w0)
    v, w = p.control_step()
    assert abs(v) < 0.02 and w >= TURN_PROGRESS
