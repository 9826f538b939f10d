"""The papers' synchronisation example on BIRON's AFSM (engine level, exact virtual times).

A person becomes the communication partner only if the person attention
reports a potential partner and the dialog reports a greeting, both within
their lifetimes, in either order. A radio saying "Hello BIRON" with nobody
there never starts an interaction.
"""

from __future__ import annotations

import pytest

from homesim.afsm.engine import EXPIRED, INAPPLICABLE, Applied, Delivery, Engine, Event, Rejected, Retained, run_deliveries
from homesim.afsm.loader import load
from homesim.xmlio import parse_bytes
from robot.supervisor import BIRON_AFSM

MS = 1_000_000
S = 1_000_000_000


@pytest.fixture(scope="module")
def biron():
    return load(BIRON_AFSM)


def greeting(created: int, n: int = 1) -> Event:
    payload = parse_bytes('<event name="greeting"><SPEECH><GREETING/></SPEECH></event>')
    return Event(f"dialog#{n}", "greeting", "dialog", created, None, payload)


def partner(created: int, n: int = 1, name: str = "potential_partner") -> Event:
    payload = parse_bytes(f'<event name="{name}"><PERSON id="p{n}" bearing="0.2"/></event>')
    return Event(f"attention#{n}", name, "person_attention", created, None, payload)


def applied(recs) -> list[tuple[str, str, str]]:
    return [(r.event.name, r.source_state, r.target_state) for r in recs if isinstance(r, Applied)]


def test_greeting_then_partner_starts_the_interaction(biron):
    e = Engine(biron)
    e.queue(greeting(1 * S), 1 * S + 5 * MS)
    recs = e.process(1 * S + 5 * MS)
    assert [type(r) for r in recs] == [Retained]  # waits for the person attention
    assert recs[0].category == "Observing"
    e.queue(partner(1 * S + 500 * MS), 1 * S + 502 * MS)
    recs = e.process(1 * S + 502 * MS)
    assert applied(recs) == [
        ("potential_partner", "LookingAround", "PotentialPartner"),
        ("greeting", "PotentialPartner", "Interacting"),
    ]
    orders = [(o.kind, o.target, o.name) for o in recs[-1].outputs]
    assert ("order", "person_attention", "interact") in orders
    assert ("condition", "dialog", "partner_found") in orders
    assert len(e) == 0


def test_partner_then_greeting_starts_the_interaction(biron):
    recs = run_deliveries(Engine(biron), [
        Delivery(partner(1 * S), 1 * S + 2 * MS),
        Delivery(greeting(2 * S), 2 * S + 10 * MS),
    ])
    assert applied(recs)[-1] == ("greeting", "PotentialPartner", "Interacting")
    # Fig. 5: the person attention's data goes to the dialog, copied from the event.
    info = recs[0].outputs[0]
    assert (info.kind, info.target, info.name) == ("condition", "dialog", "person_info")
    (pname, nodes), = info.params
    assert pname == "person" and nodes[0].get("id") == "p1"


def test_radio_greeting_with_nobody_there_expires_exactly_at_its_lifetime(biron):
    e = Engine(biron)
    created = 4 * S
    recs = run_deliveries(e, [Delivery(greeting(created), created + 15 * MS)])
    rej = [r for r in recs if isinstance(r, Rejected)]
    assert len(rej) == 1 and rej[0].reason == EXPIRED
    lifetime = biron.events["greeting"].lifetime_ns
    assert rej[0].at_ns == created + lifetime  # never later
    assert e.state == "LookingAround"
    assert not applied(recs)


def test_partner_lost_before_the_greeting_means_no_interaction(biron):
    e = Engine(biron)
    recs = run_deliveries(e, [
        Delivery(partner(1 * S), 1 * S + 2 * MS),
        Delivery(partner(1 * S + 800 * MS, 2, "potential_partner_lost"), 1 * S + 802 * MS),
        Delivery(greeting(2 * S), 2 * S + 10 * MS),
    ])
    assert e.state == "LookingAround"
    assert [(r.event.name, r.reason) for r in recs if isinstance(r, Rejected)] == [("greeting", EXPIRED)]


