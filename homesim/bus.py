"""An XCF-like XML message bus on virtual time.

Participants publish XML documents on hierarchical channels
(``/camera/faces``), subscribe to channels or subtrees
(``/camera/**``), and call named methods of named servers, awaited
with a virtual-time timeout or fire-and-forget. Channels and methods may be
typed by an XSD. A validated message that is invalid is refused with an
error naming the channel, the schema and libxml2's message, and is delivered
to nobody.

Which messages are validated is the bus's policy (``Bus(validation=...)``):

- ``"all"`` (strict: the test suite and ``homesim run --strict``): every
  message on a typed channel or method.
- ``"edges"`` (the default): payloads that arrive as text (``str``/``bytes``:
  a document from outside the process, parsed with the hardened parser) are
  validated; payloads a module built as an lxml element are trusted: not
  validated (elements from a document with a DOCTYPE and elements holding
  entity references are refused under every policy, as text with a DOCTYPE
  is: ~1 us a message). The project's own modules are checked by the test
  suite, which runs strict; checking each of their messages again costs
  ~10 us a message (about a fifth of a home tour's CPU) and changes nothing
  for a valid message. In this mode a module's *invalid* element is
  delivered (as it was built) instead of refused: run ``--strict`` to find
  such a bug.

A payload may be a typed record (:class:`~homesim.message.Typed`): the message
(:class:`~homesim.message.TypedMessage`) carries the record, receivers share it
(no copy per receiver) and its XML is built only when someone reads ``msg.xml``
(the trace, an XML-reading module; strict builds and validates it at send).

A payload may be a function that builds the element: it is called only if
someone will see the message (a subscriber, or an interceptor that wants its
channel; the trace wants all), always under the strict policy. The message is
sent either way (same id, same counters).

Each message reaches each receiver after a delay drawn from the link between
their hosts (:mod:`homesim.network`; on a link with a bandwidth the delay grows
with the message's size: its XML and attachments); per (sender, receiver) pair
delivery is FIFO (as over one TCP connection). A participant's host is the
network's placement for its name, if it has one (the run's deployment). Interceptors see every send, delivery and drop and change nothing: the
trace recorder is one. An interceptor with a ``wants(channel)`` method is shown the publishes on the channels it
wants only (asked once per channel and kept; whoever changes what it wants calls :meth:`Bus.interceptors_changed`):
a message nobody watches costs no observation and no calls.

How it fails: sending on a closed participant or calling an unknown server
raises at once; a call whose reply does not come in time raises
:class:`RemoteCallTimeout`; a server whose handler raises makes the call raise
:class:`RemoteCallFailed`; a handler that never answers (awaiting a future nobody
holds: the bus keeps its task alive) costs its caller the timeout. Exceptions
raised by subscription handlers fail the whole run (see :mod:`homesim.vloop`).
A participant sending more than :data:`MAX_SENDS_PER_S` messages within one
virtual second is failed (:meth:`Bus.flooded`; the simulation crashes its
module, announced with ``reason="flood"``): a send loop without a real wait
would otherwise grow the run's memory until the process is killed.
"""

from __future__ import annotations

import asyncio
import inspect
import math
import os
import re
from collections import deque
from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple, Union

from lxml import etree

from .errors import (
    BadMessageError,
    BusError,
    MessageValidationError,
    SubscriptionClosed,
    XMLInputError,
    RemoteCallFailed,
    RemoteCallTimeout,
    UnknownParticipantError,
)
from .message import _NO_ATTACHMENTS, ERROR, PUBLISH, REPLY, REQUEST, Attachment, Message, Typed, TypedMessage
from .network import LinkStats, Network
import numpy as np

from .vloop import BARE, NS_PER_S, VirtualEventLoop, _Delivery, to_ns
from .xmlio import Schema, load_schema, parse_bytes

XMLLike = Union[etree._Element, str, bytes]
#: A payload, or a function that builds it (built only if someone receives or observes the message).
PayloadLike = Union[etree._Element, str, bytes, Typed, Callable[[], etree._Element]]
Handler = Callable[[Message], Any]
SchemaLike = Union[Schema, str, "os.PathLike[str]", None]

SEND = "send"
DELIVER = "deliver"
VALIDATE_ALL = "all"
VALIDATE_EDGES = "edges"
VALIDATIONS = (VALIDATE_ALL, VALIDATE_EDGES)
DROP = "drop"


class Observation(NamedTuple):
    """What an interceptor sees: a send, a delivery or a drop, at a time.

    For a send, ``receivers`` lists every intended receiver (sorted); for a
    delivery or a drop, the one receiver concerned. ``reason`` says why a
    message was dropped ("lost", "receiver closed", "receiver hung",
    "overflow"). Immutable (a named tuple: the bus makes one per send,
    delivery and drop while anyone intercepts).
    """

    t_ns: int
    event: str
    message: Message
    receivers: tuple[str, ...]
    reason: str = ""


Interceptor = Callable[[Observation], None]

_tuple_new = tuple.__new__  # builds a named tuple without its Python-level __new__ (hot path)
_Element = etree._Element
_Entity = etree.Entity
#: Default of :attr:`Bus.max_sends_per_s`.
MAX_SENDS_PER_S = 10_000


def _created_ns(created: float, now: int, channel: str) -> int:
    """A sender's own creation time (seconds) as ns: finite and not after the send (an event created in
    the future would jump the ES's queue and never expire in time); otherwise :class:`BusError`."""
    if not isinstance(created, (int, float)) or isinstance(created, bool) or not math.isfinite(created):
        raise BusError(f"{channel}: created={created!r} is not a finite virtual time in seconds")
    ns = to_ns(created) if created <= (now + 1) / NS_PER_S else now + 1  # (1e300 s overflows to_ns)
    if ns > now:
        raise BusError(f"{channel}: created={created!r} s is after the send ({now / NS_PER_S:.9f} s)")
    return ns
