"""The robot's blind half: what the sonar rings say is there, and the rule every base command keeps to it.

The laser looks ahead only, from 0.13 m ahead of the centre; beside and behind that line the robot
has only its sonar rings (``/robot/sonar``, :mod:`robot.hardware.sonar`). Backing off, turning on the
spot, yielding and the corridor back-out all move the footprint into that half, and the people the
robot was touching there (contacts9: someone pressed within 5 cm of its side or back, out of the
laser's view and misplaced or untracked) were invisible to every check the modules make. So each
module that sends ``/robot/base/cmd`` (the follower, the player, person attention) keeps a
:class:`SonarEchoes` and holds its command to :func:`blind_clear` before it sends it; a command
that is not clear is sent as a stop.

What a reading says: something lies somewhere on the arc at its range across the transducer's cone
(a sonar gives no bearing within its cone), so each reading becomes :data:`ARC_POINTS` points on
that arc. A reading the floor plan explains (its arc within :data:`EXPLAIN` m of a wall or a piece
of furniture the robot knows) is the flat's, which the modules' own floor-plan checks keep to; the
others may be a person's legs, and a person's body reaches nearer to the footprint than the echo of
their far leg by up to the 0.25 m body and the 0.1 m the leg stands off its centre, less the part of the
leg's 0.06 m radius that faces the footprint (the near leg may lie between two cones and go unheard).
The echo is the leg's point nearest the *transducer*, not the footprint: at the rear gaps (115-120 and
240-245 degrees) a flank transducer hears the far leg obliquely and its arc lies up to 0.348 m further
from the footprint than her body (3673 placements of someone 0-5 cm off the footprint, exact readings,
fixsafe13; 0.29 m straight on, the old gap's premise, 99th percentile 0.28 m). So the
footprint keeps :data:`BLIND_GAP` from them, or comes no nearer than it is (standing still is always
clear); with 0.30 m a turn pressed against her flank at 116 degrees swung the rear corner 3 mm into her
within one control period (tests/test_sonar.py's property). Only
echoes behind the laser's line count: ahead of it the laser sees, and the modules' people rules
already hold.

Known limits: a reading's arc stands for the leg it heard, not for the body round it, so held open
loop for the whole look-ahead a turn past someone pressed against the flank can end a few millimetres
into them (the modules decide again every 0.1 s, on fresh readings); and the cones leave gaps (between
the 90 and 130 degree transducers a leg pressed against the flank is heard by none). Measured (safe13,
exact readings, with the gap at 0.30 m; not measured again at 0.35 m): of someone standing with her body 1-30 cm off the footprint behind the laser's line,
anywhere round it, 0.8 % are heard by no transducer, and 0.7 % of the commands that would touch her pass
this check held open loop 0.5 s, all at 115-120 degrees (the rear gaps); person attention's turn, closed
loop with laser and sonar as tests/test_attention_turn_people runs it, touches someone standing 1-15 cm
off at 100-130 degrees in 3 % of turns, by 2-14 mm. The bumper rings' corner segments lie at those gaps:
such a touch presses one, and every module's bumper reflex stops the turn (:mod:`robot.bumpers`).

Someone walking up from behind (:meth:`SonarEchoes.closing`, the go-to's yield): a rear-facing transducer's
unexplained echo near the footprint whose range fell, between its two latest readings, by more than the robot's own
travel toward that cone explains plus :data:`CLOSING_SPEED` m/s (fresh7/split_goto_ramp_child: a child overtook the
go-to at 0.9 m/s, 0.03 m off its flank, tracked only once level with it).

The echoes are kept in the odometry frame, one per transducer (the newest with an echo, and the range and pose of
the one before it), and forgotten after :data:`ECHO_AGE` s: a reading lost to a dropout does not open a hole for the
0.32 s a ring takes to come round again. Pure code and one small bounded state; no world, no
ground truth: the robot sees only the sonar's messages and its own odometry.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
from lxml import etree

from homesim.message import Message
from robot.footprint import footprint_distance, sweep_poses
from robot.sonar_packet import SonarPacket, echoes_of

#: m: readings farther than this are no concern of a command (none sweeps that far in its horizon)
SONAR_REACH = 1.2
#: s: an echo older than this is forgotten (two turns of a ring)
ECHO_AGE = 0.7
#: points sampled on a reading's arc across the cone
ARC_POINTS = 5
#: m: the laser's line (its offset ahead of the centre): echoes behind it are the sonar's alone
BLIND_X = 0.13
#: m: the footprint keeps this far from an unexplained echo (a person's body beyond their far leg, heard
#: obliquely: up to 0.348 m measured), or comes no nearer
BLIND_GAP = 0.35
#: m: a reading whose arc comes this close to the floor plan's outline is the flat's
EXPLAIN = 0.12
#: m: laser echoes this close to a tracked person's position are that person's legs (:func:`seen_legs`; as the
#: follower's dynamic window leaves its partner's legs out: 0.45 m)
LEGS_NEAR = 0.45
#: m/s: an unexplained echo behind the laser's line whose range fell faster than this between its transducer's two
#: latest readings, beyond what the robot's own travel and turn between them explain, is someone
#: walking up beside or behind the robot (:meth:`SonarEchoes.closing`): a wall, a chair or someone standing reads no
#: nearer than the robot moved toward them. A walk is 0.8-1.4 m/s; a reading's range jitters by a centimetre or two.
CLOSING_SPEED = 0.4
#: m: ... and its arc now within this much of the footprint (the personal space a passer-by is yielded to, with a
#: body's reach: the echo is the leg, the body reaches nearer)
CLOSING_NEAR = 0.8
#: rad: only transducers facing back this far or more hear someone closing in (the rear ring's 130, 150 and 170 degree
#: ones): someone walking up from behind is heard there first, while things passed beside the robot come and go in the
#: side ones' cones (a leg entering a cone's edge reads nearer at once, as if it walked up)
REAR = math.radians(120.0)
#: rad: the half width of a transducer's cone, with a leg's width, over which its reading's bearing is unknown
CONE_REACH = math.radians(25.0)
#: m: a transducer's reach from the robot's centre (the footprint's corner), for what a turn alone changes a range by
TRANSDUCER_REACH = 0.34

Pose = tuple[float, float, float]


Arc = tuple[int, np.ndarray, np.ndarray, float, float]

def near_arcs(packet: etree._Element | SonarPacket) -> list[Arc]:
    """(transducer, x, y, range, bearing) robot-frame points (:data:`ARC_POINTS` each) on the arc of every echo of ``packet``
    nearer than :data:`SONAR_REACH`: what a reading says, wherever the robot is. A function of the packet
    alone, so a record's arcs are worked out once for all its receivers and kept on the record
    (:meth:`SonarPacket.derived`; the arrays are read-only); no state of this module is shared by the
    modules that read it (separate processes on the robot) or outlives a run."""
    if packet.__class__ is SonarPacket:
        return packet.derived("near_arcs", _arcs)  # type: ignore[union-attr]
    return _arcs(packet)


@functools.lru_cache(maxsize=8)
def _arc_offsets(cone: float) -> np.ndarray:
    """The ARC_POINTS bearings (rad) across a transducer's ``cone`` (degrees), read-only: one array per cone for
    the whole run (every packet's arcs read it; the rings have one cone)."""
    half = math.radians(cone) / 2
    offsets = np.linspace(-half, half, ARC_POINTS)
    offsets.flags.writeable = False
    return offsets


def _arcs(packet: etree._Element | SonarPacket) -> list[Arc]:
    top = float(packet.get("max_range", "5"))
    offsets = _arc_offsets(float(packet.get("cone", "30")))
    out: list[Arc] = []
    for e in (packet.echoes() if packet.__class__ is SonarPacket else echoes_of(packet)):  # type: ignore[union-attr]
        r = e.range
        if r >= top or r > SONAR_REACH:
            continue  # no echo (or far): the last echo stands until it is too old
        tb = e.bearing
        px, py = e.x + r * np.cos(tb + offsets), e.y + r * np.sin(tb + offsets)
        px.flags.writeable = py.flags.writeable = False
        out.append((e.id, px, py, r, tb))
    return out


class SonarEchoes:
    """The newest echo of every transducer, as odometry-frame arc points (see the module docstring)."""

    __slots__ = ("_latest", "_ranges", "_before", "_bearing")

    def __init__(self) -> None:
        self._latest: dict[int, tuple[float, np.ndarray]] = {}  # transducer -> (time, (ARC_POINTS, 2) odometry frame)
        # transducer -> (time, range, odometry pose read at) of its latest reading, and of the one before it
        self._ranges: dict[int, tuple[float, float, Pose]] = {}
        self._before: dict[int, tuple[float, float, Pose]] = {}
        self._bearing: dict[int, float] = {}  # transducer -> its bearing (rad, robot frame)

    def update(self, packet: etree._Element | SonarPacket, odom: Pose | None, now: float) -> None:
        """Take a ``<sonar>`` packet (its XML, or the record it came as) read at odometry pose ``odom``
        (None: not yet known, ignored)."""
        if odom is None:
            return
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        for ident, px, py, rng, bearing in near_arcs(packet):
            self._bearing[ident] = bearing
            last = self._ranges.get(ident)
            if last is not None and last[0] < now:
                self._before[ident] = last
            self._ranges[ident] = (now, rng, odom)
            self._latest[ident] = (now, np.column_stack((ox + c * px - s * py, oy + s * px + c * py)))

    def hear(self, msg: Message, odom: Pose | None, now: float) -> None:
        """:meth:`update` with a ``/robot/sonar`` message: its shared record when it came as one, else its XML."""
        data = msg.data
        self.update(data if data.__class__ is SonarPacket else msg.xml, odom, now)

    def arcs(self, odom: Pose | None, now: float) -> list[np.ndarray]:
        """The fresh echoes' arcs, robot frame at ``odom`` (each (ARC_POINTS, 2)); stale ones are dropped."""
        self._forget(now)
        if odom is None:
            return []
        return [_to_robot(pts, odom) for _, pts in self._latest.values()]

    def _forget(self, now: float) -> None:
        for k in [k for k, (t, _) in self._latest.items() if now - t > ECHO_AGE]:
            del self._latest[k]
        for k in [k for k, (t, _, _) in self._before.items() if now - t > ECHO_AGE or k not in self._latest]:
            del self._before[k]

    def closing(self, odom: Pose | None, now: float, explains: Callable[[np.ndarray], bool] | None = None, *,
                speed: float = CLOSING_SPEED, near: float = CLOSING_NEAR) -> bool:
        """Whether a transducer's latest echo, behind the laser's line (:data:`BLIND_X`) and not explained by the floor
        plan (``explains``), lies within ``near`` m of the footprint and read nearer than the same transducer's reading
        before it by more than the robot's own motion between the two explains (its travel, and its turn times the
        transducer's reach) plus ``speed`` m/s: someone walking up beside or behind the robot, where the laser does not
        look (see :data:`CLOSING_SPEED`). A reading gives no bearing within its cone, so ranges are compared, not places."""
        self._forget(now)
        if odom is None:
            return False
        for k, (t, pts) in self._latest.items():
            prev = self._before.get(k)
            if prev is None or abs(self._bearing[k]) < REAR:
                continue
            t0, r0, (x0, y0, th0) = prev
            _t1, r1, (x1, y1, th1) = self._ranges[k]
            if t <= t0:
                continue
            own = _toward(self._bearing[k], (x0, y0, th0), (x1, y1)) + abs(math.remainder(th1 - th0, 2 * math.pi)) * (r0 + TRANSDUCER_REACH)
            if r0 - r1 - own <= speed * (t - t0):
                continue
            arc = _to_robot(pts, odom)
            blind = arc[:, 0] < BLIND_X
            if (blind.any() and float(footprint_distance(arc[blind, 0], arc[blind, 1]).min()) <= near
                    and (explains is None or not explains(arc))):
                return True
        return False


def _toward(bearing: float, then: Pose, now: tuple[float, float]) -> float:
    """How much nearer the robot's travel from ``then`` to ``now`` (odometry frame) can bring a transducer at
    ``bearing`` (robot frame) to something standing in its cone (with a leg's width either side): the travel's
    largest component toward any direction in it, none for a transducer facing away from the travel."""
    x0, y0, th0 = then
    dx, dy = now[0] - x0, now[1] - y0
    c, s = math.cos(th0), math.sin(th0)
    fx, fy = c * dx + s * dy, -s * dx + c * dy  # the travel in the robot's frame then
    half = CONE_REACH
    return max(0.0, max(fx * math.cos(bearing + a) + fy * math.sin(bearing + a) for a in (-half, -half / 2, 0.0, half / 2, half)))


def _to_robot(pts: np.ndarray, odom: Pose) -> np.ndarray:
    """Odometry-frame points in the robot's frame at ``odom``."""
    ox, oy, oth = odom
    c, s = math.cos(oth), math.sin(oth)
    dx, dy = pts[:, 0] - ox, pts[:, 1] - oy
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy))


