"""Reading a trace as module communication: messages, causes, processing spans, streams, phases.

The trace (:mod:`homesim.trace`) records each send with its ``causes`` (the
ids of the messages it was made from) and each delivery with its time. A
module's *processing span* is read from that, with nothing modelled here:
it runs from the delivery of a message's latest cause to the module that
sent the message, to the send (the understanding's span for a greeting is
the recognition time; the supervisor's is its reconfiguration time).
Messages sent several times a second for a sustained time are *continuous
streams* (scans, odometry, tracks; the papers' Fig. 6 draws them lighter);
the others are *events*. Heartbeats (``/system/heartbeat/``) are left out
unless asked for. Phases: "A start" at 0, and whatever the registered phase
markers (:func:`register_phases`; the run package's read the robot's
supervisor log) find in the records. Spans carry what they measure (``kind``):
registered span markers (:func:`register_spans`) name or replace the spans they
recognise (the run package's: speech detection, speech recognition, the ES's
reconfiguration). With the run's deployment in the trace header (``run.hosts``,
``run.placement``, ``run.link_worst_ms``), lanes are grouped by host and the
messages that crossed a slow link (slower than the LAN) are known (:meth:`Timeline.crosses_slow_link`).

Both passes stream the file; memory holds one small record per event
message in the asked window, a thinned sample of each stream, and bounded
look-up tables of recent sends and deliveries (:data:`RECENT`).
"""

from __future__ import annotations

import os
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import Any

from .errors import InputError
from .trace import read_trace

#: How many recent sends and deliveries are kept to resolve causes (a cause older than this is not linked).
RECENT = 1 << 16
#: A stream is continuous when it sends at least this often (per second) ...
STREAM_RATE = 0.9
#: ... and at least this many messages.
STREAM_MIN = 20
#: A timeline shows at most about this many messages of each stream in its window (thinned evenly).
STREAM_SAMPLES = 40
HEARTBEAT = "/system/heartbeat/"
SENDS = ("publish", "request", "reply", "error")
#: A phase marker reads every sent record (``channel``, record) in trace order and returns the
#: phases it starts there, as ``(mark, label)`` pairs; it may keep state between records.
PhaseMarker = Callable[[str, dict[str, Any]], Iterable[tuple[str, str]]]
#: Factories of phase markers, one marker per timeline read (the run package registers its robot's).
PHASE_MARKERS: list[Callable[[], PhaseMarker]] = []


def register_phases(factory: Callable[[], PhaseMarker]) -> None:
    """Add a phase marker factory (each :func:`read_timeline` makes a fresh marker from it)."""
    if factory not in PHASE_MARKERS:
        PHASE_MARKERS.append(factory)


#: A span marker reads every sent record (``channel``, record, the span :func:`walk` found for it
#: or None) in trace order and returns the span to draw for it (with its ``kind``), or None to keep
#: what it was given; it may keep state between records.
SpanMarker = Callable[[str, dict[str, Any], "Span | None"], "Span | None"]
#: Factories of span markers, one marker per timeline read (the run package registers its robot's).
SPAN_MARKERS: list[Callable[[], SpanMarker]] = []


def register_spans(factory: Callable[[], SpanMarker]) -> None:
    """Add a span marker factory (each :func:`read_timeline` makes a fresh marker from it)."""
    if factory not in SPAN_MARKERS:
        SPAN_MARKERS.append(factory)


class _Recent(OrderedDict):
    """A bounded map: the oldest entries fall out past ``RECENT``."""

    def put(self, key: Any, value: Any) -> None:
        self[key] = value
        if len(self) > RECENT:
            self.popitem(last=False)


@dataclass(frozen=True)
class Message:
    """One sent message as the timeline draws it (``delivered``: receiver -> time)."""

    id: str
    kind: str
    sender: str
    channel: str
    t: float
    label: str
    causes: tuple[str, ...]
    continuous: bool
    delivered: dict[str, float] = field(default_factory=dict, compare=False)


@dataclass(frozen=True)
class Span:
    """A module working: from the delivery of a message's latest cause to the module, to its send.

    ``kind`` says what it measures ("processing" unless a span marker names it).
    """

    lane: str
    start: float
    end: float
    cause: str
    effect: str
    kind: str = "processing"


@dataclass(frozen=True)
class Flow:
    """A cause -> message link (ids, senders and send times of both)."""

    cause: str
    cause_sender: str
    cause_t: float
    effect: str
    effect_sender: str
    effect_t: float


