"""Loading AFSM documents: every stage's errors name the file, the line and the rule broken."""

from __future__ import annotations

import pytest

from homesim.afsm.loader import check, check_file, dumps, load, loads
from homesim.cli import main
from homesim.errors import AFSMProblems, XMLInputError

HEAD = '<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0"'
MODULES = '<es:module name="dialog" layer="deliberative"/><es:module name="attention" layer="reactive"/>'


def doc(body: str, *, attrs: str = "") -> str:
    return f"{HEAD} {attrs}>\n{MODULES}\n{body}\n</scxml>\n"


def problems(text: str) -> list[tuple[int | None, str]]:
    return [(p.line, p.message) for p in check(text, source="m.scxml")]


def test_a_good_document_loads_with_lifetimes_and_docs():
    m = loads(doc('<es:event name="greeting" lifetime="2.5"/>\n<!-- why A -->\n<state id="A"><transition event="greeting" target="A"/></state>',
                  attrs='es:default-lifetime="4"'))
    assert m.lifetime_ns("greeting") == 2_500_000_000
    assert m.lifetime_ns("other") == 4_000_000_000
    assert m.states["A"].doc == "why A"


def test_malformed_xml_names_file_and_line():
    with pytest.raises(XMLInputError, match=r"m.scxml:4: malformed XML: .*state line 3"):
        loads(doc("<state id='A'>"), source="m.scxml")


def test_doctype_is_refused():
    text = '<?xml version="1.0"?><!DOCTYPE scxml [<!ENTITY x "y">]>' + doc('<state id="A"/>')
    assert "DOCTYPE" in problems(text)[0][1]


def test_unsupported_scxml_features_are_named_as_such():
    found = problems(doc('<parallel id="P"/>\n<state id="A">\n<onentry/>\n<transition event="x" type="internal"/>\n</state>'))
    assert (3, "SCXML <parallel> is not supported by the ES engine (it implements <scxml>, <state>, <transition>, <send>, <param>)") in found
    assert any(line == 5 and "<onentry>" in msg for line, msg in found)
    assert any(line == 6 and "'type' of <transition>" in msg for line, msg in found)


def test_unknown_elements_and_attributes_fail_the_schema_with_lines():
    found = problems(doc('<state id="A" colour="red">\n<transition event="x" target="A"/>\n</state>\n<es:module name="m" layer="sideways"/>'))
    assert any(line == 3 and "attribute 'colour'" in msg and "afsm-profile.xsd" in msg for line, msg in found)
    assert any(line == 6 and "sideways" in msg for line, msg in found)


def test_a_non_scxml_root_is_refused():
    (p,) = check("<machine/>", source="m.xml")
    assert "SCXML document" in p.message


@pytest.mark.parametrize(
    "body, line, words",
    [
        ('<state id="A"/>\n<state id="A"/>', 4, "duplicate state id 'A' (first defined at line 3"),
        ('<state id="A"><transition event="x" target="Nowhere"/></state>', 3, "target 'Nowhere' does not exist"),
        ('<state id="A"/>\n<state id="Island"/>', 4, "'Island' is unreachable"),
        ('<state id="A"><transition event="x" target="A"><send event="o" target="ghost" es:kind="order"/></transition></state>',
         3, "unknown module 'ghost'"),
        ('<state id="A"><transition event="x" target="A"><send event="o" target="dialog" es:kind="order"/></transition></state>',
         3, "order 'o' sent upward to deliberative module 'dialog'"),
        ('<state id="A"><transition event="x" target="A"><send event="c" target="attention" es:kind="condition"/></transition></state>',
         3, "condition 'c' sent downward to reactive module 'attention'"),
        ('<state id="A"><transition event="x" target="A" cond="@a ="/></state>', 3, "invalid XPath"),
        ('<state id="A"><transition event="x" target="A" cond="nosuch()"/></state>', 3, "cannot be evaluated"),
        ('<state id="A"><transition event="a.*" target="A"/></state>', 3, "wildcards"),
        ('<state id="A" initial="B"/><state id="B"/>', 3, "initial state 'B' of 'A'"),
        ('<state id="A"><transition event="error" target="A"/><transition event="error.send" target="A"/></state>',
         3, "'error' is a prefix of 'error.send'; SCXML would match"),
        ('<es:event name="ping.late"/>\n<state id="A"><transition event="ping" target="A"/></state>', 4,
         "'ping' is a prefix of 'ping.late'"),
    ],
)
def test_semantic_rules(body: str, line: int, words: str):
    found = problems(doc(body))
    assert any(ln == line and words in msg for ln, msg in found), found


