"""The execution supervisor's event queue and AFSM processing (docs/semantics.md §2), time injected.

Pure: no bus, no asyncio, no clock. The caller passes virtual time as
integer nanoseconds; :meth:`Engine.queue` only enqueues, :meth:`Engine.process`
runs the scan and returns records of what happened (sismic's
``queue``/``execute_once``). A supervisor module on the bus wraps it.

The rules, exactly:

* The queue is ordered by creation time; ties keep arrival order. An event
  created earlier but delivered later is inserted before newer ones.
* :meth:`process` scans from the oldest event. For each event: (1) if
  ``now >= created + lifetime`` it is removed and rejected as *expired* (in
  the state the scan has reached); (2) if the current state (or, failing that, an enclosing state, as
  in SCXML) has a transition on its name whose guard holds, it is removed,
  the transition's sends are evaluated, the state changes, and the scan
  restarts from the oldest; (3) else if any transition on its name is
  written on the current *category* (the innermost compound state around
  the current state) or on any state inside it, it is *retained*; (4) else
  it is removed and rejected as *inapplicable*.
* The same-instant rule (``docs/semantics.md`` §2): the caller queues every
  event arriving at an instant ``t`` before it processes ``t`` (expiries of
  ``t`` included); the scan then takes the oldest first, so an older event
  arriving at the very instant a newer one expires is applied first and the
  newer one is rejected in the state that transition left. Which arrival's
  delivery was scheduled first (link latency) changes nothing.
  :func:`run_deliveries` and the supervisor do so.
* :meth:`next_deadline` is the earliest expiry among queued events: call
  :meth:`process` then, and expired events are rejected exactly at their
  expiry.
* ``process(now, max_applied=1)`` stops after one transition, for a caller
  whose transitions take time (the supervisor's cost): it calls again when
  it can decide; :meth:`expire` is step 1 alone, for the time in between.
* An arrival created before events still queued is inserted ahead of them;
  :attr:`Queued.ahead` says of how many, :attr:`Engine.sorted_ahead` counts
  such arrivals (an arrival out of creation order whose newer predecessor has
  already left the queue is sorted ahead of nothing).
* Conservation: ``stats()['queued'] == applied + expired + inapplicable +
  len(queue)`` always holds; an id cannot be queued twice while queued.
* ``Engine(order="arrival")`` is an ablation, not the ES: the queue keeps
  arrival order (lifetimes still count from creation), so a study or a test
  can ask what the creation-time ordering decides in a run
  (docs/deployment.md: for a greeting and the potential partner it overtook,
  nothing; for which potential partner a greeting is paired with when several
  arrive after it, or for a stale ``potential_partner_lost``, everything).

How it fails: time going backwards raises :class:`ClockError`; a duplicate
queued id raises :class:`SupervisorError`; a replacement or extension that
is invalid, or that would remove the current state, raises
:class:`AFSMModificationRefused` and leaves everything as it was.
"""

from __future__ import annotations

import itertools
import math
from bisect import bisect_right
from collections import deque
from collections.abc import Callable
from copy import deepcopy
from dataclasses import dataclass, field
from typing import Any, NamedTuple

from lxml import etree

from ..errors import AFSMModificationRefused, AFSMProblems, ClockError, SupervisorError
from .model import MAX_LIFETIME_NS, Machine, Send, Transition, _lifetime_ok, merge, validate

#: Largest event payload (elements, the root included) the ES evaluates guards
#: on. With the model's limit of MAX_XPATH_DEEP_STEPS (2) descendant steps per
#: guard, a guard visits at most 256**2 nodes: its cost is bounded.
MAX_PAYLOAD_ELEMENTS = 256


def payload_problem(payload: etree._Element | None) -> str | None:
    """None when ``payload`` is small enough for guards, else why not (counts at most one element too many)."""
    if payload is None:
        return None
    if len(payload) == 0:  # no children (len counts comments and PIs too): the root alone
        return None
    if len(list(itertools.islice(payload.iter(), MAX_PAYLOAD_ELEMENTS + 1))) > MAX_PAYLOAD_ELEMENTS:
        return f"event payload has more than {MAX_PAYLOAD_ELEMENTS} elements (rule: guards run on small payloads)"
    return None