_new = object.__new__


def _as_schema(schema: SchemaLike) -> Schema | None:
    if schema is None or isinstance(schema, Schema):
        return schema
    return load_schema(schema)


class Subscription:
    """Messages of one channel (or subtree) for one participant.

    Either a ``handler`` is called at each delivery, or messages queue up to
    be awaited with :meth:`get` / ``async for``. With ``maxlen`` the oldest
    queued message is dropped when the queue is full (a sensor stream where
    only the latest matters).
    """

    def __init__(self, participant: Participant, pattern: str, handler: Handler | None, maxlen: int | None) -> None:
        if maxlen is not None and maxlen < 1:
            raise BusError(f"subscription {pattern!r}: maxlen must be >= 1 (or None), got {maxlen}")
        self.participant = participant
        self.pattern = pattern
        self.handler = handler
        self.maxlen = maxlen
        self._items: deque[Message] = deque()
        self._waiters: deque[asyncio.Future[None]] = deque()
        self.closed = False
        self.delivered = 0

    def _push(self, msg: Message) -> Message | None:
        """Queue one message; return the message dropped for overflow, if any."""
        dropped = None
        if self.maxlen is not None and len(self._items) >= self.maxlen:
            dropped = self._items.popleft()
        self._items.append(msg)
        self._wake_next()
        return dropped

    def _wake_next(self) -> None:
        while self._waiters:
            w = self._waiters.popleft()
            if not w.done():
                w.set_result(None)
                return

    async def get(self) -> Message:
        """Wait (in virtual time) for the next message.

        Raises :class:`SubscriptionClosed` when the subscription is closed
        and nothing is left to read.
        """
        while not self._items:
            if self.closed:
                raise SubscriptionClosed(f"subscription {self.pattern!r} of {self.participant.name!r} is closed")
            fut = self.participant.bus.loop.create_future()
            self._waiters.append(fut)
            try:
                await fut
            except asyncio.CancelledError:
                # As asyncio.Queue: a cancelled reader must not swallow the wake-up.
                fut.cancel()
                if fut in self._waiters:
                    self._waiters.remove(fut)
                if self._items:
                    self._wake_next()
                raise
        self.delivered += 1
        return self._items.popleft()

    def get_nowait(self) -> Message | None:
        """The next queued message, or None."""
        if self._items:
            self.delivered += 1
            return self._items.popleft()
        return None

    def drain(self) -> list[Message]:
        """Every queued message, oldest first; the queue is left empty."""
        items = list(self._items)
        self._items.clear()
        self.delivered += len(items)
        return items

    def qsize(self) -> int:
        return len(self._items)

    def __aiter__(self) -> Subscription:
        return self

    async def __anext__(self) -> Message:
        """Iterate until the subscription is closed and drained."""
        try:
            return await self.get()
        except SubscriptionClosed:
            raise StopAsyncIteration from None

    def close(self) -> None:
        """Stop receiving; queued messages stay readable."""
        if not self.closed:
            self.closed = True
            self.participant.bus._remove_subscription(self)
            for w in self._waiters:
                if not w.done():
                    w.set_result(None)


@dataclass(slots=True)
class _Method:
    server: Participant
    name: str
    handler: Callable[[Message], Any]
    request_schema: Schema | None
    reply_schema: Schema | None


