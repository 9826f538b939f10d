"""The same-instant rule (docs/semantics.md §2, "Same instant"): every arrival of an instant is
queued before anything is decided at it, then the scan takes the oldest first.

When an older event arrives at the very instant a newer one expires, the older
is applied first and the newer rejected (expired) in the state that left,
whether the arrival was scheduled (by its link latency) before or after the
ES's expiry timer; when the ES's processing cost ends at ``t``, an event
arriving at ``t`` is queued before it decides. The engine driven by
:func:`run_deliveries`, the ES on the bus and an independent reference
(tests/afsm_reference.py) agree, so what the dialog is told does not depend on latency.
"""

from __future__ import annotations

from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.afsm.engine import EXPIRED, Applied, Delivery, Engine, Event, Rejected, record_dict, run_deliveries
from homesim.afsm.loader import loads
from homesim.network import LinkModel
from homesim.sim import Simulation
from robot.supervisor import ES_EVENTS, ExecutionSupervisor, event_xml
from .conftest import examples

MS = 1_000_000

# The minimal case: category C0 = {s0, s1}, s0 --b--> s1, s1 --a--> s0, start s0.
C0 = """<scxml xmlns="http://www.w3.org/2005/07/scxml" xmlns:es="urn:homesim:afsm:1" version="1.0"
       name="c0" initial="s0" es:default-lifetime="1">
  <state id="C0" initial="s0">
    <state id="s0"><transition event="b" target="s1"/></state>
    <state id="s1"><transition event="a" target="s0"/></state>
  </state>
</scxml>"""


def machine():
    return loads(C0, source="c0.scxml")


def ev(name: str, created_ms: int, lifetime_ms: int | None = None, n: int = 1) -> Event:
    return Event(f"{name}#{n}", name, "dialog", created_ms * MS, None if lifetime_ms is None else lifetime_ms * MS)


def outcome(recs) -> list[tuple]:
    out = []
    for r in recs:
        if isinstance(r, Rejected):
            out.append((r.kind, r.event.name, r.at_ns, r.state, r.reason))
        elif isinstance(r, Applied):
            out.append((r.kind, r.event.name, r.at_ns, r.source_state, r.target_state))
    return out


# b (older) is applied first; a, whose lifetime ends at that very instant, is rejected in s1.
MINIMAL = [("applied", "b", 20 * MS, "s0", "s1"), ("rejected", "a", 20 * MS, "s1", EXPIRED)]


def test_minimal_case_run_deliveries_scans_from_the_oldest_at_the_instant():
    """a (created 10 ms, lifetime 10 ms, delivered 10 ms) expires at 20 ms, when b (created 5 ms) arrives."""
    recs = run_deliveries(Engine(machine()), [Delivery(ev("a", 10, 10), 10 * MS), Delivery(ev("b", 5), 20 * MS)])
    assert outcome(recs) == MINIMAL


def test_minimal_case_engine_scans_from_the_oldest_expired_where_it_is_reached():
    """The arrival queued before the instant is processed: b applied, then a rejected (expired) in s1."""
    engine = Engine(machine())
    engine.queue(ev("a", 10, 10), 10 * MS)
    engine.process(10 * MS)
    engine.queue(ev("b", 5), 20 * MS)
    assert outcome(engine.process(20 * MS)) == MINIMAL


# ------------------------------------------------------------------ on the bus
def run_on_bus(events: list[tuple[str, int, int | None, int, int]], *, cost: float = 0.0):
    """Each event: (name, created ns, lifetime ns or None, published ns, link delay ns), one host per event.

    The ES sits on a zero-delay link, so each event arrives exactly at published + delay.
    Returns the ES's records and the bus's delivery order (ids).
    """
    sim = Simulation(seed=1, scenario="same-instant")
    try:
        sim.network.set_link(LinkModel("zero", 0.0, 0.0))
        sim.network.add_host("es", link="zero")
        es = ExecutionSupervisor(sim, machine(), host="es", cost=cost, heartbeat=None)
        arrivals: list[str] = []
        es.bus.subscribe(ES_EVENTS, lambda m: arrivals.append(m.id))
        for i, (name, created, lifetime, published, delay) in enumerate(events):
            sim.network.set_link(LinkModel(f"l{i}", delay / 1e9, delay / 1e9))
            sim.network.add_host(f"h{i}", link=f"l{i}")
            who = sim.bus.participant(f"p{i}", host=f"h{i}")
            xml = event_xml(name, lifetime=None if lifetime is None else lifetime / 1e9)
            sim.loop.call_at_ns(published, lambda w=who, x=xml, c=created: w.publish(ES_EVENTS, x, created=c / 1e9))
        sim.start()
        sim.run(until=2.0)
        return list(es.engine.history), arrivals
    finally:
        sim.close()