@dataclass(frozen=True)
class Phase:
    """A phase mark (the papers' A-E, plus teaching and good-bye)."""

    t: float
    mark: str
    label: str


@dataclass(frozen=True)
class StreamStats:
    count: int
    first: float
    last: float

    @property
    def continuous(self) -> bool:
        span = self.last - self.first
        return self.count >= STREAM_MIN and span > 0 and (self.count - 1) / span >= STREAM_RATE


@dataclass
class Timeline:
    """Everything the Fig. 6 drawing needs, for the window ``start``-``end``."""

    scenario: str
    seed: int
    start: float
    end: float
    lanes: list[str]
    messages: list[Message]  # events and the thinned stream sample, by send time
    spans: list[Span]
    flows: list[Flow]
    phases: list[Phase]
    streams: dict[tuple[str, str], StreamStats]
    hosts: dict[str, str] = field(default_factory=dict)  # lane -> host (the run's deployment, from the header)
    host_order: list[str] = field(default_factory=list)
    #: (sender, receiver) lanes joined by a slow link -> that link's name
    slow: dict[tuple[str, str], str] = field(default_factory=dict)
    #: the links the run used that are slower than its fastest one between hosts (the LAN), slowest first
    slow_links: tuple[str, ...] = ()

    def crosses_slow_link(self, sender: str, receiver: str) -> bool:
        """Whether a message from ``sender`` to ``receiver`` went over a slow link (one of :attr:`slow_links`)."""
        return (sender, receiver) in self.slow


def label_of(rec: dict[str, Any]) -> str:
    """A short label: the root element and its name (``event greeting``), or the words of an utterance or an understood frame."""
    xml = rec.get("xml") or ""
    tag = xml[1:].split(" ", 1)[0].split(">", 1)[0].split("/", 1)[0]
    name = ""
    head = xml[:xml.find(">") + 1]  # the root's start tag: a child's name (a state's <event name>) is not the root's
    for key in (' name="', ' text="', ' state="'):
        i = head.find(key)
        if i >= 0:
            name = head[i + len(key):head.find('"', i + len(key))]
            break
    if not name and tag == "utterance":
        name = xml[xml.find(">") + 1:xml.rfind("<")]
    if tag == "understood" and "<words>" in xml:  # what was understood: its words, not a slot's value
        name = xml[xml.find("<words>") + 7:xml.find("</words>")]
    return f"{tag} {name}".strip()[:60]


_STR = (str,)
_NUM = (int, float)
#: The fields the readers here use, by record kind, with their JSON types.
_FIELDS: dict[str, dict[str, tuple[type, ...]]] = {
    "send": {"t": _NUM, "sender": _STR, "channel": _STR, "id": _STR, "kind": _STR},
    "deliver": {"t": _NUM, "id": _STR},
}


def check_record(path: str | os.PathLike[str], n: int, rec: dict[str, Any]) -> None:
    """A send or delivery record with the fields and types the readers use; else ``InputError`` at ``path:n``."""
    kind = rec.get("kind")
    want = _FIELDS["send"] if kind in SENDS else _FIELDS["deliver"] if kind == "deliver" else None
    if want is None:
        return
    for name, types in want.items():
        v = rec.get(name)
        if not isinstance(v, types) or isinstance(v, bool):
            raise InputError(f"a {kind} record without a valid {name!r} (got {v!r:.60})", source=str(path), line=n)
    for name in ("receivers", "causes"):
        v = rec.get(name, [])
        if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
            raise InputError(f"a {kind} record whose {name!r} is not a list of names (got {v!r:.60})", source=str(path), line=n)
    if "xml" in rec and not isinstance(rec["xml"], str):
        raise InputError(f"a {kind} record whose 'xml' is not text", source=str(path), line=n)


def channel_stats(path: str | os.PathLike[str]) -> tuple[dict[str, Any], dict[tuple[str, str], StreamStats]]:
    """First pass: the header, and per (sender, channel) the count and first/last send time."""
    header: dict[str, Any] | None = None
    acc: dict[tuple[str, str], list[float]] = {}
    for n, rec in enumerate(read_trace(path), 1):
        if header is None:
            if not isinstance(rec, dict) or "homesim_trace" not in rec:
                raise InputError("not a homesim trace (no header)", source=str(path), line=1)
            header = rec
            continue
        check_record(path, n, rec)
        if rec.get("kind") in SENDS:
            key = (rec["sender"], rec["channel"])
            a = acc.get(key)
            if a is None:
                acc[key] = [1, rec["t"], rec["t"]]
            else:
                a[0] += 1
                a[2] = rec["t"]
    if header is None:
        raise InputError("empty trace", source=str(path))
    return header, {k: StreamStats(int(c), f, la) for k, (c, f, la) in acc.items()}