class Participant:
    """A named module's connection to the bus (one per module)."""

    def __init__(self, bus: Bus, name: str, host: str) -> None:
        self.bus = bus
        self.name = name
        self.host = host
        self.closed = False
        self.hung = False
        self.published: set[str] = set()
        self.subscriptions: list[Subscription] = []
        # Per channel this participant publishes on: how to reach each receiver (Bus._plan).
        self._plans: dict[str, tuple[tuple[Any, ...], ...]] = {}
        # [messages sent under this name]: kept by the bus per name (ids stay unique across re-registration).
        self._count = bus._counters.setdefault(name, [0])
        # The rate guard: the current one-second window (ends at, the first message number in it).
        self._window_end = -1
        self._window_first = 0

    def _rate(self, now: int, n: int) -> None:
        """Count message ``n`` sent at ``now`` against :data:`MAX_SENDS_PER_S` (see :meth:`Bus.flooded`)."""
        if now >= self._window_end:
            self._window_end = now + NS_PER_S
            self._window_first = n
        elif n - self._window_first >= self.bus.max_sends_per_s:
            self.bus.flooded(self)

    def __repr__(self) -> str:
        return f"Participant({self.name!r}, host={self.host!r})"

    # ----------------------------------------------------------- publishing
    def publish(
        self,
        channel: str,
        xml: PayloadLike,
        *,
        attachments: Mapping[str, Attachment] | None = None,
        causes: tuple[str, ...] | list[str] = (),
        created: float | None = None,
        transfer: bool = False,
    ) -> Message:
        """Send ``xml`` on ``channel`` (validated per the bus's policy); return the sent message.

        The payload is copied into a document of its own, so later changes by
        the sender reach nobody. ``transfer=True`` hands over a parentless
        element the sender has just built and will not touch again: it is
        sent without that copy (a hot-path saving for modules such as the
        supervisor). Every receiver but the last gets a copy of its own; the last
        gets the sent document itself (with ``transfer=True``, the sender's element).

        ``xml`` may also be a function that builds and returns a new element
        (handed over as with ``transfer=True``): it is called at once if
        anyone will see the message (a subscriber, or an interceptor such as
        the trace; always when strict), and not at all otherwise. The message
        is sent either way (its id, the counters); unbuilt, its ``xml`` is None.

        ``xml`` may also be a :class:`~homesim.message.Typed` record: the message is a
        :class:`~homesim.message.TypedMessage` whose XML is built only when read (see the module
        docstring); under the strict policy it is built and validated at once.
        """
        bus = self.bus
        if xml.__class__ is _Element and not bus.validate_all and not self.closed:
            # _make's trusted path (the default policy, a module's own element) and the
            # message, inlined: the commonest send. Keep the two alike.
            if xml.getroottree().docinfo.internalDTD is not None:  # any DOCTYPE (a copy would drop the DTD, not what it expanded)
                raise XMLInputError("elements from documents with a DOCTYPE are refused on the bus", source=f"<bus:{channel}>")
            if not transfer or xml.getparent() is not None:
                xml = xml.__copy__()  # lxml copies the whole subtree, in C
            if xml.tail is not None:
                xml.tail = None
            if len(xml):  # an element without children holds no entity reference (len counts them)
                for _ in xml.iter(_Entity):
                    raise XMLInputError("entity references are refused on the bus", source=f"<bus:{channel}>")
            now = bus.loop._now_ns
            name = self.name
            count = self._count
            n = count[0] = count[0] + 1
            if now >= self._window_end:  # the rate guard (_rate), inlined
                self._window_end = now + NS_PER_S
                self._window_first = n
            elif n - self._window_first >= bus.max_sends_per_s:
                bus.flooded(self)
            msg = _tuple_new(Message, (
                f"{name}#{n}",
                PUBLISH,
                name,
                channel,
                xml,
                now if created is None else _created_ns(created, now, channel),
                now,
                causes if causes.__class__ is tuple else tuple(causes),
                _frozen_attachments(attachments, channel) if attachments else _NO_ATTACHMENTS,
            ))
            bus._publish(self, msg)
            return msg
        if isinstance(xml, Typed):
            msg = self._make_typed(channel, xml, attachments, causes, created)
            bus._publish(self, msg)
            return msg
        if callable(xml) and not isinstance(xml, (etree._Element, str, bytes)):
            bus = self.bus
            if not bus.validate_all and not bus._has_audience(channel):
                # Nobody will see it: what _make and _publish do for a message without a payload
                # and without receivers (its id, the counters), without their general path.
                if self.closed:
                    raise BusError(f"participant {self.name!r} is closed")
                now = bus.loop._now_ns
                name = self.name
                count = self._count
                n = count[0] = count[0] + 1
                self._rate(now, n)
                msg = _tuple_new(Message, (
                    f"{name}#{n}", PUBLISH, name, channel, None, now if created is None else to_ns(created), now,
                    causes if causes.__class__ is tuple else tuple(causes),
                    _frozen_attachments(attachments, channel) if attachments else _NO_ATTACHMENTS,
                ))
                self.published.add(channel)
                bus.sent += 1
                bus.unheard += 1
                return msg
            xml = xml()
            if not isinstance(xml, etree._Element):  # (None marks an unbuilt payload: never send it as one)
                raise BusError(f"{self.name}: the payload function for {channel} returned "
                               f"{type(xml).__name__}, not an XML element (nothing sent)")
            transfer = True
        msg = self._make(PUBLISH, channel, xml, attachments, causes, created, transfer=transfer)
        self.bus._publish(self, msg)
        return msg

    def subscribe(self, pattern: str, handler: Handler | None = None, *, maxlen: int | None = None) -> Subscription:
        """Receive messages on ``pattern``: a channel, or ``/prefix/**`` for a subtree."""
        self._check_open()
        _check_channel_name(pattern, allow_subtree=True)
        sub = Subscription(self, pattern, handler, maxlen)
        self.subscriptions.append(sub)
        self.bus._add_subscription(sub)
        return sub

    # ------------------------------------------------------------------ RPC
    def serve(
        self,
        method: str,
        handler: Callable[[Message], etree._Element | Awaitable[etree._Element]],
        *,
        request_schema: SchemaLike = None,
        reply_schema: SchemaLike = None,
    ) -> None:
        """Expose ``handler`` as ``<this participant>/<method>``.

        The handler gets the request message and returns the reply element
        (or an awaitable of it); raising makes the caller's call fail.
        """
        self._check_open()
        key = (self.name, method)
        if key in self.bus._methods:
            raise BusError(f"method {self.name}/{method} is already served")
        self.bus._methods[key] = _Method(self, method, handler, _as_schema(request_schema), _as_schema(reply_schema))

    def unserve(self, method: str) -> None:
        """Withdraw a method (calls in flight get no reply and time out)."""
        self.bus._methods.pop((self.name, method), None)

    async def call(
        self,
        server: str,
        method: str,
        xml: XMLLike,
        *,
        timeout: float = 1.0,
        causes: tuple[str, ...] | list[str] = (),
        attachments: Mapping[str, Attachment] | None = None,
    ) -> Message:
        """Call ``server/method`` and await its reply message (virtual-time timeout)."""
        _, fut = self._send_request(server, method, xml, causes, attachments, want_reply=True)
        assert fut is not None
        try:
            async with asyncio.timeout(timeout):
                return await fut
        except TimeoutError:
            raise RemoteCallTimeout(
                f"{self.name}: call {server}/{method} got no reply within {timeout} s (virtual)"
            ) from None

    def call_nowait(
        self,
        server: str,
        method: str,
        xml: XMLLike,
        *,
        causes: tuple[str, ...] | list[str] = (),
        attachments: Mapping[str, Attachment] | None = None,
    ) -> Message:
        """Fire-and-forget call: the request is sent, any reply is discarded."""
        msg, _ = self._send_request(server, method, xml, causes, attachments, want_reply=False)
        return msg

    def _send_request(
        self,
        server: str,
        method: str,
        xml: XMLLike,
        causes: tuple[str, ...] | list[str],
        attachments: Mapping[str, Attachment] | None,
        *,
        want_reply: bool,
    ) -> tuple[Message, asyncio.Future[Message] | None]:
        entry = self.bus._methods.get((server, method))
        if entry is None:
            known = sorted(m for (s, m) in self.bus._methods if s == server)
            what = f"server {server!r} has no method {method!r} (it serves {known})" if known else f"no server {server!r} is registered"
            raise UnknownParticipantError(f"{self.name}: cannot call {server}/{method}: {what}")
        msg = self._make(REQUEST, f"{server}/{method}", xml, attachments, causes, None, schema=entry.request_schema)
        fut: asyncio.Future[Message] | None = self.bus.loop.create_future() if want_reply else None
        self.bus._request(self, entry, msg, fut)
        return msg, fut

    # ------------------------------------------------------------- internals
    def _refuse_invalid(self, schema: Schema | None, xml: etree._Element, channel: str) -> None:
        """Raise :class:`MessageValidationError` when ``xml`` breaks the channel's ``schema`` (None: no contract)."""
        if schema is not None and not schema.is_valid(xml):
            errors = schema.errors(xml)
            detail = errors[0][1] if errors else "invalid"
            raise MessageValidationError(
                f"{self.name}: message on {channel} refused (nothing delivered): "
                f"schema {schema.name}: {detail}"
            )

    def _next_seq(self, now: int) -> int:
        """This participant's next message number (the id's ``#n``), counted into its send rate."""
        count = self._count
        n = count[0] = count[0] + 1
        self._rate(now, n)
        return n

    def _make_typed(
        self,
        channel: str,
        record: Typed,
        attachments: Mapping[str, Attachment] | None,
        causes: tuple[str, ...] | list[str],
        created: float | None,
    ) -> TypedMessage:
        """A published :class:`TypedMessage`: no XML built, unless strict (then built and validated now)."""
        if self.closed:
            raise BusError(f"participant {self.name!r} is closed")
        bus = self.bus
        built = None
        if bus.validate_all:  # --strict: the record's XML is checked against the channel's contract at send
            built = record.to_xml()
            if not isinstance(built, etree._Element):
                raise BusError(f"{self.name}: {type(record).__name__}.to_xml() for {channel} returned "
                               f"{type(built).__name__}, not an XML element (nothing sent)")
            self._refuse_invalid(bus.channel_schema(channel), built, channel)
        now = bus.loop._now_ns
        name = self.name
        n = self._next_seq(now)
        msg = _tuple_new(TypedMessage, (
            f"{name}#{n}",
            PUBLISH,
            name,
            channel,
            record,
            now if created is None else _created_ns(created, now, channel),
            now,
            causes if causes.__class__ is tuple else tuple(causes),
            _frozen_attachments(attachments, channel) if attachments else _NO_ATTACHMENTS,
        ))
        if built is not None:
            msg.__dict__["_xml"] = built
        return msg

    def _make(
        self,
        kind: str,
        channel: str,
        xml: XMLLike,
        attachments: Mapping[str, Attachment] | None,
        causes: tuple[str, ...] | list[str],
        created: float | None,
        *,
        schema: Schema | None = None,
        transfer: bool = False,
    ) -> Message:
        if self.closed:
            raise BusError(f"participant {self.name!r} is closed")
        bus = self.bus
        if xml is None:  # a payload function not called: nobody will see this message
            check = False
        elif isinstance(xml, etree._Element):
            check = bus.validate_all
            if check:
                xml = _own_payload(xml, channel, transfer)
            else:  # trusted (the default policy): the module's own element, not validated
                xml = _own_payload(xml, channel, transfer)
        else:
            check = True
            xml = _own_payload(xml, channel, transfer)
        if check and kind == PUBLISH:  # (a trusted element is not validated: no schema needed)
            schema = bus.channel_schema(channel)
        if check:
            self._refuse_invalid(schema, xml, channel)
        now = bus.loop._now_ns
        name = self.name
        n = self._next_seq(now)
        return _tuple_new(Message, (
            f"{name}#{n}",
            kind,
            name,
            channel,
            xml,
            now if created is None else _created_ns(created, now, channel),
            now,
            causes if causes.__class__ is tuple else tuple(causes),
            _frozen_attachments(attachments, channel) if attachments else _NO_ATTACHMENTS,
        ))

    def _check_open(self) -> None:
        if self.closed:
            raise BusError(f"participant {self.name!r} is closed")

    def close(self) -> None:
        """Leave the bus: subscriptions end, methods are withdrawn, the name is freed."""
        if self.closed:
            return
        for sub in list(self.subscriptions):
            sub.close()
        for key in [k for k in self.bus._methods if k[0] == self.name]:
            del self.bus._methods[key]
        self.closed = True
        self.bus._participants.pop(self.name, None)