def explained_by_points(mapped: np.ndarray) -> Callable[[np.ndarray], bool]:
    """An explanation test from the floor plan's outline points (robot frame): an arc within :data:`EXPLAIN` of one."""
    def explains(arc: np.ndarray) -> bool:
        if not len(mapped):
            return False
        d2 = (mapped[None, :, 0] - arc[:, 0, None]) ** 2 + (mapped[None, :, 1] - arc[:, 1, None]) ** 2
        return bool(d2.min() <= EXPLAIN * EXPLAIN)
    return explains


def seen_legs(echoes: np.ndarray, people: np.ndarray, reach: float = LEGS_NEAR) -> np.ndarray:
    """The laser's ``echoes`` (robot frame) ahead of its line (:data:`BLIND_X`) within ``reach`` m of a tracked person
    (``people``: (P, 2) robot-frame positions): their legs, seen. A sonar reading whose arc comes within
    :data:`EXPLAIN` of one is that person (:func:`explained_by_points` on them with the floor plan), not something
    unseen: a flank transducer hears someone standing beside the robot's front across its cone, and its arc runs on
    round the flank, where a turn on the spot swings a corner (face20: the follower's turn back to her; turn21: the
    person attention's). The person's body is the turning module's own concern, kept clear by its sweep of the
    tracked bodies (:func:`robot.footprint.turn_clear`), so nobody is turned into; a reading far from every seen leg
    is judged as before. The follower and person attention share this rule."""
    people = np.asarray(people, dtype=float).reshape(-1, 2)
    if not len(echoes) or not len(people):
        return np.zeros((0, 2))
    ahead = echoes[echoes[:, 0] >= BLIND_X]
    if not len(ahead):
        return np.zeros((0, 2))
    d2 = (ahead[:, None, 0] - people[None, :, 0]) ** 2 + (ahead[:, None, 1] - people[None, :, 1]) ** 2
    return ahead[d2.min(axis=1) <= reach * reach]


