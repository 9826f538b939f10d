"""Heartbeats: modules fail perceptibly.

The papers: "messages which are initiated by the main loop of each module and
sent in fixed intervals"; a module that stops sending them "stopped working
correctly", and corrective action can be taken. :class:`Heartbeat` is called
from a module's main loop (so a hung loop stops beating);
:class:`HeartbeatMonitor` watches every module's beats and publishes
``module_failed`` once a module has missed ``misses`` beats in a row, and
``module_recovered`` when beats come back.
"""

from __future__ import annotations

import asyncio
from pathlib import Path

from lxml import etree

from .bus import SEND, Observation, Participant
from .errors import BadMessageError
from .message import Message, Typed
from .vloop import NS_PER_S, to_ns

HEARTBEAT_PREFIX = "/system/heartbeat"
HEALTH_CHANNEL = "/system/health"
#: The kernel's message types (heartbeat, module_failed/recovered, fault).
SYSTEM_SCHEMA = Path(__file__).with_name("schemas") / "system.xsd"
#: Heartbeat intervals accepted (seconds), here and in system.xsd: 1 ms to 1 hour.
MIN_INTERVAL_S = 0.001
MAX_INTERVAL_S = 3600.0


class BeatForm:
    """What every beat of one module shares: its name, its interval and the ``<heartbeat/>`` they make.

    Made once per :class:`Heartbeat` from the module's name and interval, so a beat's fields and its
    XML come from the same values and cannot disagree; immutable, and its template never leaves it.
    """

    __slots__ = ("module", "interval", "_template", "_size0")

    def __init__(self, module: str, interval: int | float) -> None:
        template = etree.Element("heartbeat", module=module, seq="0", interval=repr(interval))
        set_ = object.__setattr__
        set_(self, "module", module)
        set_(self, "interval", float(repr(interval)))  # float(the interval attribute's text): what an XML reader reads
        set_(self, "_template", template)
        set_(self, "_size0", len(etree.tostring(template)) - 1)  # without seq's one digit "0"

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("BeatForm is immutable (every beat of a module shares it)")

    def __delattr__(self, name: str) -> None:
        raise AttributeError("BeatForm is immutable (every beat of a module shares it)")


class BeatRecord(Typed):
    """A heartbeat as a typed record (:class:`~homesim.message.Typed`): its XML is built only when read.

    Every module beats (about 40 beats per simulated second in the home tour) and the monitor
    reads two fields, so a beat carries its module's :class:`BeatForm` and its number, and its
    ``<heartbeat module= seq= interval=/>`` is made (for the trace, ``--strict``, an XML reader) as
    a copy of the form's template with ``seq`` set (lxml checks an attribute's name whenever one is
    set by name, ~2k instructions each in CPython 3.11: one name instead of a tag and three). The
    same bytes as before. Immutable (receivers share it); ``module`` and ``interval`` are the
    form's, so what the monitor reads is what the XML says.
    """

    __slots__ = ("form", "seq")

    def __init__(self, form: BeatForm, seq: int) -> None:
        object.__setattr__(self, "form", form)
        object.__setattr__(self, "seq", int(seq))

    @property
    def module(self) -> str:
        return self.form.module

    @property
    def interval(self) -> float:
        return self.form.interval

    def to_xml(self) -> etree._Element:
        el = self.form._template.__copy__()
        el.set("seq", str(self.seq))  # (set in place: the attributes keep their order)
        return el

    def size(self) -> int:
        return self.form._size0 + len(str(self.seq))


class Heartbeat:
    """Sends ``<heartbeat module= seq= interval=/>`` at most every ``interval`` seconds.

    Every module beats, so a beat is cheap: a :class:`BeatRecord` (no XML unless read).
    """

    def __init__(self, participant: Participant, interval: float) -> None:
        if not (isinstance(interval, (int, float)) and not isinstance(interval, bool)
                and MIN_INTERVAL_S <= interval <= MAX_INTERVAL_S):
            raise ValueError(f"heartbeat interval must be {MIN_INTERVAL_S:g} to {MAX_INTERVAL_S:g} s, got {interval!r}")
        # A plain int or float: the beat writes repr(interval), and numpy 2's repr of its float64 (a
        # float subclass) is 'np.float64(0.5)', which no monitor can read (the module went unwatched).
        if interval.__class__ is not int:
            interval = float(interval)
        self.participant = participant
        self.interval = interval
        self.channel = f"{HEARTBEAT_PREFIX}/{participant.name}"
        participant.bus.declare_channel(self.channel, SYSTEM_SCHEMA)
        self._interval_ns = to_ns(interval)
        self._loop = participant.bus.loop
        self._next_ns = -1  # the first call beats
        self._form = BeatForm(participant.name, interval)
        self.seq = 0

    def beat(self) -> bool:
        """Send a heartbeat if one is due; return whether one was sent."""
        now = self._loop._now_ns
        if now < self._next_ns:
            return False
        self.seq += 1
        self.participant.publish(self.channel, BeatRecord(self._form, self.seq))
        self._next_ns = now + self._interval_ns
        return True


