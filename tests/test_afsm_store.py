"""es:store / es:with: the ES keeps data from one event and copies it, concatenated, into a later order or condition."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.afsm.engine import Applied, Engine, Event
from homesim.afsm.loader import dumps, loads
from homesim.check import check_paths
from homesim.errors import AFSMProblems

from .conftest import examples

DOC = '''<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0" initial="A">
<es:module name="dialog" layer="deliberative"/>
<state id="A">
  <transition event="keep"><es:store name="kept" expr="X"/></transition>
  <transition event="add"><es:store name="kept" expr="X" append="true"/></transition>
  <transition event="use"><send event="told" target="dialog" es:kind="condition"><param name="p" expr="Y" es:with="kept"/></send></transition>
</state></scxml>'''


def _event(i: int, name: str, body: str) -> Event:
    return Event(f"e{i}", name, "dialog", i, 10**12, etree.fromstring(f"<event>{body}</event>"))


@settings(max_examples=examples(60, 300), deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["keep", "add", "use"]), st.integers(0, 99)), max_size=30))
def test_a_condition_carries_what_was_stored_then_what_its_own_event_says(steps):
    engine = Engine(loads(DOC, source="t"))
    model: list[str] = []  # the texts stored under "kept", as the rule says
    for i, (name, n) in enumerate(steps, start=1):
        tag = "Y" if name == "use" else "X"
        engine.queue(_event(i, name, f"<{tag}>{n}</{tag}>"), i)
        recs = engine.process(i)
        assert len(recs) == 1 and isinstance(recs[0], Applied)
        if name == "keep":
            model = [str(n)]
        elif name == "add":
            model = model + [str(n)]
        else:
            ((pname, value),) = recs[0].outputs[0].params
            assert pname == "p"
            assert [x.text for x in value] == model + [str(n)]
            assert [x.tag for x in value] == ["X"] * len(model) + ["Y"]
    # what is stored is a copy: the events' payloads are not touched
    assert [x.text for x in engine.stored.get("kept", ())] == model


def test_the_extension_survives_a_round_trip_through_scxml():
    m = loads(DOC, source="t")
    again = loads(dumps(m), source="t2")
    assert again.states["A"].transitions == m.states["A"].transitions


def test_a_parameter_with_data_nobody_stores_is_refused_by_homesim_check(tmp_path: Path, capsys):
    bad = tmp_path / "bad.scxml"
    bad.write_text(DOC.replace('es:with="kept"', 'es:with="lost"'))
    with pytest.raises(AFSMProblems, match="uses stored data 'lost'"):
        loads(bad.read_text(), source=str(bad))
    assert check_paths([str(bad)]) == 1
    assert "uses stored data 'lost'" in capsys.readouterr().out
    good = tmp_path / "good.scxml"
    good.write_text(DOC)
    assert check_paths([str(good)]) == 0


def test_biron_tells_the_dialog_who_greeted_and_what_they_said():
    """BIRON's AFSM stores the potential partner's PERSON and copies it with the greeting's SPEECH into partner_found."""
    from homesim.afsm.loader import load
    from robot.supervisor import BIRON_AFSM

    engine = Engine(load(BIRON_AFSM))
    person = '<PERSON id="t3" bearing="-4.0" distance="1.400" speaking="true" facing="true"/>'
    engine.queue(Event("a#1", "potential_partner", "person_attention", 1, 10**9, etree.fromstring(f"<event>{person}</event>")), 1)
    engine.process(1)
    greeting = "<event><SPEECH><GREETING/></SPEECH></event>"
    engine.queue(Event("d#1", "greeting", "dialog", 2, 3 * 10**9, etree.fromstring(greeting)), 2)
    (applied,) = engine.process(2)
    found = next(o for o in applied.outputs if o.name == "partner_found")
    partner = dict(found.params)["partner"]
    assert [x.tag for x in partner] == ["PERSON", "SPEECH"] and partner[0].get("id") == "t3"


def test_biron_keeps_and_tells_who_took_the_lost_partners_place():
    """After a loss (Following -> Interacting), new_partner stores the new PERSON in place of the greeter's
    and tells the dialog (person_info); the interaction goes on in Interacting."""
    from homesim.afsm.loader import load
    from robot.supervisor import BIRON_AFSM

    engine = Engine(load(BIRON_AFSM))
    ev = lambda eid, name, src, t, life, xml: engine.queue(Event(eid, name, src, t, life, etree.fromstring(xml)), t)
    ev("a#1", "potential_partner", "person_attention", 1, 10**9, '<event><PERSON id="t3" bearing="0" distance="1.2" speaking="true" facing="true"/></event>')
    engine.process(1)
    ev("d#1", "greeting", "dialog", 2, 3 * 10**9, "<event><SPEECH><GREETING/></SPEECH></event>")
    ev("d#2", "follow", "dialog", 3, 5 * 10**9, "<event><SPEECH><FOLLOW/></SPEECH></event>")
    ev("a#2", "partner_lost", "person_attention", 4, 2 * 10**9, "<event/>")
    engine.process(4)
    assert engine.state == "Interacting"
    ev("a#3", "new_partner", "person_attention", 5, 2 * 10**9, '<event><PERSON id="t9" bearing="10" distance="1.5" speaking="true" facing="true"/></event>')
    (applied,) = engine.process(5)
    assert engine.state == "Interacting"
    (info,) = [o for o in applied.outputs if o.name == "person_info"]
    assert dict(info.params)["person"][0].get("id") == "t9"
    assert [p.get("id") for p in engine.stored["partner"]] == ["t9"]
