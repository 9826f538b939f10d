"""The supervisor/dialog flow of a home tour, end to end in flats and with users written for it
(tests/scenarios/flow/; the rates over seeds 0-9 are in the branch's report)."""

from __future__ import annotations

from pathlib import Path

import pytest

from homesim.tour.runner import RunOptions, run_file

SCENES = Path(__file__).resolve().parent / "scenarios" / "flow"


@pytest.mark.parametrize("name", ["show_again_occluded", "show_again_walking"])
def test_showing_an_object_again_while_the_robot_looks_is_taken_at_once(name):
    """Her second "this is my ..." while the robot waits for her to step aside restarts the search:
    nothing expires in the supervisor's queue, the object is learned where it is, and the robot
    never says it could not find it while it starts looking again."""
    s = run_file(SCENES / f"{name}.xml", RunOptions(seed=0))
    failed = [f"{e['name']}: {e['detail']}" for e in s["expectations"] if not e["passed"]]
    assert not failed, failed
    assert s["es"]["rejected_expired"] == 0


@pytest.mark.parametrize("name", ["bystander_remarks_while_following", "bystander_in_beam_while_following",
                                  "greet_slow_laptop", "new_person_takes_over"])
def test_the_review_scenes_pass(name):
    """The outside review's scenes (seed 0): a bystander's remarks while following (beside the way, and
    inside the recogniser's beam), a greeting over a slow laptop, and someone taking a lost partner's
    place: he speaks to the robot near it, so the 'nobody there' rule must not end the interaction
    on him, and his request is answered."""
    s = run_file(SCENES / f"{name}.xml", RunOptions(seed=0))
    failed = [f"{e['name']}: {e['detail']}" for e in s["expectations"] if not e["passed"]]
    assert not failed, failed