def blind_points(arcs: list[np.ndarray], explains: Callable[[np.ndarray], bool] | None = None) -> np.ndarray:
    """(K, 2) robot-frame points of the echoes a command must keep clear of: those in the blind half
    (behind :data:`BLIND_X`) whose reading the floor plan does not explain (``explains``; None: none is)."""
    keep = []
    for arc in arcs:
        blind = arc[arc[:, 0] < BLIND_X]
        if len(blind) and (explains is None or not explains(arc)):
            keep.append(blind)
    return np.concatenate(keep) if keep else np.zeros((0, 2))


def blind_clear(v: float, w: float, points: np.ndarray, *, duration: float, gap: float = BLIND_GAP) -> bool:
    """Whether the footprint swept by (``v``, ``w``) held ``duration`` s keeps ``gap`` from every one of ``points``
    (robot frame), or, from one already closer, comes no nearer to it. Per point: one echo pressed
    against the robot must not make a sweep into another clear. Standing still is always clear."""
    if not len(points) or (v == 0.0 and w == 0.0):
        return True
    x, y, th = sweep_poses(v, w, duration)
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    dx, dy = points[None, :, 0] - x[:, None], points[None, :, 1] - y[:, None]
    d = footprint_distance(c * dx + s * dy, -s * dx + c * dy)  # (poses, K)
    return bool(np.all(d.min(axis=0) >= np.minimum(d[0], gap) - 1e-3))
