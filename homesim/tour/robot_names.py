"""Names in a scenario that only the robot knows, checked (a ``homesim.scenario_checks`` entry point).

``<robot profile=...>`` names a robot profile (``robot/profiles.py``);
``<state-reached state=...>``, ``<event-applied event=... state=...>`` and
``<event-rejected event=... state=...>`` name states and events of the
state machine the robot's execution supervisor runs. The kernel's checks
cannot know them (the AFSM belongs to the robot, and the kernel never names
the robot); the run package, which composes the robot, can: it hands this
check to the kernel through the entry point, so ``homesim check`` and every
run refuse ``state="Interactng"`` or ``event="greting"`` with file:line and
the closest name, instead of a failed expectation after the whole run.

The states a run reports (and these expectations match) are the AFSM's leaf
states; a category is refused with its leaves named. The events are those
the AFSM declares or has a transition for.

``<metric name=...>`` names a value of the run's summary: its first part must
be a metric the run package registers (:mod:`homesim.tour.metrics`), so a
misspelt metric is refused before the run instead of failing after it. The
parts below it are the keys of that metric's summary, which depend on the
run (people, links, dialogs); those are checked when the run ends, where a
missing key is answered with the closest one the run has.
"""

from __future__ import annotations

from functools import lru_cache

from robot.profiles import PROFILES
from robot.supervisor import BIRON_AFSM

from ..afsm.loader import load
from ..scoring import registry as metric_registry
from ..errors import ScenarioError
from ..scenario.checks import unknown_name
from ..scenario.model import Expectation, Scenario
from . import metrics as _metrics  # noqa: F401  (registers the run's metrics)

#: The expectation kinds that name the supervisor's states or events.
KINDS = ("state-reached", "event-applied", "event-rejected")


@lru_cache(maxsize=1)
def vocabulary() -> tuple[dict[str, list[str]], list[str]]:
    """The robot's AFSM: category -> its leaf states (``""`` -> every leaf state), and its event names."""
    m = load(str(BIRON_AFSM))
    groups = {c: [s for s in m.descendants(c) if s in m.leaves()] for c in m.categories()}
    groups[""] = m.leaves()
    events = sorted(set(m.events) | set(m.event_names()))
    return groups, events


def check_scenario(sc: Scenario) -> list[ScenarioError]:
    """An unknown robot profile, and every expectation that names a state or an event the robot's supervisor does not have."""
    groups, events = vocabulary()
    out: list[ScenarioError] = []
    profile = sc.robot.profile
    if profile is not None and profile not in PROFILES:
        out.append(ScenarioError(f"profile={profile!r}: {unknown_name('robot profile', profile, PROFILES)}",
                                 source=sc.source, line=sc.robot.line, element="robot"))
    for e in sc.expectations:
        if e.kind in KINDS:
            out += _problems(sc, e, groups, events)
        elif e.kind == "metric":
            out += _metric(sc, e)
    return out


def _metric(sc: Scenario, e: Expectation) -> list[ScenarioError]:
    """A metric expectation whose first part is not a registered metric."""
    name = str(e.get("name") or "")
    head = name.split(".", 1)[0]
    known = sorted(metric_registry())
    if head in known:
        return []
    return [ScenarioError(f"name={name!r}: {unknown_name('metric', head, known)}",
                          source=sc.source, line=e.line, element=e.kind)]


def _problems(sc: Scenario, e: Expectation, groups: dict[str, list[str]], events: list[str]) -> list[ScenarioError]:
    where = f"the supervisor's AFSM ({BIRON_AFSM.parent.name}/{BIRON_AFSM.name})"
    found = []
    state = e.get("state")
    if state is not None and str(state) not in groups[""]:
        if str(state) in groups:
            why = (f"state={state!r} is a category of {where}; the supervisor reports leaf states: "
                   f"name one of {', '.join(groups[str(state)])}")
        else:
            why = f"state={state!r}: {unknown_name('state', state, groups[''])} in {where}"
        found.append(ScenarioError(why, source=sc.source, line=e.line, element=e.kind))
    event = e.get("event")
    if event is not None and str(event) not in events:
        found.append(ScenarioError(f"event={event!r}: {unknown_name('event', event, events)} in {where}",
                                   source=sc.source, line=e.line, element=e.kind))
    return found