class HeartbeatMonitor:
    """Watches heartbeats; publishes ``module_failed``/``module_recovered`` on /system/health.

    A module is watched from its first beat on (or from :meth:`watch`). It has
    failed when no beat arrived for ``misses`` of its intervals (plus a grace
    of ``slack`` seconds for latency). The check runs every ``period`` seconds.
    """

    def __init__(self, participant: Participant, *, misses: int = 3, period: float = 0.1, slack: float = 0.05,
                 listen: bool = True) -> None:
        self.participant = participant
        self.misses = misses
        self.period = period
        self.slack = slack
        self.last_beat_ns: dict[str, int] = {}
        self.intervals: dict[str, float] = {}
        self.failed: dict[str, int] = {}
        # No watched module can be late up to this time (ns): a lower bound of every deadline
        # found by check()'s last look (-1: look), and the (misses, slack) it was found with.
        self._quiet_until = -1
        self._quiet_for = (misses, slack)
        participant.bus.declare_channel(HEALTH_CHANNEL, SYSTEM_SCHEMA)
        if listen:
            participant.subscribe(HEARTBEAT_PREFIX + "/**", self._on_beat)

    def watch(self, module: str, interval: float) -> None:
        """Watch ``module`` even before its first beat (its silence counts from now).

        ``interval`` is what a heartbeat could carry (:data:`MIN_INTERVAL_S` to
        :data:`MAX_INTERVAL_S` seconds); anything else is a :class:`ValueError` here, not a
        failed run at the next check.
        """
        if not (isinstance(interval, (int, float)) and not isinstance(interval, bool)
                and MIN_INTERVAL_S <= interval <= MAX_INTERVAL_S):
            raise ValueError(f"watch {module!r}: interval must be {MIN_INTERVAL_S:g} to {MAX_INTERVAL_S:g} s, got {interval!r}")
        self.intervals[module] = float(interval)
        self.last_beat_ns.setdefault(module, self.participant.bus.loop.now_ns)
        self._quiet_until = -1

    def _limit_ns(self, interval: float) -> int:
        """How long a module beating every ``interval`` s may stay silent (ns)."""
        return to_ns(self.misses * interval + self.slack)

    def _on_beat(self, msg: Message) -> None:
        """Record a beat; a message that is not a usable heartbeat is refused (reported, not fatal)."""
        name, interval = _read_beat(msg)
        self.last_beat_ns[name] = created = msg.created_ns
        self.intervals[name] = interval
        if self._quiet_until >= 0 and created + self._limit_ns(interval) < self._quiet_until:
            self._quiet_until = -1  # (a new module, a shorter interval): its deadline comes first, look again
        if name in self.failed:
            del self.failed[name]
            el = etree.Element("module_recovered", module=name, t=repr(msg.created_ns / NS_PER_S))
            self.participant.publish(HEALTH_CHANNEL, el, causes=(msg.id,))

    def check(self) -> list[str]:
        """Publish ``module_failed`` for newly silent modules; return their names.

        A beat only moves its module's deadline later, so the earliest deadline the last
        look found stays a lower bound of them all unless a beat or :meth:`watch` brings an
        earlier one (a new module, a shorter interval: they ask for a new look): before it nobody
        can be late, and the modules are not looked at (the watchdog checks ten times a second).
        """
        now = self.participant.bus.loop.now_ns
        if now <= self._quiet_until and self._quiet_for == (self.misses, self.slack):
            return []
        newly = []
        earliest = -1
        for name in sorted(self.last_beat_ns):
            if name in self.failed:
                continue
            deadline = self.last_beat_ns[name] + self._limit_ns(self.intervals[name])
            if now > deadline:
                self.failed[name] = now
                newly.append(name)
                self.participant.publish(HEALTH_CHANNEL, self.failure(name))
            elif earliest < 0 or deadline < earliest:
                earliest = deadline
        self._quiet_until = earliest
        self._quiet_for = (self.misses, self.slack)
        return newly

    def failure(self, name: str) -> etree._Element:
        """The ``module_failed`` report for ``name`` (a subclass may add what it decided)."""
        return etree.Element("module_failed", module=name, last_beat=repr(self.last_beat_ns[name] / NS_PER_S),
                             missed=str(self.misses))

    async def run(self) -> None:
        """Check periodically, forever."""
        while True:
            self.check()
            await asyncio.sleep(self.period)


