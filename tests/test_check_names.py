"""`homesim check` finds what a run would trip on: names that refer to nothing (states and events of the
supervisor's AFSM, places, people, objects), every problem listed (not the first of each kind), and schema
errors as `file:line: <element>: message` saying what is expected."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.cli import main
from homesim.errors import ScenarioError
from homesim.scenario.loader import check_scenario_file, load_scenario
from homesim.tour.robot_names import vocabulary

ROOT = Path(__file__).resolve().parents[1]
TOUR = (ROOT / "scenarios" / "home_tour.xml").read_text(encoding="utf-8")


def _write(tmp_path: Path, *swaps: tuple[str, str], name: str = "s.xml") -> Path:
    text = TOUR
    for old, new in swaps:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _line(path: Path, needle: str) -> int:
    return next(i for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if needle in line)


def test_a_misspelt_state_is_refused_with_its_line_and_the_closest_state(tmp_path):
    path = _write(tmp_path, ('<state-reached state="Interacting" by="25"/>', '<state-reached state="Interactng" by="25"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.line == _line(path, 'state="Interactng"') and problem.element == "state-reached"
    assert str(problem).startswith(f"{path}:{problem.line}: <state-reached>: state='Interactng'")
    assert "did you mean 'Interacting'?" in str(problem)


def test_a_misspelt_event_is_refused_with_the_closest_event(tmp_path):
    path = _write(tmp_path, ('<event-rejected event="greeting" never="true"/>', '<event-rejected event="greting" never="true"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.line == _line(path, 'event="greting"')
    assert "event='greting'" in problem.message and "did you mean 'greeting'?" in problem.message


def test_a_category_is_refused_with_its_states(tmp_path):
    path = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached state="Interaction"/>'))
    (problem,) = check_scenario_file(path)
    assert "category" in problem.message and "Interacting, Following, ObjectTeaching" in problem.message


def test_the_run_refuses_the_scenario_before_it_starts(tmp_path, capsys):
    path = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached state="Folowing"/>'))
    assert main(["run", str(path), "--until", "1"]) == 2
    err = capsys.readouterr().err
    assert f"{path}:{_line(path, 'Folowing')}: <state-reached>:" in err and "did you mean 'Following'?" in err


def test_unknown_people_places_and_learned_names_get_the_closest_name(tmp_path):
    path = _write(tmp_path,
                  ('<following-distance who="anna"', '<following-distance who="ana"'),
                  ('<robot-near room="kitchen"/>', '<robot-near room="kichen"/>'),
                  ('<place-learned name="kitchen"/>', '<place-learned name="kitchn"/>'))
    problems = check_scenario_file(path)
    text = "\n".join(map(str, problems))
    assert len(problems) == 3, text
    assert "there is no human named 'ana' (did you mean 'anna'?" in text
    assert "there is no room named 'kichen' (did you mean 'kitchen'?" in text
    assert "name='kitchn': nobody says it" in text and "did you mean 'kitchen'?" in text


def test_a_name_she_uses_for_a_place_may_be_learned(tmp_path):
    """place-learned names her word for it: a word somebody says is fine although no room is called so."""
    path = _write(tmp_path, ('<place-learned name="kitchen"/>', '<place-learned name="galley"/>'),
                  ('text="This is the kitchen"', 'text="This is the galley"'))
    assert check_scenario_file(path) == []
    never = _write(tmp_path, ('<place-learned name="kitchen"/>', '<place-learned name="attic" never="true"/>'), name="never.xml")
    assert check_scenario_file(never) == []  # what must never be learned need not exist
    earlier = _write(tmp_path, ('<place-learned name="kitchen"/>', '<place-learned name="attic"/>'),
                     ('<robot x="2.0" y="2.5" heading="0"/>', '<robot x="2.0" y="2.5" heading="0" memory="required"/>'),
                     name="earlier.xml")
    assert check_scenario_file(earlier) == []  # taught in an earlier run whose store this one starts from


def test_every_problem_is_listed_not_the_first_of_each_kind(tmp_path):
    """Two people outside the flat: both named; and the expectation problems after them too."""
    text = TOUR.replace("</humans>", '<human name="bob" x="50" y="50" heading="0"/>\n'
                                     '    <human name="carl" x="-40" y="3" heading="0"/>\n  </humans>', 1)
    text = text.replace('<state-reached state="Following"/>', '<state-reached state="Folowing"/>', 1)
    text = text.replace('<event-rejected event="goodbye" never="true"/>', '<event-rejected event="godbye" never="true"/>', 1)
    path = tmp_path / "many.xml"
    path.write_text(text, encoding="utf-8")
    problems = check_scenario_file(path)
    text_out = "\n".join(map(str, problems))
    assert "human 'bob'" in text_out and "human 'carl'" in text_out
    assert "Folowing" in text_out and "godbye" in text_out
    assert len(problems) == 4, text_out
    assert [p.line for p in problems] == sorted(p.line for p in problems[:2]) + [p.line for p in problems[2:]]
    with pytest.raises(ScenarioError, match=r"and 3 more problem\(s\); 'homesim check' lists them"):
        load_scenario(path)


def test_homesim_check_prints_every_problem_and_fails(tmp_path, capsys):
    path = _write(tmp_path, ('<state-reached state="Interacting" by="25"/>', '<state-reached state="Interactng" by="25"/>'),
                  ('<event-rejected event="greeting" never="true"/>', '<event-rejected event="greting" never="true"/>'))
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr()
    assert len([line for line in out.out.splitlines() if line.startswith(f"{path}:")]) == 2
    assert "2 problems in 1 file" in out.err


def test_schema_errors_name_the_element_and_say_what_is_expected(tmp_path):
    path = _write(tmp_path,
                  ('<place name="window"', '<palce name="window"'),
                  ('<room name="kitchen"', '<room nme="kitchen"'),
                  ('x="3.5" y="2.3"/>', 'x="abc" y="2.3"/>'),
                  ('size="0.09"', 'size="-1"'),
                  ('<event-rejected event="greeting" never="true"/>', '<event-rejected event="greeting" reason="expird"/>'))
    problems = check_scenario_file(path)
    lines = [str(p) for p in problems]
    assert all(re.match(rf"{re.escape(str(path))}:\d+: <[a-z-]+>: ", line) for line in lines), lines
    text = "\n".join(lines)
    assert f":{_line(path, '<palce')}: <palce>: <palce> is not expected here; expected <place>" in text
    assert "<room>: attribute nme= is not allowed here (did you mean name=?)" in text
    assert "<room>: attribute name= is required but missing" in text
    assert "<place>: x='abc' is not valid; expected a number" in text and "at least -1000" in text
    assert "<object>: size='-1' is too small; expected greater than 0" in text
    assert "reason='expird' is not valid; expected one of 'expired', 'inapplicable' (did you mean 'expired'?)" in text
    assert "facet" not in text and "atomic type" not in text


def test_a_misspelt_optional_attribute_gets_the_closest_one_and_the_list(tmp_path):
    path = _write(tmp_path, ('<robot x="2.0" y="2.5" heading="0"/>', '<robot x="2.0" y="2.5" haeding="0"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.element == "robot" and "attribute haeding= is not allowed here (did you mean heading=?)" in problem.message
    assert "<robot> takes " in problem.message and "max-speed=" in problem.message


def test_every_library_scenario_names_only_what_exists():
    for path in sorted((ROOT / "scenarios").glob("*.xml")):
        assert check_scenario_file(path) == [], path


_LEAVES = vocabulary()[0][""]
_EVENTS = vocabulary()[1]


@settings(max_examples=40, deadline=None)
@given(st.one_of(st.sampled_from(_LEAVES), st.from_regex(r"[A-Za-z][A-Za-z_]{0,15}", fullmatch=True)),
       st.one_of(st.sampled_from(_EVENTS), st.from_regex(r"[a-z][a-z_]{0,15}", fullmatch=True)))
def test_a_state_or_event_is_refused_exactly_when_the_supervisor_does_not_have_it(tmp_path_factory, state, event):
    path = _write(tmp_path_factory.mktemp("names"),
                  ('<state-reached state="Following"/>', f'<state-reached state="{state}"/>'),
                  ('<event-rejected event="goodbye" never="true"/>', f'<event-rejected event="{event}" never="true"/>'))
    problems = check_scenario_file(path)
    refused_state = any(f"state={state!r}" in p.message for p in problems)
    refused_event = any(f"event={event!r}" in p.message for p in problems)
    assert refused_state == (state not in _LEAVES)
    assert refused_event == (event not in _EVENTS)
    assert len(problems) == refused_state + refused_event


def test_an_unknown_robot_profile_is_refused_by_check_and_the_command_line(tmp_path, capsys):
    path = _write(tmp_path, ('<robot x="2.0" y="2.5" heading="0"/>', '<robot x="2.0" y="2.5" heading="0" profile="biron2005"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.element == "robot" and "did you mean 'biron-2005'?" in problem.message
    assert main(["run", str(ROOT / "scenarios" / "radio.xml"), "--profile", "ful"]) == 2
    assert "argument --profile: invalid choice: 'ful'" in capsys.readouterr().err
