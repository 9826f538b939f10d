"""Latency and loss between the hosts a simulated system runs on.

BIRON's modules ran on two on-board PCs linked by Ethernet and a laptop on
WLAN; the papers report "a few ms" per message, more over WLAN. Each host
names the kind of link it sits on; two participants on the same host talk
over the ``local`` link, otherwise over the slower of their two hosts' links.
Delays are drawn from the seeded generator the run hands in, in send order,
so a run's timing is reproducible to the nanosecond.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import HomesimError
from .vloop import NS_PER_S


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

    def sample_ns(self, rng: np.random.Generator) -> int | None:
        """One delay in integer nanoseconds, or None when the message is lost."""
        if self.loss > 0.0 and rng.random() < self.loss:
            return None
        delay = self.min_s if self.max_s == self.min_s else rng.uniform(self.min_s, self.max_s)
        if self.jitter_s > 0.0:
            delay += abs(rng.normal(0.0, self.jitter_s))
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
        self._rng = rng
        self._links: dict[str, LinkModel] = dict(DEFAULT_LINKS)
        self._hosts: dict[str, str] = {}

    def set_link(self, model: LinkModel) -> None:
        """Add or replace a link kind (e.g. a lossy WLAN for a fault test)."""
        self._links[model.name] = model

    def add_host(self, host: str, *, link: str = "lan") -> None:
        """Declare a host and the kind of link it is attached by."""
        if link not in self._links:
            raise HomesimError(f"host {host!r}: unknown link {link!r}; known: {sorted(self._links)}")
        self._hosts[host] = link

    def ensure_host(self, host: str) -> None:
        """Declare ``host`` on the LAN if it is not known yet."""
        if host not in self._hosts:
            self._hosts[host] = "lan"

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
        host's link loses it (both losses apply).
        """
        if host_a == host_b:
            return self._links["local"].sample_ns(self._rng)
        a = self._links[self._hosts[host_a]]
        b = self._links[self._hosts[host_b]]
        slow, other = (a, b) if (a.max_s + a.jitter_s) >= (b.max_s + b.jitter_s) else (b, a)
        if other.loss > 0.0 and self._rng.random() < other.loss:
            return None
        return slow.sample_ns(self._rng)
