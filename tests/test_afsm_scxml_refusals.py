"""Standard SCXML the ES profile does not implement is refused by name, without misleading follow-ons.

Each case is a document an SCXML user would write; the problems must name the
feature (not a schema facet or a "required attribute" message) and nothing
that only follows from the refusal (a target naming a refused <final>).
"""

from __future__ import annotations

import pytest

from homesim.afsm.engine import Engine, Event
from homesim.afsm.loader import check, loads
from homesim.errors import AFSMProblems
from homesim.xmlio import parse_bytes

HEAD = '<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0"'


def problems(body: str, *, attrs: str = 'initial="A"') -> list[tuple[int | None, str]]:
    text = f"{HEAD} {attrs}>\n{body}\n</scxml>\n"
    return [(p.line, p.message) for p in check(text, source="m.scxml")]


def test_an_eventless_transition_is_refused_as_such():
    found = problems('<state id="A">\n<transition target="B"/>\n</state>\n<state id="B"/>')
    assert found == [(3, 'eventless transitions are not supported by the ES engine (it only reacts to events): '
                         'give the transition an event="..."')]  # and B is not reported unreachable


def test_an_event_list_is_refused_naming_each_event():
    found = problems('<state id="A">\n<transition event="go  run" target="B"/>\n</state>\n<state id="B"/>')
    assert len(found) == 1
    line, msg = found[0]
    assert line == 3 and "event lists are not supported" in msg and "'go', 'run'" in msg
    assert "facet" not in msg and "pattern" not in msg


@pytest.mark.parametrize("where", ["scxml", "state"])
def test_an_initial_naming_several_states_is_refused(where):
    if where == "scxml":
        found = problems('<state id="A"/>\n<state id="B"/>', attrs='initial="A B"')
        line = 1
    else:
        found = problems('<state id="C" initial="A B">\n<state id="A"/>\n<state id="B"/>\n</state>', attrs="")
        line = 2
    assert len(found) == 1, found
    assert found[0][0] == line and "an initial naming several states is not supported" in found[0][1]
    assert "'A B'" in found[0][1] and "facet" not in found[0][1]


@pytest.mark.parametrize("refused", ["final", "parallel"])
def test_no_follow_on_problems_after_a_refused_final_or_parallel(refused):
    """A target and an initial naming the refused element only repeat the refusal."""
    body = (f'<state id="A">\n<transition event="done" target="pass"/>\n</state>\n<{refused} id="pass"/>\n'
            '<state id="Outer" initial="pass">\n<state id="In"/>\n</state>')
    found = problems(body, attrs='initial="pass"')
    assert [line for line, _ in found] == [5], found
    assert f"SCXML <{refused}> is not supported" in found[0][1]
    assert not any("does not exist" in msg for _, msg in found)


def test_a_refused_parallel_with_states_inside_has_no_follow_ons_for_them():
    body = ('<state id="A">\n<transition event="split" target="left"/>\n</state>\n'
            '<parallel id="P">\n<state id="left"/>\n<state id="right"/>\n</parallel>')
    found = problems(body)
    assert len(found) == 1 and "<parallel>" in found[0][1]


@pytest.mark.parametrize("cond", ["true", "false", " TRUE ", "True"])
def test_boolean_literal_guards_are_refused_saying_how_to_write_one(cond):
    found = problems(f'<state id="A">\n<transition event="x" target="A" cond="{cond}"/>\n</state>')
    assert len(found) == 1
    line, msg = found[0]
    word = cond.strip().lower()
    assert line == 3 and "is not a boolean" in msg and f"write {word}()" in msg


@pytest.mark.parametrize("cond", ["_event.data.ok", "$_event/data/ok = 1", "not(_event/data)"])
def test_guards_on_scxml_event_variable_are_refused(cond):
    (p,) = problems(f'<state id="A">\n<transition event="x" target="A" cond="{cond}"/>\n</state>')
    assert p[0] == 3 and "SCXML's _event" in p[1] and "evaluated on the <event> element itself" in p[1]


def test_the_documented_way_true_function_holds_and_a_test_on_the_event_works():
    """What the refusal tells the user to write does what they meant."""
    m = loads(f'''{HEAD} initial="A">
      <state id="A"><transition event="x" target="B" cond="true()"/></state>
      <state id="B"><transition event="y" target="A" cond="@ok = 'yes' and GREETING"/></state>
    </scxml>''', source="m.scxml")
    e = Engine(m)
    e.queue(Event("1", "x", "dialog", 0, 10**9, parse_bytes(b'<event name="x"/>')), 0)
    assert [r.kind for r in e.process(0)] == ["applied"] and e.state == "B"
    e.queue(Event("2", "y", "dialog", 0, 10**9, parse_bytes(b'<event name="y" ok="yes"><GREETING/></event>')), 0)
    e.process(0)
    assert e.state == "A"


def test_a_guard_selecting_a_real_child_named_like_a_word_is_still_fine():
    """Only the bare boolean words are refused: a path such as ok/true stays an ordinary XPath."""
    assert problems('<state id="A">\n<transition event="x" target="A" cond="flags/true"/>\n</state>') == []


def test_loading_raises_with_every_refusal():
    with pytest.raises(AFSMProblems) as info:
        loads(f'{HEAD} initial="A B">\n<state id="A"><transition target="B"/></state>\n<state id="B"/>\n</scxml>',
              source="m.scxml")
    text = [str(p) for p in info.value.problems]
    assert len(text) == 2 and all(t.startswith("m.scxml:") for t in text)
    assert "initial naming several states" in text[0] and "eventless transitions" in text[1]
