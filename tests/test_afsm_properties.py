"""Property tests of the ES engine against the reference model (docs/semantics.md §2).

Random machines and random event streams (random creation times, lifetimes
and delivery delays) drive the engine and :mod:`tests.afsm_reference` side
by side, as the supervisor drives it: processing on every arrival and at
every expiry deadline.
"""

from __future__ import annotations

import copy
import json

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from homesim.afsm.engine import (
    EXPIRED,
    INAPPLICABLE,
    RETAINED,
    Applied,
    Engine,
    Event,
    Rejected,
    record_dict,
    run_deliveries,
)
from homesim.afsm.loader import dumps, loads
from homesim.afsm.model import Machine
from homesim.afsm.strategies import EVENT_NAMES, event_streams, machines, payloads

from .afsm_reference import ReferenceES
from .conftest import examples

MS = 1_000_000


def project(records: list) -> list[tuple]:
    out = []
    for r in records:
        if isinstance(r, Applied):
            out.append(("applied", r.event.id, r.target_state, ""))
        elif isinstance(r, Rejected):
            out.append(("rejected", r.event.id, r.state, r.reason))
    return out


def category_names(m: Machine, state: str) -> set[str]:
    cat = m.states[state].parent
    if cat is None:
        return set()
    return {t.event for sid in [cat, *m.descendants(cat)] for t in m.states[sid].transitions}


class SupervisorQueue(RuleBasedStateMachine):
    """The engine and the reference agree on every record; the invariants hold throughout."""

    @initialize(m=machines())
    def setup(self, m: Machine) -> None:
        self.m = m
        self.engine = Engine(m)
        self.ref = ReferenceES(m)
        self.now = 0
        self.n = 0
        self.delivered: dict[str, Event] = {}
        self.arrived: dict[str, int] = {}
        self.outcome: dict[str, str] = {}

    def _process(self, now: int) -> None:
        recs = self.engine.process(now)
        assert project(recs) == self.ref.process(now)
        for r in recs:
            ev = r.event
            expires = ev.created_ns + ev.lifetime_ns
            if isinstance(r, Applied):
                assert r.at_ns < expires, "applied at or after its expiry"
            elif isinstance(r, Rejected):
                if r.reason == EXPIRED:
                    # exactly at expiry, or on arrival if it came already expired
                    assert r.at_ns == max(expires, self.arrived[ev.id])
                else:
                    assert r.reason == INAPPLICABLE and r.at_ns < expires
            else:
                continue
            assert ev.id not in self.outcome, f"{ev.id} handled twice"
            self.outcome[ev.id] = r.kind if isinstance(r, Applied) else r.reason
        # Every event still queued is retained by the current category and not expired.
        names = category_names(self.m, self.engine.state)
        for q in self.engine.queued():
            assert q.status == RETAINED
            assert q.expires_ns > now
            assert q.event.name in names

    @rule(
        name=st.sampled_from(EVENT_NAMES),
        # Coarse times make ties (same creation time, expiry at an arrival) common.
        age=st.integers(0, 20).map(lambda k: k * 100 * MS),
        lifetime=st.one_of(st.none(), st.integers(1, 30).map(lambda k: k * 100 * MS), st.integers(1, 3_000 * MS)),
        payload=payloads(),
    )
    def deliver(self, name: str, age: int, lifetime: int | None, payload: object) -> None:
        """An event arrives now, created ``age`` ago (latency puts it before newer ones)."""
        self.n += 1
        ev = Event(f"e#{self.n}", name, "dialog", self.now - age, lifetime, payload)
        self.delivered[ev.id] = ev
        self.arrived[ev.id] = self.now
        self.engine.queue(ev, self.now)
        self.ref.queue(ev.id, name, ev.created_ns, lifetime, payload)
        self._process(self.now)

    @rule(dt=st.one_of(st.integers(0, 30).map(lambda k: k * 100 * MS), st.integers(0, 3_000 * MS)))
    def wait(self, dt: int) -> None:
        """Time passes: the ES wakes at every expiry deadline on the way."""
        target = self.now + dt
        while (d := self.engine.next_deadline()) is not None and d <= target:
            assert d > self.now
            self.now = d
            self._process(d)
        self.now = target
        self._process(target)

    @rule()
    def swap_in_an_equal_machine(self) -> None:
        """Run-time replacement keeps the queue; nothing changes for the reference."""
        self.engine.replace(self.m.copy())
        self._process(self.now)

    @invariant()
    def conservation(self) -> None:
        if not hasattr(self, "engine"):
            return
        queued = [q.event.id for q in self.engine.queued()]
        assert queued == self.ref.pending_ids()
        assert not set(queued) & set(self.outcome)
        assert set(queued) | set(self.outcome) == set(self.delivered)
        s = self.engine.stats()
        assert s["queued"] == s["applied"] + s["expired"] + s["inapplicable"] + s["pending"] == len(self.delivered)
        assert self.engine.state == self.ref.state

    @invariant()
    def queue_in_creation_order(self) -> None:
        if not hasattr(self, "engine"):
            return
        keys = [(q.event.created_ns, q.seq) for q in self.engine.queued()]
        assert keys == sorted(keys)


