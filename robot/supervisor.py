"""BIRON's execution supervisor (ES): the AFSM engine as a bus module.

Modules publish events (``<event name="greeting" lifetime="3">payload</event>``)
on ``/robot/es/events``; heartbeat failures from ``/system/health`` become
events too (``module_failed`` / ``module_recovered``, with ``still_failed``: how
many modules the ES knows to be failed after this one). The ES queues each event
with the bus message's creation time (so latency puts it where it belongs),
runs the engine of :mod:`homesim.afsm.engine` at once, and again at the
earliest expiry among retained events, so an expired event is rejected exactly
at ``created + lifetime``.

What comes out, all as typed bus messages (``robot/schemas/es-*.xsd``):

* orders on ``/robot/es/orders/<module>`` and conditions on
  ``/robot/es/conditions/<module>``, parameters copied from the triggering
  event by the AFSM's XPaths (the ES interprets no data);
* a rejected event whose source is the dialog goes back to it on
  ``/robot/es/rejected/dialog`` with the reason and a copy of the event;
* every decision (applied / rejected / retained) on ``/robot/es/log`` and a
  status snapshot on ``/robot/es/status`` after each state change, so both
  land in the trace;
* an arrival inserted ahead of queued newer events (its creation-time
  ordering at work) on ``/robot/es/sorted``: how many it went before and the
  first of them; :meth:`ExecutionSupervisor.arrivals` counts such arrivals
  (``sorted_ahead``) apart from all arrivals out of creation order.

RPC methods of the ``supervisor`` participant: ``introspect`` (reply
``<es_status>``), ``replace`` and ``extend`` (request: an SCXML document;
validated before the swap, refused with the reason, the queue survives).

Time: the ES is a serial processor. When it is free, it decides at the instant
of an event's arrival and at the earliest expiry among queued events. A
transition costs ``cost`` virtual seconds (the papers: under 20 ms to
reconfigure the system): its orders and conditions leave at ``decision +
cost``, and the next decision (the scan restarting from the oldest event) is
taken then, so a burst of k transitions is decided at t, t+cost, ... While
busy the ES only queues arrivals and rejects events whose lifetime ends,
exactly at their expiry and, like every decision, after that instant's
arrivals, oldest first; no event is ever applied at or after it. Messages
to other modules (orders, conditions, rejections returned to the dialog)
leave in decision order: nothing decided later overtakes them.

Same instant (docs/semantics.md §2): a decision at ``t`` (on an arrival, an
expiry, the end of a cost) is taken once every event arriving at ``t`` is
queued (in a callback scheduled at ``t``, after every delivery already due
then), scanning from the oldest: an older event arriving at the very instant
a newer one expires is applied first, and the newer one is rejected in the
state that left. Link latency, which orders deliveries against the ES's own
timers, changes none of its decisions.
"""

from __future__ import annotations

import asyncio
import math
import os
from collections import deque
from copy import deepcopy
from functools import partial
from pathlib import Path
from typing import Any

from lxml import etree

from homesim.afsm.engine import Applied, Engine, Event, Output, Queued, Record, Rejected, payload_problem, record_dict
from homesim.afsm.loader import from_element, load, loads, to_element
from homesim.afsm.model import CONDITION, MAX_LIFETIME_NS, Machine
from homesim.errors import AFSMError, AFSMModificationRefused, BadMessageError, InputError
from homesim.heartbeat import HEALTH_CHANNEL
from homesim.message import Message
from homesim.module import Module
from robot.deployment import cost_scale
from homesim.vloop import BARE, NS_PER_S, to_ns
from robot.contract import ES_CONDITIONS, ES_EVENTS, ES_LOG, ES_ORDERS, ES_REJECTED, ES_SORTED, ES_STATUS


SCHEMAS = Path(__file__).with_name("schemas")
BIRON_AFSM = Path(__file__).with_name("afsm") / "biron.scxml"


def event_xml(name: str, *, lifetime: float | None = None, attrs: dict[str, str] | None = None,
              children: tuple[etree._Element, ...] = ()) -> etree._Element:
    """Build an ES event document (what modules publish on ``/robot/es/events``)."""
    el = etree.Element("event", name=name)
    if lifetime is not None:
        el.set("lifetime", repr(float(lifetime)))
    for k, v in (attrs or {}).items():
        el.set(k, v)
    for c in children:
        el.append(deepcopy(c))
    return el