EXPIRED = "expired"
INAPPLICABLE = "inapplicable"
WAITING = "waiting"
RETAINED = "retained"

ParamValue = str | tuple[Any, ...]
#: One stored item (es:store): an element (a detached copy) or a string.
ParamValueItem = Any


@dataclass(slots=True)
class Event:
    """An event for the ES. ``lifetime_ns`` None: the machine's default for ``name``."""

    id: str
    name: str
    source: str
    created_ns: int
    lifetime_ns: int | None = None
    payload: etree._Element | None = None


@dataclass(slots=True)
class Queued:
    """An event in the queue: its arrival sequence, expiry and status."""

    event: Event
    seq: int
    arrived_ns: int
    expires_ns: int
    status: str = WAITING
    retained_in: str | None = None  # the state it was last retained in
    #: Queued events it was inserted ahead of when it arrived (created earlier than they were): the
    #: ES's timestamp ordering at work. Always 0 with ``order="arrival"``.
    ahead: int = 0

    @property
    def key(self) -> tuple[int, int]:
        return (self.event.created_ns, self.seq)


class Output(NamedTuple):
    """An order or condition to send: parameters already copied out of the event.

    Parameter values are strings, or tuples of the nodes/strings the XPath
    selected (nodes still belong to the event payload: copy before reuse).
    """

    kind: str
    target: str
    name: str
    params: tuple[tuple[str, ParamValue], ...]
    event_id: str


class Applied(NamedTuple):
    """An event took a transition (records are immutable: observers cannot change them)."""

    at_ns: int
    event: Event
    source_state: str
    target_state: str
    owner: str  # the state the transition is written on
    outputs: tuple[Output, ...]
    kind: str = "applied"


class Rejected(NamedTuple):
    """An event left the queue unapplied; ``reason`` is EXPIRED or INAPPLICABLE."""

    at_ns: int
    event: Event
    state: str
    reason: str
    detail: str
    kind: str = "rejected"


class Retained(NamedTuple):
    """An event was kept in the queue because the current category can use it (first time per state)."""

    at_ns: int
    event: Event
    state: str
    category: str
    kind: str = "retained"


Record = Applied | Rejected | Retained


def _xpath_true(value: Any) -> bool:
    """XPath's boolean() of an evaluation result."""
    if isinstance(value, bool):
        return value
    if isinstance(value, float):
        return value == value and value != 0.0
    if isinstance(value, list):
        return bool(value)
    return bool(value)


@dataclass(frozen=True, slots=True)
class _Compiled:
    transition: Transition
    owner: str
    target_leaf: str  # the leaf entered (the source leaf for targetless)
    guard: Callable[[Any], Any] | None
    sends: tuple[tuple[Send, tuple[tuple[str, Callable[[Any], Any]], ...]], ...]
    # es:store: (name, XPath, append); es:with per send: per parameter the stored names ((): none)
    stores: tuple[tuple[str, Callable[[Any], Any], bool], ...] = ()
    withs: tuple[tuple[tuple[str, ...], ...], ...] = ()


