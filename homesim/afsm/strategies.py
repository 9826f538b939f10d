"""Hypothesis strategies for AFSMs and event streams, public so users can test their own machines.

* :func:`machines` draws valid random machines: leaves, categories (nested
  up to a few levels), transitions on a small event alphabet with optional
  guards on the payload (``@ok='1'``), targetless transitions, orders and
  conditions with parameters copied from the payload. Unreachable states
  are pruned, so every drawn machine passes :func:`~homesim.afsm.model.validate`.
* :func:`events` / :func:`event_streams` draw events with random creation
  times, lifetimes (or none: the machine's default applies) and delivery
  delays, as :class:`~homesim.afsm.engine.Delivery` lists ready for
  :func:`~homesim.afsm.engine.run_deliveries`.

Payloads look like ``<event ok="1" v="3"/>``; use ``payload=`` to supply
your own strategy. Example::

    from hypothesis import given
    from homesim.afsm import load
    from homesim.afsm.strategies import event_streams

    M = load("machine.scxml")

    @given(event_streams(M.event_names()))
    def test_never_stuck(stream): ...
"""

from __future__ import annotations

from collections.abc import Sequence

from hypothesis import strategies as st
from lxml import etree

from .engine import Delivery, Event
from .model import CONDITION, ORDER, Machine, ModuleDecl, Param, Send, State, Transition, reachable_leaves, validate

#: Modules every random machine declares: one above, one below the ES.
RANDOM_MODULES = {"dialog": "deliberative", "attention": "reactive"}
#: The default event alphabet of random machines.
EVENT_NAMES = ("a", "b", "c", "d")
GUARDS = ("@ok='1'", "@ok='0'")
MS = 1_000_000


def _sends(events: Sequence[str]) -> st.SearchStrategy[tuple[Send, ...]]:
    one = st.builds(
        lambda up, name, with_param: Send(
            CONDITION if up else ORDER,
            "dialog" if up else "attention",
            f"{'c' if up else 'o'}_{name}",
            (Param("v", "@v"), Param("all", ".")) if with_param else (),
        ),
        st.booleans(),
        st.sampled_from(list(events)),
        st.booleans(),
    )
    return st.lists(one, max_size=2).map(tuple)


@st.composite
def machines(
    draw: st.DrawFn,
    *,
    max_leaves: int = 6,
    max_categories: int = 3,
    events: Sequence[str] = EVENT_NAMES,
    guards: bool = True,
    max_transitions: int = 3,
) -> Machine:
    """A valid random machine (reachable states only, categories possibly nested)."""
    n_leaves = draw(st.integers(1, max_leaves))
    n_cats = draw(st.integers(0, max_categories))
    cat_parent = [draw(st.sampled_from([None, *range(j)])) if j else None for j in range(n_cats)]
    leaf_parent = [draw(st.sampled_from([None, *range(n_cats)])) for _ in range(n_leaves)]
    cats = [f"C{j}" for j in range(n_cats)]
    leaves = [f"S{i}" for i in range(n_leaves)]
    all_ids = leaves + cats
    cond = st.sampled_from([None, *GUARDS]) if guards else st.none()
    target = st.one_of(st.sampled_from(all_ids), st.none()) if all_ids else st.none()
    trans = st.lists(
        st.builds(Transition, st.sampled_from(list(events)), target, cond, _sends(events)),
        max_size=max_transitions,
    )
    transitions = {sid: draw(trans) for sid in all_ids}
    # A spine makes every leaf reachable: leaf i is the target of a transition
    # from some earlier leaf (or the category around it), inserted at a random place.
    for i in range(1, n_leaves):
        src = leaves[draw(st.integers(0, i - 1))]
        owner = src if leaf_parent[int(src[1:])] is None or draw(st.booleans()) else cats[leaf_parent[int(src[1:])]]
        t = Transition(draw(st.sampled_from(list(events))), leaves[i], draw(cond), draw(_sends(events)))
        lst = transitions[owner]
        lst.insert(draw(st.integers(0, len(lst))), t)
    initial = leaves[0]

    # Build in document order: a container's children are its categories, then its leaves.
    states: dict[str, State] = {}
    roots: list[str] = []

    def add(sid: str, parent: str | None) -> None:
        states[sid] = State(sid, parent, [], list(transitions[sid]))
        if parent is None:
            roots.append(sid)
        else:
            states[parent].children.append(sid)
        if sid.startswith("C"):
            j = int(sid[1:])
            for k in range(n_cats):
                if cat_parent[k] == j:
                    add(cats[k], sid)
            for i in range(n_leaves):
                if leaf_parent[i] == j:
                    add(leaves[i], sid)

    for k in range(n_cats):
        if cat_parent[k] is None:
            add(cats[k], None)
    for i in range(n_leaves):
        if leaf_parent[i] is None:
            add(leaves[i], None)
    m = Machine("random", states, roots, initial=initial,
                modules={n: ModuleDecl(n, layer) for n, layer in RANDOM_MODULES.items()})
    _drop_leafless_categories(m)
    _prune_unreachable(m)
    problems = validate(m)
    assert not problems, [str(p) for p in problems]
    return m


def _remove(m: Machine, sid: str) -> None:
    st_ = m.states.pop(sid)
    if st_.parent is None:
        m.roots.remove(sid)
    else:
        m.states[st_.parent].children.remove(sid)


def _drop_leafless_categories(m: Machine) -> None:
    """Categories with no leaf inside would be leaves: make them so by dropping them."""
    changed = True
    while changed:
        changed = False
        for sid in list(m.states):
            s = m.states[sid]
            if sid.startswith("C") and not s.children:
                _remove(m, sid)
                changed = True
    live = set(m.states)
    for s in m.states.values():
        s.transitions = [t for t in s.transitions if t.target is None or t.target in live]


def _prune_unreachable(m: Machine) -> None:
    reach = set(reachable_leaves(m))
    for leaf in m.leaves():
        if leaf not in reach:
            _remove(m, leaf)
    _drop_leafless_categories(m)


def payloads() -> st.SearchStrategy[etree._Element]:
    """Small payloads ``<event ok=".." v=".."/>`` that random guards and params read."""
    return st.builds(lambda ok, v: etree.Element("event", ok="1" if ok else "0", v=str(v)),
                     st.booleans(), st.integers(0, 9))


@st.composite
def event_streams(
    draw: st.DrawFn,
    names: Sequence[str] = EVENT_NAMES,
    *,
    max_events: int = 20,
    horizon_ns: int = 5_000 * MS,
    max_lifetime_ns: int = 3_000 * MS,
    max_delay_ns: int = 800 * MS,
    payload: st.SearchStrategy[etree._Element] | None = None,
    sources: Sequence[str] = ("dialog", "attention"),
) -> list[Delivery]:
    """Events created at random times with random lifetimes, delivered after random delays.

    A delivery may overtake an older event (latency), so creation order and
    arrival order differ. Ids are ``<source>#<n>`` (unique in the stream).
    """
    pay = payload if payload is not None else payloads()
    n = draw(st.integers(0, max_events))
    out = []
    for k in range(n):
        src = draw(st.sampled_from(list(sources)))
        created = draw(st.integers(0, horizon_ns))
        lifetime = draw(st.one_of(st.none(), st.integers(1, max_lifetime_ns)))
        delay = draw(st.integers(0, max_delay_ns))
        ev = Event(f"{src}#{k + 1}", draw(st.sampled_from(list(names))), src, created, lifetime, draw(pay))
        out.append(Delivery(ev, created + delay))
    return out