def test_partner_delivered_late_is_put_before_the_newer_greeting(biron):
    """Latency: the partner event was created first but arrives after the greeting."""
    e = Engine(biron)
    e.queue(greeting(1 * S + 100 * MS), 1 * S + 102 * MS)  # LAN
    e.process(1 * S + 102 * MS)
    e.queue(partner(1 * S), 1 * S + 300 * MS)  # over a slow WLAN
    assert [q.event.name for q in e.queued()] == ["potential_partner", "greeting"]
    recs = e.process(1 * S + 300 * MS)
    assert applied(recs) == [
        ("potential_partner", "LookingAround", "PotentialPartner"),
        ("greeting", "PotentialPartner", "Interacting"),
    ]


def test_greeting_and_partner_too_far_apart_do_not_belong_together(biron):
    """The greeting's lifetime bounds the interval: a partner 3 s later is too late."""
    e = Engine(biron)
    recs = run_deliveries(e, [
        Delivery(greeting(1 * S), 1 * S + 5 * MS),
        Delivery(partner(4 * S + 1), 4 * S + 3 * MS),
    ])
    assert e.state == "PotentialPartner"
    assert [(r.event.name, r.reason) for r in recs if isinstance(r, Rejected)] == [("greeting", EXPIRED)]


def test_an_object_taught_while_following_is_rejected_at_once(biron):
    """Following is a category of its own (Leading): teaching does not apply there, so the ES rejects
    it at once (the dialog says "say stop first") instead of keeping it silently for its lifetime."""
    e = Engine(biron)
    e.queue(partner(0), 1 * MS)
    e.queue(greeting(10 * MS), 11 * MS)
    e.queue(Event("dialog#2", "follow", "dialog", 1 * S), 1 * S)
    e.process(1 * S)
    assert e.state == "Following"
    teach = Event("dialog#3", "object_teaching", "dialog", 2 * S, None,
                  parse_bytes('<event name="object_teaching"><SPEECH><OBJECT type="cup"/></SPEECH></event>'))
    e.queue(teach, 2 * S)
    (rec,) = e.process(2 * S)
    assert isinstance(rec, Rejected) and rec.reason == INAPPLICABLE and "Following" in rec.detail
    e.queue(Event("dialog#4", "stop", "dialog", 5 * S), 5 * S)
    assert applied(e.process(5 * S)) == [("stop", "Following", "Interacting")]


def test_a_dialog_instruction_while_navigating_is_rejected_at_once(biron):
    e = Engine(biron)
    e.queue(partner(0), 1 * MS)
    e.queue(greeting(10 * MS), 11 * MS)
    e.queue(Event("dialog#2", "goto", "dialog", 1 * S), 1 * S)
    e.process(1 * S)
    assert e.state == "Navigating"
    e.queue(Event("dialog#3", "follow", "dialog", 2 * S), 2 * S)
    (rec,) = e.process(2 * S)
    assert isinstance(rec, Rejected) and rec.reason == INAPPLICABLE and "Navigating" in rec.detail


def test_a_missing_heartbeat_fails_perceptibly_from_any_state(biron):
    e = Engine(biron)
    e.queue(partner(0), 1 * MS)
    e.queue(greeting(10 * MS), 11 * MS)
    e.queue(Event("dialog#2", "follow", "dialog", 1 * S), 1 * S)
    e.process(1 * S)
    failed = Event("monitor#1", "module_failed", "monitor", 2 * S, None, parse_bytes('<module_failed module="laser"/>'))
    e.queue(failed, 2 * S)
    (rec,) = e.process(2 * S)
    assert rec.target_state == "TechnicalFailure"
    cond = [o for o in rec.outputs if o.kind == "condition"][0]
    assert cond.name == "technical_failure" and cond.params[0] == ("module", ("laser",))
