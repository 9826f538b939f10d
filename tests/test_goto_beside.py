"""A go-to whose place someone stands on (issue 26 item 4, goto25): the robot stops short at a polite
distance, beside them, and says so, instead of standing blocked, replanning and asking for help.

Scene ``tests/scenarios/goto25/laundry_person_beside_the_spot.xml``, seed 1: Karl stands 0.5 m beside the
spot the laundry was taught at, off the robot's lane; the dynamic window stops it short of his space
before the lane's wait does (on main it stood there 7 s, then arrived without a word of him). Ground truth
is read here, in the test, never by the robot."""

from __future__ import annotations

from pathlib import Path

from homesim.tour.runner import RunOptions, run_file

SCENE = Path(__file__).resolve().parent / "scenarios" / "goto25" / "laundry_person_beside_the_spot.xml"


def test_a_go_to_to_a_place_someone_stands_beside_arrives_beside_them_and_says_so():
    s = run_file(SCENE, RunOptions(seed=1, until=90.0))
    said = [u["text"] for u in s["utterances"] if u.get("speaker") == "robot"]
    arrived = [t for t in said if t.startswith("I have arrived at the laundry")]
    assert arrived and "standing on that spot" in arrived[0]
    assert not any("help" in t.lower() for t in said)
    social = s["metrics"]["social"]
    assert social["collisions_people"] == 0
    assert social["min_person_clearance_moving_m"] >= 0.25
