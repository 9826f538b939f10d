"""Shared test configuration: Hypothesis profiles.

Locally the ``dev`` profile keeps the suite fast; CI (``CI=true``) uses the
``ci`` profile: derandomized (the same examples on every run, so a red CI is
reproducible) and with more examples where a test asks for them via
:func:`examples`.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

ON_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")

settings.register_profile("dev", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile(
    "ci", deadline=None, derandomize=True, print_blob=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("ci" if ON_CI else "dev")


def examples(dev: int, ci: int) -> int:
    """Number of Hypothesis examples: ``dev`` locally, ``ci`` on CI."""
    return ci if ON_CI else dev
