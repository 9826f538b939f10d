"""Hosts, the links between them, and what a message takes to cross one.

A distributed system runs its participants on hosts; each host is attached
by one kind of link (a LAN segment, a WLAN, ...). Two participants on the
same host talk over the ``local`` link (the loopback); otherwise a message
takes the slower of the sender's host's link *out* (its uplink: by default
the link it is attached by) and the receiver's host's link *in* (the link it
is attached by), so a WLAN station whose access point queues the frames to
it (bufferbloat on the downlink) can be slower one way than the other. A
route (:meth:`Network.set_route`) overrides that for one ordered pair of
hosts: messages from ``a`` to ``b`` take exactly its link, whatever the
hosts' attachments (two hosts with a path of their own, a tunnel, a
pair that shares a congested hop). A link is data
(:class:`LinkModel`): a base latency (uniform in ``[min_s, max_s]``), a
half-normal jitter, a bandwidth (so a message's size matters: a scan with
its attachment takes longer than a heartbeat), and a loss probability per
attempt with a retransmission delay that grows by ``backoff`` per retry (a
reliable transport: a lost attempt is sent again; after ``max_retries``
the message is lost for good). Without a retransmission delay a lost
message is dropped at once.

Hosts may carry a CPU speed (MHz): modules read it to scale their
processing costs. A placement maps participant names to hosts, so which
module runs where is data too (a deployment document, loaded by the run).

Delays are drawn from the seeded generator the run hands in, in send order,
so a run's timing is reproducible to the nanosecond. Per link the network
keeps what its deliveries took (:class:`LinkStats`: count, mean, a bounded
histogram for percentiles, max), never a list of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import HomesimError
from .vloop import NS_PER_S


class Draws:
    """Standard uniform and normal numbers from a seeded generator, drawn in blocks.

    One numpy call per block instead of one per message: the bus draws a
    delay for every delivery. Deterministic: the same generator gives the
    same sequence of draws, whatever the block boundaries.
    """

    __slots__ = ("_rng", "_u", "_ui", "_n", "_ni", "block")

    def __init__(self, rng: np.random.Generator, *, block: int = 1024) -> None:
        self._rng = rng
        self.block = block
        self._u: list[float] = []
        self._ui = 0
        self._n: list[float] = []
        self._ni = 0

    def uniform(self) -> float:
        """A number in [0, 1)."""
        if self._ui == len(self._u):
            self._u = self._rng.random(self.block).tolist()
            self._ui = 0
        self._ui += 1
        return self._u[self._ui - 1]

    def normal(self) -> float:
        """A standard normal number."""
        if self._ni == len(self._n):
            self._n = self._rng.standard_normal(self.block).tolist()
            self._ni = 0
        self._ni += 1
        return self._n[self._ni - 1]


#: The message size a link's worst-case delay is bounded for: a megabyte, far beyond any of
#: BIRON's messages (the largest, a laser scan with its ranges attached, is about 4 kB).
LARGEST_MESSAGE_BYTES = 1_000_000
#: A typical message (an event, a frame, a pose: XML of about a kilobyte).
TYPICAL_MESSAGE_BYTES = 1_000


@dataclass(frozen=True, slots=True)
class LinkModel:
    """One kind of link.

    - delay: uniform in ``[min_s, max_s]`` plus ``|N(0,1)| * jitter_s``;
    - ``bandwidth_bps`` (bits per second, 0: unlimited): a message of ``n``
      bytes takes ``8 n / bandwidth_bps`` more;
    - ``loss``: the probability that one attempt is lost; with
      ``retransmit_s`` > 0 a lost attempt is sent again after
      ``retransmit_s * backoff**k`` (k-th retry), at most ``max_retries``
      times, then the message is lost; with ``retransmit_s`` = 0 a lost
      attempt is a lost message.
    """

    name: str
    min_s: float
    max_s: float
    jitter_s: float = 0.0
    loss: float = 0.0
    bandwidth_bps: float = 0.0
    retransmit_s: float = 0.0
    backoff: float = 2.0
    max_retries: int = 7

    def __post_init__(self) -> None:
        bad = None
        if not (0.0 <= self.min_s <= self.max_s):
            bad = f"need 0 <= min_s <= max_s, got {self.min_s}, {self.max_s}"
        elif not (self.jitter_s >= 0):
            bad = f"jitter_s must be >= 0, got {self.jitter_s}"
        elif not (0.0 <= self.loss < 1.0):
            bad = f"loss must be in [0, 1), got {self.loss}"
        elif not (self.bandwidth_bps >= 0) or math.isinf(self.bandwidth_bps):
            bad = f"bandwidth_bps must be finite and >= 0 (0: unlimited), got {self.bandwidth_bps}"
        elif not (self.retransmit_s >= 0) or math.isinf(self.retransmit_s):
            bad = f"retransmit_s must be finite and >= 0, got {self.retransmit_s}"
        elif not (1.0 <= self.backoff <= 16.0):
            bad = f"backoff must be in [1, 16], got {self.backoff}"
        elif not (0 <= self.max_retries <= 64):
            bad = f"max_retries must be in [0, 64], got {self.max_retries}"
        elif max(self.max_s, self.jitter_s) > 3600.0:
            bad = "a delay over an hour is not a link"
        elif self.bound_s > 3600.0:
            bad = (f"its worst-case delay is {self.bound_s:.3g} s (base and jitter {self.max_s + 6.0 * self.jitter_s:.3g} s, "
                   f"retransmissions up to {self.retransmissions_s:.3g} s, a {LARGEST_MESSAGE_BYTES} byte message "
                   f"{self.transfer_s(LARGEST_MESSAGE_BYTES):.3g} s): a delay over an hour is not a link")
        if bad is not None:
            raise HomesimError(f"link {self.name!r}: {bad}")

    @property
    def typical_s(self) -> float:
        """A rough delay of a typical message (1 kB of XML), bandwidth included: which of two hops is the slower."""
        return self.worst_s + self.transfer_s(TYPICAL_MESSAGE_BYTES)

    @property
    def retransmissions_s(self) -> float:
        """The longest series of retransmission waits: ``retransmit_s * (1 + backoff + ... + backoff**(max_retries-1))``."""
        if self.loss <= 0.0 or self.retransmit_s <= 0.0:
            return 0.0
        return self.retransmit_s * sum(self.backoff ** k for k in range(self.max_retries))

    def transfer_s(self, size: int) -> float:
        """Seconds ``size`` bytes take at the link's bandwidth (0 when unlimited)."""
        return 8.0 * size / self.bandwidth_bps if self.bandwidth_bps > 0.0 else 0.0

    @property
    def bound_s(self) -> float:
        """A bound on a delivered message's delay: the jitter counted to six sigma, every retry, the largest message."""
        return self.max_s + 6.0 * self.jitter_s + self.retransmissions_s + self.transfer_s(LARGEST_MESSAGE_BYTES)

    @property
    def simple(self) -> bool:
        """No loss, no jitter, no bandwidth limit: one uniform draw per message."""
        return self.loss == 0.0 and self.jitter_s == 0.0 and self.bandwidth_bps == 0.0

    @property
    def worst_s(self) -> float:
        """A rough upper bound of a small message's delay (which of two links is the slower)."""
        return self.max_s + 3.0 * self.jitter_s + self.loss * self.retransmit_s

    def sample_ns(self, draws: Draws, size: int = 0) -> int | None:
        """One delay in integer nanoseconds for a message of ``size`` bytes, or None when it is lost."""
        return _sample(self, draws, size, 0.0, None)


