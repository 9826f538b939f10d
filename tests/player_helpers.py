"""A go-to player built without a bus or a map, already driving a ``move_to``: the unit tests of its speed rules share it."""

from __future__ import annotations

import math

from lxml import etree

from homesim.sim import Simulation
from robot.navigation.player import Player


def moving_player(goal: tuple[float, float], v: float) -> Player:
    """A player at the origin facing +x, driving at ``v`` m/s toward ``goal`` (no bus, no map)."""
    p = Player(Simulation(seed=0))

    class _Bus:
        def publish(self, channel, el):  # noqa: ANN001, ANN202
            pass

    p.bus = _Bus()  # type: ignore[assignment]
    p._pose_xml = etree.Element("pose", x="0", y="0", theta="0")
    odo = etree.Element("odometry", x="0", y="0", theta="0", v=f"{v}", w="0")
    p.odo.update(odo)
    p._odo_xml_at_pose = odo
    p.goal = (goal[0], goal[1], 0.0, 0.2, False)
    p.leg_start = (0.0, 0.0)
    p._facing = False
    p._best, p._best_t = math.inf, 0.0
    p.state = "moving"
    return p