def _own_payload(xml: XMLLike, channel: str, transfer: bool = False) -> etree._Element:
    """The payload as a fresh document the sender can no longer change (text, or strict).

    Text is parsed with the hardened parser. An element is deep-copied into a
    document of its own (so receivers cannot see its parent, siblings or
    tail, and later changes by the sender do not reach them); an element
    from a document with a DOCTYPE (what its DTD expanded is in it already)
    or holding entity references is refused, as text with a DOCTYPE is,
    under every policy (the default one only skips the schema).
    """
    if not isinstance(xml, etree._Element):
        return parse_bytes(xml, source=f"<bus:{channel}>")
    if xml.getroottree().docinfo.internalDTD is not None:  # any DOCTYPE, even one without an internal subset
        raise XMLInputError("elements from documents with a DOCTYPE are refused on the bus", source=f"<bus:{channel}>")
    if transfer and xml.getparent() is None:
        own = xml
    else:
        own = xml.__copy__()  # lxml copies the whole subtree, in C
    if own.tail is not None:
        own.tail = None
    if len(own):  # an element without children holds no entity reference (len counts them)
        for _ in own.iter(_Entity):
            raise XMLInputError("entity references are refused on the bus", source=f"<bus:{channel}>")
    return own


def _frozen_attachments(attachments: Mapping[str, Attachment], channel: str) -> dict[str, Attachment]:
    """Read-only copies of numpy attachments (bytes are immutable already)."""
    out: dict[str, Attachment] = {}
    for name, value in attachments.items():
        if isinstance(value, np.ndarray):
            if value.dtype.hasobject:
                raise BusError(f"attachment {name!r} on {channel}: object arrays are refused (not data, not reproducible)")
            value = np.array(value, copy=True)
            value.flags.writeable = False
        elif not isinstance(value, bytes):
            raise BusError(f"attachment {name!r} on {channel}: must be bytes or a numpy array, not {type(value).__name__}")
        out[name] = value
    return out


