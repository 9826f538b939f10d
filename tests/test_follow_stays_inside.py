"""The follower stays inside the flat (review of issue 26): a partner who leaves through the
exit door is searched for up to the door, inside, and then the robot turns back to the room so
the people in the flat can speak to it. Scored with the ``robot-inside`` expectation (ground truth)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from homesim.tour.runner import Run, RunOptions

FOLLOW = Path(__file__).resolve().parent / "scenarios" / "follow"


@pytest.mark.parametrize("seed", [0, 1])
def test_a_partner_who_leaves_the_flat_is_not_followed_out_and_the_robot_turns_back_to_the_room(seed):
    with Run.from_file(FOLLOW / "leaves_flat.xml", RunOptions(seed=seed)) as run:
        run.run()
        verdicts = run.finish()
        x, y, th = run.world.robot.pose
        inside = run.world.room_of(x, y)
        ahead_room = run.world.room_of(x + 1.0 * math.cos(th), y + 1.0 * math.sin(th))
    assert all(v.passed for v in verdicts), [v.line() for v in verdicts if not v.passed]
    assert inside == "hall"
    # facing into the flat (toward whoever speaks there), not out of the exit door in the wall x = 0
    assert ahead_room is not None, f"at ({x:.2f}, {y:.2f}) heading {math.degrees(th):.0f} deg: it faces out of the flat"
