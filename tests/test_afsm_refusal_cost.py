"""Refusing a bad AFSM stays near-linear; a guard's cost is bounded.

Class: documents whose refusal used to cost quadratic time (one problem per
state, each resolved by scanning every sibling; unbounded validation
rounds), and guards whose cost grows as payload_size ** nesting. The check
now resolves problem paths with per-round sibling tables, stops after
MAX_SCHEMA_ROUNDS rounds saying so, and bounds guards (length, descendant
steps) and the payloads they run on (elements).
"""

from __future__ import annotations

import pytest
from lxml import etree

from homesim.afsm.engine import MAX_PAYLOAD_ELEMENTS, Engine, Event
from homesim.afsm.loader import MAX_SCHEMA_ROUNDS, check, loads
from homesim.afsm.model import MAX_XPATH_DEEP_STEPS, MAX_XPATH_LENGTH
from homesim.errors import SupervisorError

HEAD = '<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0" initial="S0">\n'


def test_every_state_with_an_unknown_element_is_reported_at_its_own_line():
    n = 2000
    body = "".join(f'<state id="S{i}"><foo/><transition event="e" target="S{(i + 1) % n}"/></state>\n' for i in range(n))
    problems = check(HEAD + body + "</scxml>", source="big.scxml")
    assert len(problems) == n
    assert [p.line for p in problems] == list(range(2, n + 2))
    assert all("foo" in p.message for p in problems)


def test_many_unexpected_siblings_stop_after_a_bounded_number_of_rounds():
    body = '<state id="S0">' + "<foo/>\n" * 3000 + "</state>\n"
    problems = check(HEAD + body + "</scxml>", source="big.scxml")
    assert MAX_SCHEMA_ROUNDS <= len(problems) <= MAX_SCHEMA_ROUNDS + 1
    assert [p for p in problems if "more problems may follow" in p.message]


def _machine_with_guard(guard: str) -> str:
    return (HEAD + f'<state id="S0"><transition event="e" target="S1" cond="{guard}"/></state>\n'
            '<state id="S1"><transition event="back" target="S0"/></state>\n</scxml>')


@pytest.mark.parametrize("guard", [
    "count(//*[count(//*[count(//*) &gt; 0]) &gt; 0])",
    "descendant::a/ancestor::b/following::c",
    "//a//b//c",
])
def test_guards_with_too_many_deep_steps_are_refused_with_the_line(guard):
    problems = check(_machine_with_guard(guard), source="g.scxml")
    assert len(problems) == 1 and problems[0].line == 2
    assert f"at most {MAX_XPATH_DEEP_STEPS}" in problems[0].message


def test_long_guards_are_refused_and_cheap_ones_accepted():
    assert check(_machine_with_guard("count(//*[count(//*) &gt; 0]) &gt; 0")) == []
    long = " or ".join(["@a = '1'"] * (MAX_XPATH_LENGTH // 10 + 1)).replace("'", "&apos;")
    problems = check(_machine_with_guard(long))
    assert len(problems) == 1 and "longer than" in problems[0].message


def test_the_engine_refuses_payloads_larger_than_the_bound():
    m = loads(_machine_with_guard("count(//*[count(//*) &gt; 0]) &gt; 0"))
    engine = Engine(m)
    ok = etree.Element("p")
    for _ in range(MAX_PAYLOAD_ELEMENTS - 1):
        etree.SubElement(ok, "x")
    engine.queue(Event("a#1", "e", "dialog", 0, None, ok), 0)
    big = etree.Element("p")
    for _ in range(MAX_PAYLOAD_ELEMENTS):
        etree.SubElement(big, "x")
    with pytest.raises(SupervisorError, match=f"more than {MAX_PAYLOAD_ELEMENTS} elements"):
        engine.queue(Event("a#2", "e", "dialog", 0, None, big), 0)


def test_a_huge_event_over_the_bus_is_reported_and_the_supervisor_goes_on():
    from homesim.sim import Simulation
    from robot.supervisor import ES_EVENTS, ExecutionSupervisor, event_xml

    with Simulation(seed=3) as sim:
        rec = sim.record_trace()
        es = ExecutionSupervisor(sim)
        dialog = sim.bus.participant("dialog")
        sim.start()
        big = etree.Element("SPEECH")
        for _ in range(MAX_PAYLOAD_ELEMENTS + 10):
            etree.SubElement(big, "W")
        dialog.publish(ES_EVENTS, event_xml("greeting", children=(big,)))
        sim.run(until=1.0)
        drops = [r for r in rec.records() if r.get("kind") == "drop"]
        assert any("more than" in r["reason"] and r["receivers"] == [es.name] for r in drops)
        dialog.publish(ES_EVENTS, event_xml("greeting", children=(etree.Element("SPEECH"),)))
        sim.run(until=2.0)  # the supervisor still runs and handles the next event
        assert es.engine.stats()["queued"] >= 1
