"""Shared test configuration: Hypothesis profiles.

Locally the ``dev`` profile keeps the suite fast; CI (``CI=true``) uses the
``ci`` profile: derandomized (the same examples on every run, so a red CI is
reproducible) and with more examples where a test asks for them via
:func:`examples`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, settings

from homesim.errors import HomesimError
from homesim.sim import Simulation

ON_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")

settings.register_profile("dev", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile(
    "ci", deadline=None, derandomize=True, print_blob=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("ci" if ON_CI else "dev")


def examples(dev: int, ci: int) -> int:
    """Number of Hypothesis examples: ``dev`` locally, ``ci`` on CI."""
    return ci if ON_CI else dev


@pytest.fixture(autouse=True, scope="session")
def _strict_bus() -> Iterator[None]:
    """The suite runs strict: every message on a typed channel is validated.

    A module that builds an invalid message fails its tests (the product's
    default trusts the modules' own elements; see :mod:`homesim.bus`). Session
    scoped, so simulations built by module-scoped fixtures are strict too; a
    test that passes ``strict=`` itself keeps its choice.
    """
    original = Simulation.__init__

    def strict_init(self: Simulation, *args: object, **kwargs: object) -> None:
        kwargs.setdefault("strict", True)
        original(self, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Simulation, "__init__", strict_init)
        yield


@pytest.fixture(autouse=True)
def _close_left_simulations(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Close every Simulation a test left open, at that test's teardown.

    Many tests build a run and inspect it without ``with Simulation(...)``;
    their loops would otherwise be closed by the garbage collector during some
    later, unrelated test (a ``ResourceWarning`` blamed on the wrong test). CI
    runs with ``-W error::ResourceWarning``, so a loop the product itself
    leaves open (outside a test's own objects) still fails the suite.
    """
    created: list[Simulation] = []
    original = Simulation.__init__

    def tracking_init(self: Simulation, *args: object, **kwargs: object) -> None:
        original(self, *args, **kwargs)
        created.append(self)

    monkeypatch.setattr(Simulation, "__init__", tracking_init)
    yield
    for sim in created:
        if not sim.loop.is_closed():
            try:
                sim.close()
            except HomesimError:
                # A test that left a failed run behind: its own assertions
                # already judged that failure, and close() closed the loop.
                pass


@pytest.fixture
def robot() -> Iterator[object]:
    """A dialog on a bus of its own (tests/test_dialog_bus.py's ``Robot`` harness), closed after the test."""
    from tests.test_dialog_bus import Robot

    r = Robot()
    yield r
    r.sim.close()
