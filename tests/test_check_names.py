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
    assert "<room>: attribute name= is required but missing" not in text  # said once, as the misspelling
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


# --- metrics: the first part names a registered metric; a missing key at the end is answered with the closest


def test_a_misspelt_metric_is_refused_by_check_with_the_closest_registered_metric(tmp_path):
    path = _write(tmp_path, ("<expect>", '<expect>\n    <metric name="folowing.identity_switches" max="0"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.line == _line(path, 'name="folowing.identity_switches"') and problem.element == "metric"
    assert "did you mean 'following'?" in problem.message


def test_a_metric_no_package_registers_is_refused(tmp_path):
    path = _write(tmp_path, ("<expect>", '<expect>\n    <metric name="es.rejected_expird" min="1"/>'))
    (problem,) = check_scenario_file(path)
    assert "there is no metric named 'es'" in problem.message and "following" in problem.message


def test_a_registered_metric_passes_the_check(tmp_path):
    path = _write(tmp_path, ("<expect>", '<expect>\n    <metric name="teaching.position_error_m.max" max="0.1"/>'))
    assert check_scenario_file(path) == []


def test_a_missing_metric_key_at_the_end_of_the_run_suggests_the_closest_key():
    from homesim.scenario.expectations import MetricCheck
    from homesim.scenario.model import Expectation

    sc = load_scenario(ROOT / "scenarios" / "home_tour.xml")
    check = MetricCheck(Expectation("metric", (("name", "following.identity_switchs"), ("max", 0.0))), sc, None)
    ok, detail = check.verdict(10.0, {"metrics": {"following": {"identity_switches": 0, "episodes": 1}}})
    assert not ok and "did you mean 'following.identity_switches'?" in detail


def test_a_problem_behind_an_unexpected_element_is_listed_too_in_line_order(tmp_path):
    # libxml2 stops checking a script at <wiat>; the misspelt attribute two lines below must still be reported.
    path = _write(tmp_path, ('<wait for="1"/>\n        <face robot="true"/>\n        <say text="Hello BIRON"/>',
                             '<wiat for="1"/>\n        <face robot="true"/>\n        <say txt="Hello BIRON"/>'))
    problems = check_scenario_file(path)
    assert [p.line for p in problems] == [_line(path, "<wiat"), _line(path, 'txt="Hello BIRON"')], [str(p) for p in problems]
    assert "did you mean <wait>?" in problems[0].message and "did you mean text=?" in problems[1].message


def test_check_lists_each_files_problems_in_line_order(tmp_path, capsys):
    # the robot's name check (a state, line 119) runs after the kernel's (a room, line 125): printed by line all the same
    path = _write(tmp_path, ('<state-reached state="Interacting" by="25"/>', '<state-reached state="Interactng" by="25"/>'),
                  ('<robot-near room="kitchen"/>', '<robot-near room="kichen"/>'))
    assert main(["check", str(path)]) == 1
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith(f"{path}:")]
    assert [int(line.split(":")[1]) for line in lines] == [_line(path, "Interactng"), _line(path, '"kichen"')], lines


@pytest.mark.parametrize("wrong, right", [("state-reachd", "state-reached"), ("no-colision", "no-collision")])
def test_a_misspelt_expectation_lists_what_expect_holds_and_the_closest(tmp_path, wrong, right):
    # libxml2 says nothing of what it expected inside <expect> (an unbounded xs:choice): read from the schema
    path = _write(tmp_path, ("<no-collision/>\n  </expect>", f"<{wrong}/>\n  </expect>") if right == "no-collision"
                  else ('<state-reached state="Following"/>', f'<{wrong} state="Following"/>'))
    (problem,) = check_scenario_file(path)
    assert problem.line == _line(path, f"<{wrong}")
    assert f"<{wrong}> is not expected here; expected one of <robot-says>, <state-reached>," in problem.message
    assert "<metric>" in problem.message and f"(did you mean <{right}>?)" in problem.message


@pytest.mark.parametrize("swap, words", [
    (('seed="0"', 'seed="-1"'), "seed='-1' is not valid; expected a whole number 0 or more (at most 18 digits)"),
    (('timeout="6" retries="2"', 'timeout="6" retries="two"'), "retries='two' is not valid; expected a whole number 0 or more, at most 10"),
])
def test_an_attribute_of_an_anonymous_type_says_what_it_accepts(tmp_path, swap, words):
    path = _write(tmp_path, swap)
    problems = check_scenario_file(path)
    assert any(words in p.message for p in problems), [str(p) for p in problems]
    assert not any("a value this attribute accepts" in p.message for p in problems)


def test_a_misspelt_required_attribute_is_one_problem_not_two(tmp_path):
    path = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached stat="Following"/>'))
    (problem,) = check_scenario_file(path)
    assert "attribute stat= is not allowed here (did you mean state=?)" in problem.message


def test_a_required_attribute_left_out_is_still_reported(tmp_path):
    path = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached/>'))
    (problem,) = check_scenario_file(path)
    assert "attribute state= is required but missing" in problem.message


def test_one_problem_is_counted_in_the_singular(tmp_path, capsys):
    path = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached state="Folowing"/>'))
    assert main(["check", str(path)]) == 1
    assert "homesim check: 1 problem in 1 file" in capsys.readouterr().err


def test_check_says_names_are_checked_once_schema_problems_are_fixed(tmp_path, capsys):
    # the misspelt state cannot be checked while the file breaks the schema: the summary says so
    path = _write(tmp_path, ('<place name="window"', '<palce name="window"'),
                  ('<state-reached state="Following"/>', '<state-reached state="Folowing"/>'))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "checked for names, references and geometry once they are fixed" in err
    ok = _write(tmp_path, ('<state-reached state="Following"/>', '<state-reached state="Folowing"/>'), name="t.xml")
    assert main(["check", str(ok)]) == 1
    assert "once they are fixed" not in capsys.readouterr().err
