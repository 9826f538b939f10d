"""Running statistics in constant memory (Welford), shared by the metrics."""

from __future__ import annotations

import math
from typing import Any


class Running:
    """Count, mean, standard deviation, min and max of a stream of numbers."""

    __slots__ = ("n", "mean", "_m2", "lo", "hi")

    def __init__(self) -> None:
        self.n = 0
        self.mean = 0.0
        self._m2 = 0.0
        self.lo = math.inf
        self.hi = -math.inf

    def add(self, x: float) -> None:
        self.n += 1
        d = x - self.mean
        self.mean += d / self.n
        self._m2 += d * (x - self.mean)
        self.lo = min(self.lo, x)
        self.hi = max(self.hi, x)

    @property
    def std(self) -> float:
        return math.sqrt(self._m2 / self.n) if self.n else 0.0

    def as_dict(self, digits: int = 4) -> dict[str, Any]:
        if not self.n:
            return {"n": 0}
        r = lambda v: round(v, digits)  # noqa: E731
        return {"n": self.n, "mean": r(self.mean), "std": r(self.std), "min": r(self.lo), "max": r(self.hi)}
