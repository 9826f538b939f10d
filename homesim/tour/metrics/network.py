"""Network metrics: what messages took per link, and the supervisor's out-of-order arrivals.

Per link kind of the run's deployment (``local``, ``lan``, ``wlan``, ...):
deliveries, mean / p95 / max latency in ms (send to delivery, FIFO waits
included), messages lost and TCP-style retransmissions
(:class:`homesim.network.LinkStats`: bounded, never a list of delays). From
the supervisor: events received and how many of them arrived out of creation
order (an older event delivered after a newer one: the case the ES's
timestamp-ordered queue exists for), and how many of those it inserted
ahead of newer events still queued (``es_sorted_ahead``; an out-of-order
arrival whose newer predecessor was already applied or rejected is sorted
ahead of nothing). The same figures are in the run
summary (``deployment.links``, ``es``); as a metric they reach sweeps and
``<metric name="network.es_out_of_order" min="1"/>`` expectations.
"""

from __future__ import annotations

from typing import Any

from . import Observer


class NetworkMetric(Observer):
    def summary(self) -> dict[str, Any]:
        arrivals = getattr(getattr(self.run, "supervisor", None), "arrivals", None)
        counts = arrivals() if callable(arrivals) else {}
        return {
            "es_received": counts.get("events_received", 0),
            "es_out_of_order": counts.get("received_out_of_order", 0),
            # of those, arrivals the ES inserted ahead of queued newer events (the rest found them gone)
            "es_sorted_ahead": counts.get("sorted_ahead", 0),
            "links": {name: st.summary() for name, st in self.run.sim.network.stats().items()},
        }


OBSERVERS = {"network": NetworkMetric}
