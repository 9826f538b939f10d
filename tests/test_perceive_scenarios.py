"""Issue 26 items 1, 3, 5, 11 end to end, one seed each, in flats and with users written for them
(scenarios/perceive/; the rates over seeds 0-9 are in the branch's report). Ground truth is read
here, in the test, never by the robot."""

from __future__ import annotations

import math
from pathlib import Path

from homesim.tour.runner import RunOptions, run_file

SCENES = Path(__file__).resolve().parent.parent / "scenarios" / "perceive"


def _run(name: str, seed: int = 0) -> dict:
    return run_file(SCENES / f"{name}.xml", RunOptions(seed=seed))


def _said(summary: dict) -> list[str]:
    return [u["text"] for u in summary["utterances"] if u.get("speaker") == "robot"]


def test_two_people_in_the_same_colour_crossing_twice_keep_their_identities():
    s = _run("cross_two_similar")
    t = s["metrics"]["tracking"]
    assert t["mota"] >= 0.9 and t["id_switches"] == 0


def test_four_people_crossing_keep_their_identities():
    t = _run("cross_four")["metrics"]["tracking"]
    assert t["mota"] >= 0.9 and t["id_switches"] <= 1


def test_a_partner_who_steps_aside_to_a_shelf_is_not_declared_gone():
    s = _run("step_aside_shelf")
    assert s["verdict"] == "PASS"
    assert not any("left" in t.lower() and "look around" in t.lower() for t in _said(s))


def test_a_partner_who_walks_out_of_the_flat_has_left():
    s = _run("leave_after_chat")
    assert any("you left" in t.lower() for t in _said(s))


def test_of_two_red_cups_a_tenth_of_a_metre_apart_the_one_meant_is_stored_with_its_own_position_and_size():
    s = _run("cups_across_10")
    assert s["verdict"] == "PASS"
    (cup,) = s["learned"]["objects"]
    left = (3.45, 2.05)  # the cup she points at and names ("the left one")
    assert math.hypot(float(cup["x"]) - left[0], float(cup["y"]) - left[1]) < 0.05
    assert abs(float(cup["size"]) - 0.09) < 0.02


def test_an_object_hidden_by_the_partner_is_learned_after_asking_her_to_step_aside():
    s = _run("occluded_plant")
    assert any("step aside" in t.lower() for t in _said(s))
    assert s["verdict"] == "PASS"


def test_a_greeting_from_beyond_the_lasers_half_circle_is_turned_to_and_answered():
    s = _run("greet_side_90")
    assert s["verdict"] == "PASS"


def test_an_object_shown_before_the_sentence_by_a_partner_standing_close_is_learned_where_it_stands():
    s = _run("teach_close_two")
    assert s["verdict"] == "PASS"
    (vase,) = s["learned"]["objects"]
    assert math.hypot(float(vase["x"]) - 3.45, float(vase["y"]) - 0.3) < 0.1  # the blue vase, not the white one 0.45 m away


def test_a_far_object_she_hides_with_nowhere_to_see_it_from_is_learned_after_asking_her_to_step_aside():
    # hidden15: a narrow study, the radio 3.4 m away behind her; no place to see it from while she stands there
    s = _run("study_far_behind_user")
    said = " ".join(_said(s)).lower()
    assert "step aside" in said and "could not find" not in said
    assert any(o.get("type") == "radio" and o.get("owner") == "partner" for o in s["learned"]["objects"])


TEST_SCENES = Path(__file__).resolve().parent / "scenarios"


def test_a_radio_hidden_behind_him_in_a_door_frame_is_learned_after_he_steps_aside_and_confirms_pointing():
    # obj23 (issue 26 item 11 in another flat): he points at the radio behind him from the study's door frame, steps
    # aside in view when asked, and confirms with "Yes, that's my radio": the request's gesture is kept, the radio stored
    s = run_file(TEST_SCENES / "perceive" / "doorway_hides_radio_in_view.xml", RunOptions(seed=0))
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]


def test_no_and_a_room_to_the_offer_after_a_go_to_to_an_unknown_room_is_a_go_to_there_not_a_teaching():
    # dlg23 (review22 R3): "drive to the lounge" (never shown) - "Shall I follow you there?" - "No, the living room":
    # the robot drives to the living room and stores no room where it stands
    s = run_file(TEST_SCENES / "nav" / "dlg23_offer_no_the_room.xml", RunOptions(seed=0))
    assert s["verdict"] == "PASS", [e for e in s["expectations"] if not e["passed"]]


def test_a_partner_asked_to_step_aside_who_steps_out_of_view_through_a_door_is_not_taken_for_gone():
    # obj24: asked to step aside, she steps into the kitchen beside the door, out of the robot's view behind the
    # wall (on main: "You left" seconds later, before the robot could look again); the vase is learned where it stands
    s = run_file(TEST_SCENES / "perceive" / "kitchen_door_hides_vase.xml", RunOptions(seed=0))
    said = " ".join(_said(s)).lower()
    assert "you left" not in said and "could not find" not in said
    assert any(o["type"] == "vase" and o["colour"] == "green" for o in s["learned"]["objects"])
    assert s["metrics"]["teaching"]["precision"] == 1


def test_of_three_like_cups_seen_at_a_slant_the_middle_one_he_points_at_is_stored_at_its_own_position():
    # obj24 (fresh11/rail_three_books' defect C in another flat): three like red cups 0.22 m apart along a counter,
    # seen at a slant; the middle one is stored, at its own position, never a neighbour or a point between two
    s = run_file(TEST_SCENES / "perceive" / "three_cups_counter.xml", RunOptions(seed=0))
    assert s["metrics"]["teaching"]["precision"] == 1
    assert s["metrics"]["teaching"]["position_error_m"]["max"] < 0.1