class _Tables:
    """Per-leaf look-up tables of a machine (built once per machine version)."""

    def __init__(self, m: Machine) -> None:
        self.machine = m
        xp_cache: dict[str, Callable[[Any], Any]] = {}

        def xp(expr: str) -> Callable[[Any], Any]:
            f = xp_cache.get(expr)
            if f is None:
                f = etree.XPath(expr)
                xp_cache[expr] = f
            return f

        self.candidates: dict[str, dict[str, tuple[_Compiled, ...]]] = {}
        self.retain: dict[str, frozenset[str]] = {}
        self.category: dict[str, str | None] = {}
        by_category: dict[str, frozenset[str]] = {}
        for leaf in m.leaves():
            table: dict[str, list[_Compiled]] = {}
            for owner in m.ancestors(leaf):  # innermost first: the state's own transitions win
                for t in m.states[owner].transitions:
                    target = leaf if t.target is None else m.resolve_leaf(t.target)
                    sends = tuple((s, tuple((p.name, xp(p.expr)) for p in s.params)) for s in t.sends)
                    stores = tuple((sto.name, xp(sto.expr), sto.append) for sto in t.stores)
                    withs = tuple(tuple(p.stored for p in s.params) for s in t.sends)
                    comp = _Compiled(t, owner, target, xp(t.cond) if t.cond is not None else None, sends, stores,
                                     withs if any(w for ws in withs for w in ws) else ())
                    table.setdefault(t.event, []).append(comp)
            self.candidates[leaf] = {k: tuple(v) for k, v in table.items()}
            cat = m.category_of(leaf)
            self.category[leaf] = cat
            if cat is None:
                self.retain[leaf] = frozenset()
                continue
            names = by_category.get(cat)
            if names is None:  # once per category, not per leaf (setup stays linear)
                names = frozenset(t.event for sid in [cat, *m.descendants(cat)] for t in m.states[sid].transitions)
                by_category[cat] = names
            self.retain[leaf] = names


