"""The actors a test puts on a :class:`~homesim.tour.stage.Stage`: a run's, or one kind of them.

The stage names no actor and has no default (the kernel never names the robot or the humans): a test hands
in the install functions itself, as :mod:`homesim.tour.runner` does for a run.
"""

from __future__ import annotations

from homesim.tour.runner import ACTORS
from humans.install import install as install_people
from robot.hardware.install import install as install_hardware

#: The scripted people and sound sources alone.
PEOPLE = (install_people,)
#: The PeopleBot's hardware models alone.
HARDWARE = (install_hardware,)

__all__ = ["ACTORS", "HARDWARE", "PEOPLE"]
