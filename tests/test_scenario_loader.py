"""Loading scenario files: the example loads; every error names file, line and problem."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.errors import ScenarioError
from homesim.scenario.loader import load_scenario, load_scenario_text
from homesim.scenario.model import Repeat, Say, WaitFor, WalkTo
from tests.conftest import examples
from tests.world_helpers import EXAMPLE, ROOM

ROOM_TEXT = ROOM.read_text(encoding="utf-8")


def _line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def _mutated(old: str, new: str) -> str:
    assert old in ROOM_TEXT, old
    return ROOM_TEXT.replace(old, new, 1)


def _load(text: str):
    return load_scenario_text(text, source="bad.xml")


def test_the_example_flat_loads_with_everything_in_it():
    sc = load_scenario(EXAMPLE)
    assert sc.name == "two_people_radio" and sc.seed == 7 and sc.duration == 40
    assert [r.name for r in sc.rooms] == ["living room", "kitchen"]
    assert [h.name for h in sc.humans] == ["anna", "tom"]
    assert [(s.kind, s.name) for s in sc.sources] == [("radio", "radio")]
    assert sc.piece("table").clearance == pytest.approx(0.7)
    assert sc.human("tom").heading == 0.0 and sc.human("anna").heading == 0.0
    assert sc.human("tom").x == pytest.approx(0.9)
    assert sc.robot.max_turn == pytest.approx(math.radians(100)) and sc.robot.laser_rate == 10
    assert [d.name for _, d in sc.exits()] == ["front door"]
    anna = sc.human("anna").script
    assert isinstance(anna[2], Say) and anna[2].text == "Hello BIRON"
    assert isinstance(anna[3], WaitFor) and anna[3].timeout == 3
    assert isinstance(sc.human("tom").script[0], Repeat) and sc.human("tom").script[0].times == 2
    radio = sc.sources[0].script
    assert isinstance(radio[1], Repeat) and radio[1].times is None
    assert len(sc.expectations) == 7 and sc.expectations[0].line is not None
    assert [e.get("absent") for e in sc.expectations[1:3]] == [True, False]


def test_malformed_xml_names_file_and_line():
    text = _mutated('<place name="middle" x="4" y="3"/>', '<place name="middle" x="4" y="3">')
    with pytest.raises(ScenarioError, match=r"^bad\.xml:\d+: malformed XML") as exc:
        _load(text)
    assert exc.value.line is not None


def test_doctype_is_refused():
    text = ROOM_TEXT.replace('<?xml version="1.0" encoding="UTF-8"?>', '<?xml version="1.0"?>\n<!DOCTYPE scenario [<!ENTITY x "y">]>')
    with pytest.raises(ScenarioError, match="DOCTYPE"):
        _load(text)


def test_schema_violation_names_the_line():
    text = _mutated('<robot x="1" y="3" heading="0"/>', '<robot y="3" heading="0"/>')
    with pytest.raises(ScenarioError, match=r": <robot>: attribute x= is required but missing \(scenario\.xsd\)") as exc:
        _load(text)
    assert exc.value.line == _line_of(text, "<robot ") and exc.value.element == "robot"


def test_bad_value_type_is_caught_by_the_schema():
    text = _mutated('height="1.70"', 'height="tall"')
    with pytest.raises(ScenarioError, match="height") as exc:
        _load(text)
    assert exc.value.line == _line_of(text, '<human name="ann"')


@pytest.mark.parametrize(
    "old,new,message,anchor",
    [
        ('<place name="middle"', '<place name="table"', "name 'table' is already used by the furniture", '<place name="table"'),
        ('points="6.5,0.2 7.8,0.2 7.8,0.8 6.5,0.8"', 'points="6.5,0.2 7.8,0.2 7.0,0.4 6.5,0.8"', "not convex", '<furniture name="cupboard"'),
        ('<robot x="1" y="3"', '<robot x="5" y="5.2"', "overlaps the wall", "<robot "),
        ('<human name="ann" x="3" y="3"', '<human name="ann" x="3.5" y="1.0"', "overlaps furniture 'table'", '<human name="ann"'),
        ('x="3.6" y="1.0" on="table"', 'x="5.6" y="1.0" on="table"', "is not on 'table'", '<object name="cup"'),
        ('on="table"', 'on="middle"', "not a piece of furniture", '<object name="cup"'),
        ('<robot x="1" y="3"', '<robot x="11" y="3"', "not inside any room", "<robot "),
        ('<door name="exit" at="3" width="0.9" exit="true"/>', '<door name="exit" at="5.8" width="0.9" exit="true"/>', "outside the wall", '<wall from="0 6"'),
        ('clearance="0.7"', 'clearance="0.8"', "clearance 0.8 m must be below its height", '<furniture name="table"'),
        ('<room name="room" points="0,0 8,0 8,6 0,6"/>', '<room name="room" points="0,0 8,6 8,0 0,6"/>', "not a simple polygon: edges", "<room "),
        ('<room name="room" points="0,0 8,0 8,6 0,6"/>', '<room name="room" points="0,0 8,0 8,6 0,6"/>\n    <room name="den" points="6,4 9,4 9,7 6,7"/>',
            "room 'den' overlaps room 'room'", '<room name="den"'),
    ],
)
def test_semantic_errors_name_the_line_and_the_problem(old, new, message, anchor):
    text = _mutated(old, new)
    with pytest.raises(ScenarioError, match=message) as exc:
        _load(text)
    assert exc.value.line == _line_of(text, anchor)
    assert str(exc.value).startswith(f"bad.xml:{exc.value.line}:")


def _with_script(body: str, *, radio: bool = False) -> str:
    if radio:
        return _mutated("</humans>", f'</humans>\n  <sources>\n    <radio name="radio" x="6" y="3">\n      <script>\n{body}\n      </script>\n    </radio>\n  </sources>')
    return _mutated('torso="yellow"/>', f'torso="yellow">\n      <script>\n{body}\n      </script>\n    </human>')


@pytest.mark.parametrize(
    "body,radio,message,anchor",
    [
        ('<walk-to place="kitchen"/>', False, "there is no place named 'kitchen'", "<walk-to"),
        ('<walk-to place="middle" object="cup"/>', False, "give one target, not 2", "<walk-to"),
        ('<point robot="true"/>', False, "cannot take a robot", "<point"),
        ('<wait-for timeout="3"/>', False, "needs robot-says or robot-within", "<wait-for"),
        ('<wait-for robot-says="(hello" timeout="3"/>', False, "not a regular expression", "<wait-for"),
        ('<say text="hi"/>\n<wait-for robot-says="hello" repair="(again" retries="1"/>', False, "is not a regular expression", "<wait-for"),
        ('<say text="hi"/>\n<wait-for robot-within="1" timeout="3" retries="1"/>', False, "retries= needs robot-says", "<wait-for"),
        ('<say text="hi"/>\n<wait-for robot-says="hello" timeout="3" retries="11"/>', False, "retries", "<wait-for"),
        ('<repeat><wait for="1"/></repeat>\n<say text="never"/>', False, "unreachable", "<say"),
        ('<leave/>\n<wait for="1"/>', False, "nothing can follow", '<wait for="1"'),
        ('<face human="ann"/>', False, "cannot target themselves", "<face"),
        ('<walk-to place="middle"/>', True, "can only say, wait", "<walk-to"),
        ('<repeat><face angle="90"/></repeat>', False, "never lets time pass", "<repeat"),
        ('<repeat times="100000"><face robot="true"/></repeat>\n<say text="done"/>', False, "never lets time pass", "<repeat"),
        ('<repeat><walk-to place="middle"/><leave/></repeat>', False, "cannot be inside the <repeat>", "<leave"),
        ('<repeat times="2"><wait for="1"/><repeat times="3"><say text="bye"/><leave/></repeat></repeat>', False, "only once", "<leave"),
    ],
)
def test_script_errors_name_the_action_line(body, radio, message, anchor):
    text = _with_script(body, radio=radio)
    with pytest.raises(ScenarioError, match=message) as exc:
        _load(text)
    assert exc.value.line == _line_of(text, anchor)


def test_leave_needs_an_exit_door():
    text = _with_script("<leave/>").replace(' exit="true"', "")
    with pytest.raises(ScenarioError, match="no door of the flat has exit"):
        _load(text)


def test_expectation_references_and_windows_are_checked():
    text = _mutated("</humans>", '</humans>\n  <expect>\n    <reached who="bob" place="middle"/>\n  </expect>')
    with pytest.raises(ScenarioError, match="no human named 'bob'") as exc:
        _load(text)
    assert exc.value.line == _line_of(text, "<reached")
    text = _mutated("</humans>", '</humans>\n  <expect>\n    <face-seen bearing="0" between="2 30"/>\n  </expect>')
    with pytest.raises(ScenarioError, match="after the run"):
        _load(text)


def test_unreadable_file_is_a_scenario_error(tmp_path):
    with pytest.raises(ScenarioError, match="cannot read file"):
        load_scenario(tmp_path / "missing.xml")


def test_a_good_script_loads_into_plain_actions():
    sc = _load(_with_script('<walk-to robot="true" stop-at="1.2"/>\n<say text="hi there" loudness="70"/>'))
    walk, say = sc.human("ann").script
    assert isinstance(walk, WalkTo) and walk.target.kind == "robot" and walk.stop_at == 1.2
    assert isinstance(say, Say) and say.loudness == 70 and say.duration is None


@pytest.mark.parametrize(
    "old,new,anchor",
    [
        ('points="0,0 8,0 8,6 0,6"', 'points="0,0 8..1,0 8,6 0,6"', "<room "),
        ('from="0 0" to="8 0"', 'from="0 0" to="8. ."', '<wall from="0 0"'),
        ("</humans>", '</humans>\n  <expect>\n    <face-seen bearing="0" between="1..2 3"/>\n  </expect>', "<face-seen"),
        ("</humans>", '</humans>\n  <expect>\n    <face-seen bearing="0" between="1e999 3"/>\n  </expect>', "<face-seen"),
        ('points="0,0 8,0 8,6 0,6"', 'points="0,0 8,0 8,6e999 0,6"', "<room "),
    ],
)
def test_malformed_numbers_in_lists_name_the_line(old, new, anchor):
    """Numbers inside points, polygons and windows: a typo is an error on its own line, never a line-less one."""
    text = _mutated(old, new)
    with pytest.raises(ScenarioError) as exc:
        _load(text)
    assert exc.value.line == _line_of(text, anchor), str(exc.value)


_NUMBERISH = st.text(alphabet="0123456789.-+eE ,", min_size=1, max_size=12)


@settings(max_examples=examples(60, 300))
@given(window=_NUMBERISH, point=_NUMBERISH)
def test_every_loading_error_of_a_number_has_a_line(window, point):
    text = _mutated("</humans>", f'</humans>\n  <expect>\n    <face-seen bearing="0" between="{window}"/>\n  </expect>')
    text = text.replace('<wall from="5 4.5"', f'<wall from="{point}"', 1)
    try:
        _load(text)
    except ScenarioError as exc:
        assert exc.line is not None, str(exc)