class Engine:
    """An AFSM and its event queue. Deterministic: same calls, same records."""

    def __init__(self, machine: Machine, *, history: int = 1000, order: str = "created") -> None:
        if order not in ORDERS:
            raise SupervisorError(f"unknown queue order {order!r}: use one of {ORDERS}")
        self._key = _key if order == "created" else _arrival_key
        self.order = order
        problems = validate(machine)
        if problems:
            raise AFSMProblems(problems)
        self._tables = _Tables(machine.copy())  # the caller's machine stays the caller's
        self.state = machine.initial_leaf()
        self._queue: list[Queued] = []
        self._ids: dict[str, Queued] = {}
        self._seq = 0
        self._now = -math.inf
        self.history: deque[Record] = deque(maxlen=history)
        self.counts = {"queued": 0, "applied": 0, "expired": 0, "inapplicable": 0}
        #: Arrivals inserted ahead of at least one queued event (:attr:`Queued.ahead` > 0).
        self.sorted_ahead = 0
        #: es:store: data copied out of applied events, by name (survives replace/extend).
        self.stored: dict[str, tuple[ParamValueItem, ...]] = {}

    # ------------------------------------------------------------- queries
    @property
    def machine(self) -> Machine:
        """A copy of the running machine (changing it changes nothing here: use replace/extend)."""
        return self._tables.machine.copy()

    @property
    def machine_name(self) -> str:
        """The running machine's name (cheap: no copy)."""
        return self._tables.machine.name

    @property
    def category(self) -> str | None:
        """The category (innermost compound state) of the current state, if any."""
        return self._tables.category[self.state]

    def __len__(self) -> int:
        return len(self._queue)

    def queued(self) -> list[Queued]:
        """The queue, oldest first (a copy; the items are live, do not modify)."""
        return list(self._queue)

    def accepts(self) -> tuple[list[str], list[str]]:
        """Events the current state applies now, and events it would retain (sorted names).

        What the robot can do now, for self-explanation: an applicable event
        has a transition from the current state or a state containing it; a
        retained one waits for another state of the category.
        """
        applies = sorted(self._tables.candidates[self.state])
        waits = sorted(self._tables.retain[self.state] - set(applies))
        return applies, waits

    def next_deadline(self) -> int | None:
        """Earliest expiry (ns) among queued events; None when the queue is empty."""
        if not self._queue:
            return None
        return min(q.expires_ns for q in self._queue)

    def stats(self) -> dict[str, int]:
        """Counts of events queued, applied, expired, inapplicable, and still waiting."""
        out = dict(self.counts)
        out["pending"] = len(self._queue)
        return out

    # ----------------------------------------------------------- time guard
    def _advance(self, now_ns: int) -> None:
        if now_ns < self._now:
            raise ClockError(f"time can't go backwards: engine is at {self._now} ns, asked for {now_ns} ns")
        self._now = now_ns

    # --------------------------------------------------------------- queue
    def queue(self, event: Event, now_ns: int, *, payload_checked: bool = False) -> Queued:
        """Insert ``event`` (arriving at ``now_ns``) by creation time; nothing is processed.

        ``payload_checked``: the caller has already found the payload small
        enough with :func:`payload_problem` (the supervisor does, to report a
        too large payload as a dropped message); it is not counted again.
        """
        self._advance(now_ns)
        if event.id in self._ids:
            raise SupervisorError(f"event {event.id!r} is already queued (an event is handled exactly once)")
        too_big = None if payload_checked else payload_problem(event.payload)
        if too_big is not None:
            raise SupervisorError(f"event {event.id!r} ({event.name}): {too_big}")
        lifetime = event.lifetime_ns
        if lifetime is not None and not _lifetime_ok(lifetime):
            raise SupervisorError(f"event {event.id!r} ({event.name}): lifetime {lifetime!r:.40} ns is not an integer "
                                  f"in 1 to {MAX_LIFETIME_NS} ns (an hour)")
        if lifetime is None:
            lifetime = self._tables.machine.lifetime_ns(event.name)
            # the caller's event is left as it was; records carry this copy
            event = Event(event.id, event.name, event.source, event.created_ns, lifetime, event.payload)
        self._seq += 1
        item = Queued(event, self._seq, now_ns, event.created_ns + lifetime)
        q = self._queue
        if q and self._key(q[-1]) > self._key(item):  # it goes before a queued event: sorted ahead
            pos = bisect_right(q, self._key(item), key=self._key)
            q.insert(pos, item)
            item.ahead = len(q) - 1 - pos
            self.sorted_ahead += 1
        else:
            q.append(item)
        self._ids[event.id] = item
        self.counts["queued"] += 1
        return item

    # ------------------------------------------------------------- process
    def process(self, now_ns: int, *, max_applied: int | None = None) -> list[Record]:
        """Scan the queue at ``now_ns`` per docs/semantics.md §2; return what happened, in order.

        ``max_applied`` stops the scan right after that many transitions (the
        scan would restart from the oldest event anyway): a caller whose
        transitions take time (the supervisor's processing cost) calls again
        at the virtual time the next decision can be taken.
        """
        self._advance(now_ns)
        records: list[Record] = []
        if not self._queue:
            return records
        applied = 0
        q = self._queue
        tables = self._tables
        i = 0
        while i < len(q):
            item = q[i]
            ev = item.event
            if now_ns >= item.expires_ns:  # (1) expired: rejected in the state the scan has reached
                del q[i]
                records.append(self._reject(item, now_ns, EXPIRED, f"lifetime ended at {item.expires_ns} ns"))
                continue
            comp = None
            cands = tables.candidates[self.state].get(ev.name)
            if cands is not None:
                payload = ev.payload
                for c in cands:
                    g = c.guard
                    if g is None or (payload is not None and _xpath_true(g(payload))):
                        comp = c
                        break
            if comp is not None:
                del q[i]
                records.append(self._apply(item, comp, now_ns))
                applied += 1
                if max_applied is not None and applied >= max_applied:
                    return records
                i = 0
                continue
            if ev.name in tables.retain[self.state]:
                if item.status != RETAINED or item.retained_in != self.state:
                    item.status = RETAINED
                    item.retained_in = self.state
                    rec = Retained(now_ns, ev, self.state, tables.category[self.state])  # type: ignore[arg-type]
                    records.append(rec)
                    self.history.append(rec)
                i += 1
                continue
            del q[i]
            why = "a guard does not hold" if cands else "no transition on it"
            records.append(self._reject(item, now_ns, INAPPLICABLE, f"not applicable in state {self.state!r}: {why}"))
        return records

    def expire(self, now_ns: int) -> list[Rejected]:
        """Only step 1 of the scan: reject (expired) every event with ``now >= created + lifetime``.

        For a caller that cannot take decisions now (the supervisor while it
        pays a transition's processing cost) but must still reject expired
        events exactly at their expiry. Oldest first; nothing else changes.
        """
        if now_ns < self._now:
            self._advance(now_ns)  # raises
        self._now = now_ns
        q = self._queue
        if not q or min(item.expires_ns for item in q) > now_ns:
            return []
        out: list[Rejected] = []
        keep: list[Queued] = []
        for item in q:
            if now_ns >= item.expires_ns:
                out.append(self._reject(item, now_ns, EXPIRED, f"lifetime ended at {item.expires_ns} ns"))
            else:
                keep.append(item)
        q[:] = keep
        return out

    def _reject(self, item: Queued, now_ns: int, reason: str, detail: str) -> Rejected:
        del self._ids[item.event.id]
        self.counts[reason] += 1
        rec = Rejected(now_ns, item.event, self.state, reason, detail)
        self.history.append(rec)
        return rec

    def _apply(self, item: Queued, comp: _Compiled, now_ns: int) -> Applied:
        ev = item.event
        del self._ids[ev.id]
        self.counts["applied"] += 1
        outputs: tuple[Output, ...] = ()
        if comp.sends:
            payload = ev.payload
            if comp.withs:
                outputs = tuple([
                    Output(s.kind, s.target, s.name, tuple([
                        (name, self._with(ws, _param_value(f, payload))) for (name, f), ws in zip(params, withs)]), ev.id)
                    for (s, params), withs in zip(comp.sends, comp.withs)
                ])
            else:
                outputs = tuple([
                    Output(s.kind, s.target, s.name, tuple([(name, _param_value(f, payload)) for name, f in params]), ev.id)
                    for s, params in comp.sends
                ])
        if comp.stores:
            for name, f, append in comp.stores:
                value = _param_value(f, ev.payload)
                items = tuple(deepcopy(x) if isinstance(x, etree._Element) else x
                              for x in (value if isinstance(value, tuple) else ((value,) if value else ())))
                self.stored[name] = (self.stored.get(name, ()) + items) if append else items
        rec = Applied(now_ns, ev, self.state, comp.target_leaf, comp.owner, outputs)
        self.state = comp.target_leaf
        self.history.append(rec)
        return rec

    def _with(self, names: tuple[str, ...], value: ParamValue) -> ParamValue:
        """``value`` after the stored data ``names`` (es:with), concatenated in order."""
        if not names:
            return value
        items: tuple[ParamValueItem, ...] = ()
        for n in names:
            items += self.stored.get(n, ())
        return items + (value if isinstance(value, tuple) else ((value,) if value else ()))

    # -------------------------------------------------------- modification
    def replace(self, machine: Machine) -> None:
        """Swap in ``machine`` (validated first); the queue survives, retention is re-decided.

        Refused, with the reason, if the machine is invalid or if the current
        state would not exist (as a leaf) afterwards.
        """
        problems = validate(machine)
        if problems:
            raise AFSMModificationRefused(
                f"refused: the new machine is invalid: {problems[0].message}"
                + (f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""),
                source=problems[0].source, line=problems[0].line, element=problems[0].element,
            )
        st = machine.states.get(self.state)
        if st is None or st.children:
            what = "would not exist" if st is None else "would become a category, not a state"
            raise AFSMModificationRefused(
                f"refused: the current state {self.state!r} {what} after the change", source=machine.source
            )
        self._tables = _Tables(machine.copy())
        for item in self._queue:
            item.status = WAITING
            item.retained_in = None

    def extend(self, extension: Machine) -> Machine:
        """Merge states/transitions of ``extension`` into the running machine (see :func:`merge`)."""
        merged = merge(self._tables.machine, extension)
        self.replace(merged)
        return merged

    # ------------------------------------------------------- introspection
    def snapshot(self) -> dict[str, Any]:
        """Current state, category, queue with statuses and expiry, counts (JSON-ready)."""
        return {
            "state": self.state,
            "category": self.category,
            "queue": [
                {
                    "id": q.event.id,
                    "name": q.event.name,
                    "source": q.event.source,
                    "created_ns": q.event.created_ns,
                    "expires_ns": q.expires_ns,
                    "status": q.status,
                }
                for q in self._queue
            ],
            "stats": self.stats(),
        }