@dataclass
class Send:
    """A send as :func:`walk` reports it: the record, whether it is a stream, its span and cause links."""

    rec: dict[str, Any]
    continuous: bool
    span: Span | None
    flows: list[Flow]


@dataclass
class Delivery:
    rec: dict[str, Any]


def walk(path: str | os.PathLike[str], streams: dict[tuple[str, str], StreamStats], *,
         progress: Callable[[float, float], None] | None = None) -> Iterator[Send | Delivery]:
    """Second pass: every send with its processing span and cause links, and every delivery, in file order.

    ``progress(t, end)`` is called every few thousand records with the virtual time reached."""
    sent = _Recent()  # id -> (sender, t)
    delivered = _Recent()  # (id, receiver) -> t
    end = max((s.last for s in streams.values()), default=0.0)
    it = read_trace(path)
    next(it, None)  # the header
    for n, rec in enumerate(it):
        if progress is not None and n % 4096 == 0 and isinstance(rec.get("t"), (int, float)):
            progress(rec["t"], end)
        kind = rec.get("kind")
        if kind == "deliver":
            for r in rec.get("receivers", ()):
                delivered.put((rec["id"], r), rec["t"])
            yield Delivery(rec)
            continue
        if kind not in SENDS:
            continue
        sender, t = rec["sender"], rec["t"]
        cont = streams[(sender, rec["channel"])].continuous
        flows: list[Flow] = []
        latest: tuple[float, str] | None = None
        for c in rec.get("causes", ()):
            src = sent.get(c)
            if src is not None:
                flows.append(Flow(c, src[0], src[1], rec["id"], sender, t))
            got = delivered.get((c, sender))
            if got is not None and got <= t and (latest is None or got > latest[0]):
                latest = (got, c)
        span = None if latest is None else Span(sender, latest[0], t, latest[1], rec["id"])
        sent.put(rec["id"], (sender, t))
        yield Send(rec, cont, span, flows)