def _lifetime_ns(channel: str, text: str) -> int:
    """An event's ``lifetime`` attribute (seconds) as nanoseconds; a value the schema refuses is a bad message (a drop)."""
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not 0.0 < seconds <= MAX_LIFETIME_NS / NS_PER_S:  # also NaN and inf
        raise BadMessageError(f"{channel}: lifetime={text[:40]!r} is not a number of seconds in (0, {MAX_LIFETIME_NS // NS_PER_S}]")
    return max(1, to_ns(seconds))


def _seconds(ns: int) -> str:
    """Integer nanoseconds as exact decimal seconds (``1.5``, ``0``, ``-0.000000001``)."""
    whole, frac = divmod(abs(ns), NS_PER_S)
    text = f"{whole}.{frac:09d}".rstrip("0").rstrip(".") if frac else str(whole)
    return "-" + text if ns < 0 else text


def declare_channels(bus: Any, machine: Machine) -> None:
    """Type every ES channel on ``bus`` with its XSD (events, outputs per module, log, status)."""
    bus.declare_channel(ES_EVENTS, SCHEMAS / "es-event.xsd")
    bus.declare_channel(ES_LOG, SCHEMAS / "es-log.xsd")
    bus.declare_channel(ES_STATUS, SCHEMAS / "es-status.xsd")
    bus.declare_channel(ES_SORTED, SCHEMAS / "es-sorted.xsd")
    for name in machine.modules:
        bus.declare_channel(f"{ES_ORDERS}/{name}", SCHEMAS / "es-order.xsd")
        bus.declare_channel(f"{ES_CONDITIONS}/{name}", SCHEMAS / "es-condition.xsd")
        bus.declare_channel(f"{ES_REJECTED}/{name}", SCHEMAS / "es-rejected.xsd")


def output_xml(out: Output, state: str) -> etree._Element:
    """An order/condition element; copied nodes are deep copies (the event stays intact)."""
    el = _Element(out.kind)
    el.set("name", out.name)
    el.set("target", out.target)
    el.set("event", out.event_id)
    el.set("state", state)
    for pname, value in out.params:
        p = _SubElement(el, "param")
        p.set("name", pname)
        _fill_param(p, value)
    return el


def _fill_param(p: Any, value: Any) -> None:
    """Put a parameter's value into its ``<param>``: text as is, elements deep-copied after it."""
    if isinstance(value, str):
        p.text = value
        return
    texts = []
    for v in value:
        if isinstance(v, str):
            texts.append(v)
        else:
            p.append(v.__deepcopy__(None))
    if texts:
        p.text = " ".join(texts)


_Element = etree.Element
_SubElement = etree.SubElement


def _output_template(out: Output, state: str) -> etree._Element:
    """The parts of ``out``'s element that are the same for every event: a copy of it is filled per event.

    Attributes in :func:`output_xml`'s order (``event`` holds its place with an
    empty value) and one empty ``<param name>`` per parameter.
    """
    el = _Element(out.kind)
    el.set("name", out.name)
    el.set("target", out.target)
    el.set("event", "")
    el.set("state", state)
    for pname, _ in out.params:
        _SubElement(el, "param").set("name", pname)
    return el


class OutputBuilder:
    """Builds orders and conditions as :func:`output_xml` does, bit for bit, from per-send templates.

    An AFSM's outputs are known at load time up to the event id and the
    copied parameters, so each (kind, name, target, state, parameter names)
    gets one pre-built element; an output is a C-level copy of it with the
    event id and the parameters filled in (about half the cost of building
    the element attribute by attribute). The templates never leave this
    object; what is returned is a new parentless element the caller owns.
    Bounded: one template per distinct send of the machines seen
    (:meth:`clear` on a change of machine).
    """

    def __init__(self) -> None:
        self._templates: dict[tuple[str, ...], etree._Element] = {}

    def clear(self) -> None:
        """Forget the templates (the machine changed)."""
        self._templates.clear()

    def __call__(self, out: Output, state: str) -> etree._Element:
        params = out.params
        key = (out.kind, out.name, out.target, state, *[p[0] for p in params]) if params else \
            (out.kind, out.name, out.target, state)
        tmpl = self._templates.get(key)
        if tmpl is None:
            tmpl = self._templates[key] = _output_template(out, state)
        el = tmpl.__copy__()
        el.set("event", out.event_id)
        if params:
            for p, (_, value) in zip(el, params):
                _fill_param(p, value)
        return el


