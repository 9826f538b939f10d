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


def player_standing_at(x: float, y: float, th: float, goal: tuple[float, float], w0: float) -> Player:
    """A player standing at (x, y, th) on the first leg of a plan (a replan's, from where it stands), heading for
    ``goal``, its odometry turning at ``w0``: the go-to's decisions at one place, without a simulation."""
    p = moving_player(goal, 0.0)
    p._pose_xml = etree.Element("pose", x=f"{x}", y=f"{y}", theta=f"{th}")
    odo = etree.Element("odometry", x=f"{x}", y=f"{y}", theta=f"{th}", v="0", w=f"{w0}")
    p.odo.update(odo)
    p._odo_xml_at_pose = odo
    p.goal = (goal[0], goal[1], 0.0, 0.25, False)
    p.leg_start = (x, y)
    p._facing = True  # a first leg, from where it stands
    return p
