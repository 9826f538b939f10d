"""The same-instant rule (docs/semantics.md §2, "Same instant"): expiry first, arrivals before a decision.

An event whose lifetime ends at ``t`` is rejected in the state the ES held as
``t`` began, whether an event arriving at ``t`` was scheduled (by its link
latency) before or after the ES's expiry timer; and when the ES's processing
cost ends at ``t``, an event arriving at ``t`` is queued before it decides.
The engine driven by :func:`run_deliveries` and the ES on the bus follow the
same rule, so what the dialog is told does not depend on latency.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.afsm.engine import EXPIRED, Applied, Delivery, Engine, Event, Rejected, record_dict, run_deliveries
from homesim.afsm.loader import loads
from homesim.network import LinkModel
from homesim.sim import Simulation
from robot.supervisor import EVENT_CHANNEL, ExecutionSupervisor, event_xml
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


MINIMAL = [("applied", "b", 20 * MS, "s0", "s1")]
EXPIRED_IN_S0 = ("rejected", "a", 20 * MS, "s0", EXPIRED)


def test_minimal_case_run_deliveries_rejects_the_expired_event_in_the_state_it_waited_in():
    """a (created 10 ms, lifetime 10 ms, delivered 10 ms) is dead at 20 ms, when b (created 5 ms) arrives."""
    recs = run_deliveries(Engine(machine()), [Delivery(ev("a", 10, 10), 10 * MS), Delivery(ev("b", 5), 20 * MS)])
    assert outcome(recs) == [EXPIRED_IN_S0, *MINIMAL]


def test_minimal_case_engine_gives_the_same_records_whichever_is_handled_first():
    """Expiry processed before the arrival is queued, or after: the same records, in the same order."""
    first = Engine(machine())
    first.queue(ev("a", 10, 10), 10 * MS)
    first.process(10 * MS)
    recs_a = first.process(20 * MS) + (first.queue(ev("b", 5), 20 * MS) and first.process(20 * MS))
    second = Engine(machine())
    second.queue(ev("a", 10, 10), 10 * MS)
    second.process(10 * MS)
    second.queue(ev("b", 5), 20 * MS)  # queued before the expiry is processed
    recs_b = second.process(20 * MS)
    assert outcome(recs_a) == outcome(recs_b) == [EXPIRED_IN_S0, *MINIMAL]


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
        es.bus.subscribe(EVENT_CHANNEL, lambda m: arrivals.append(m.id))
        for i, (name, created, lifetime, published, delay) in enumerate(events):
            sim.network.set_link(LinkModel(f"l{i}", delay / 1e9, delay / 1e9))
            sim.network.add_host(f"h{i}", link=f"l{i}")
            who = sim.bus.participant(f"p{i}", host=f"h{i}")
            xml = event_xml(name, lifetime=None if lifetime is None else lifetime / 1e9)
            sim.loop.call_at_ns(published, lambda w=who, x=xml, c=created: w.publish(EVENT_CHANNEL, x, created=c / 1e9))
        sim.start()
        sim.run(until=2.0)
        return list(es.engine.history), arrivals
    finally:
        sim.close()


def test_minimal_case_on_the_bus_does_not_depend_on_the_link_latency():
    """b arrives at 20 ms: sent at 5 ms over a 15 ms link (scheduled before the ES's expiry timer) or
    at 19 ms over a 1 ms link (scheduled after it). Both: a expired in s0, then b applied."""
    a = ("a", 10 * MS, 10 * MS, 10 * MS, 0)
    for b in [("b", 5 * MS, None, 5 * MS, 15 * MS), ("b", 5 * MS, None, 19 * MS, 1 * MS)]:
        recs, _ = run_on_bus([a, b])
        assert outcome(recs) == [EXPIRED_IN_S0, *MINIMAL]


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
