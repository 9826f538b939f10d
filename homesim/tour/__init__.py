"""The run package: BIRON's home tour composed from the kernel, the robot and the people.

The top layer of ``homesim`` and the only part of it that imports ``robot``
and ``humans`` (only the command line, :mod:`homesim.cli`, imports it):
:mod:`.stage` (the world with its people and the robot's hardware),
:mod:`.runner` (one scenario becomes one run), the commands ``run`` /
``replay`` (:mod:`.run_cli`), ``sweep``, ``plot`` (:mod:`.plot_cli`) and
``export`` (:mod:`.export_cli`, :mod:`.mcap_export`), the BIRON-specific
expectation kinds (:mod:`.expect`), metrics (:mod:`.metrics`), percepts to
draw (:mod:`.percepts`) and timeline phases (:mod:`.phases`); generated flats and
tours (``generate``: :mod:`.generate`, :mod:`.flatgen`, :mod:`.objectgen`,
:mod:`.phrasing`) and studies over them (``study``: :mod:`.study`,
:mod:`.capabilities`).

Importing the package fills the kernel's registries with the robot's
expectation kinds and timeline phases (the metrics register when
:mod:`.metrics` is imported, as the runner does).
"""

from __future__ import annotations

from ..documents import register_example
from . import expect, phases  # noqa: F401 (they register on import)

#: The AFSM BIRON's supervisor runs: the example ``homesim afsm`` and ``homesim check`` show in ``--help``.
register_example("AFSM", "robot/afsm/biron.scxml")
