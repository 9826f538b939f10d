"""Engine rules of docs/semantics.md §2 on small hand-written machines, and run-time modification."""

from __future__ import annotations

import pytest

from homesim.afsm.engine import EXPIRED, INAPPLICABLE, RETAINED, WAITING, Applied, Engine, Event, Rejected, Retained
from homesim.afsm.loader import loads
from homesim.afsm.model import Transition
from homesim.afsm.render import AFSMView, to_dot, to_mermaid
from homesim.errors import AFSMModificationRefused, AFSMProblems, ClockError, SupervisorError
from homesim.xmlio import parse_bytes

MACHINE = """<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0"
       name="t" initial="A" es:default-lifetime="1">
  <es:module name="dialog" layer="deliberative"/>
  <es:module name="attention" layer="reactive"/>
  <es:event name="ping" lifetime="10"/>
  <state id="Cat">
    <transition event="reset" target="A"/>
    <transition event="x" target="C"/>
    <state id="A">
      <transition event="go" target="B"/>
      <transition event="x" target="B" cond="@ok='1'">
        <send event="hello" target="dialog" es:kind="condition"><param name="v" expr="@v"/><param name="kids" expr="kid"/></send>
      </transition>
    </state>
    <state id="B">
      <transition event="need" target="A"/>
      <transition event="ping"><send event="pong" target="attention" es:kind="order"/></transition>
    </state>
  </state>
  <state id="C"><transition event="back" target="Cat"/></state>
</scxml>"""

MS = 1_000_000


@pytest.fixture
def engine() -> Engine:
    return Engine(loads(MACHINE, source="t.scxml"))


def ev(i: int, name: str, created: int, *, xml: str | None = None, lifetime: int | None = None) -> Event:
    return Event(f"e#{i}", name, "dialog", created, lifetime, parse_bytes(xml) if xml else None)


def kinds(recs) -> list[tuple]:
    return [(r.kind, r.event.id) + ((r.target_state,) if isinstance(r, Applied) else (r.reason,) if isinstance(r, Rejected) else ())
            for r in recs]


def test_state_own_transition_wins_over_the_category(engine):
    engine.queue(ev(1, "x", 0, xml='<e ok="1" v="7"><kid n="1"/><kid n="2"/></e>'), 0)
    (rec,) = engine.process(0)
    assert rec.target_state == "B" and rec.owner == "A"
    (out,) = rec.outputs
    assert out.params[0] == ("v", ("7",)) and [k.get("n") for k in out.params[1][1]] == ["1", "2"]


def test_category_transition_applies_when_the_guard_fails(engine):
    engine.queue(ev(1, "x", 0, xml='<e ok="0"/>'), 0)
    (rec,) = engine.process(0)
    assert (rec.target_state, rec.owner) == ("C", "Cat")


def test_targeting_a_category_enters_its_initial_state(engine):
    engine.queue(ev(1, "x", 0, xml='<e ok="0"/>'), 0)
    engine.queue(ev(2, "back", 1), 1)
    recs = engine.process(1)
    assert recs[-1].target_state == "A"


def test_targetless_transition_stays_and_sends(engine):
    engine.queue(ev(1, "go", 0), 0)
    engine.queue(ev(2, "ping", 1), 1)
    recs = engine.process(1)
    assert kinds(recs) == [("applied", "e#1", "B"), ("applied", "e#2", "B")]
    assert recs[1].outputs[0].name == "pong"


def test_retained_event_applies_after_a_later_one_changes_state(engine):
    engine.queue(ev(1, "need", 0), 0)  # only B uses it: retained in A (same category)
    recs = engine.process(0)
    assert kinds(recs) == [("retained", "e#1")] and engine.queued()[0].status == RETAINED
    engine.queue(ev(2, "go", 5), 5)
    assert engine.queued()[1].status == WAITING
    assert kinds(engine.process(5)) == [("applied", "e#2", "B"), ("applied", "e#1", "A")]


def test_outside_any_category_unusable_events_are_rejected_at_once(engine):
    engine.queue(ev(1, "x", 0, xml='<e ok="0"/>'), 0)
    engine.process(0)
    assert engine.state == "C" and engine.category is None
    engine.queue(ev(2, "go", 1), 1)
    (rec,) = engine.process(1)
    assert rec.reason == INAPPLICABLE and "'C'" in rec.detail