def _retries(link: LinkModel, draws: Draws, stats: LinkStats | None) -> float | None:
    """After a lost attempt on ``link``: the retransmission waits until one gets through, or None
    (no retransmission, or every one of ``max_retries`` lost)."""
    if link.retransmit_s <= 0.0:
        return None
    extra = 0.0
    rto = link.retransmit_s
    for _ in range(link.max_retries):
        if stats is not None:
            stats.retried += 1
        extra += rto
        rto *= link.backoff
        if draws.uniform() >= link.loss:
            return extra
    return None


def _sample(link: LinkModel, draws: Draws, size: int, other_loss: float, stats: LinkStats | None,
            other: LinkModel | None = None) -> int | None:
    """Draw a delay over ``link``; ``other_loss``: the other host's link's loss. A loss there is resent
    with ``other``'s retransmission (TCP runs end to end: either hop's loss is retransmitted); without
    ``other`` (or without its retransmission) it loses the message.

    The draw order (the other link's loss, this link's loss, the uniform
    base, the jitter; then per retry one loss draw) is fixed: the same
    generator gives the same delays.
    """
    extra = 0.0
    if other_loss > 0.0 and draws.uniform() < other_loss:
        resent = _retries(other, draws, stats) if other is not None else None
        if resent is None:
            return None
        extra += resent
    if link.loss > 0.0 and draws.uniform() < link.loss:
        resent = _retries(link, draws, stats)
        if resent is None:
            return None
        extra += resent
    delay = link.min_s + (link.max_s - link.min_s) * draws.uniform()
    if link.jitter_s > 0.0:
        delay += abs(draws.normal()) * link.jitter_s
    if link.bandwidth_bps > 0.0 and size > 0:
        delay += 8.0 * size / link.bandwidth_bps
    return int(round((delay + extra) * NS_PER_S))


