"""flow7: "excuse me" when someone standing holds the robot up (issue 26; bystander_at_door).

The follower sends ``way_blocked`` to the ES when a person standing in its way (ahead in its lane, or
beside it) keeps it stopped or crawling for 2 s; the ES passes ``excuse_me`` to the dialog, which asks
to pass; a simulated person standing in the robot's way who hears it steps out of its lane. End to end
in tests/scenarios/follow/bystander_at_door.xml (main: "Please slow down" to the partner, the bystander
never moved); the bystander's step as a Hypothesis property of its geometry."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.tour.runner import Run, RunOptions
from humans.person import PASS_BESIDE, PASS_LANE, PASS_NEAR, PASS_STEP, Person

SCENE = Path(__file__).resolve().parent / "scenarios" / "follow" / "bystander_at_door.xml"


def test_held_up_by_a_bystander_the_robot_asks_to_pass_and_he_steps_aside():
    with Run.from_file(SCENE, RunOptions(seed=0, until=32)) as run:
        start = run.world.humans["olaf"].position
        run.run()
        said = [u.text for u in run.world.sound.all() if u.source == "robot"]
        end = run.world.humans["olaf"].position
        run.finish()
    assert any("excuse me" in t.lower() for t in said), said  # main: never
    assert not any("slow down" in t.lower() for t in said), said  # main: "Please slow down" at 20.3 s: she was not too fast
    # he stood in the door (3.75, 2.10) from 8 s on; asked, he stepped out of the robot's way
    assert math.hypot(end[0] - 3.75, end[1] - 2.10) > 0.6, (start, end)


def _person(x: float, y: float, rx: float, ry: float, th: float) -> Person:
    p = Person.__new__(Person)
    p.world = SimpleNamespace(robot=SimpleNamespace(pose=(rx, ry, th)), humans={})
    p.body = SimpleNamespace(position=(x, y))
    return p


@settings(max_examples=300, deadline=None)
@given(x=st.floats(-4, 4), y=st.floats(-4, 4), rx=st.floats(-4, 4), ry=st.floats(-4, 4), th=st.floats(-math.pi, math.pi))
def test_only_who_stands_in_its_way_steps_aside_and_out_of_its_lane(x, y, rx, ry, th):
    spot = _person(x, y, rx, ry, th).in_the_way()
    c, s = math.cos(th), math.sin(th)
    along, lateral = c * (x - rx) + s * (y - ry), -s * (x - rx) + c * (y - ry)
    ahead = 0.0 < along < PASS_NEAR and abs(lateral) < PASS_LANE
    beside = along > -0.3 and math.hypot(along, lateral) < PASS_BESIDE
    if not (ahead or beside):
        assert spot is None  # behind it, far, or off its lane: she stays
        return
    assert spot is not None
    a2, l2 = c * (spot[0] - rx) + s * (spot[1] - ry), -s * (spot[0] - rx) + c * (spot[1] - ry)
    assert math.isclose(a2, along, abs_tol=1e-9)  # straight across its lane, not along it
    assert math.isclose(abs(l2), abs(lateral) + PASS_STEP, abs_tol=1e-9)  # further out, on her own side