def test_check_reports_every_problem_not_just_the_first():
    text = doc(
        '<state id="A">\n'
        '  <transition event="x" target="Nowhere"/>\n'
        '  <transition event="y" target="B"><send event="o" target="dialog" es:kind="order"/></transition>\n'
        '</state>\n<state id="B"/>\n<state id="A"/>\n<state id="Island"/>'
    )
    found = problems(text)
    assert len(found) == 4
    with pytest.raises(AFSMProblems) as info:
        loads(text, source="m.scxml")
    assert len(info.value.problems) == 4 and "and 3 more problems" in str(info.value)
    assert str(info.value).startswith("m.scxml:")


def test_dump_then_load_is_the_same_machine(tmp_path):
    m = load("robot/afsm/biron.scxml")
    path = tmp_path / "again.scxml"
    path.write_text(dumps(m), encoding="utf-8")
    again = load(path)
    assert list(again.states) == list(m.states)
    assert [(s, t) for s, t in again.transitions()] == [(s, t) for s, t in m.transitions()]
    assert again.events == m.events and again.modules == m.modules


def test_biron_machine_has_a_comment_on_every_state_and_category():
    m = load("robot/afsm/biron.scxml")
    assert check_file("robot/afsm/biron.scxml") == []
    assert all(s.doc for s in m.states.values()), [s.id for s in m.states.values() if not s.doc]