def _key(item: Queued) -> tuple[int, int]:
    return (item.event.created_ns, item.seq)


def _arrival_key(item: Queued) -> tuple[int, int]:
    return (item.arrived_ns, item.seq)


#: Queue orders: "created" (the ES's, docs/semantics.md §2) and "arrival" (an ablation).
ORDERS = ("created", "arrival")


def _param_value(f: Callable[[Any], Any], payload: etree._Element | None) -> ParamValue:
    """Evaluate a parameter XPath: node-sets become tuples, scalars strings."""
    if payload is None:
        return ""
    v = f(payload)
    if isinstance(v, list):
        return tuple(x if isinstance(x, etree._Element) else str(x) for x in v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return str(int(v)) if v.is_integer() else repr(v)
    return str(v)


def record_dict(rec: Record) -> dict[str, Any]:
    """A record as plain JSON-ready data (traces, introspection, determinism checks)."""
    ev = rec.event
    out: dict[str, Any] = {"kind": rec.kind, "at_ns": rec.at_ns, "event": ev.id, "name": ev.name, "source": ev.source}
    if isinstance(rec, Applied):
        out.update(source_state=rec.source_state, target_state=rec.target_state, owner=rec.owner,
                   outputs=[{"kind": o.kind, "target": o.target, "name": o.name,
                             "params": {n: (v if isinstance(v, str) else [_node_text(x) for x in v]) for n, v in o.params}}
                            for o in rec.outputs])
    elif isinstance(rec, Rejected):
        out.update(state=rec.state, reason=rec.reason, detail=rec.detail)
    else:
        out.update(state=rec.state, category=rec.category)
    return out


def _node_text(x: Any) -> str:
    return etree.tostring(x, encoding="unicode") if isinstance(x, etree._Element) else str(x)


@dataclass(frozen=True, slots=True)
class Delivery:
    """An event and the virtual time it reaches the ES (created + latency)."""

    event: Event
    at_ns: int


def run_deliveries(engine: Engine, deliveries: list[Delivery], *, until_ns: int | None = None) -> list[Record]:
    """Drive ``engine`` as the supervisor does, without a loop: all records, in order.

    Deliveries are taken in order of arrival (ties: list order). Before the
    arrivals of an instant the engine is processed at every expiry deadline
    that comes first (expired events are rejected exactly at their expiry);
    then every event arriving at that instant is queued and the engine is
    processed once (the same-instant rule: expiries at that instant too, each
    where the scan from the oldest reaches it). Afterwards deadlines are followed up to ``until_ns``
    (every remaining one when None). Raises :class:`ClockError` if an arrival
    lies before the engine's current time.
    """
    records: list[Record] = []
    order = sorted(range(len(deliveries)), key=lambda k: (deliveries[k].at_ns, k))
    for j, k in enumerate(order):
        d = deliveries[k]
        if j == 0 or deliveries[order[j - 1]].at_ns != d.at_ns:  # the instant's first arrival
            _follow_deadlines(engine, d.at_ns, records, inclusive=False)
        engine.queue(d.event, d.at_ns)
        if j + 1 < len(order) and deliveries[order[j + 1]].at_ns == d.at_ns:
            continue  # the same-instant rule: every arrival of the instant is queued before it is processed
        records.extend(engine.process(d.at_ns))
    _follow_deadlines(engine, until_ns, records, inclusive=True)
    if until_ns is not None:
        records.extend(engine.process(until_ns))
    return records


def _follow_deadlines(engine: Engine, limit: int | None, records: list[Record], *, inclusive: bool) -> None:
    while True:
        d = engine.next_deadline()
        if d is None or (limit is not None and (d > limit or (d == limit and not inclusive))):
            return
        records.extend(engine.process(max(d, engine._now)))  # type: ignore[arg-type]