_XML_UNSAFE = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _check_channel_name(name: str, *, allow_subtree: bool = False) -> None:
    body = name[:-3] if allow_subtree and name.endswith("/**") else name
    if not body.startswith("/") or "//" in body or (len(body) > 1 and body.endswith("/")) or "*" in body:
        raise BusError(f"bad channel name {name!r}: use /a/b/c (subscriptions may end in /**)")


class Bus:
    """The message bus of one simulation: participants, channels, methods, links."""

    def __init__(self, loop: VirtualEventLoop, *, network: Network, validation: str = VALIDATE_EDGES) -> None:
        if validation not in VALIDATIONS:
            raise BusError(f"unknown validation policy {validation!r}: use one of {VALIDATIONS}")
        self.loop = loop
        self.validation = validation
        # Read on every message: a plain attribute, not a property.
        self.validate_all = validation == VALIDATE_ALL
        self.network = network
        self._participants: dict[str, Participant] = {}
        self._exact: dict[str, list[Subscription]] = {}
        self._subtree: list[Subscription] = []
        self._route_cache: dict[str, tuple[Subscription, ...]] = {}
        self._receivers_cache: dict[str, tuple[str, ...]] = {}
        self._methods: dict[tuple[str, str], _Method] = {}
        self._channel_schemas: dict[str, Schema] = {}
        self._schema_cache: dict[str, Schema | None] = {}
        self._interceptors: list[Interceptor] = []
        # Per channel: the interceptors shown a publish on it (those without ``wants``, and those that want it), in
        # their order (:meth:`_watchers_of`; cleared by :meth:`interceptors_changed`).
        self._watchers: dict[str, tuple[Interceptor, ...]] = {}
        # Handler tasks still running. asyncio keeps only weak references to tasks: a handler
        # awaiting a future nobody else holds would be collected (and the run failed, at a time
        # the garbage collector picks); held here, it just never answers and the caller times out.
        self._handling: set[asyncio.Task[Any]] = set()
        # The interceptors that see deliveries and drops (those that declare
        # ``observes`` without them, such as the run's dispatcher, are spared the call).
        self._delivery_interceptors: list[Interceptor] = []
        # Per (sender name, receiver name): [the time of the last delivery scheduled], for FIFO per pair.
        self._last_delivery: dict[tuple[str, str], list[int]] = {}
        network.on_change(self._forget_plans)
        # Message counters per participant name: ids stay unique across re-registration.
        self._counters: dict[str, list[int]] = {}
        #: The rate guard: a participant sending more than this many messages within one virtual
        #: second is failed (:meth:`flooded`). Far above any sane rate (a 100 Hz sensor sends 100;
        #: the busiest module of a home tour a few hundred): a loop publishing with a tiny sleep
        #: would otherwise grow the run's memory until the process is killed.
        self.max_sends_per_s = MAX_SENDS_PER_S
        #: Called with a participant that exceeded the rate (the simulation crashes its module);
        #: it must raise (else :class:`BusError` is raised: the message is not sent).
        self.on_flood: Callable[[Participant], None] | None = None
        self.sent = 0
        self.delivered = 0
        self.dropped = 0
        self.unheard = 0  # published on a channel nobody subscribes to (sent, never delivered, not a drop)

    # -------------------------------------------------------- registration
    def participant(self, name: str, *, host: str = "robot") -> Participant:
        """Register a participant; names are unique while registered."""
        if not name or "/" in name or "#" in name:
            raise BusError(f"bad participant name {name!r}: no '/' or '#', not empty")
        if name in self._participants:
            raise BusError(f"a participant named {name!r} is already registered")
        host = self.network.host_for(name, host)
        self.network.ensure_host(host)
        p = Participant(self, name, host)
        self._participants[name] = p
        return p

    def get(self, name: str) -> Participant:
        """The registered participant ``name``."""
        try:
            return self._participants[name]
        except KeyError:
            raise UnknownParticipantError(f"no participant named {name!r} is registered") from None

    def registry(self) -> list[dict[str, Any]]:
        """Every participant with its host, channels, subscriptions and methods (sorted)."""
        out = []
        for name in sorted(self._participants):
            p = self._participants[name]
            out.append(
                {
                    "name": name,
                    "host": p.host,
                    "hung": p.hung,
                    "publishes": sorted(p.published),
                    "subscribes": sorted(s.pattern for s in p.subscriptions if not s.closed),
                    "methods": sorted(m for (s, m) in self._methods if s == name),
                }
            )
        return out

    def declare_channel(self, channel: str, schema: SchemaLike) -> None:
        """Type a channel: every message published on it must satisfy ``schema``.

        The bus checks that when it sends, per its validation policy (see the
        module docstring): always when strict, else for payloads sent as text.

        ``/a/b/**`` types every channel under ``/a/b/`` that has no type of its
        own (the kernel types ``/system/heartbeat/**`` so that nobody can put
        an untyped heartbeat there); the longest declared prefix wins.
        """
        _check_channel_name(channel, allow_subtree=True)
        sch = _as_schema(schema)
        if sch is None:
            self._channel_schemas.pop(channel, None)
        else:
            self._channel_schemas[channel] = sch
        self._schema_cache.clear()

    def channel_schema(self, channel: str) -> Schema | None:
        """The schema messages on ``channel`` must satisfy (its own, else its nearest typed subtree's)."""
        try:
            return self._schema_cache[channel]
        except KeyError:
            pass
        sch = self._channel_schemas.get(channel)
        if sch is None:
            cut = len(channel)
            while sch is None and cut > 0:
                cut = channel.rfind("/", 0, cut)
                if cut < 0:
                    break
                sch = self._channel_schemas.get(channel[:cut] + "/**")
        self._schema_cache[channel] = sch
        return sch

    def add_interceptor(self, interceptor: Interceptor) -> None:
        """Observe every send, delivery and drop (called synchronously, in order).

        An interceptor with an ``observes`` attribute (a collection of
        ``"send"``, ``"deliver"``, ``"drop"``) is called only for those events;
        one that watches sends only thus costs nothing per delivery. One with a
        ``wants(channel)`` method is shown only the publishes on channels it wants
        (asked once per channel; call :meth:`interceptors_changed` when that changes).
        """
        self._interceptors.append(interceptor)
        self._sort_interceptors()

    def remove_interceptor(self, interceptor: Interceptor) -> None:
        self._interceptors.remove(interceptor)
        self._sort_interceptors()

    def interceptors_changed(self) -> None:
        """What an interceptor ``wants`` may have changed (the run's dispatcher got a handler): ask again."""
        self._watchers.clear()

    def _watchers_of(self, channel: str) -> tuple[Interceptor, ...]:
        """The interceptors a publish on ``channel`` is shown to (kept per channel): every one without a
        ``wants(channel)`` method (the trace recorder), and those that want it, in their order."""
        watchers = []
        for fn in self._interceptors:
            wants = getattr(fn, "wants", None)
            if wants is None or wants(channel):
                watchers.append(fn)
        got = self._watchers[channel] = tuple(watchers)
        return got

    def flooded(self, participant: Participant) -> None:
        """``participant`` sent more than :attr:`max_sends_per_s` messages in one virtual second: fail it.

        Raises (the message being sent is not sent): whatever :attr:`on_flood` raises, else :class:`BusError`.
        """
        if self.on_flood is not None:
            self.on_flood(participant)
        raise BusError(f"participant {participant.name!r} sent more than {self.max_sends_per_s} messages within one "
                       "virtual second (a send loop without a real wait?): refused")

    def _has_audience(self, channel: str) -> bool:
        """Whether a message on ``channel`` would reach anyone: a subscriber, or an interceptor.

        An interceptor with a ``wants(channel)`` method is asked; one without
        sees every send (the trace recorder).
        """
        routes = self._route_cache.get(channel)
        if routes is None:
            routes = self._routes(channel)
        if routes:
            return True
        watchers = self._watchers.get(channel)
        if watchers is None:
            watchers = self._watchers_of(channel)
        return bool(watchers)

    def _sort_interceptors(self) -> None:
        self._watchers.clear()
        self._delivery_interceptors = [
            fn for fn in self._interceptors
            if not {DELIVER, DROP}.isdisjoint(getattr(fn, "observes", (SEND, DELIVER, DROP)))
        ]

    # ------------------------------------------------------ subscriptions
    def _add_subscription(self, sub: Subscription) -> None:
        if sub.pattern.endswith("/**"):
            self._subtree.append(sub)
        else:
            self._exact.setdefault(sub.pattern, []).append(sub)
        self._route_cache.clear()
        self._receivers_cache.clear()
        self._forget_plans()

    def _remove_subscription(self, sub: Subscription) -> None:
        if sub.pattern.endswith("/**"):
            self._subtree.remove(sub)
        else:
            lst = self._exact.get(sub.pattern, [])
            if sub in lst:
                lst.remove(sub)
        if sub in sub.participant.subscriptions:
            sub.participant.subscriptions.remove(sub)
        self._route_cache.clear()
        self._receivers_cache.clear()
        self._forget_plans()

    def _forget_plans(self) -> None:
        """Subscriptions, hosts or links changed: every publisher's delivery plans are rebuilt on use."""
        for p in self._participants.values():
            p._plans.clear()

    def _fifo(self, sender: str, receiver: str) -> list[int]:
        """The FIFO state of one (sender, receiver) pair: ``[last delivery time scheduled, ns]``."""
        key = (sender, receiver)
        state = self._last_delivery.get(key)
        if state is None:
            state = self._last_delivery[key] = [0]
        return state

    def _plan(self, sender: Participant, channel: str) -> tuple[tuple[Any, ...], ...]:
        """How ``sender``'s messages on ``channel`` reach each receiver, worked out once.

        One entry per route, in delivery order: ``(subscription, receiver, fifo, lo, span, path)``
        where ``fifo`` is the pair's FIFO state, ``path`` the network's :class:`~homesim.network.Route`
        and ``lo``/``span`` the link's uniform delay (seconds) when the link is simple (no loss,
        jitter or bandwidth limit: one uniform draw, made inline by ``_publish``), else ``lo``
        is None and the network draws. Cached per participant; dropped when subscriptions,
        hosts or links change.
        """
        sender.published.add(channel)
        routes = self._route_cache.get(channel)
        if routes is None:
            routes = self._routes(channel)
        net = self.network
        plan = []
        for sub in routes:
            receiver = sub.participant
            path = net.route(sender.host, receiver.host)
            plan.append((sub, receiver, self._fifo(sender.name, receiver.name), path.lo, path.span, path))
        out = sender._plans[channel] = tuple(plan)
        return out

    def _routes(self, channel: str) -> tuple[Subscription, ...]:
        cached = self._route_cache.get(channel)
        if cached is not None:
            return cached
        subs = list(self._exact.get(channel, ()))
        for s in self._subtree:
            prefix = s.pattern[:-3]
            if prefix == "" or channel == prefix or channel.startswith(prefix + "/"):
                subs.append(s)
        # Order: registration order is deterministic; keep it.
        routes = tuple(subs)
        self._route_cache[channel] = routes
        return routes

    # ---------------------------------------------------------- delivery
    def _observe(self, obs: Observation) -> None:
        for fn in self._interceptors if obs.event == SEND else self._delivery_interceptors:
            fn(obs)

    def _schedule(self, sender: Participant, receiver: Participant, msg: Message, action: Callable[..., None], *args: Any) -> None:
        """Deliver ``msg`` to ``receiver`` after the link's delay, FIFO per pair; ``action`` gets the
        link's statistics and the delay last, to count the message there if it is delivered."""
        net = self.network
        path = net.route(sender.host, receiver.host)
        delay = net.draw(path, message_size(msg) if path.link.bandwidth_bps else 0)
        if delay is None:
            self._drop(msg, receiver.name, "lost")
            return
        fifo = self._fifo(sender.name, receiver.name)
        now = self.loop._now_ns
        when = now + delay
        if when < fifo[0]:
            when = fifo[0]
        fifo[0] = when
        # Deliveries run in no copied context: a receiver does not inherit the
        # sender's context variables (and copying one per message is costly).
        self.loop._call_at_bare(when, action, (receiver, msg, *args, path.stats, when - now))

    def _drop(self, msg: Message, receiver: str, reason: str) -> None:
        self.dropped += 1
        if self._delivery_interceptors:
            obs = _tuple_new(Observation, (self.loop._now_ns, DROP, msg, (receiver,), reason))
            for fn in self._delivery_interceptors:
                fn(obs)

    def _receivable(self, receiver: Participant, msg: Message) -> bool:
        if receiver.closed:
            self._drop(msg, receiver.name, "receiver closed")
            return False
        if receiver.hung:
            self._drop(msg, receiver.name, "receiver hung")
            return False
        return True

    def _publish(self, sender: Participant, msg: Message) -> None:
        channel = msg[3]
        plan = sender._plans.get(channel)
        if plan is None:
            plan = self._plan(sender, channel)
        self.sent += 1
        if not plan:
            self.unheard += 1
        if self._interceptors and msg[4] is not None:  # (an unbuilt lazy payload has no audience)
            watchers = self._watchers.get(channel)
            if watchers is None:
                watchers = self._watchers_of(channel)
            if watchers:  # (an interceptor is shown the channels it wants only: the run's dispatcher, the backstop)
                receivers = self._receivers_cache.get(channel)
                if receivers is None:
                    routes = self._route_cache.get(channel) or self._routes(channel)
                    receivers = self._receivers_cache[channel] = tuple(sorted({s.participant.name for s in routes}))
                obs = _tuple_new(Observation, (msg.sent_ns, SEND, msg, receivers, ""))
                for fn in watchers:
                    fn(obs)
        if not plan:
            return
        # What _schedule does per receiver, inlined (this is the hot path of every message):
        # the link's delay, FIFO per pair, a _Delivery timer pushed on the loop's TimerQueue.
        loop = self.loop
        now = loop._now_ns
        push = loop.timers.push
        deliver = self._deliver_publish
        draws = self.network._draws
        left = len(plan)
        size = -1
        for sub, receiver, fifo, lo, span, path in plan:
            left -= 1
            # Each receiver gets a payload of its own (as XCF deserialises one
            # per receiver): one receiver moving nodes cannot change another's.
            own = _copy_message(msg) if left else msg
            if lo is None:  # a link with loss, jitter or a bandwidth: the network draws
                if path.link.bandwidth_bps and size < 0:
                    size = message_size(msg)
                delay = self.network.draw(path, size if size > 0 else 0)
                if delay is None:
                    self._drop(own, receiver.name, "lost")
                    continue
            else:  # Network.delay_ns without loss or jitter: one uniform draw (the same draws)
                i = draws._ui
                if i == len(draws._u):
                    draws._u = draws._rng.random(draws.block).tolist()
                    i = 0
                draws._ui = i + 1
                delay = int(round((lo + span * draws._u[i]) * NS_PER_S))
            when = now + delay
            if when < fifo[0]:
                when = fifo[0]
            fifo[0] = when
            # Deliveries run in no copied context: a receiver does not inherit the
            # sender's context variables (and copying one per message is costly).
            # The link's statistics count it when it is delivered (not a message the receiver
            # no longer takes: closed, hung, unsubscribed); a loss is counted apart, above.
            handle = _new(_Delivery)
            handle._callback = deliver
            handle._args = (receiver, own, sub, path.stats, when - now)
            push(when, handle)

    def _deliver_publish(self, receiver: Participant, msg: Message, sub: Subscription, stats: LinkStats, ns: int) -> None:
        if sub.closed:
            self._drop(msg, receiver.name, "receiver closed")
            return
        if receiver.closed or receiver.hung:
            self._receivable(receiver, msg)
            return
        self.delivered += 1
        stats.add(ns)
        if self._delivery_interceptors:
            obs = _tuple_new(Observation, (self.loop._now_ns, DELIVER, msg, (receiver.name,), ""))
            for fn in self._delivery_interceptors:
                fn(obs)
        if sub.handler is not None:
            sub.delivered += 1
            try:
                result = sub.handler(msg)
            except BadMessageError as exc:  # the sender's bad data, not our bug: report, go on
                self._drop(msg, receiver.name, f"refused by the receiver: {exc}")
                return
            if result is not None and inspect.isawaitable(result):
                self._hold(self.loop.create_task(_await_reporting(result, self, msg, receiver.name), name=f"{receiver.name}:{sub.pattern}<-{msg.id}"))
        else:
            dropped = sub._push(msg)
            if dropped is not None:
                self._drop(dropped, receiver.name, "overflow")

    def _request(self, caller: Participant, entry: _Method, msg: Message, fut: asyncio.Future[Message] | None) -> None:
        self.sent += 1
        if self._interceptors:
            self._observe(Observation(msg.sent_ns, SEND, msg, (entry.server.name,)))
        self._schedule(caller, entry.server, msg, self._deliver_request, entry, caller, fut)

    def _deliver_request(self, server: Participant, msg: Message, entry: _Method, caller: Participant, fut: asyncio.Future[Message] | None,
                         stats: LinkStats, ns: int) -> None:
        if self._methods.get((server.name, entry.name)) is not entry:
            self._drop(msg, server.name, "method withdrawn")
            return
        if not self._receivable(server, msg):
            return
        self.delivered += 1
        stats.add(ns)
        if self._interceptors:
            self._observe(Observation(self.loop.now_ns, DELIVER, msg, (server.name,)))
        try:
            result = entry.handler(msg)
        except Exception as exc:  # the server's failure becomes the caller's error
            self._reply_error(server, caller, msg, fut, exc)
            return
        if inspect.isawaitable(result):
            task = self.loop.create_task(_await(result), name=f"{server.name}/{entry.name}<-{msg.id}")
            task.add_done_callback(lambda t: self._reply_from_task(t, server, caller, msg, entry, fut))
            self._hold(task)
        else:
            self._reply(server, caller, msg, entry, fut, result)

    def _hold(self, task: asyncio.Task[Any]) -> None:
        """Keep a handler's task alive until it ends (see ``_handling``)."""
        self._handling.add(task)
        task.add_done_callback(self._handling.discard)

    def _reply_from_task(self, task: asyncio.Task[Any], server: Participant, caller: Participant, request: Message, entry: _Method, fut: asyncio.Future[Message] | None) -> None:
        if task.cancelled():
            return
        exc = task.exception()
        if exc is not None:
            self._reply_error(server, caller, request, fut, exc)
        else:
            self._reply(server, caller, request, entry, fut, task.result())

    def _reply(self, server: Participant, caller: Participant, request: Message, entry: _Method, fut: asyncio.Future[Message] | None, result: Any) -> None:
        if server.closed or server.hung:
            return
        if not isinstance(result, etree._Element):
            exc = BusError(f"handler of {server.name}/{entry.name} returned {type(result).__name__}, not an XML element")
            self._reply_error(server, caller, request, fut, exc)
            return
        try:
            reply = server._make(REPLY, request.channel, result, None, (request.id,), None, schema=entry.reply_schema)
        except MessageValidationError as exc:
            self._reply_error(server, caller, request, fut, exc)
            return
        self._send_reply(server, caller, reply, fut)

    def _reply_error(self, server: Participant, caller: Participant, request: Message, fut: asyncio.Future[Message] | None, exc: BaseException) -> None:
        if server.closed or server.hung:
            return
        err = etree.Element("error", type=type(exc).__name__)
        err.text = _XML_UNSAFE.sub("\ufffd", str(exc))
        reply = server._make(ERROR, request.channel, err, None, (request.id,), None)
        self._send_reply(server, caller, reply, fut)

    def _send_reply(self, server: Participant, caller: Participant, reply: Message, fut: asyncio.Future[Message] | None) -> None:
        self.sent += 1
        if self._interceptors:
            self._observe(Observation(reply.sent_ns, SEND, reply, (caller.name,)))
        self._schedule(server, caller, reply, self._deliver_reply, fut)

    def _deliver_reply(self, caller: Participant, reply: Message, fut: asyncio.Future[Message] | None, stats: LinkStats, ns: int) -> None:
        if not self._receivable(caller, reply):
            return
        self.delivered += 1
        stats.add(ns)
        if self._interceptors:
            self._observe(Observation(self.loop.now_ns, DELIVER, reply, (caller.name,)))
        if fut is None or fut.done():
            return
        if reply.kind == ERROR:
            fut.set_exception(RemoteCallFailed(f"{reply.channel} failed on the server: {reply.xml.get('type')}: {reply.xml.text}"))
        else:
            fut.set_result(reply)


