"""What the ES's creation-time ordering decides, on BIRON's AFSM (engine level, exact virtual times).

The ES sorts its queue by creation time (docs/semantics.md §2). ``Engine(order="arrival")``
is the ablation: the same engine with a queue in arrival order (lifetimes still from
creation). Comparing the two over any latencies shows what the sorting decides:

- a greeting that overtakes the potential partner it belongs to starts the interaction
  either way: in LookingAround the greeting is *retained* (the category Observing has a
  transition on it), so whichever order the queue has, the potential partner moves the ES
  to PotentialPartner and the waiting greeting is applied next. Retention and lifetimes
  synchronise the pair; the order does not (docs/deployment.md);
- the order decides when the attention's events that the greeting overtook are more than
  one: it pairs the greeting with the *latest* potential partner created before it (its
  PERSON data, es:with); in arrival order the greeting, first in the queue, is applied
  right after the first potential partner, whatever came after it. (A
  ``potential_partner_lost`` older than the greeting could keep it from a stale potential
  partner only if that partner were still alive on arrival; the person attention reports
  the loss 1.5 s after its last potential partner, which is that event's lifetime, so it
  cannot happen with BIRON's attention.)
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.afsm.engine import Applied, Delivery, Engine, Event, run_deliveries
from homesim.afsm.loader import load
from homesim.errors import SupervisorError
from homesim.xmlio import parse_bytes
from robot.supervisor import BIRON_AFSM

from .conftest import examples

MS = 1_000_000
S = 1_000_000_000
BIRON = load(BIRON_AFSM)


def greeting(created: int) -> Event:
    return Event("dialog#1", "greeting", "dialog", created, None,
                 parse_bytes('<event name="greeting"><SPEECH><GREETING/></SPEECH></event>'))


def attention(created: int, n: int, name: str = "potential_partner", person: str = "t1") -> Event:
    return Event(f"person_attention#{n}", name, "person_attention", created, None,
                 parse_bytes(f'<event name="{name}"><PERSON id="{person}" bearing="0.2"/></event>'))


def replay(deliveries: list[Delivery], order: str) -> tuple[bool, Applied | None]:
    """Whether the interaction started, and the greeting's transition, with the queue in ``order``."""
    recs = run_deliveries(Engine(BIRON, order=order), deliveries)
    start = next((r for r in recs if isinstance(r, Applied) and r.event.name == "greeting"
                  and r.target_state == "Interacting"), None)
    return start is not None, start


def partner_of(start: Applied) -> str:
    out = next(o for o in start.outputs if o.name == "partner_found")
    nodes = dict(out.params)["partner"]
    return next(n.get("id") for n in nodes if n.tag == "PERSON")


def test_an_unknown_order_is_refused():
    with pytest.raises(SupervisorError, match="unknown queue order"):
        Engine(BIRON, order="random")


@settings(max_examples=examples(60, 300), deadline=None)
@given(pp_at=st.integers(0, 3000), pp_lat=st.integers(0, 2500), g_at=st.integers(0, 3000), g_lat=st.integers(0, 2500))
def test_one_potential_partner_and_a_greeting_start_alike_whatever_the_queue_order(pp_at, pp_lat, g_at, g_lat):
    """Any creation times and latencies: sorted or not, the pair starts the interaction in the same cases."""
    deliveries = [Delivery(attention(pp_at * MS, 1), (pp_at + pp_lat) * MS), Delivery(greeting(g_at * MS), (g_at + g_lat) * MS)]
    assert replay(deliveries, "created")[0] == replay(deliveries, "arrival")[0]


@settings(max_examples=examples(60, 300), deadline=None)
@given(kinds=st.lists(st.sampled_from(["potential_partner", "potential_partner_lost"]), min_size=1, max_size=5),
       gaps=st.lists(st.integers(1, 1500), min_size=5, max_size=5), lats=st.lists(st.integers(0, 2500), min_size=5, max_size=5),
       g_at=st.integers(0, 6000), g_lat=st.integers(0, 2500))
def test_with_the_attention_fifo_the_sorted_queue_never_starts_where_arrival_order_would_not(kinds, gaps, lats, g_at, g_lat):
    """The person attention's events arrive in their creation order (one connection, FIFO); the greeting
    anywhere among them. Whenever the sorted ES starts the interaction, the arrival-ordered one does too:
    sorting can keep a greeting from a potential partner that was already lost, never make one start."""
    deliveries, t, arrive = [], 0, 0
    for n, (kind, gap, lat) in enumerate(zip(kinds, gaps, lats)):
        t += gap
        arrive = max(arrive, t + lat)  # FIFO per sender/receiver pair
        deliveries.append(Delivery(attention(t * MS, n, kind), arrive * MS))
    deliveries.append(Delivery(greeting(g_at * MS), (g_at + g_lat) * MS))
    if replay(deliveries, "created")[0]:
        assert replay(deliveries, "arrival")[0]


def test_the_order_decides_which_potential_partner_a_greeting_is_paired_with():
    """Two people in turn are potential partners (Anna, then Ben, who greets); their events reach the ES
    together after the greeting (one connection, held up behind a resent frame). Sorted, the greeting
    goes with Ben, the potential partner when it was made; in arrival order with Anna."""
    d = [
        Delivery(greeting(2_000 * MS), 2_005 * MS),
        Delivery(attention(1_000 * MS, 1, person="anna"), 2_400 * MS),
        Delivery(attention(1_600 * MS, 2, person="ben"), 2_400 * MS),
    ]
    (started, s_sorted), (started_a, s_arrival) = replay(d, "created"), replay(d, "arrival")
    assert started and started_a
    assert partner_of(s_sorted) == "ben" and partner_of(s_arrival) == "anna"