def test_minimal_case_on_the_bus_does_not_depend_on_the_link_latency():
    """b arrives at 20 ms: sent at 5 ms over a 15 ms link (scheduled before the ES's expiry timer) or
    at 19 ms over a 1 ms link (scheduled after it). Both: b applied, then a expired in s1."""
    a = ("a", 10 * MS, 10 * MS, 10 * MS, 0)
    for b in [("b", 5 * MS, None, 5 * MS, 15 * MS), ("b", 5 * MS, None, 19 * MS, 1 * MS)]:
        for cost in (0.0, 0.003):
            recs, _ = run_on_bus([a, b], cost=cost)
            assert outcome(recs) == MINIMAL


def test_an_event_arriving_when_the_cost_ends_is_queued_before_the_next_decision():
    """Cost 10 ms: b applied at 10 ms (s0 -> s1), a1 (created 15 ms) queued while busy; the ES is free at
    20 ms, when a2 (created 8 ms, older) arrives. The decision at 20 ms takes the oldest, a2, whether a2's
    delivery was scheduled before the ES's end-of-cost timer (sent at 8 ms, 12 ms link) or after it
    (sent at 19 ms, 1 ms link)."""
    b = ("b", 10 * MS, 50 * MS, 10 * MS, 0)
    a1 = ("a", 15 * MS, 50 * MS, 15 * MS, 0)
    for a2 in [("a", 8 * MS, 50 * MS, 8 * MS, 12 * MS), ("a", 8 * MS, 50 * MS, 19 * MS, 1 * MS)]:
        recs, _ = run_on_bus([b, a1, a2], cost=0.010)
        applied = [(r.event.id, r.at_ns, r.source_state, r.target_state) for r in recs if isinstance(r, Applied)]
        assert applied == [("p0#1", 10 * MS, "s0", "s1"), ("p2#1", 20 * MS, "s1", "s0")]