def test_expiry_uses_the_event_lifetime_then_the_name_then_the_default(engine):
    engine.queue(ev(1, "need", 0, lifetime=300 * MS), 0)
    engine.queue(ev(2, "ping", 0), 0)  # declared for the name: 10 s
    engine.queue(ev(3, "need", 0), 0)  # default: 1 s
    engine.process(0)
    assert [q.expires_ns for q in engine.queued()] == [300 * MS, 10_000 * MS, 1_000 * MS]
    assert engine.next_deadline() == 300 * MS
    assert engine.process(300 * MS - 1) == []
    (rec,) = engine.process(300 * MS)
    assert (rec.event.id, rec.reason, rec.at_ns) == ("e#1", EXPIRED, 300 * MS)


def test_an_event_arriving_already_expired_is_rejected_on_arrival(engine):
    engine.queue(ev(1, "go", 0, lifetime=5 * MS), 10 * MS)
    (rec,) = engine.process(10 * MS)
    assert rec.reason == EXPIRED and engine.state == "A"


def test_ties_in_creation_time_keep_arrival_order(engine):
    for i, name in enumerate(["need", "go", "ping"]):
        engine.queue(ev(i, name, 100), 200 + i)
    assert [q.event.name for q in engine.queued()] == ["need", "go", "ping"]
    assert kinds(engine.process(300)) == [
        ("retained", "e#0"), ("applied", "e#1", "B"), ("applied", "e#0", "A"), ("retained", "e#2"),
    ]


def test_time_cannot_go_backwards(engine):
    engine.process(10)
    with pytest.raises(ClockError, match="backwards"):
        engine.process(9)


def test_the_same_event_cannot_be_queued_twice(engine):
    e = ev(1, "need", 0)
    engine.queue(e, 0)
    with pytest.raises(SupervisorError, match="already queued"):
        engine.queue(ev(1, "need", 0), 0)


def test_invalid_machine_is_refused_by_the_engine():
    bad = loads(MACHINE).copy()
    bad.states["A"].transitions.append(Transition("go", "Nope"))
    with pytest.raises(AFSMProblems, match="Nope"):
        Engine(bad)


def test_replace_keeps_the_queue_and_re_decides_retention(engine):
    engine.queue(ev(1, "need", 0, lifetime=5_000 * MS), 0)
    engine.process(0)
    smaller = MACHINE.replace('<transition event="need" target="A"/>', "")
    engine.replace(loads(smaller))
    assert engine.queued()[0].status == WAITING
    (rec,) = engine.process(1)
    assert rec.reason == INAPPLICABLE  # nobody in the category uses it any more
    assert engine.stats() == {"queued": 1, "applied": 0, "expired": 0, "inapplicable": 1, "pending": 0}


def test_replace_refused_when_the_current_state_would_vanish(engine):
    engine.queue(ev(1, "need", 0), 0)
    engine.process(0)
    other = MACHINE.replace('id="A"', 'id="A2"').replace('target="A"', 'target="A2"').replace('initial="A"', 'initial="A2"')
    with pytest.raises(AFSMModificationRefused, match="current state 'A' would not exist"):
        engine.replace(loads(other))
    assert engine.machine.name == "t" and len(engine) == 1


def test_extend_adds_states_and_transitions_without_restarting(engine):
    ext = loads("""<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0">
      <state id="A"><transition event="new" target="D"/></state>
      <state id="Cat"><state id="D"><transition event="go" target="A"/></state></state></scxml>""", fragment=True)
    engine.extend(ext)
    engine.queue(ev(1, "new", 0), 0)
    engine.queue(ev(2, "go", 1), 1)
    assert kinds(engine.process(1)) == [("applied", "e#1", "D"), ("applied", "e#2", "A")]


def test_extend_that_breaks_the_machine_is_refused(engine):
    ext = loads("""<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0">
      <state id="A"><transition event="new" target="Ghost"/></state></scxml>""", fragment=True)
    with pytest.raises(AFSMModificationRefused, match="Ghost"):
        engine.extend(ext)
    assert all(t.event != "new" for t in engine.machine.states["A"].transitions)


def test_snapshot_lists_queue_with_status_and_expiry(engine):
    engine.queue(ev(1, "need", 0), 0)
    engine.process(0)
    snap = engine.snapshot()
    assert snap["state"] == "A" and snap["category"] == "Cat"
    assert snap["queue"] == [{"id": "e#1", "name": "need", "source": "dialog", "created_ns": 0,
                              "expires_ns": 1_000 * MS, "status": "retained"}]
    assert isinstance(engine.history[-1], Retained)