SupervisorQueue.TestCase.settings = settings(max_examples=examples(60, 500), stateful_step_count=30)
TestSupervisorQueue = SupervisorQueue.TestCase


@settings(max_examples=examples(60, 500))
@given(machines(), event_streams())
def test_whole_output_stream_is_deterministic(m: Machine, stream: list) -> None:
    """Same machine + same stream -> byte-identical records (ids, times, outputs)."""
    a = [record_dict(r) for r in run_deliveries(Engine(m), copy.deepcopy(stream))]
    b = [record_dict(r) for r in run_deliveries(Engine(copy.deepcopy(m)), copy.deepcopy(stream))]
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


@settings(max_examples=examples(60, 500))
@given(machines(), event_streams())
def test_every_event_ends_exactly_once_when_deadlines_are_followed(m: Machine, stream: list) -> None:
    """After the last deadline the queue is empty and each event ended once."""
    engine = Engine(m)
    recs = run_deliveries(engine, stream)
    ended = [r.event.id for r in recs if not r.kind == "retained"]
    assert sorted(ended) == sorted(d.event.id for d in stream)
    assert len(engine) == 0


@settings(max_examples=examples(60, 500))
@given(machines())
def test_scxml_round_trip_keeps_the_machine(m: Machine) -> None:
    """dump -> load yields the same states, transitions and sends."""
    back = loads(dumps(m), source="<roundtrip>")
    assert list(back.states) == list(m.states)
    for sid, s in m.states.items():
        b = back.states[sid]
        assert (b.parent, b.children) == (s.parent, s.children)
        assert [(t.event, t.target, t.cond, [(x.kind, x.target, x.name, [(p.name, p.expr) for p in x.params]) for x in t.sends])
                for t in b.transitions] == \
               [(t.event, t.target, t.cond, [(x.kind, x.target, x.name, [(p.name, p.expr) for p in x.params]) for x in t.sends])
                for t in s.transitions]


@settings(max_examples=examples(60, 500))
@given(machines(), event_streams())
def test_one_transition_at_a_time_gives_the_same_records(m: Machine, stream: list) -> None:
    """``process(now, max_applied=1)`` repeated (the supervisor with cost 0) = one full scan."""
    full = Engine(m)
    stepped = Engine(copy.deepcopy(m))
    for d in sorted(stream, key=lambda d: d.at_ns):
        full.queue(copy.deepcopy(d.event), d.at_ns)
        stepped.queue(copy.deepcopy(d.event), d.at_ns)
        want = full.process(d.at_ns)
        got: list = []
        while True:
            recs = stepped.process(d.at_ns, max_applied=1)
            got += recs
            if not recs or not isinstance(recs[-1], Applied):
                break
            assert sum(isinstance(r, Applied) for r in recs) == 1
        assert project(got) == project(want)
        assert stepped.state == full.state


@settings(max_examples=examples(60, 500))
@given(machines(), event_streams())
def test_expire_rejects_exactly_the_expired_and_nothing_else(m: Machine, stream: list) -> None:
    engine = Engine(m)
    for d in sorted(stream, key=lambda d: d.at_ns):
        engine.queue(d.event, d.at_ns)
        state = engine.state
        before = {q.event.id: q.expires_ns for q in engine.queued()}
        recs = engine.expire(d.at_ns)
        assert all(r.reason == EXPIRED and r.at_ns == d.at_ns for r in recs)
        assert {r.event.id for r in recs} == {i for i, x in before.items() if x <= d.at_ns}
        assert engine.state == state