#: The kernel's defaults when no deployment says otherwise. A run normally loads
#: a deployment document (hosts, links, placement; see homesim.deployment).
DEFAULT_LINKS: dict[str, LinkModel] = {
    "local": LinkModel("local", 0.00005, 0.0002),
    "lan": LinkModel("lan", 0.001, 0.003),
    "wlan": LinkModel("wlan", 0.005, 0.020, jitter_s=0.003),
}

#: Histogram bins per e-fold of delay (ln-spaced: a bin spans 1 %).
_BINS_PER_E = 100.0


class LinkStats:
    """What one link's deliveries took: count, sum, max and a ln-spaced histogram (1 % bins).

    Bounded memory whatever the run's length (at most a few thousand bins
    between 1 ns and an hour). Percentiles are read from the histogram
    (the bin's geometric middle: within 0.5 % of the true value).
    """

    __slots__ = ("name", "count", "sum_ns", "max_ns", "bins", "lost", "retried")

    def __init__(self, name: str) -> None:
        self.name = name
        self.count = 0
        self.sum_ns = 0
        self.max_ns = 0
        self.bins: dict[int, int] = {}
        self.lost = 0
        self.retried = 0

    def add(self, ns: int) -> None:
        """One delivery that took ``ns`` nanoseconds (from send to delivery)."""
        self.count += 1
        self.sum_ns += ns
        if ns > self.max_ns:
            self.max_ns = ns
        b = int(math.log(ns) * _BINS_PER_E) if ns > 0 else -1
        bins = self.bins
        bins[b] = bins.get(b, 0) + 1

    def percentile_ns(self, q: float) -> float:
        """The ``q``-th percentile (0-100) of the delays, from the histogram (0.0 without deliveries)."""
        if not self.count:
            return 0.0
        rank = q / 100.0 * self.count
        seen = 0
        for b in sorted(self.bins):
            seen += self.bins[b]
            if seen >= rank:
                if b < 0:
                    return 0.0
                return min(float(self.max_ns), math.exp((b + 0.5) / _BINS_PER_E))
        return float(self.max_ns)

    def summary(self) -> dict[str, Any]:
        """Plain data for a run summary: deliveries, mean / p95 / max in ms, lost, retried."""
        mean = self.sum_ns / self.count / 1e6 if self.count else 0.0
        return {
            "deliveries": self.count,
            "mean_ms": round(mean, 4),
            "p95_ms": round(self.percentile_ns(95.0) / 1e6, 4),
            "max_ms": round(self.max_ns / 1e6, 4),
            "lost": self.lost,
            "retransmitted": self.retried,
        }


class Route:
    """How a message goes from one host to another: the link it takes and its draw plan.

    ``other``/``other_loss``: the other host's link and its loss (a loss
    there is retransmitted with that link's parameters); ``lo``/``span``: the uniform base delay in seconds when
    the link is simple (the bus draws it inline), else ``lo`` is None.
    """

    __slots__ = ("link", "other", "other_loss", "stats", "lo", "span")

    def __init__(self, link: LinkModel, other_loss: float, stats: LinkStats, other: LinkModel | None = None) -> None:
        self.link = link
        self.other = other
        self.other_loss = other_loss
        self.stats = stats
        simple = link.simple and other_loss == 0.0
        self.lo = link.min_s if simple else None
        self.span = link.max_s - link.min_s