def test_rendering_shows_categories_and_current_state():
    m = loads(MACHINE)
    dot = to_dot(m, current="B")
    assert 'subgraph "cluster_Cat"' in dot and '"B" [label="B", fillcolor="#ffe08a"' in dot
    assert 'ltail="cluster_Cat"' in dot  # the category's own transitions leave the cluster
    mm = to_mermaid(m)
    assert "state Cat {" in mm and "A --> B : x [@ok='1'] / ↑dialog.hello" in mm
    assert "Cat --> C : x" in mm and "C --> Cat : C→A꞉ back" not in mm and "C --> Cat : back" in mm
    view = AFSMView(m, current="A")
    assert view._repr_markdown_().startswith("```mermaid\nstateDiagram-v2")
    assert "2 states" not in repr(view) and "3 states, 1 categories" in repr(view)


@pytest.mark.parametrize("body, line, words", [
    ('<state id="A">\n\n<transition event="new" target="Ghost"/></state>', 4, "target 'Ghost' does not exist"),
    ('<state id="A"><transition event="new" target="A">\n\n<send event="o" target="ghost" es:kind="order"/>'
     '</transition></state>', 4, "unknown module 'ghost'"),
    ('<state id="A"><transition event="new" target="A">\n<send event="o" target="attention" es:kind="order">\n'
     '<param name="p" expr="@a ="/></send></transition></state>', 4, "invalid XPath"),
    ('<state id="Cat">\n<state id="D"/></state>', 3, "'D' is unreachable"),
])
def test_errors_in_an_extension_name_the_extension_file_and_line(engine, tmp_path, body, line, words):
    path = tmp_path / "ext.scxml"
    path.write_text('<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0">\n'
                    + body + "\n</scxml>\n", encoding="utf-8")
    from homesim.afsm.loader import load

    with pytest.raises(AFSMModificationRefused) as info:
        engine.extend(load(path, fragment=True))
    assert (info.value.source, info.value.line) == (str(path), line), str(info.value)
    assert words in info.value.message


def test_a_problem_in_the_base_still_names_the_base_after_merging(engine):
    from homesim.afsm.model import Machine, State, merge, validate

    ext = Machine(name="ext", states={"A": State("A", transitions=[Transition("new", "Ghost", line=2)])},
                  roots=["A"], source="api-ext")
    (p,) = validate(merge(engine.machine, ext))
    assert (p.source, p.line) == ("api-ext", 2)  # built by API: the extension's source
    assert all(t.file == "t.scxml" for _, t in merge(engine.machine, ext).transitions() if t.event != "new")


def test_engine_setup_computes_each_category_once(monkeypatch):
    """Retention names per category, not per leaf: 4000 leaves in one category stay linear."""
    from homesim.afsm.model import Machine

    n = 4000
    text = ('<scxml xmlns="http://www.w3.org/2005/07/scxml" version="1.0"><state id="C">'
            + "".join(f'<state id="s{i}"><transition event="e" target="s{(i + 1) % n}"/></state>' for i in range(n))
            + "</state></scxml>")
    m = loads(text)
    calls = []
    real = Machine.descendants
    monkeypatch.setattr(Machine, "descendants", lambda self, sid: calls.append(sid) or real(self, sid))
    Engine(m)
    assert calls.count("C") <= 2  # validation may ask too; never once per leaf


def test_the_engine_does_not_change_the_callers_event_or_share_its_machine():
    m = loads(MACHINE, source="t.scxml")
    e = Engine(m)
    event = ev(1, "go", 0)
    e.queue(event, 0)
    (rec,) = e.process(0)
    assert event.lifetime_ns is None  # the caller's event is untouched
    assert rec.event.lifetime_ns == 1_000_000_000 and rec.event.id == "e#1"  # the engine's own copy
    m.states["B"].transitions.clear()  # the caller changes its machine afterwards...
    m.name = "changed"
    assert e.machine.name == "t" and e.machine.states["B"].transitions  # ...the engine's is its own
    e.machine.states["B"].transitions.clear()  # and what it hands out is a copy
    assert e.machine.states["B"].transitions
    e.queue(ev(2, "need", 1), 1)
    assert kinds(e.process(1)) == [("applied", "e#2", "A")]