def test_cli_check_lists_every_problem_and_fails(tmp_path, capsys):
    bad = tmp_path / "bad.scxml"
    bad.write_text(doc('<state id="A"><transition event="x" target="Nowhere"/></state>\n<state id="Island"/>'))
    assert main(["afsm", "check", str(bad)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 2 and all(line.startswith(f"{bad}:") for line in out)
    assert main(["afsm", "check", "robot/afsm/biron.scxml"]) == 0
    assert "ok (8 states, 6 categories" in capsys.readouterr().out


def test_cli_show_renders_dot_and_mermaid(capsys):
    assert main(["afsm", "show", "robot/afsm/biron.scxml", "--format", "dot"]) == 0
    dot = capsys.readouterr().out
    assert dot.startswith('digraph "biron"') and 'subgraph "cluster_Observing"' in dot
    assert main(["afsm", "show", "robot/afsm/biron.scxml", "--format", "mermaid"]) == 0
    mm = capsys.readouterr().out
    assert mm.startswith("stateDiagram-v2") and "state Interaction {" in mm


# ------------------------------------------- every problem, in one run (check_all)
H2 = ('<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0" initial="A">\n'
      '<es:module name="dialog" layer="deliberative"/>\n')


@pytest.mark.parametrize("body, expected", [
    pytest.param('<state id="A">\n<onentry/>\n<transition event="x" target="Nowhere"/>\n</state>',
                 [(4, "<onentry> is not supported"), (5, "target 'Nowhere' does not exist")], id="unsupported+semantic"),
    pytest.param('<state id="A" colour="red">\n<transition event="x" target="Nowhere"/>\n</state>',
                 [(3, "attribute 'colour'"), (4, "target 'Nowhere' does not exist")], id="attribute+semantic"),
    pytest.param('<state id="A">\n<foo/>\n<bar/>\n<transition event="x" target="A"/>\n</state>',
                 [(4, "'foo': This element is not expected"), (5, "'bar': This element is not expected")],
                 id="two-unknown-elements"),
    pytest.param('<state id="A">\n<foo/>\n<transition event="x" target="A" colour="r"/>\n</state>',
                 [(4, "'foo': This element is not expected"), (5, "attribute 'colour'")],
                 id="unknown-element-then-attribute"),
    pytest.param('<state id="A">\n<transition event="x" target="A">\n<send event="o" target="dialog" es:kind="sometimes"/>\n'
                 '</transition>\n<transition event="y" target="Nowhere"/>\n</state>\n<es:event name="e" lifetime="-1"/>',
                 [(5, "'sometimes'"), (7, "target 'Nowhere' does not exist"), (9, "'-1'")], id="bad-values+semantic"),
    pytest.param('<es:module name="m" layer="sideways"/>\n<state id="A">\n<transition event="x" target="A">\n'
                 '<send event="o" target="m" es:kind="order"/></transition>\n</state>',
                 [(3, "'sideways'")], id="bad-module-not-repeated-as-unknown-module"),
])
def test_check_reports_schema_and_semantic_problems_together(body, expected):
    found = [(p.line, p.message) for p in check(H2 + body + "\n</scxml>", source="m.scxml")]
    assert len(found) == len(expected), found
    for (line, words), (fline, fmsg) in zip(expected, found):
        assert fline == line and words in fmsg, found


def test_problems_name_the_line_an_element_starts_on():
    text = (HEAD + ' initial="A">\n<state id="A">\n  <transition\n      event="x"\n      target="Nowhere"/>\n'
            '  <transition event="y"\n      target="A"\n      cond="@a ="/>\n</state>\n<state\n   id="B"\n   colour="c"/>\n</scxml>')
    found = [(p.line, p.message) for p in check(text, source="m.scxml")]
    assert [line for line, _ in found] == [3, 6, 10, 10], found
    assert "Nowhere" in found[0][1] and "XPath" in found[1][1]
    assert {"colour" in found[2][1] or "colour" in found[3][1], "unreachable" in found[2][1] + found[3][1]} == {True}


@pytest.mark.parametrize("name", ["arm*", "arm/left", "two words", "1arm", "es:arm"])
def test_module_names_are_ncnames_in_the_schema_and_in_validate(name):
    from homesim.afsm.model import ModuleDecl, validate

    found = problems(doc(f'<es:module name="{name}" layer="reactive"/>\n<state id="A"/>'))
    assert any(line == 3 and "NCName" in msg for line, msg in found), found
    m = loads(doc('<state id="A"/>'), source="m.scxml")
    m.modules[name] = ModuleDecl(name, "reactive", 9)
    (p,) = validate(m)
    assert (p.source, p.line) == ("m.scxml", 9) and "NCName" in p.message


def _taken(m, state: str, event: str):
    """The transition an event takes in ``state``: the innermost state's own wins (SCXML)."""
    sid = state
    while sid is not None:
        for t in m.states[sid].transitions:
            if t.event == event:
                return t
        sid = m.states[sid].parent
    return None


def test_goodbye_or_partner_lost_during_object_teaching_stops_the_base_and_the_search():
    # a viewpoint drive (player move_to) may be under way while the object attention searches:
    # the interaction's end must stop the player and cancel the search, not leave them running
    m = load("robot/afsm/biron.scxml")
    for event in ("goodbye", "partner_lost"):
        t = _taken(m, "ObjectTeaching", event)
        assert t is not None and t.target == "LookingAround"
        sends = {(s.target, s.name) for s in t.sends}
        assert ("player", "stop") in sends and ("object_attention", "cancel") in sends
        assert ("person_attention", "look_around") in sends and ("dialog", "interaction_ended") in sends