# Arrivals and expiries on a 1 ms grid so that they often fall on the same instant.
@st.composite
def streams(draw):
    """(name, created, lifetime, arrival) in ns; arrivals often fall exactly on an earlier event's expiry."""
    out: list[tuple[str, int, int | None, int]] = []
    used: set[int] = set()
    for _ in range(draw(st.integers(1, 7))):
        name = draw(st.sampled_from(["a", "b", "c"]))  # c: on no transition (inapplicable)
        lifetime = draw(st.one_of(st.none(), st.integers(1, 10)))  # ms; None: the machine's 1 s
        expiries = sorted({(c + lt) // MS for _, c, lt, _ in out if lt is not None} - used)
        fresh = st.integers(1, 16)
        at = draw(st.one_of(st.sampled_from(expiries), fresh) if expiries else fresh)
        if at in used:
            continue
        used.add(at)
        created = at - draw(st.integers(0, min(at, 10)))
        out.append((name, created * MS, None if lifetime is None else lifetime * MS, at * MS))
    return out


def split(stream, fractions):
    """Send each event somewhere between its creation and its arrival: the link delay covers the rest."""
    out = []
    for (name, created, lifetime, at), f in zip(stream, fractions):
        published = created + (at - created) * f // 1000
        out.append((name, created, lifetime, published, at - published))
    return out


@settings(max_examples=examples(60, 400), deadline=None)
@given(streams(), st.data(), st.sampled_from([0.0, 0.003, 0.010]))
def test_the_supervisors_decisions_do_not_depend_on_link_latency(stream, data, cost):
    """Same creation and arrival instants, random link delays: the same records, in the same order.

    With no processing cost they are also exactly :func:`run_deliveries`' records (the engine alone).
    """
    # early or late sending: the delivery is scheduled before or after the ES's own timers for that instant
    fraction = st.one_of(st.sampled_from([0, 1000]), st.integers(0, 1000))
    fractions = st.lists(fraction, min_size=len(stream), max_size=len(stream))
    one, _ = run_on_bus(split(stream, data.draw(fractions)), cost=cost)
    two, _ = run_on_bus(split(stream, data.draw(fractions)), cost=cost)
    assert [record_dict(r) for r in one] == [record_dict(r) for r in two]
    ended = [r for r in one if r.kind != "retained"]
    assert len(ended) == len(stream)  # every event ended once (the run is long enough)
    if cost == 0.0:
        deliveries = [Delivery(Event(f"p{i}#1", name, f"p{i}", created, lifetime), at)
                      for i, (name, created, lifetime, at) in enumerate(stream)]
        want = run_deliveries(Engine(machine()), deliveries)
        assert outcome(one) == outcome(want)


# ------------------------------------------------- arrivals and expiries on shared instants
@st.composite
def shared_instants(draw, names=("a", "b", "c")):
    """(name, created, lifetime, arrival) in ns, every creation time distinct (ties would fall to delivery
    order); arrivals are forced onto instants where another event expires or another arrives."""
    out: list[tuple[str, int, int | None, int]] = []
    created_used: set[int] = set()
    for _ in range(draw(st.integers(1, 8))):
        name = draw(st.sampled_from(names))
        lifetime = draw(st.one_of(st.none(), st.integers(1, 10)))  # ms; None: the machine's default
        expiries = sorted({(c + lt) // MS for _, c, lt, _ in out if lt is not None})
        arrivals = sorted({at // MS for *_, at in out})
        fresh = st.integers(1, 16)
        choices = [fresh] + ([st.sampled_from(expiries)] * 2 if expiries else []) + ([st.sampled_from(arrivals)] if arrivals else [])
        at = draw(st.one_of(*choices))
        free = [c for c in range(0, at + 1) if c not in created_used]
        if not free:
            continue
        created = draw(st.sampled_from(free[-11:]))
        created_used.add(created)
        out.append((name, created * MS, None if lifetime is None else lifetime * MS, at * MS))
    return out


def _ref(m, stream, ids, until):
    from .afsm_reference import reference_run

    return reference_run(m, [(i, name, created, lifetime, None, at) for i, (name, created, lifetime, at) in zip(ids, stream)], until)


def _timed(recs) -> list[tuple]:
    out = []
    for r in recs:
        if isinstance(r, Applied):
            out.append((r.at_ns, "applied", r.event.id, r.target_state, ""))
        elif isinstance(r, Rejected):
            out.append((r.at_ns, "rejected", r.event.id, r.state, r.reason))
    return out


@settings(max_examples=examples(100, 1000), deadline=None)
@given(st.data())
def test_the_engine_at_shared_instants_follows_the_reference(data):
    """Random machines, arrivals and expiries forced onto the same instants: run_deliveries gives the
    independent reference's records (every arrival of an instant queued, then one scan from the oldest)."""
    from homesim.afsm.strategies import EVENT_NAMES, machines

    m = data.draw(machines())
    stream = data.draw(shared_instants(names=EVENT_NAMES))
    ids = [f"e{i}" for i in range(len(stream))]
    until = 2_000 * MS
    deliveries = [Delivery(Event(i, name, "dialog", created, lifetime), at) for i, (name, created, lifetime, at) in zip(ids, stream)]
    got = _timed(run_deliveries(Engine(m), deliveries, until_ns=until))
    assert got == _ref(m, stream, ids, until)


@settings(max_examples=examples(60, 400), deadline=None)
@given(shared_instants(), st.data(), st.sampled_from([0.0, 0.003, 0.010]))
def test_the_supervisor_at_shared_instants_does_not_depend_on_latency(stream, data, cost):
    """Several arrivals and expiries on one instant, random link delays: the same records; with no
    processing cost, the reference's."""
    fraction = st.one_of(st.sampled_from([0, 1000]), st.integers(0, 1000))
    fractions = st.lists(fraction, min_size=len(stream), max_size=len(stream))
    one, _ = run_on_bus(split(stream, data.draw(fractions)), cost=cost)
    two, _ = run_on_bus(split(stream, data.draw(fractions)), cost=cost)
    assert [record_dict(r) for r in one] == [record_dict(r) for r in two]
    assert len([r for r in one if r.kind != "retained"]) == len(stream)
    if cost == 0.0:
        assert _timed(one) == _ref(machine(), stream, [f"p{i}#1" for i in range(len(stream))], 2_000 * MS)


# ------------------------------------------- expiries while the ES pays a transition's cost
# b applied at 1 ms makes the ES busy for 3 ms; at 3 ms p0 (created 2 ms) expires and p1 (created 1 ms)
# arrives already expired. Sent at 3 ms over a 0 ms link, p1's delivery was scheduled after the ES's
# expiry timer for p0: still, every arrival of the instant is queued first and the scan rejects p1 first.
BUSY_CASE = [("a", 2 * MS, 1 * MS, 2 * MS), ("a", 1 * MS, 1 * MS, 3 * MS), ("b", 1 * MS, None, 1 * MS)]


def test_while_paying_a_cost_expiries_at_an_instant_follow_its_arrivals_oldest_first():
    for fractions in ([0, 0, 0], [0, 1000, 0]):
        recs, _ = run_on_bus(split(BUSY_CASE, fractions), cost=0.003)
        ended = [(r.kind, r.event.id, r.at_ns) for r in recs if r.kind != "retained"]
        assert ended == [("applied", "p2#1", 1 * MS), ("rejected", "p1#1", 3 * MS), ("rejected", "p0#1", 3 * MS)]


@st.composite
def busy_instants(draw):
    """A ``b`` applied first makes the ES busy; then events whose arrivals are forced onto instants
    where another expires or arrives, inside that busy time, some arriving already expired."""
    start = draw(st.integers(0, 2))
    out: list[tuple[str, int, int | None, int]] = [("b", start * MS, None, start * MS)]
    created_used = {start}
    for _ in range(draw(st.integers(1, 6))):
        lifetime = draw(st.integers(1, 4))
        expiries = sorted({(c + lt) // MS for _, c, lt, _ in out if lt is not None})
        arrivals = sorted({at // MS for *_, at in out})
        choices = [st.integers(start, start + 12)] + [st.sampled_from(expiries)] * 3 * bool(expiries) + \
            [st.sampled_from(arrivals)] * bool(arrivals)
        at = draw(st.one_of(*choices))
        free = [c for c in range(max(0, at - 8), at + 1) if c not in created_used]
        if not free:
            continue
        created = draw(st.sampled_from(free))
        created_used.add(created)
        out.append((draw(st.sampled_from(["a", "c"])), created * MS, lifetime * MS, at * MS))
    return out


def _expiries_oldest_first(recs) -> None:
    """At each instant the expired events are rejected in queue order (creation times are distinct)."""
    by_instant: dict[int, list[int]] = {}
    for r in recs:
        if isinstance(r, Rejected) and r.reason == EXPIRED:
            by_instant.setdefault(r.at_ns, []).append(r.event.created_ns)
    for at, created in by_instant.items():
        assert created == sorted(created), (at, created)


@settings(max_examples=examples(80, 500), deadline=None)
@given(busy_instants(), st.data(), st.sampled_from([0.003, 0.010]))
@example(BUSY_CASE, None, 0.003).via("the lead's case: p0 expires as p1 arrives expired, mid-cost")
def test_expiries_during_a_cost_follow_the_instants_arrivals_whatever_the_latency(stream, data, cost):
    """Arrivals forced onto expiry instants while the ES pays a cost: the same records over any link
    delays (early, late, or exactly at the arrival), expired events rejected oldest first."""
    if data is None:  # the explicit example: the two sendings of the lead's report
        runs = [run_on_bus(split(stream, f), cost=cost)[0] for f in ([0, 0, 0], [0, 1000, 0])]
    else:
        fraction = st.one_of(st.sampled_from([0, 1000]), st.integers(0, 1000))
        fractions = st.lists(fraction, min_size=len(stream), max_size=len(stream))
        runs = [run_on_bus(split(stream, data.draw(fractions)), cost=cost)[0] for _ in range(2)]
    one, two = runs
    assert [record_dict(r) for r in one] == [record_dict(r) for r in two]
    assert len([r for r in one if r.kind != "retained"]) == len(stream)
    _expiries_oldest_first(one)
