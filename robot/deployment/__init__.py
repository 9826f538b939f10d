"""BIRON's deployment: which host each module ran on, and processing costs per host.

:data:`DEFAULT` is the papers' set-up (``biron.xml``: two robot PCs on a 100 Mbit
LAN, the speech and dialog laptop on 11 Mbit WLAN; docs/deployment.md gives the
source of every figure). The run loads it, applies the scenario's
``<deployment>`` override and places every module before it joins the bus.

Processing costs: the modules' virtual processing times (speech recognition,
understanding, dialog, the supervisor's reconfiguration) are calibrated to the
papers' Fig. 6, i.e. to the host each module ran on then. Deployed on another
host, a module's cost scales with the CPU speed: ``cost * papers_mhz /
host_mhz`` (:func:`cost_scale`; 1 on the papers' deployment, and 1 when either
speed is unknown). A crude model (clock rate only), but it keeps the default
timing the papers' and lets a study ask "what if the dialog ran on pc2".
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any

from homesim.deployment import Deployment, check_file, load
from homesim.documents import DocumentType
from homesim.errors import InputError

#: Every module of a full run, by name: the hardware models (``robot.hardware.install``), the
#: execution supervisor and those ``robot.install.SUBSYSTEMS`` install. What a deployment may place
#: (``<place module>``): the kernel does not know BIRON's modules, the run and ``homesim check`` pass
#: this list (tests/test_deployment.py checks it against a run's modules).
MODULES: tuple[str, ...] = (
    # hardware
    "base", "camera", "display", "laser", "map_server", "microphones", "sonar", "speaker",
    # the execution supervisor
    "supervisor",
    # the subsystems
    "localiser", "person_attention", "scene_model", "object_attention", "understanding", "dialog", "watchdog",
    "follower", "planner", "sequencer", "player",
)

#: The papers' deployment (the default of every run).
DEFAULT = Path(__file__).with_name("biron.xml")


@lru_cache(maxsize=1)
def papers() -> Deployment:
    """The default document, loaded once (its placements checked against BIRON's modules)."""
    return load(DEFAULT, modules=MODULES)


def _check(path: str) -> list[InputError]:
    return check_file(path, modules=MODULES)


#: ``homesim check`` of a deployment document (entry point ``homesim.documents``): the kernel's checks
#: and every ``<place module>`` one of BIRON's modules (:data:`MODULES`).
DOCUMENT_TYPE = DocumentType("deployment", "deployment", _check)


def cost_scale(sim: Any, module: str, host: str) -> float:
    """How much slower (> 1) or faster (< 1) ``module`` computes on ``host`` than on its papers' host."""
    ref = papers()
    try:
        ref_mhz = ref.host(ref.host_of(module)).cpu_mhz
    except KeyError:
        return 1.0
    mhz = sim.network.host_speed(host)
    if not ref_mhz or not mhz:
        return 1.0
    return ref_mhz / mhz


def check_scenario(sc: Any) -> "list[Any] | None":
    """``homesim.scenario_checks``: the scenario's ``<deployment>`` merged into BIRON's default.

    What the schema cannot see (a host, route or placement naming a host or
    link that neither the default nor the override declares, a placement of a
    module BIRON does not have, an ``href`` document that does not load) is found by ``homesim check``, not first by
    ``homesim run``. Raises :class:`~homesim.errors.ScenarioError` naming the
    file and line.
    """
    if sc.deployment is None:
        return
    from homesim.deployment import DeploymentProblems, resolve
    from homesim.errors import InputError, ScenarioError

    base_dir = Path(sc.source).parent if sc.source and not str(sc.source).startswith("<") else None
    try:
        resolve(papers(), sc.deployment, base_dir=base_dir, modules=MODULES)
    except DeploymentProblems as exc:  # every one, at its line
        return [ScenarioError(p.message, source=p.source, line=p.line, element=p.element) for p in exc.problems]
    except InputError as exc:
        raise ScenarioError(exc.message, source=exc.source, line=exc.line, element=exc.element) from exc
    return None
