"""``homesim check FILE...``: any of the project's documents by its root element, every problem with
file and line, exit 1; and scenario number lists reported as what is expected, not a regex."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim import documents as checkmod
from homesim.check import check_path
from homesim.documents import DocumentType, register_document
from homesim.cli import main
from homesim.errors import InputError, ScenarioError
from homesim.scenario.loader import load_scenario_text
from .conftest import examples

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "two_people_radio.xml"
BIRON = ROOT / "robot" / "afsm" / "biron.scxml"
EXAMPLE_TEXT = EXAMPLE.read_text(encoding="utf-8")

AFSM_BAD = """<scxml xmlns="http://www.w3.org/2005/07/scxml" version="1.0" initial="A">
  <state id="A">
    <transition target="B"/>
  </state>
  <state id="B"><transition event="x" target="Nowhere"/></state>
</scxml>
"""


def bad_scenario(tmp_path: Path, *swaps: tuple[str, str]) -> Path:
    text = EXAMPLE_TEXT
    for old, new in swaps:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "bad.xml"
    path.write_text(text, encoding="utf-8")
    return path


def line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


def test_good_documents_of_each_kind_pass(capsys):
    assert main(["check", str(EXAMPLE), str(BIRON)]) == 0
    out = capsys.readouterr().out
    assert f"{EXAMPLE}: ok (scenario)" in out and f"{BIRON}: ok (AFSM)" in out


def test_every_problem_of_every_file_with_file_and_line(tmp_path, capsys):
    scenario = bad_scenario(tmp_path, ('points="0,0 6,0 6,5 0,5"', 'points="0,0;6,0;6,5;0,5"'),
                            ('seed="7"', 'seed="seven"'))
    afsm = tmp_path / "m.scxml"
    afsm.write_text(AFSM_BAD, encoding="utf-8")
    assert main(["check", str(scenario), str(afsm), str(EXAMPLE)]) == 1
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert f"{scenario}:5: " in captured.out and "seven" in captured.out  # the seed
    points = [x for x in lines if x.startswith(f"{scenario}:15: ")]
    assert len(points) == 1 and "expected points: 'x,y x,y ...' with at least 3 points" in points[0]
    assert any(x.startswith(f"{afsm}:3: ") and "eventless transitions" in x for x in lines)
    assert any(x.startswith(f"{afsm}:5: ") and "'Nowhere' does not exist" in x for x in lines)
    assert f"{EXAMPLE}: ok (scenario)" in lines
    assert "4 problems in 2 files" in captured.err


def test_a_semantic_scenario_problem_is_reported_with_its_line(tmp_path, capsys):
    path = bad_scenario(tmp_path, ('<place name="stove"', '<place name="window"'))
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    line = line_of(EXAMPLE_TEXT, '<place name="stove"')
    assert f"{path}:{line}:" in out and "window" in out


def test_malformed_and_unknown_documents_are_problems_too(tmp_path, capsys):
    broken = tmp_path / "broken.xml"
    broken.write_text("<scenario>\n<room>\n</scenario>\n", encoding="utf-8")
    other = tmp_path / "other.xml"
    other.write_text('<?xml version="1.0"?>\n<dialog xmlns="urn:x"/>\n', encoding="utf-8")
    assert main(["check", str(broken), str(other)]) == 1
    out = capsys.readouterr().out
    assert f"{broken}:3: malformed XML" in out
    assert f"{other}:2: root element <dialog xmlns=\"urn:x\"> is not a document homesim knows" in out
    assert "<scenario> (scenario)" in out and "(AFSM)" in out


def test_another_package_registers_its_document_type(tmp_path):
    """The dialog (or any) document plugs in by its root QName; the kernel does not import it."""
    seen: list[str] = []

    def check_dialog(path: str) -> list[InputError]:
        seen.append(path)
        return [InputError("no greeting rule", source=path, line=2)]

    doc = tmp_path / "d.xml"
    doc.write_text('<dialog xmlns="urn:test:dialog">\n<rule/>\n</dialog>\n', encoding="utf-8")
    register_document(DocumentType("{urn:test:dialog}dialog", "dialog", check_dialog))
    try:
        kind, problems = check_path(str(doc))
    finally:
        checkmod._registered.pop("{urn:test:dialog}dialog")
    assert kind == "dialog" and seen == [str(doc)]
    assert [str(p) for p in problems] == [f"{doc}:2: no greeting rule"]


@pytest.mark.parametrize("swap, words", [
    (('points="0,0 6,0 6,5 0,5"', 'points="0,0;6,0;6,5;0,5"'),
     "<room>: points='0,0;6,0;6,5;0,5' is not valid; expected points: 'x,y x,y ...' with at least 3 points"),
    (('points="0,0 6,0 6,5 0,5"', 'points="0,0 6,0"'), "expected points: 'x,y x,y ...' with at least 3 points"),
    (('<place name="window" x="4.0" y="0.5"/>', '<place name="window" x="4.0" y="0.5"/><no-such/>'), None),
])
def test_a_malformed_number_list_says_what_is_expected_not_the_regex(swap, words):
    text = EXAMPLE_TEXT.replace(*swap)
    with pytest.raises(ScenarioError) as info:
        load_scenario_text(text, source="s.xml")
    msg = str(info.value)
    if words is None:  # other schema messages are left as libxml2 words them
        assert "no-such" in msg
        return
    assert words in msg and msg.startswith("s.xml:15: ")
    assert "[0-9]" not in msg and "facet" not in msg and len(msg) < 250


def test_every_document_shipped_in_the_repository_checks_ok(capsys):
    # the test scenarios too: tests/scenarios/teaching_cups.xml once held a text placeholder that
    # 'homesim check' refused, although authors copy these files as examples
    files = sorted(str(p) for p in [*(ROOT / "scenarios").glob("*.xml"), *(ROOT / "tests" / "scenarios").rglob("*.xml"),
                                    *(ROOT / "robot").rglob("*.scxml")])
    assert len(files) >= 2
    assert main(["check", *files]) == 0, capsys.readouterr().out
    assert capsys.readouterr().out.count(": ok (") == len(files)


@settings(max_examples=examples(30, 200), deadline=None)
@given(st.text(alphabet="0123456789,;. -eE", min_size=0, max_size=30),
       st.sampled_from([("room", "points"), ("furniture", "points")]))
def test_any_refused_number_list_is_reported_as_the_expected_form(value, where):
    """Whatever the pattern refuses, the message names the element, the attribute and the form, never the regex."""
    element, attribute = where
    old = {"room": 'points="0,0 6,0 6,5 0,5"', "furniture": 'points="0.3,0.3 2.5,0.3 2.5,1.1 0.3,1.1"'}[element]
    text = EXAMPLE_TEXT.replace(old, f'{attribute}="{value}"', 1)
    try:
        load_scenario_text(text, source="s.xml")
    except ScenarioError as exc:
        msg = exc.message
        if "(scenario.xsd)" in msg and exc.element == element and msg.startswith(f"{attribute}="):
            assert "expected points: 'x,y x,y ...' with at least 3 points" in msg
            assert "facet" not in msg and "[0-9]" not in msg
