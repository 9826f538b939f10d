""""Which one do you mean?" answered not only by colour: by position as the robot sees the
objects (``side-of=``), by where the object stands, by pointing at it again; and never by a
colour that cannot tell two same-colour objects apart."""

from __future__ import annotations

import math
import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from homesim.errors import ScenarioError
from homesim.scenario.loader import load_scenario_text
from homesim.tour import usergen as U
from homesim.tour.generate import TourWriter, generate_one, where_it_stands
from homesim.tour.objectgen import ObjectPlan
from humans.script import side_seen_by_robot

SCENARIO = Path(__file__).parent / "scenarios" / "users" / "users_which_side.xml"


def _world(robot: tuple[float, float, float], *objects: tuple[str, str, float, float]) -> SimpleNamespace:
    objs = {n: SimpleNamespace(name=n, type=t, x=x, y=y) for n, t, x, y in objects}
    return SimpleNamespace(objects=objs, robot=SimpleNamespace(pose=robot))


@given(st.floats(-math.pi, math.pi), st.floats(0.15, 0.35), st.floats(1.0, 3.0), st.floats(-math.pi, math.pi),
       st.floats(-0.5, 0.5))
def test_of_two_similar_objects_one_is_left_and_one_right_and_the_robot_behind_them_swaps_them(a, gap, d, pair, look):
    """Seen from the robot, two cups side by side are "left" and "right"; seen from the other
    side of the pair they swap, whatever way the robot's body faces (its line of sight is to them)."""
    cx, cy = 2.0, 1.0
    dx, dy = gap / 2 * math.cos(pair), gap / 2 * math.sin(pair)
    cups = (("a", "cup", cx + dx, cy + dy), ("b", "cup", cx - dx, cy - dy), ("book", "book", cx + 0.1, cy))
    rx, ry = cx + d * math.cos(a), cy + d * math.sin(a)
    along = abs(math.sin(pair - a))  # how far the pair is from lying along the line of sight
    if along < 0.2:
        return  # one behind the other: no honest left or right
    front = _world((rx, ry, math.atan2(cy - ry, cx - rx) + look), *cups)
    sides = {side_seen_by_robot(front, n) for n in ("a", "b")}
    assert sides == {"left", "right"}
    behind = _world((2 * cx - rx, 2 * cy - ry, math.atan2(ry - cy, rx - cx)), *cups)
    assert side_seen_by_robot(behind, "a") != side_seen_by_robot(front, "a")


def test_the_left_one_is_the_one_counterclockwise_and_three_have_a_middle():
    w = _world((0.0, 0.0, 0.0), ("l", "cup", 2.0, 0.2), ("m", "cup", 2.0, 0.0), ("r", "cup", 2.0, -0.2))
    assert [side_seen_by_robot(w, n) for n in ("l", "m", "r")] == ["left", "middle", "right"]
    alone = _world((0.0, 0.0, 0.0), ("cup", "cup", 2.0, -0.5), ("far cup", "cup", 2.0, 2.0))
    assert side_seen_by_robot(alone, "cup") == "right"


def _plan(name: str, colour: str, x: float, on: object, twin: str | None) -> ObjectPlan:
    return ObjectPlan(name, "cup", colour, 0.09, 0.1, x, 1.0, on, 0, twin)


def _answers(a: ObjectPlan, b: ObjectPlan, n: int = 200) -> set[str]:
    tw = TourWriter(np.random.default_rng(3), None, "eva", (0.0, 0.0), 0, None, objects={a.name: a, b.name: b})  # type: ignore[arg-type]
    kinds = set()
    for _ in range(n):
        (say, *rest) = tw.which_answer(a)
        kinds.add(say.get("request"))
        if say.get("request") == "which":
            assert say.get("about") == a.colour and rest and rest[0].tag == "point"
        if say.get("request") == "which-side":
            assert say.get("side-of") == a.name and not rest
        if say.get("request") == "which-place":
            assert say.get("about") == where_it_stands(a)
    return kinds


def test_a_same_colour_twin_is_never_told_apart_by_colour_nor_by_the_table_both_stand_on():
    table = SimpleNamespace(name="kitchen table")
    same = _answers(_plan("cup 1", "red", 1.0, table, "cup 2"), _plan("cup 2", "red", 1.2, table, "cup 1"))
    assert same == {"which-side", "which-pointing"}
    other = _answers(_plan("cup 1", "red", 1.0, table, "cup 2"), _plan("cup 2", "blue", 1.2, None, "cup 1"))
    assert other == {"which", "which-side", "which-place", "which-pointing"}
    assert where_it_stands(_plan("c", "red", 1, SimpleNamespace(name="desk 2"), None)) == "on the desk"
    assert where_it_stands(_plan("c", "red", 1, None, None)) == "on the floor"


def test_generated_tours_answer_which_one_every_way_and_pass_homesim_check():
    seen: dict[str, int] = {}
    for k in range(30):
        xml = generate_one(2024, k).xml.decode()
        for kind in ("which", "which-side", "which-place", "which-pointing"):
            seen[kind] = seen.get(kind, 0) + xml.count(f'request="{kind}"')
    assert all(seen[k] > 0 for k in seen), seen


def test_side_of_names_an_object_and_needs_a_request():
    text = SCENARIO.read_text(encoding="utf-8")
    load_scenario_text(text.encode(), source="ok.xml")
    broken = text.replace('side-of="cup b"/>', 'side-of="cup c"/>')
    with pytest.raises(ScenarioError, match="side-of") as err:
        load_scenario_text(broken.encode(), source="bad.xml")
    assert err.value.line == next(i for i, line in enumerate(broken.splitlines(), 1) if 'side-of="cup c"' in line)
    with pytest.raises(ScenarioError, match="needs request="):
        load_scenario_text(text.replace('<say request="which-side" side-of="cup b"/>', '<say text="x" side-of="cup b"/>').encode(), source="b.xml")
    with pytest.raises(ScenarioError, match="one slot"):
        load_scenario_text(text.replace('side-of="cup b"/>', 'side-of="cup b" about="x"/>').encode(), source="b.xml")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])
def test_asked_which_cup_she_names_its_side_as_the_robot_sees_it(seed, tmp_path, capsys):
    """Two red cups: the robot asks "Do you mean the cup on the right or the one on the left?"
    and Eva, who pointed at the one on the robot's right, says "right", never a colour."""
    import json

    from homesim.cli import main

    summary = tmp_path / "s.json"
    main(["run", str(SCENARIO), "--seed", str(seed), "--summary", str(summary)])
    doc = json.loads(summary.read_text())
    said = [(u["speaker"], u["text"]) for u in doc["utterances"]]
    asked = [i for i, (who, text) in enumerate(said) if who == "robot" and text.startswith("Do you mean")]
    assert asked, said
    answer = said[asked[0] + 1]
    words = re.findall(r"[a-z]+", answer[1].lower())
    assert answer[0] == "eva" and "right" in words and "left" not in words and "red" not in words, answer
    if seed == 0:  # the robot understood her: it learned the cup on its right (cup b, y = 2.425)
        (cup,) = doc["learned"]["objects"]
        assert abs(float(cup["y"]) - 2.425) < 0.05