def read_timeline(path: str | os.PathLike[str], *, start: float | None = None, end: float | None = None,
                  heartbeats: bool = False, stream_per_s: float | None = None,
                  progress: Callable[[float, float], None] | None = None) -> Timeline:
    """The timeline of a trace file between ``start`` and ``end`` (virtual seconds; default: all of it).

    Stream messages are thinned to at most ``stream_per_s`` per second per
    stream (default: 2 per second, fewer in a long window, so that each stream
    shows at most :data:`STREAM_SAMPLES` arrows: a whole run stays readable).
    Fails (``InputError``) for a file that is not a trace or an empty window.
    """
    header, streams = channel_stats(path)
    t0 = 0.0 if start is None else start
    t1 = max((s.last for s in streams.values()), default=0.0) if end is None else end
    if t1 <= t0:
        raise InputError(f"the window {t0:g}-{t1:g} s is empty", source=str(path))
    if stream_per_s is None:
        stream_per_s = min(2.0, STREAM_SAMPLES / (t1 - t0))
    msgs: dict[str, Message] = {}
    order: list[Message] = []
    spans: dict[tuple[str, float], Span] = {}
    flows: list[Flow] = []
    phases: list[Phase] = [Phase(0.0, "A", "start")] if t0 <= 0.0 else []
    last_sample: dict[tuple[str, str], float] = {}
    markers = [factory() for factory in PHASE_MARKERS]
    span_markers = [factory() for factory in SPAN_MARKERS]
    depth: _Recent = _Recent()
    lane_depths: dict[str, list[int]] = {}  # a module's events' causal depths (one int per event message)
    lane_first: dict[str, float] = {}
    stream_first: dict[str, float] = {}  # modules that send streams: their first stream message
    for ev in walk(path, streams, progress=progress):
        rec = ev.rec
        if isinstance(ev, Delivery):
            m = msgs.get(rec["id"])
            if m is not None:
                for r in rec.get("receivers", ()):
                    m.delivered.setdefault(r, rec["t"])
            continue
        t, sender, ch = rec["t"], rec["sender"], rec["channel"]
        if ch.startswith(HEARTBEAT) and not heartbeats:
            continue
        d = 1 + max((depth.get(c, -1) for c in rec.get("causes", ())), default=-1)
        depth.put(rec["id"], d)
        for marker in markers:
            for mark, label in marker(ch, rec):
                if t0 <= t <= t1:
                    phases.append(Phase(t, mark, label))
        span = None if ev.continuous else ev.span
        for smarker in span_markers:
            named = smarker(ch, rec, span)
            if named is not None:
                span = named
        if not t0 <= t <= t1:
            continue
        if not ev.continuous:
            lane_depths.setdefault(sender, []).append(d)
            lane_first.setdefault(sender, t)
        else:
            stream_first.setdefault(sender, t)
            key = (sender, ch)
            if t - last_sample.get(key, -1e18) < 1.0 / stream_per_s:
                continue
            last_sample[key] = t
        m = Message(rec["id"], rec["kind"], sender, ch, t, label_of(rec), tuple(rec.get("causes", ())), ev.continuous)
        msgs[m.id] = m
        order.append(m)
        if not ev.continuous:
            flows.extend(ev.flows)
            if span is not None:
                k = (sender, span.start)
                old = spans.get(k)
                spans[k] = span if old is None else Span(sender, old.start, max(old.end, t), old.cause, old.effect,
                                                         span.kind if span.kind != "processing" else old.kind)
        if len(msgs) > RECENT:  # only deliveries of recent messages are still to come
            msgs.pop(next(iter(msgs)))
    # Lanes: modules that only stream (the sensors) first, then by the median causal depth of their events
    # (how many messages lie between them and a sensor), so that arrows mostly run down.
    receivers = {r for m in order for r in m.delivered}
    names = set(lane_depths) | set(stream_first) | receivers

    def rank(name: str) -> tuple[int, float, float, str]:
        if name in lane_depths:
            ds = sorted(lane_depths[name])
            return (1, ds[len(ds) // 2], lane_first[name], name)
        if name in stream_first:
            return (0, 0, stream_first[name], name)
        return (2, 0, t1, name)
    hosts, host_order, slow, slow_links = _deployment(header, names, order)
    order_of = {h: i for i, h in enumerate(host_order)}
    lanes = sorted(names, key=lambda n: (order_of.get(hosts.get(n, ""), len(order_of)), rank(n)))
    return Timeline(str(header.get("scenario", "?")), int(header.get("seed", 0)), t0, t1, lanes, order,
                    sorted(spans.values(), key=lambda s: (s.start, s.lane)), flows, phases, streams,
                    hosts, host_order, slow, slow_links)


def _deployment(header: dict[str, Any], names: set[str], order: list[Message]
                ) -> tuple[dict[str, str], list[str], dict[tuple[str, str], str], tuple[str, ...]]:
    """From the header's run deployment: lane -> host, the hosts in order, the (sender, receiver)
    pairs whose messages took a slow link -> that link (as the network does: the pair's route if it
    has one, else the slower of the sender's uplink and the receiver's link), and the slow links,
    slowest first. A slow link is one slower (worst case) than the fastest link the run's hosts use:
    with the papers' deployment the WLAN; with a laptop that receives over a queued downlink and sends
    over the WLAN, both (its messages out are slower than the LAN too)."""
    run = header.get("run") if isinstance(header.get("run"), dict) else {}

    def mapping(key: str) -> dict[str, Any]:
        v = run.get(key)
        return v if isinstance(v, dict) else {}

    host_links, placement, worst = mapping("hosts"), mapping("placement"), mapping("link_worst_ms")
    uplinks, routes = mapping("uplinks"), mapping("routes")
    if not placement:
        return {}, [], {}, ()
    default = placement.get("default")
    hosts = {n: str(placement.get(n, default)) for n in names}
    slow: dict[tuple[str, str], str] = {}
    used = set(host_links.values()) | set(uplinks.values()) | set(routes.values())
    kinds = {lk for lk in used if isinstance(worst.get(lk), (int, float))}
    if len(kinds) < 2:
        return hosts, list(host_links), slow, ()
    fastest = min(worst[lk] for lk in kinds)
    slow_kinds = {lk for lk in kinds if worst[lk] > fastest}
    for m in order:
        for r in m.delivered:
            a, b = hosts.get(m.sender, ""), hosts.get(r, "")
            la, lb = uplinks.get(a, host_links.get(a)), host_links.get(b)
            if a == b or la is None or lb is None:
                continue
            link = routes.get(f"{a}->{b}") or (la if worst.get(la, 0) >= worst.get(lb, 0) else lb)
            if link in slow_kinds:
                slow[(m.sender, r)] = link
    return hosts, list(host_links), slow, tuple(sorted(slow_kinds, key=lambda lk: (-worst[lk], lk)))
