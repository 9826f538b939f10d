"""A small, separately written reference of the ES's queue semantics (docs/semantics.md §2).

Written for clarity, not speed, and from the rules' text rather than from
homesim.afsm.engine: the queue is re-sorted on every look, applicable
transitions are found by walking up the state tree of the model, the set of
retainable names is recomputed from the category's subtree each time, and
guards go through lxml's ``element.xpath`` with XPath's boolean() rules.
"""

from __future__ import annotations

from dataclasses import dataclass

from homesim.afsm.model import Machine, Transition


@dataclass
class RefItem:
    id: str
    name: str
    created: int
    seq: int
    expires: int
    payload: object


def _truthy(v: object) -> bool:
    if isinstance(v, float):
        return not (v != v or v == 0.0)
    return bool(v)


class ReferenceES:
    """What the ES must do; ``process`` returns (kind, event id, state/target, reason) tuples."""

    def __init__(self, m: Machine) -> None:
        self.m = m
        start = m.initial if m.initial is not None else m.roots[0]
        self.state = self._enter(start)
        self.pending: list[RefItem] = []
        self.n = 0

    def _enter(self, sid: str) -> str:
        while self.m.states[sid].children:
            s = self.m.states[sid]
            sid = s.initial or s.children[0]
        return sid

    def queue(self, ev_id: str, name: str, created: int, lifetime: int | None, payload: object) -> None:
        if lifetime is None:
            d = self.m.events.get(name)
            lifetime = d.lifetime_ns if d is not None and d.lifetime_ns is not None else self.m.default_lifetime_ns
        self.n += 1
        self.pending.append(RefItem(ev_id, name, created, self.n, created + lifetime, payload))

    def _find(self, item: RefItem) -> Transition | None:
        sid: str | None = self.state
        while sid is not None:  # the state itself first, then each enclosing state
            for t in self.m.states[sid].transitions:
                if t.event != item.name:
                    continue
                if t.cond is None or (item.payload is not None and _truthy(item.payload.xpath(t.cond))):
                    return t
            sid = self.m.states[sid].parent
        return None

    def retainable(self) -> set[str]:
        """Event names some transition of the current category (or a state inside it) is labelled with."""
        cat = self.m.states[self.state].parent
        if cat is None:
            return set()
        names: set[str] = set()
        todo = [cat]
        while todo:
            sid = todo.pop()
            names.update(t.event for t in self.m.states[sid].transitions)
            todo.extend(self.m.states[sid].children)
        return names

    def process(self, now: int) -> list[tuple]:
        out: list[tuple] = []
        # docs/semantics.md §2 as written: one scan from the oldest; an expired event is rejected where the
        # scan reaches it, in the state the scan has reached (the caller queues every arrival of
        # `now` first: the same-instant rule, docs/semantics.md §2)
        pos = 0
        while True:
            ordered = sorted(self.pending, key=lambda it: (it.created, it.seq))
            if pos >= len(ordered):
                return out
            it = ordered[pos]
            if now >= it.expires:
                self.pending.remove(it)
                out.append(("rejected", it.id, self.state, "expired"))
                continue
            t = self._find(it)
            if t is not None:
                self.pending.remove(it)
                if t.target is not None:
                    self.state = self._enter(t.target)
                out.append(("applied", it.id, self.state, ""))
                pos = 0
                continue
            if it.name in self.retainable():
                pos += 1
                continue
            self.pending.remove(it)
            out.append(("rejected", it.id, self.state, "inapplicable"))

    def pending_ids(self) -> list[str]:
        return [it.id for it in sorted(self.pending, key=lambda it: (it.created, it.seq))]


def reference_run(m: Machine, deliveries: list[tuple[str, str, int, int | None, object, int]], until: int) -> list[tuple]:
    """The records of a whole run, from the rules' text: deliveries are (id, name, created, lifetime, payload, at).

    Time moves from instant to instant: the next arrival or the next expiry of a queued event,
    whichever comes first. At an instant, every event arriving then is queued (in delivery
    order) and then the queue is scanned once (:meth:`ReferenceES.process`). Written without
    :func:`homesim.afsm.engine.run_deliveries`.
    """
    es = ReferenceES(m)
    todo = sorted(range(len(deliveries)), key=lambda k: (deliveries[k][5], k))
    out: list[tuple] = []
    while True:
        expiries = [it.expires for it in es.pending]
        candidates = expiries + ([deliveries[todo[0]][5]] if todo else [])
        if not candidates:
            break
        now = min(candidates)
        if now > until:
            break
        while todo and deliveries[todo[0]][5] == now:
            ev_id, name, created, lifetime, payload, _ = deliveries[todo.pop(0)]
            es.queue(ev_id, name, created, lifetime, payload)
        out += [(now, *rec) for rec in es.process(now)]
    return out
