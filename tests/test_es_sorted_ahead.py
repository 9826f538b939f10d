"""The ES says when its timestamp ordering acts: an arrival inserted ahead of queued newer events.

An event out of creation order whose newer predecessor has already left the queue (applied
or rejected) is sorted ahead of nothing; only one that goes before events still queued is
counted (``Engine.sorted_ahead``, ``Queued.ahead``) and, on the bus, published on
``/robot/es/sorted`` (the trace, the transcript, the summary's ``es.sorted_ahead``).
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.afsm.engine import Engine, Event
from homesim.afsm.loader import load
from homesim.xmlio import parse_bytes
from robot.supervisor import BIRON_AFSM

MS = 1_000_000
BIRON = load(BIRON_AFSM)


def _greeting(created: int) -> Event:
    return Event("dialog#1", "greeting", "dialog", created, None,
                 parse_bytes('<event name="greeting"><SPEECH><GREETING/></SPEECH></event>'))


def _pp(created: int, n: int = 1) -> Event:
    return Event(f"person_attention#{n}", "potential_partner", "person_attention", created, None,
                 parse_bytes('<event name="potential_partner"><PERSON id="t1" bearing="0.2"/></event>'))


def test_older_partner_is_sorted_ahead_of_the_retained_greeting_and_the_interaction_starts() -> None:
    e = Engine(BIRON)
    e.queue(_greeting(400 * MS), 410 * MS)
    recs = e.process(410 * MS)
    assert [r.kind for r in recs] == ["retained"]  # LookingAround keeps it (category Observing)
    item = e.queue(_pp(100 * MS), 600 * MS)
    assert item.ahead == 1 and e.sorted_ahead == 1
    recs = e.process(600 * MS)
    assert [(r.kind, r.event.name) for r in recs] == [("applied", "potential_partner"), ("applied", "greeting")]
    assert e.state == "Interacting"


def test_out_of_order_after_the_newer_event_left_the_queue_is_not_sorted() -> None:
    e = Engine(BIRON)
    e.queue(_pp(400 * MS, 1), 410 * MS)
    e.process(410 * MS)  # applied: the queue is empty again
    item = e.queue(_pp(300 * MS, 2), 600 * MS)  # older, but nothing newer is queued
    assert item.ahead == 0 and e.sorted_ahead == 0


def test_arrival_order_ablation_never_sorts() -> None:
    e = Engine(BIRON, order="arrival")
    e.queue(_greeting(400 * MS), 410 * MS)
    e.process(410 * MS)
    item = e.queue(_pp(100 * MS), 600 * MS)
    assert item.ahead == 0 and e.sorted_ahead == 0
    e.process(600 * MS)
    assert e.state == "Interacting"  # retention starts it in arrival order too (docs/deployment.md)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(0, 50), min_size=1, max_size=12))
def test_ahead_counts_the_queued_events_created_later(created: list[int]) -> None:
    """Invariant: ``ahead`` is the number of queued events created after the arrival; the queue stays sorted."""
    e = Engine(BIRON)
    now = 1000 * MS
    sorted_ahead = 0
    for n, c in enumerate(created):
        before = [q.event.created_ns for q in e.queued()]
        # events no state applies in LookingAround's category are retained or rejected: use goodbye-free names
        item = e.queue(Event(f"x#{n}", "greeting", "dialog", c * MS, None,
                             parse_bytes('<event name="greeting"><SPEECH><GREETING/></SPEECH></event>')), now)
        assert item.ahead == sum(1 for b in before if b > c * MS)
        sorted_ahead += item.ahead > 0
        keys = [q.event.created_ns for q in e.queued()]
        assert keys == sorted(keys)
    assert e.sorted_ahead == sorted_ahead