def record_xml(rec: Record) -> etree._Element:
    """One decision as an ``<es_record>`` for the log channel."""
    ev = rec.event
    el = etree.Element("es_record", kind=rec.kind, event=ev.id, name=ev.name, source=ev.source,
                       created=_seconds(ev.created_ns))
    if isinstance(rec, Applied):
        el.set("state", rec.source_state)
        el.set("to", rec.target_state)
        el.set("outputs", str(len(rec.outputs)))
    elif isinstance(rec, Rejected):
        el.set("state", rec.state)
        el.set("reason", rec.reason)
        el.set("detail", rec.detail)
    else:
        el.set("state", rec.state)
        el.set("category", rec.category)
    return el


def sorted_xml(item: Queued, nxt: Event, state: str) -> etree._Element:
    """An ``<es_sorted>``: ``item`` went ahead of ``item.ahead`` queued events, ``nxt`` the first of them."""
    ev = item.event
    return etree.Element("es_sorted", {"event": ev.id, "name": ev.name, "source": ev.source, "created": _seconds(ev.created_ns),
                                       "state": state, "ahead": str(item.ahead), "ahead-of": nxt.id,
                                       "ahead-of-name": nxt.name, "ahead-of-created": _seconds(nxt.created_ns)})


class ExecutionSupervisor(Module):
    """The ES module. ``machine``: a :class:`Machine`, or a path to an SCXML file (default BIRON's).

    ``cost`` is the reconfiguration time per transition in virtual seconds;
    ``return_to`` names the source modules whose rejected events are sent
    back (the dialog, per the papers); ``history`` bounds the remembered
    records. Raises :class:`AFSMProblems` if the machine does not load.
    """

    def __init__(
        self,
        sim: Any,
        machine: Machine | str | os.PathLike[str] = BIRON_AFSM,
        *,
        name: str = "supervisor",
        host: str = "robot",
        cost: float = 0.005,
        heartbeat: float | None = 0.5,
        return_to: tuple[str, ...] = ("dialog",),
        history: int = 1000,
        health_channel: str | None = HEALTH_CHANNEL,
        typed: bool = True,
    ) -> None:
        super().__init__(sim, name, host=host, heartbeat=heartbeat)
        m = machine if isinstance(machine, Machine) else load(machine)
        self.engine = Engine(m, history=history)
        # Under 20 ms on the papers' hardware (Fig. 6); on another host the CPU speed scales it (docs/deployment.md).
        self.cost_ns = to_ns(cost * cost_scale(sim, self.name, self.bus.host))
        self.return_to = tuple(return_to)
        self._loop = sim.loop
        self._busy_until = -1  # busy while now < this; at this instant the decision waits for its arrivals
        self._settling: Any = None  # the pending decision at the current instant (_settle_later)
        self._outbox: deque[tuple[int, Applied | Rejected]] = deque()
        self._timer: asyncio.TimerHandle | None = None
        self._timer_at: int | None = None
        self._failed: set[str] = set()
        # Arrivals on the event channel: how many, and how many were created before one received earlier.
        self._received = 0
        self._out_of_order = 0
        self._newest_ns = -1
        self._output_xml = OutputBuilder()
        if typed:
            declare_channels(sim.bus, m)
        self.bus.subscribe(ES_EVENTS, self._on_event)
        if health_channel is not None:
            self.bus.subscribe(health_channel, self._on_health)
        self.bus.serve("introspect", lambda msg: self.status_xml(), reply_schema=SCHEMAS / "es-status.xsd")
        self.bus.serve("replace", self._rpc_replace)
        self.bus.serve("extend", self._rpc_extend)

    # ------------------------------------------------------------ main loop
    async def run(self) -> None:
        """Beat the heartbeat; events are handled as they are delivered."""
        self.publish_status()
        while True:
            self.beat()
            await asyncio.sleep(self.heartbeat.interval if self.heartbeat else 1.0)

    @property
    def state(self) -> str:
        """The current AFSM state."""
        return self.engine.state

    # --------------------------------------------------------------- input
    def _on_event(self, msg: Message) -> None:
        xml = msg.xml
        too_big = payload_problem(xml)
        if too_big is not None:  # another module's bad data: reported as a drop, the ES goes on
            raise BadMessageError(f"{msg.channel}: {too_big}")
        lt = xml.get("lifetime")
        self._received += 1
        if msg.created_ns < self._newest_ns:
            self._out_of_order += 1
        else:
            self._newest_ns = msg.created_ns
        ev = Event(msg.id, xml.get("name"), msg.sender, msg.created_ns, None if lt is None else _lifetime_ns(msg.channel, lt), xml)
        self.submit(ev, payload_checked=True)

    def _on_health(self, msg: Message) -> None:
        """A health message becomes an event; its payload says how many modules are still failed.

        The heartbeat monitor reports each module on its own; the AFSM must
        know whether *any* module is still down (a second failure must not be
        forgotten when the first recovers), so the ES keeps the set of failed
        modules and adds ``still_failed`` (its size after this message).
        """
        xml = msg.xml
        tag = xml.tag
        module = xml.get("module")
        if tag not in ("module_failed", "module_recovered") or module == self.name:
            return
        key = module if module is not None else msg.sender
        if tag == "module_failed":
            self._failed.add(key)
        else:
            self._failed.discard(key)
        payload = etree.Element(tag, dict(xml.attrib))
        payload.set("still_failed", str(len(self._failed)))
        self.submit(Event(msg.id, str(tag), msg.sender, msg.created_ns, None, payload))

    def arrivals(self) -> dict[str, int]:
        """Events received on the event channel, and how many of them out of creation order
        (created before an event received earlier: latency put them behind it; the queue sorts them back)."""
        return {"events_received": self._received, "received_out_of_order": self._out_of_order,
                "sorted_ahead": self.engine.sorted_ahead}

    @property
    def failed_modules(self) -> frozenset[str]:
        """Modules the heartbeat monitor reported failed and not recovered yet."""
        return frozenset(self._failed)

    def submit(self, event: Event, *, payload_checked: bool = False) -> None:
        """Queue ``event`` now; the ES decides at this instant once every arrival of it is queued.

        ``payload_checked``: the caller found the payload small enough already
        (:func:`payload_problem`). Raises :class:`SupervisorError` for a
        payload too large or an id already queued.
        """
        now = self._loop._now_ns
        item = self.engine.queue(event, now, payload_checked=payload_checked)
        if item.ahead:  # sorted ahead of queued newer events: on the trace, so it can be seen and counted
            queue = self.engine.queued()
            nxt = queue[len(queue) - item.ahead].event  # the oldest of the events it went before
            self.bus.publish(ES_SORTED, partial(sorted_xml, item, nxt, self.engine.state), causes=(event.id,))
        # The same-instant rule: decide once every event arriving at this instant is queued (a
        # callback scheduled now runs after every delivery already due now), scanning from the oldest.
        # While the ES pays a cost that decision only rejects what has expired, still oldest first.
        self._settle_later(now)

    @property
    def busy_until_ns(self) -> int:
        """Virtual time (ns) until which the ES pays its last transition's cost (no decisions before)."""
        return self._busy_until

    def _wake(self) -> None:
        self._timer = None
        self._timer_at = None
        if self.bus.closed or self.bus.hung:
            return
        now = self._loop._now_ns
        # An expiry while the ES pays a cost is settled like any decision: after every arrival of the
        # instant (an older event arriving expired now is rejected before a newer one expiring now).
        if now == self._busy_until:
            self._flush(now)  # the transition's outputs leave as its cost ends
        # An expiry, or the end of a cost: decide only after every delivery already due at this instant
        # (the same-instant rule), whether its link latency scheduled it before or after this timer.
        self._settle_later(now)

    def _settle_later(self, now: int) -> None:
        """Decide at ``now`` in a callback that runs after everything already due at ``now`` (once)."""
        if self._settling is None:
            self._settling = self._loop.call_at_ns(now, self._settle, context=BARE)

    def _settle(self) -> None:
        self._settling = None
        if self.bus.closed or self.bus.hung:
            return
        now = self._loop._now_ns
        if now >= self._busy_until:
            self._busy_until = -1
        self._tick(now)

    def _tick(self, now: int) -> list[Record]:
        """Everything due at ``now``, in decision order.

        Held messages whose time has come leave first. While the ES pays a
        transition's cost it takes no decision; it only rejects events whose
        lifetime ends (exactly at their expiry). Once free it scans the queue
        up to the first transition (docs/semantics.md §2); that transition makes it busy for
        ``cost``, and the scan goes on, from the oldest event, when it is
        free again.
        """
        before = self.engine.state
        records: list[Record] = []
        box = self._outbox
        while True:
            if box and box[0][0] <= now:
                self._flush(now)
            if now < self._busy_until:
                recs: list[Record] = list(self.engine.expire(now))
                self._emit(recs, now)
                records += recs
                break
            recs = self.engine.process(now, max_applied=1)
            if not recs:
                break
            self._emit(recs, now)
            records += recs
            if not isinstance(recs[-1], Applied):
                break
            if self.cost_ns:
                self._busy_until = now + self.cost_ns
                break
        if self.engine.state != before:
            self.publish_status()
        self._arm(now)
        return records

    def _arm(self, now: int) -> None:
        """One timer: the earliest of the next expiry, the end of the busy time, the next held message."""
        wake = self.engine.next_deadline()
        if self._busy_until >= now and (wake is None or self._busy_until < wake):
            wake = self._busy_until
        if self._outbox and (wake is None or self._outbox[0][0] < wake):
            wake = self._outbox[0][0]
        if wake == self._timer_at:
            return
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        self._timer_at = wake
        if wake is not None:
            self._timer = self._loop.call_at_ns(wake, self._wake, context=BARE)  # (no context: the ES reads no context variables)

    # -------------------------------------------------------------- output
    def _emit(self, records: list[Record], now: int) -> None:
        """Log every decision now; orders, conditions and returned rejections go through the outbox.

        The outbox keeps decision order: a transition's outputs leave ``cost``
        after its decision, and nothing decided later overtakes them.
        """
        for rec in records:
            # Built only if someone receives or observes the log (the trace, expectations, metrics).
            self.bus.publish(ES_LOG, partial(record_xml, rec), causes=(rec.event.id,))
            if isinstance(rec, Applied):
                if rec.outputs:
                    self._outbox.append((now + self.cost_ns, rec))
            elif isinstance(rec, Rejected) and rec.event.source in self.return_to:
                self._outbox.append((now, rec))
        box = self._outbox
        if box and box[0][0] <= now:
            self._flush(now)

    def _flush(self, now: int) -> None:
        box = self._outbox
        while box and box[0][0] <= now:
            _, rec = box.popleft()
            if self.bus.closed or self.bus.hung:
                continue
            if isinstance(rec, Applied):
                self._send_outputs(rec)
            else:
                self._send_rejection(rec)

    def _send_rejection(self, rec: Rejected) -> None:
        el = etree.Element("rejected", event=rec.event.id, name=rec.event.name, reason=rec.reason,
                           state=rec.state, detail=rec.detail)
        if rec.event.payload is not None:
            el.append(deepcopy(rec.event.payload))
        self.bus.publish(f"{ES_REJECTED}/{rec.event.source}", el, causes=(rec.event.id,), transfer=True)

    def _send_outputs(self, rec: Applied) -> None:
        build = self._output_xml
        state = rec.target_state
        for out in rec.outputs:
            prefix = ES_CONDITIONS if out.kind == CONDITION else ES_ORDERS
            self.bus.publish(
                f"{prefix}/{out.target}", build(out, state), causes=(out.event_id,), transfer=True
            )

    # ------------------------------------------------------- introspection
    def introspect(self) -> dict[str, Any]:
        """Current state, queue (status, expiry), counts and recent history as plain data."""
        snap = self.engine.snapshot()
        snap["machine"] = self.engine.machine_name
        snap["t_ns"] = self._loop.now_ns
        snap["history"] = [record_dict(r) for r in self.engine.history]
        return snap

    def status_xml(self, *, history: int = 20) -> etree._Element:
        """The introspection as an ``<es_status>`` element (reply of ``introspect``).

        ``history``: how many recent records to include (0: no ``<history>``
        and no ``<accepts>``, as on the status channel). ``<accepts>`` lists the
        events the current state applies now and those it would retain (what
        the dialog's self-explanation tells the user).
        """
        eng = self.engine
        s = eng.stats()
        el = etree.Element("es_status", machine=eng.machine_name, state=eng.state, t=_seconds(self._loop.now_ns),
                           **{k: str(s[k]) for k in ("queued", "applied", "expired", "inapplicable", "pending")})
        cat = eng.category
        if cat is not None:
            el.set("category", cat)
        q = etree.SubElement(el, "queue")
        for item in eng.queued():
            etree.SubElement(q, "queued", event=item.event.id, name=item.event.name, source=item.event.source,
                             created=_seconds(item.event.created_ns), expires=_seconds(item.expires_ns),
                             status=item.status)
        if history:
            applies, waits = eng.accepts()
            acc = etree.SubElement(el, "accepts")
            for name in applies:
                etree.SubElement(acc, "event", name=name, status="applies")
            for name in waits:
                etree.SubElement(acc, "event", name=name, status="waits")
            h = etree.SubElement(el, "history")
            for rec in list(eng.history)[-history:]:
                h.append(record_xml(rec))
        return el

    def publish_status(self) -> Message | None:
        """Publish the snapshot (no history) on ``/robot/es/status``; the ES does so on each change of state.

        The history stays available by the ``introspect`` RPC and in the log channel. The
        snapshot (and each decision's log record) is built only if someone receives or
        observes it (see ``Participant.publish``): the returned message's ``xml`` is None then.
        """
        if self.bus.closed or self.bus.hung:
            return None
        return self.bus.publish(ES_STATUS, partial(self.status_xml, history=0))  # built only if seen

    # -------------------------------------------------------- modification
    def replace(self, machine: Machine | str | os.PathLike[str]) -> None:
        """Swap the AFSM without restarting; refused (AFSMModificationRefused) with the reason.

        Everything is checked before anything changes: a refused replacement
        leaves the machine, the queue (with each event's status) and the
        bus channels exactly as they were.
        """
        m = self._as_machine(machine)
        self._change(lambda: (self.engine.replace(m), m)[1])

    def extend(self, extension: Machine | str | os.PathLike[str]) -> None:
        """Merge states/transitions into the running AFSM; refused with the reason, changing nothing."""
        ext = self._as_machine(extension, fragment=True)
        self._change(lambda: self.engine.extend(ext))

    def _change(self, swap: Any) -> None:
        try:
            m = swap()  # validates (module names included) before it swaps, or raises
        except AFSMModificationRefused:
            raise
        except AFSMError as exc:
            raise AFSMModificationRefused(f"refused: {exc.message}", source=exc.source, line=exc.line,
                                          element=exc.element) from exc
        self._after_change(m)

    def _as_machine(self, machine: Machine | str | os.PathLike[str] | etree._Element, *, fragment: bool = False,
                    source: str | None = None) -> Machine:
        """The machine to swap in; a document that does not load is refused like an invalid machine."""
        if isinstance(machine, Machine):
            return machine
        label = source or ("<extend>" if fragment else "<replace>")
        try:
            if isinstance(machine, etree._Element):
                return from_element(machine, source=label, fragment=fragment)
            text = str(machine)
            if text.lstrip().startswith("<"):
                return loads(text, source=label, fragment=fragment)
            return load(machine, fragment=fragment)
        except AFSMModificationRefused:
            raise
        except InputError as exc:  # AFSMProblems (every problem listed) or malformed XML
            refused = AFSMModificationRefused(f"refused: {exc.message}", source=exc.source, line=exc.line,
                                              element=exc.element)
            refused.problems = list(getattr(exc, "problems", [exc]))  # type: ignore[attr-defined]
            raise refused from exc

    def _after_change(self, m: Machine) -> None:
        self._output_xml.clear()
        if self._typed_bus():
            declare_channels(self.sim.bus, m)
        self._tick(self._loop.now_ns)
        self.publish_status()

    def _typed_bus(self) -> bool:
        return self.sim.bus.channel_schema(ES_EVENTS) is not None

    def _rpc_replace(self, msg: Message) -> etree._Element:
        self.replace(self._as_machine(msg.xml, source=f"<rpc {msg.id}>"))
        return etree.Element("ok", state=self.state, machine=self.engine.machine_name)

    def _rpc_extend(self, msg: Message) -> etree._Element:
        self.extend(self._as_machine(msg.xml, source=f"<rpc {msg.id}>", fragment=True))
        return etree.Element("ok", state=self.state, machine=self.engine.machine_name)

    def machine_xml(self) -> etree._Element:
        """The running machine as SCXML (after any run-time changes)."""
        return to_element(self.engine.machine)
