"""Dialog documents load through a checked pipeline: every problem with file and line, nothing half-loaded."""

from __future__ import annotations

import pytest

from robot.dialog.loader import BIRON_DIALOGS, DialogProblems, check, check_file, load, loads

GOOD = BIRON_DIALOGS.read_text(encoding="utf-8")


def test_birons_dialogs_load():
    doc = load()
    assert {"greeting", "capabilities", "follow", "stop", "object_teaching", "place_teaching", "goto", "where",
            "goodbye", "clarify"} <= set(doc.dialogs)
    assert doc.by_trigger("OBJECT").id == "object_teaching"
    assert doc.by_trigger("WAIT").id == "stop"
    assert check_file(BIRON_DIALOGS) == []


def test_malformed_xml_names_file_and_line(tmp_path):
    p = tmp_path / "bad.xml"
    p.write_text(GOOD.replace("<slot name=\"partner\"/>", "<slot name=\"partner\">", 1), encoding="utf-8")
    with pytest.raises(DialogProblems) as exc:
        load(p)
    assert str(p) in str(exc.value) and exc.value.line is not None
    assert "malformed XML" in exc.value.message


def test_doctype_is_refused():
    problems = check('<!DOCTYPE dialogs [<!ENTITY x "y">]><dialogs/>', source="evil.xml")
    assert problems and "DOCTYPE" in problems[0].message and problems[0].source == "evil.xml"


def _line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def test_schema_problems_are_all_reported_with_lines():
    text = GOOD.replace('<slot name="result"/>', '<slot nme="result"/>', 1).replace(
        '<when slot="request" status="filled"/>', '<when slot="request" status="maybe"/>', 1)
    problems = check(text, source="d.xml")
    assert len(problems) >= 2
    lines = {p.line for p in problems}
    assert _line_of(GOOD, '<slot name="result"/>') in lines
    assert _line_of(GOOD, '<when slot="request" status="filled"/>') in lines
    assert all(p.source == "d.xml" and "dialogs.xsd" in p.message for p in problems)


@pytest.mark.parametrize("old,new,message", [
    ('<when slot="partner" status="true"/></goal>', '<when slot="partnr" status="true"/></goal>', "slot 'partnr', which is not declared"),
    ('<send event="follow">', '<send event="dance">', "event 'dance' is not one the dialog sends"),
    ('trigger="FOLLOW"', 'trigger="FOLLOW GREETING"', "GREETING already starts dialog 'greeting'"),
    ('trigger="CAPABILITIES"', 'trigger="DANCE"', "trigger 'DANCE' is not a frame act"),
    ('<dialog id="too_fast"', '<dialog id="greeting"', "dialog 'greeting' is defined twice"),
    ('<dialog id="capabilities" trigger="CAPABILITIES" in="attending"', '<dialog id="capabilities" trigger="CAPABILITIES" in="nowhere"',
     "dialog 'capabilities': in='nowhere' names no <states> set"),
    ('<rule in="attending">', '<rule in="nowhere">', "dialog 'greeting': rule in='nowhere' names no <states> set"),
    ('select="@type"', 'select="@@type"', "is not a valid XPath"),
    ('<say>Hello, I am BIRON. What can I do for you?</say><end/>', '<say>Hello {nobody}</say><end/>',
     "the template names slot 'nobody'"),
    ('<fill slot="accepted" rejected="goto" status="false"/>', '<fill slot="accepted" rejected="follow" status="false"/>',
     "rejection of 'follow', an event this dialog never sends"),
    ('<rejection>Sorry, I can\'t do that now.</rejection>', '', "no default <rejection>"),
    ('<fill slot="reason" condition="need_help" select="param[@name=\'reason\']" status="true"/>',
     '<fill slot="reason" frame="GREETING" condition="need_help" status="true"/>', "exactly one of frame, condition, rejected"),
    # the manager's own words are the document's, with the fields each may use
    ('<sentence id="can-now">Now you can {capabilities}.</sentence>', '<sentence id="can-now">Now you can {abilities}.</sentence>',
     "sentence 'can-now': field {abilities} is not one it has (fields: capabilities)"),
    ('<sentence id="same-noun">one</sentence>', '', 'no <sentence id="same-noun">'),
    ('<sentence id="same-noun">one</sentence>', '<sentence id="same-noun">one</sentence><sentence id="farewell">Bye.</sentence>',
     "sentence 'farewell' is not one the dialog manager says"),
])
def test_semantic_problem_names_line_and_rule(old, new, message):
    assert old in GOOD, old
    text = GOOD.replace(old, new, 1)
    problems = check(text, source="d.xml")
    hit = [p for p in problems if message in p.message]
    assert hit, [p.message for p in problems]
    assert hit[0].source == "d.xml" and hit[0].line is not None
    with pytest.raises(DialogProblems):
        loads(text, source="d.xml")


def test_a_dialog_that_can_never_end_is_refused():
    text = GOOD.replace('<rule><say>I am working again.</say><end/></rule>', '<rule><say>I am working again.</say></rule>')
    problems = check(text, source="d.xml")
    assert any("never finish" in p.message and p.line == _line_of(GOOD, '<dialog id="recovered"') + 4 for p in problems)


def test_several_problems_are_reported_together_and_nothing_loads():
    text = GOOD.replace('in="nowhere"', "").replace('trigger="CAPABILITIES"', 'trigger="DANCE"', 1).replace(
        '<send event="follow">', '<send event="dance">', 1)
    with pytest.raises(DialogProblems) as exc:
        loads(text, source="d.xml")
    assert len(exc.value.problems) >= 2
    assert "more problem" in str(exc.value)


def test_wrong_root_is_refused():
    (p,) = check('<scxml xmlns="http://www.w3.org/2005/07/scxml"/>', source="x.xml")
    assert "root element must be <dialogs>" in p.message


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

LINES = GOOD.splitlines(keepends=True)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, len(LINES) - 1), st.sampled_from(["", "<slot/>\n", "<dialog id=\"x\">\n", "</policy>\n", "<when slot=\"request\" status=\"true\"/>\n"]))
def test_a_damaged_document_loads_or_names_every_problem(at, replacement):
    text = "".join(LINES[:at] + [replacement] + LINES[at + 1:])
    problems = check(text, source="damaged.xml")
    if problems:
        assert all(p.source == "damaged.xml" and p.line is not None and p.message for p in problems)
        with pytest.raises(DialogProblems):
            loads(text, source="damaged.xml")
    else:
        assert loads(text, source="damaged.xml").dialogs


def test_homesim_check_knows_the_dialog_document(tmp_path, capsys):
    from homesim.cli import main

    assert main(["check", str(BIRON_DIALOGS)]) == 0
    assert "ok (dialogs)" in capsys.readouterr().out
    bad = tmp_path / "bad.xml"
    bad.write_text(GOOD.replace('trigger="CAPABILITIES"', 'trigger="DANCE"', 1), encoding="utf-8")
    assert main(["check", str(bad)]) == 1
    out = capsys.readouterr().out
    line = _line_of(GOOD, 'trigger="CAPABILITIES"')
    assert f"{bad}:{line}: <dialog>: dialog 'capabilities': trigger 'DANCE'" in out
