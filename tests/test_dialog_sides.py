"""A side said in an answer is turned into the robot's view by whether she faces it (robot_side,
docs/semantics.md §4): face to face her left is the robot's right; beside or behind it, looking where
its camera looks, her left is its left; a plain side is the robot's own wording."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.module import choose, robot_side

SIDES = st.sampled_from(["left", "right", "middle"])
FACING = st.sampled_from(["true", "false", "unknown"])
MIRROR = {"left": "right", "right": "left", "middle": "middle"}


@given(SIDES, st.sampled_from([None, "robot", "speaker"]), FACING)
def test_only_her_own_side_face_to_face_is_mirrored(side, view, facing):
    got = robot_side(side, view, facing)
    assert got == (MIRROR[side] if view == "speaker" and facing == "true" else side)
    # mirroring twice is the identity: the rule loses nothing
    assert robot_side(got, view, facing) == side


OPTIONS = [(0, "the red cup on the left"), (1, "the red cup on the right")]


@pytest.mark.parametrize("view, facing, want", [
    ("speaker", "true", 1),     # "the one on my left", face to face: the robot's right
    ("speaker", "false", 0),    # beside it, looking the same way: the robot's left
    ("speaker", "unknown", 0),
    (None, "true", 0),          # "the left one": the robot's wording, whoever faces whom
])
def test_the_left_one_picks_by_who_faces_whom(view, facing, want):
    answer = etree.Element("THAT_ONE", side="left")
    if view is not None:
        answer.set("view", view)
    assert choose(OPTIONS, answer, facing) == want