class BackstopMonitor(HeartbeatMonitor):
    """The kernel's monitor behind a robot's own (``primary``, e.g. BIRON's watchdog).

    While the primary beats it is silent: it watches the heartbeats and the
    primary's health reports as a bus interceptor (no subscription, nothing
    delivered to it, nothing in the trace) and publishes nothing. Once the
    primary itself has missed ``misses`` beats (it crashed or hung, perhaps with
    every other module) it takes over: ``module_failed`` for the primary and
    every silent module the primary had not reported, ``module_recovered``
    when beats come back. So a failure is always reported, whoever failed.
    """

    observes = (SEND,)

    def __init__(self, participant: Participant, primary: str, **kw: float) -> None:
        super().__init__(participant, listen=False, **kw)  # type: ignore[arg-type]
        self.primary = primary
        #: Whether the primary is silent and this monitor reports in its place.
        self.active = False
        participant.bus.add_interceptor(self)

    def wants(self, channel: str) -> bool:
        return channel == HEALTH_CHANNEL or channel.startswith(HEARTBEAT_PREFIX + "/")

    def __call__(self, obs: Observation) -> None:
        msg = obs.message
        channel = msg.channel
        if not channel.startswith("/system/"):  # (called for every send: the cheapest test first)
            return
        if msg.sender == self.participant.name or not self.wants(channel):
            return
        if channel == HEALTH_CHANNEL:  # what the primary reported: not reported again
            xml = msg.xml
            if xml is None:
                return
            module = xml.get("module")
            if module is not None and xml.tag == "module_failed":
                self.failed.setdefault(module, msg.created_ns)
            elif module is not None and xml.tag == "module_recovered":
                self.failed.pop(module, None)
            return
        # A typed beat is read from its record (no XML built: every beat of every module passes
        # here); anything else from its XML, if it has one.
        if msg.data.__class__ is not BeatRecord and msg.xml is None:
            return
        try:
            name, interval = _read_beat(msg)
        except BadMessageError:
            return  # (the primary reports it as a drop; the backstop only needs real beats)
        self.last_beat_ns[name] = msg.created_ns
        self.intervals[name] = interval

    def check(self) -> list[str]:
        """Silent while the primary beats; in its place (every module looked at) once it is silent."""
        now = self.participant.bus.loop.now_ns
        last = self.last_beat_ns.get(self.primary)
        silent = last is not None and now > last + self._limit_ns(self.intervals[self.primary])
        if not silent and not self.active:
            return []
        self.active = True
        for name in sorted(self.failed):  # beats came back after the failure
            if self.last_beat_ns.get(name, -1) > self.failed[name]:
                del self.failed[name]
                el = etree.Element("module_recovered", module=name, t=repr(self.last_beat_ns[name] / NS_PER_S))
                self.participant.publish(HEALTH_CHANNEL, el)
        self._quiet_until = -1
        newly = super().check()
        if not silent:
            self.active = False  # the primary is back and reports again
        return newly


def _read_beat(msg: Message) -> tuple[str, float]:
    """(module, interval) of a heartbeat; :class:`BadMessageError` when it is not one.

    The kernel types every ``/system/heartbeat/...`` channel, so this only
    trips on a message that satisfies system.xsd without being a heartbeat
    (a ``<fault>`` sent there); the check costs little and keeps the monitor
    alive whatever arrives.
    """
    data = getattr(msg, "data", None)
    if data.__class__ is BeatRecord:  # the typed beat: the fields its XML would carry (checked when it was made)
        return data.module or msg.sender, data.interval
    xml = msg.xml
    if xml.tag != "heartbeat":
        raise BadMessageError(f"<{xml.tag}> on {msg.channel} is not a heartbeat")
    name = xml.get("module") or msg.sender
    try:
        interval = float(xml.get("interval", ""))
    except ValueError:
        raise BadMessageError(f"heartbeat interval {xml.get('interval')!r} on {msg.channel} is not a number") from None
    if not MIN_INTERVAL_S <= interval <= MAX_INTERVAL_S:
        raise BadMessageError(f"heartbeat interval {interval!r} on {msg.channel} is outside {MIN_INTERVAL_S:g} to {MAX_INTERVAL_S:g} s")
    return name, interval