def message_size(msg: Message) -> int:
    """Bytes a message puts on a link: its serialized XML plus its attachments' raw bytes.

    Computed only for links with a bandwidth (the delay's size term). A typed message's record
    gives the length of its XML from its fields (:meth:`Typed.size`): sizing builds no XML.
    """
    if msg.__class__ is TypedMessage:
        n = tuple.__getitem__(msg, 4).size()
    else:
        xml = msg.xml
        n = len(etree.tostring(xml)) if xml is not None else 0
    for value in msg[8].values():
        n += value.nbytes if isinstance(value, np.ndarray) else len(value)
    return n


def _copy_message(msg: Message) -> Message:
    """A receiver's own message: a copy of the payload; a typed message's record is shared (immutable),
    only the message object is new (so the XML one receiver builds from it is its own)."""
    if msg.__class__ is TypedMessage:
        return _tuple_new(TypedMessage, msg)
    return _tuple_new(Message, (msg[0], msg[1], msg[2], msg[3], msg[4].__copy__(), msg[5], msg[6], msg[7], msg[8]))


async def _await(result: Awaitable[Any]) -> Any:
    return await result


async def _await_reporting(result: Awaitable[Any], bus: Bus, msg: Message, receiver: str) -> Any:
    """Await an async handler; a :class:`BadMessageError` is reported as a drop, not a failure."""
    try:
        return await result
    except BadMessageError as exc:
        bus._drop(msg, receiver, f"refused by the receiver: {exc}")
        return None


def seconds(ns: int) -> float:
    """Integer nanoseconds to float seconds."""
    return ns / NS_PER_S