class Network:
    """Hosts, the links they sit on and where participants run; draws per-message delays."""

    def __init__(self, rng: np.random.Generator) -> None:
        self._draws = Draws(rng)
        self._links: dict[str, LinkModel] = dict(DEFAULT_LINKS)
        self._hosts: dict[str, str] = {}
        # Per host: the link its outgoing messages take (absent: the link it is attached by).
        self._uplinks: dict[str, str] = {}
        # Per ordered (from host, to host): the link that pair's messages take (overrides the hosts' links).
        self._routes: dict[tuple[str, str], str] = {}
        self._speeds: dict[str, float] = {}
        self._placement: dict[str, str] = {}
        #: Where a participant runs that is not placed and asks for a host nobody declared (a deployment's default).
        self.default_host: str | None = None
        self._stats: dict[str, LinkStats] = {}
        # Per (host_a, host_b): the Route, worked out once (cleared when links or hosts change).
        self._plans: dict[tuple[str, str], Route] = {}
        self._listeners: list[Callable[[], None]] = []

    def on_change(self, listener: Callable[[], None]) -> None:
        """Call ``listener()`` whenever a host or a link changes (the bus caches its delivery plans)."""
        self._listeners.append(listener)

    def _changed(self) -> None:
        self._plans.clear()
        for listener in self._listeners:
            listener()

    # ------------------------------------------------------------ topology
    def set_link(self, model: LinkModel) -> None:
        """Add or replace a link kind (e.g. a lossy WLAN for a fault test)."""
        self._links[model.name] = model
        self._changed()

    def links(self) -> dict[str, LinkModel]:
        """Link name -> model, sorted by name."""
        return dict(sorted(self._links.items()))

    def add_host(self, host: str, *, link: str = "lan", uplink: str | None = None,
                 speed_mhz: float | None = None) -> None:
        """Declare a host, the kind of link it is attached by and (optionally) its CPU speed.

        ``link`` carries what the host receives; ``uplink`` (default: ``link``)
        what it sends, for an attachment that is not the same both ways.
        """
        for kind in (link, uplink):
            if kind is not None and kind not in self._links:
                raise HomesimError(f"host {host!r}: unknown link {kind!r}; known: {sorted(self._links)}")
        if speed_mhz is not None and not (0.0 < speed_mhz < 1e6):
            raise HomesimError(f"host {host!r}: speed_mhz must be in (0, 1e6), got {speed_mhz}")
        self._hosts[host] = link
        if uplink is None or uplink == link:
            self._uplinks.pop(host, None)
        else:
            self._uplinks[host] = uplink
        if speed_mhz is not None:
            self._speeds[host] = float(speed_mhz)
        self._changed()

    def set_route(self, src: str, dst: str, link: str) -> None:
        """Messages from host ``src`` to host ``dst`` take ``link`` (one direction; the hosts' own links are ignored).

        Raises :class:`HomesimError` for an unknown host or link, or ``src == dst``
        (a host talks to itself over ``local``).
        """
        for h in (src, dst):
            if h not in self._hosts:
                raise HomesimError(f"route {src!r} -> {dst!r}: unknown host {h!r}; hosts: {sorted(self._hosts)}")
        if src == dst:
            raise HomesimError(f"route {src!r} -> {dst!r}: a host talks to itself over the local link")
        if link not in self._links:
            raise HomesimError(f"route {src!r} -> {dst!r}: unknown link {link!r}; known: {sorted(self._links)}")
        self._routes[(src, dst)] = link
        self._changed()

    def routes(self) -> dict[tuple[str, str], str]:
        """(from host, to host) -> link name of every explicit route, sorted."""
        return dict(sorted(self._routes.items()))

    def ensure_host(self, host: str) -> None:
        """Declare ``host`` on the LAN if it is not known yet."""
        if host not in self._hosts:
            self._hosts[host] = "lan"
            self._changed()

    def hosts(self) -> dict[str, str]:
        """Host -> link kind it is attached by (what it receives over), sorted by host name."""
        return dict(sorted(self._hosts.items()))

    def uplink(self, host: str) -> str:
        """The link kind ``host``'s outgoing messages take (its attachment unless an uplink is set)."""
        return self._uplinks.get(host, self._hosts[host])

    def host_speed(self, host: str) -> float | None:
        """The host's CPU speed in MHz, if its deployment says."""
        return self._speeds.get(host)

    def place(self, participant: str, host: str) -> None:
        """Run the participant named ``participant`` on ``host`` (whatever host its constructor asks for)."""
        if host not in self._hosts:
            raise HomesimError(f"cannot place {participant!r} on unknown host {host!r}; hosts: {sorted(self._hosts)}")
        self._placement[participant] = host

    def host_for(self, participant: str, default: str) -> str:
        """Where ``participant`` runs: its placement; else ``default`` if that host is declared or
        no default host is set; else the default host (a deployment's ``default-host``)."""
        placed = self._placement.get(participant)
        if placed is not None:
            return placed
        if default in self._hosts or self.default_host is None:
            return default
        return self.default_host

    def placement(self) -> dict[str, str]:
        """Participant name -> host as placed, sorted by name."""
        return dict(sorted(self._placement.items()))

    # -------------------------------------------------------------- delays
    def link_between(self, host_a: str, host_b: str) -> LinkModel:
        """The link a message takes from ``host_a`` to ``host_b``."""
        return self.route(host_a, host_b).link

    def route(self, host_a: str, host_b: str) -> Route:
        """The :class:`Route` from ``host_a`` to ``host_b`` (cached until hosts or links change)."""
        plan = self._plans.get((host_a, host_b))
        if plan is None:
            plan = self._plan(host_a, host_b)
        return plan

    def delay_ns(self, host_a: str, host_b: str, size: int = 0) -> int | None:
        """Draw one delay from ``host_a`` to ``host_b`` for ``size`` bytes; None when lost.

        The delay follows the slower of ``host_a``'s uplink and ``host_b``'s
        link (or the pair's route, alone, if one is set); a message is lost if
        either link loses it (the slower link retransmits if it can; the
        other's loss applies as a drop). Not recorded in the link's
        statistics: the bus records what a delivery took (FIFO included).
        """
        return self.draw(self.route(host_a, host_b), size)

    def draw(self, path: Route, size: int = 0) -> int | None:
        """One delay along ``path`` (see :meth:`delay_ns`); counts losses and retransmissions."""
        draws = self._draws
        if path.lo is not None:
            i = draws._ui
            if i == len(draws._u):
                draws._u = draws._rng.random(draws.block).tolist()
                i = 0
            draws._ui = i + 1
            return int(round((path.lo + path.span * draws._u[i]) * NS_PER_S))
        delay = _sample(path.link, draws, size, path.other_loss, path.stats, path.other)
        if delay is None:
            path.stats.lost += 1
        return delay

    def stats(self) -> dict[str, LinkStats]:
        """Per link name: what its deliveries took so far (sorted by name)."""
        return dict(sorted(self._stats.items()))

    def _link_stats(self, name: str) -> LinkStats:
        st = self._stats.get(name)
        if st is None:
            st = self._stats[name] = LinkStats(name)
        return st

    def _plan(self, host_a: str, host_b: str) -> Route:
        route = self._routes.get((host_a, host_b))
        other: LinkModel | None = None
        if host_a == host_b:
            other_loss, slow = 0.0, self._links["local"]
        elif route is not None:
            other_loss, slow = 0.0, self._links[route]
        else:
            a = self._links[self._uplinks.get(host_a, self._hosts[host_a])]
            b = self._links[self._hosts[host_b]]
            # the slower hop by a typical message's delay, its bandwidth included
            slow, other = (a, b) if a.typical_s >= b.typical_s else (b, a)
            other_loss = other.loss
        plan = Route(slow, other_loss, self._link_stats(slow.name), other)
        self._plans[(host_a, host_b)] = plan
        return plan
