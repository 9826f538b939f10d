"""Latency and loss between the hosts a simulated system runs on.

BIRON's modules ran on two on-board PCs linked by Ethernet and a laptop on
WLAN; the papers report "a few ms" per message, more over WLAN. Each host
names the kind of link it sits on; two participants on the same host talk
over the ``local`` link, otherwise over the slower of their two hosts' links.
Delays are drawn from the seeded generator the run hands in, in send order,
so a run's timing is reproducible to the nanosecond.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

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


@dataclass(frozen=True, slots=True)
class LinkModel:
    """One kind of link: delay uniform in [min_s, max_s] plus optional loss.

    ``jitter_s`` adds a half-normal tail on top of the uniform part (WLAN
    retransmissions); ``loss`` is the probability that a message is dropped.
    """

    name: str
    min_s: float
    max_s: float
    jitter_s: float = 0.0
    loss: float = 0.0

    def __post_init__(self) -> None:
        if not (0.0 <= self.min_s <= self.max_s):
            raise HomesimError(f"link {self.name!r}: need 0 <= min_s <= max_s, got {self.min_s}, {self.max_s}")
        if self.jitter_s < 0:
            raise HomesimError(f"link {self.name!r}: jitter_s must be >= 0, got {self.jitter_s}")
        if not (0.0 <= self.loss < 1.0):
            raise HomesimError(f"link {self.name!r}: loss must be in [0, 1), got {self.loss}")

    def sample_ns(self, draws: Draws) -> int | None:
        """One delay in integer nanoseconds, or None when the message is lost."""
        if self.loss > 0.0 and draws.uniform() < self.loss:
            return None
        delay = self.min_s + (self.max_s - self.min_s) * draws.uniform()
        if self.jitter_s > 0.0:
            delay += abs(draws.normal()) * self.jitter_s
        return int(round(delay * NS_PER_S))


#: Defaults from the papers: LAN 1-3 ms, WLAN 5-20 ms with jitter.
DEFAULT_LINKS: dict[str, LinkModel] = {
    "local": LinkModel("local", 0.00005, 0.0002),
    "lan": LinkModel("lan", 0.001, 0.003),
    "wlan": LinkModel("wlan", 0.005, 0.020, jitter_s=0.003),
}


class Network:
    """Hosts and the links they sit on; draws per-message delays."""

    def __init__(self, rng: np.random.Generator) -> None:
        self._draws = Draws(rng)
        self._links: dict[str, LinkModel] = dict(DEFAULT_LINKS)
        self._hosts: dict[str, str] = {}
        # Per (host_a, host_b): what delay_ns draws, worked out once (cleared when links or hosts change).
        self._plans: dict[tuple[str, str], tuple[float, float, float, float, float]] = {}
        self._listeners: list[Callable[[], None]] = []

    def on_change(self, listener: Callable[[], None]) -> None:
        """Call ``listener()`` whenever a host or a link changes (the bus caches its delivery plans)."""
        self._listeners.append(listener)

    def _changed(self) -> None:
        self._plans.clear()
        for listener in self._listeners:
            listener()

    def set_link(self, model: LinkModel) -> None:
        """Add or replace a link kind (e.g. a lossy WLAN for a fault test)."""
        self._links[model.name] = model
        self._changed()

    def add_host(self, host: str, *, link: str = "lan") -> None:
        """Declare a host and the kind of link it is attached by."""
        if link not in self._links:
            raise HomesimError(f"host {host!r}: unknown link {link!r}; known: {sorted(self._links)}")
        self._hosts[host] = link
        self._changed()

    def ensure_host(self, host: str) -> None:
        """Declare ``host`` on the LAN if it is not known yet."""
        if host not in self._hosts:
            self._hosts[host] = "lan"
            self._changed()

    def hosts(self) -> dict[str, str]:
        """Host -> link kind, sorted by host name."""
        return dict(sorted(self._hosts.items()))

    def link_between(self, host_a: str, host_b: str) -> LinkModel:
        """The link a message takes from ``host_a`` to ``host_b``."""
        if host_a == host_b:
            return self._links["local"]
        a = self._links[self._hosts[host_a]]
        b = self._links[self._hosts[host_b]]
        return a if (a.max_s + a.jitter_s) >= (b.max_s + b.jitter_s) else b

    def delay_ns(self, host_a: str, host_b: str) -> int | None:
        """Draw one delay from ``host_a`` to ``host_b``; None when lost.

        The delay follows the slower link; a message is lost if either
        host's link loses it (both losses apply). The draws are those of
        :meth:`LinkModel.sample_ns` (the other link's loss first), made inline:
        the bus draws one delay per delivery.
        """
        plan = self._plans.get((host_a, host_b))
        if plan is None:
            plan = self._plan(host_a, host_b)
        other_loss, loss, lo, span, jitter = plan
        draws = self._draws
        if other_loss > 0.0 and draws.uniform() < other_loss:
            return None
        if loss > 0.0 and draws.uniform() < loss:
            return None
        i = draws._ui
        if i == len(draws._u):
            draws._u = draws._rng.random(draws.block).tolist()
            i = 0
        draws._ui = i + 1
        delay = lo + span * draws._u[i]
        if jitter > 0.0:
            delay += abs(draws.normal()) * jitter
        return int(round(delay * NS_PER_S))

    def _plan(self, host_a: str, host_b: str) -> tuple[float, float, float, float, float]:
        if host_a == host_b:
            other_loss, slow = 0.0, self._links["local"]
        else:
            a = self._links[self._hosts[host_a]]
            b = self._links[self._hosts[host_b]]
            slow, other = (a, b) if (a.max_s + a.jitter_s) >= (b.max_s + b.jitter_s) else (b, a)
            other_loss = other.loss
        plan = (other_loss, slow.loss, slow.min_s, slow.max_s - slow.min_s, slow.jitter_s)
        self._plans[(host_a, host_b)] = plan
        return plan
