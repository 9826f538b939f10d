"""The people around the robot, as the person attention tracks them: whom to give way to.

Both local controllers (the follower and the player's ``move_to``) read
``/robot/attention/tracks`` (odom frame: position, velocity, ``confirmed``) and
keep out of everyone's space (``people=`` of :func:`~robot.navigation.local.dwa`)
and slow down near them (:func:`~robot.navigation.local.social_speed_limit`).
Only confirmed tracks count (a table leg seen once is no person). Positions are
predicted to now at constant velocity (at most :data:`HORIZON` s ahead, as the
follower predicts its partner), so a person walking across is given way to
where they are, not where they were.

A confirmed track of someone standing (slower than :data:`GHOST_SPEED`) that disappears
(the tracker lost a person standing still in a door frame, whose legs merge with the
jambs) is remembered where it was last, for as long as the laser still has an echo there (within :data:`GHOST_ECHO` m, at most
:data:`GHOST_MAX` s): a person the tracker loses is still a person, not free space
to drive into.

One exception to "only confirmed tracks": :meth:`People.emerging`, the tentative tracks that walk,
for the yield rule alone. Someone who comes round a door jamb toward the robot is first seen at about
a metre, and their track is confirmed three scans later: the robot drove on at walking pace meanwhile
and met him in the opening (ring_goto_other_way seeds 3, 5: Ben came through the 1.6 m dining opening
the way the robot went in; tentative at 1.06 m, confirmed at 0.74 m, the robot stopped at 0.6 m).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np

#: s: a track is predicted at most this far ahead of its message.
HORIZON = 0.5
#: m: people further than this from the robot do not matter to the local controllers.
REACH = 4.0
#: s: a lost track is remembered at most this long.
GHOST_MAX = 15.0
#: m/s: only a track this slow when lost (someone standing) is remembered.
GHOST_SPEED = 0.3
#: m: a lost track is remembered while the laser has an echo this close to where it was.
GHOST_ECHO = 0.35
#: s: any confirmed track that vanished (walking or standing) is remembered this long for what the
#: laser cannot see: behind the robot, where someone it lost sight of may have walked to.
LOST_MAX = 10.0
#: m/s: how fast someone lost from view may have walked since (a brisk walk).
WALK = 1.0
#: m^2: a tentative track counts for :meth:`People.emerging` only while its position variance (cxx + cyy)
#: is this small: measured on the last scans, not coasting on an echo that is gone (a new person's legs:
#: 0.003-0.007; a tentative track seen once and coasting grows past 1 within seconds)
TENTATIVE_VAR = 0.05


#: m: a tentative track seen for the first time this near, ahead of the robot's centre, counts for the follower's
#: contact limit before it has a velocity (:meth:`People.newborn`): someone out of a door beside its way
NEWBORN_REACH = 1.5
#: m: ... unless it is this near another track (a second track on a known person's legs, her re-found track)
NEWBORN_APART = 0.8
#: m/s: ... reckoned with as running straight at the robot's centre this fast (a child running: 1.5 m/s)
NEWBORN_WALK = 1.5


#: m/s: a confirmed track this fast walks (for :meth:`People.stopped`: the velocity it may walk on at)
RESUME_WALK = 0.5
#: m/s: a track this much slower than its fastest walk of the last :data:`RESUME_FOR` s stopped or is slowing, or is
#: setting off again (the tracker's velocity lags a restart by a few scans)
RESUME_SLOWER = 0.3
#: s: someone who stopped dead is reckoned with as walking on, as they walked, this long after they last walked
RESUME_FOR = 2.0


class People:
    """The latest ``/robot/attention/tracks`` payload, read only when a control step asks."""

    def __init__(self) -> None:
        self.xml: Any = None
        self._confirmed: dict[str, tuple[float, float, float]] = {}  # id -> last odom position and speed
        self.ghosts: dict[str, tuple[float, float, float]] = {}  # lost confirmed tracks: id -> (x, y, lost at)
        self.lost: dict[str, tuple[float, float, float]] = {}  # every vanished confirmed track: id -> (x, y, lost at)
        self.walked: dict[str, tuple[float, float, float]] = {}  # present confirmed tracks: id -> (vx, vy, when) last walking
        self._ids: frozenset[str] = frozenset()  # every track id of the latest payload
        self.new_ids: frozenset[str] = frozenset()  # ... those the payload before did not hold (first sighting)

    def update(self, xml: Any) -> None:
        """Keep the latest tracks payload (the receiver's own copy); remember tracks that vanished."""
        self.xml = xml
        ids = frozenset(str(t.get("id")) for t in xml.iterfind("track"))
        self.new_ids, self._ids = ids - self._ids, ids
        now = {}
        try:
            t0 = float(xml.get("time", "0"))
        except ValueError:
            t0 = 0.0
        walked = {}
        for t in xml.iterfind("track"):
            if t.get("confirmed") == "true":
                try:
                    tid, vx, vy = str(t.get("id")), float(t.get("vx", "0")), float(t.get("vy", "0"))
                    now[tid] = (float(t.get("x")), float(t.get("y")), math.hypot(vx, vy))
                except (TypeError, ValueError):
                    continue
                last = self.walked.get(tid)
                if last is not None and t0 - last[2] <= RESUME_FOR and math.hypot(last[0], last[1]) > math.hypot(vx, vy):
                    walked[tid] = last  # their fastest walk of the last RESUME_FOR s
                elif math.hypot(vx, vy) >= RESUME_WALK:
                    walked[tid] = (vx, vy, t0)
        self.walked = walked  # (only tracks present now: bounded)
        for tid, (x, y, speed) in self._confirmed.items():
            if tid not in now:
                self.lost[tid] = (x, y, t0)
            if tid not in now and speed < GHOST_SPEED:  # someone walking on is not remembered standing
                self.ghosts[tid] = (x, y, t0)
        for tid in now:
            self.ghosts.pop(tid, None)
            self.lost.pop(tid, None)
        for tid in [k for k, (_, _, t) in self.lost.items() if t0 - t > LOST_MAX]:
            del self.lost[tid]
        self._confirmed = now

    def clear(self) -> None:
        self.xml = None
        self._confirmed = {}
        self.ghosts = {}
        self.lost = {}
        self.walked = {}
        self._ids = frozenset()
        self.new_ids = frozenset()

    def tracks(self, odom: tuple[float, float, float], now: float, *, exclude: str | None = None,
               sure: float | None = None) -> list[tuple[str, float, float, float, float, float]]:
        """The confirmed tracks within :data:`REACH` m as (id, x, y, vx, vy, variance), robot frame, predicted to
        ``now`` (``exclude``: a track id left out; ``sure``: as in :meth:`around`; variance: ``cxx`` + ``cyy``): who
        walked at the robot is a matter of one person's track over time (the follower's making way)."""
        xml = self.xml
        if xml is None:
            return []
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        out = []
        for t, x, y, vx, vy in self._predicted(xml, now, exclude):
            try:
                var = float(t.get("cxx", "0")) + float(t.get("cyy", "0"))
            except (TypeError, ValueError):
                continue
            if sure is not None and var > sure:
                continue
            dx, dy = x - ox, y - oy
            if math.hypot(dx, dy) <= REACH:
                out.append((str(t.get("id")), c * dx + s * dy, -s * dx + c * dy, c * vx + s * vy, -s * vx + c * vy, var))
        return out

    def stopped(self, odom: tuple[float, float, float], now: float, *, reach: float = REACH,
                exclude: str | None = None) -> np.ndarray:
        """(K, 4) robot-frame centres (predicted to ``now``) of the confirmed tracks within ``reach`` m that are
        :data:`RESUME_SLOWER` m/s slower now than their fastest walk (:data:`RESUME_WALK` or faster) of the last
        :data:`RESUME_FOR` s, each with the velocity of that walk: someone who stopped dead may walk on as they walked (a child running across stops for a moment in
        front of the robot and runs on, cross_child_stops_twins seed 4: met at 0.01 m of air by a robot at full speed,
        who reckoned her standing), and as they set off again the tracker's velocity lags theirs (the same child: 0.5
        m/s reported three scans into her 2 m/s run). The tracks' own rows stay: the limit is the least over both.
        ``exclude``: a track id left out."""
        xml = self.xml
        if xml is None or not self.walked:
            return np.zeros((0, 4))
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        out = []
        for t, x, y, vx, vy in self._predicted(xml, now, exclude):
            tid = str(t.get("id"))
            if tid not in self.walked:
                continue
            wx, wy, _ = self.walked[tid]
            dx, dy = x - ox, y - oy
            if math.hypot(vx, vy) < math.hypot(wx, wy) - RESUME_SLOWER and math.hypot(dx, dy) <= reach:
                out.append((c * dx + s * dy, -s * dx + c * dy, c * wx + s * wy, -s * wx + c * wy))
        return np.array(out) if out else np.zeros((0, 4))

    def emerging(self, odom: tuple[float, float, float], now: float, *, moving: float,
                 reach: float) -> np.ndarray:
        """(K, 4) robot-frame centres and velocities (predicted to ``now``) of the tentative tracks within
        ``reach`` m, freshly measured (:data:`TENTATIVE_VAR`) and walking faster than ``moving`` m/s.

        Not a person yet for the window or the waits (a table leg seen once is no person), but enough
        to stand for (the yield, :func:`closing_in`): a leg pair that walks at the robot out of a door
        it is about to go through is someone coming round the jamb, and the scans that confirm him are
        a third of a metre of his way and the robot's (see the module docstring)."""
        xml = self.xml
        if xml is None:
            return np.zeros((0, 4))
        age = self._age(xml, now)
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        out = []
        for t in xml.iterfind("track"):
            if t.get("confirmed") == "true":
                continue
            try:
                vx, vy = float(t.get("vx", "0")), float(t.get("vy", "0"))
                var = float(t.get("cxx", "inf")) + float(t.get("cyy", "inf"))
                x = float(t.get("x")) + vx * age
                y = float(t.get("y")) + vy * age
            except (TypeError, ValueError):
                continue
            if not var <= TENTATIVE_VAR or math.hypot(vx, vy) <= moving:
                continue
            dx, dy = x - ox, y - oy
            if math.hypot(dx, dy) <= reach:
                out.append((c * dx + s * dy, -s * dx + c * dy, c * vx + s * vy, -s * vx + c * vy))
        return np.array(out) if out else np.zeros((0, 4))

    def newborn(self, odom: tuple[float, float, float], now: float, *, reach: float | None = None,
                apart: float | None = None, speed: float | None = None, exclude: str | None = None) -> np.ndarray:
        """(K, 4) robot-frame centres of the tentative tracks seen for the first time in the latest payload
        (an id the payload before did not hold: one sighting, no velocity measured yet), freshly measured
        (:data:`TENTATIVE_VAR`), ahead of the robot's centre within ``reach`` m (:data:`NEWBORN_REACH`) and at
        least ``apart`` m (:data:`NEWBORN_APART`) from every other track (not a second track on a known
        person's legs), each walking straight at the robot's centre at ``speed`` (:data:`NEWBORN_WALK`);
        ``exclude``: a track id left out (the partner, found again under a new id).

        Someone who appears that near has come out of where the laser could not see (a side door, a jamb)
        and the tracker cannot tell yet how fast or where they go: reckoned with as running at the robot
        until their second sighting says otherwise (fresh7 corr_hallway_crossing seed 1: a boy running out
        of a side door of a 1.1 m hallway at 1.5 m/s, first seen 1.13 m off with no velocity, was left out
        for that scan and the robot, at 0.47 m/s, touched him)."""
        reach = NEWBORN_REACH if reach is None else reach
        apart = NEWBORN_APART if apart is None else apart
        speed = NEWBORN_WALK if speed is None else speed
        xml = self.xml
        if xml is None or not self.new_ids:
            return np.zeros((0, 4))
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        pos: dict[str, tuple[float, float]] = {}
        fresh: list[str] = []
        for t in xml.iterfind("track"):
            tid = str(t.get("id"))
            try:
                pos[tid] = (float(t.get("x")), float(t.get("y")))
                var = float(t.get("cxx", "inf")) + float(t.get("cyy", "inf"))
            except (TypeError, ValueError):
                continue
            if tid in self.new_ids and tid != exclude and t.get("confirmed") != "true" and var <= TENTATIVE_VAR:
                fresh.append(tid)
        out = []
        for tid in fresh:
            x, y = pos[tid]
            if any(math.hypot(x - ux, y - uy) < apart for uid, (ux, uy) in pos.items() if uid != tid):
                continue
            dx, dy = x - ox, y - oy
            rx, ry = c * dx + s * dy, -s * dx + c * dy
            d = math.hypot(rx, ry)
            if rx <= 0.0 or d > reach or d < 1e-6:
                continue
            out.append((rx, ry, -speed * rx / d, -speed * ry / d))
        return np.array(out) if out else np.zeros((0, 4))

    @staticmethod
    def _age(xml: Any, now: float) -> float:
        """How far (s, at most :data:`HORIZON`) the tracks message lies behind ``now``: its tracks are
        predicted on by their velocity for that long."""
        try:
            return min(max(now - float(xml.get("time", now)), 0.0), HORIZON)
        except ValueError:
            return 0.0

    def _predicted(self, xml: Any, now: float, exclude: str | None) -> Iterator[tuple[Any, float, float, float, float]]:
        """The tracks message's confirmed tracks (but ``exclude``), each with its odom-frame position predicted to
        ``now`` by its velocity, and that velocity: (track element, x, y, vx, vy); a track with a bad number is skipped."""
        age = self._age(xml, now)
        for t in xml.iterfind("track"):
            if t.get("confirmed") != "true" or (exclude is not None and t.get("id") == exclude):
                continue
            try:
                vx, vy = float(t.get("vx", "0")), float(t.get("vy", "0"))
                x, y = float(t.get("x")) + vx * age, float(t.get("y")) + vy * age
            except (TypeError, ValueError):
                continue
            yield t, x, y, vx, vy

    def around(self, odom: tuple[float, float, float], now: float, *, exclude: str | None = None,
               near: tuple[float, float] | None = None, near_radius: float = 0.6,
               echoes: np.ndarray | None = None, moving: float | None = None, velocity: bool = False,
               standing: float | None = None, sure: float | None = None) -> np.ndarray:
        """(K, 2) robot-frame centres of the confirmed people within :data:`REACH` m, predicted to ``now``.

        ``exclude``: a track id left out (the partner the follower drives after); ``near``: an
        odom-frame point whose surroundings (``near_radius``) are left out too (a second track
        on the partner's own legs). ``echoes``: the latest scan's robot-frame points; a lost
        track is kept (see the module docstring) while one of them is near it. ``moving``: only
        tracks faster than this (m/s), and no lost ones; ``standing``: only tracks slower than this
        (m/s), lost ones too (where the laser still has an echo). ``velocity``: (K, 4), each centre with
        the person's velocity in the robot frame (m/s; 0 for a remembered lost track). ``sure``: only
        tracks whose position variance (``cxx`` + ``cyy``, m^2) is at most this (measured now, not
        coasting on its last velocity with no echo to update it).
        """
        xml = self.xml
        if xml is None:
            return np.zeros((0, 4 if velocity else 2))
        ox, oy, oth = odom
        c, s = math.cos(oth), math.sin(oth)
        out = []
        for t, x, y, vx, vy in self._predicted(xml, now, exclude):
            if near is not None and math.hypot(x - near[0], y - near[1]) < near_radius:
                continue
            if sure is not None and float(t.get("cxx", "0")) + float(t.get("cyy", "0")) > sure:
                continue
            speed = math.hypot(float(t.get("vx", "0")), float(t.get("vy", "0")))
            if (moving is not None and speed <= moving) or (standing is not None and speed >= standing):
                continue
            dx, dy = x - ox, y - oy
            if math.hypot(dx, dy) <= REACH:
                out.append((c * dx + s * dy, -s * dx + c * dy) + ((c * vx + s * vy, -s * vx + c * vy) if velocity else ()))
        for tid in sorted(self.ghosts) if moving is None else ():
            x, y, lost = self.ghosts[tid]
            if now - lost > GHOST_MAX or echoes is None or not len(echoes) or tid == exclude:
                self.ghosts.pop(tid) if now - lost > GHOST_MAX else None
                continue
            if near is not None and math.hypot(x - near[0], y - near[1]) < near_radius:
                continue
            dx, dy = x - ox, y - oy
            lx, ly = c * dx + s * dy, -s * dx + c * dy
            if math.hypot(dx, dy) <= REACH and np.min(np.hypot(echoes[:, 0] - lx, echoes[:, 1] - ly)) <= GHOST_ECHO:
                out.append((lx, ly) + ((0.0, 0.0) if velocity else ()))
            else:
                self.ghosts.pop(tid)  # nothing there any more: gone
        return np.array(out) if out else np.zeros((0, 4 if velocity else 2))


def maybe_behind(people: People, odom: tuple[float, float, float], now: float, *, reach: float,
                 walk: float = WALK) -> bool:
    """Whether someone the tracker lost sight of in the last :data:`LOST_MAX` s may stand within
    ``reach`` m of the robot now (the last place seen no further than ``reach`` plus how far they
    could have walked since). The laser does not look behind: a person who walked out of its view
    (behind the robot, to the door it waits at) is not free space to reverse into (goto_l_flat
    seed 0: Ben, lost from view as the robot turned to the door, was touched by a back-off).
    """
    ox, oy, _ = odom
    for x, y, lost in people.lost.values():
        dt = now - lost
        if 0.0 <= dt <= LOST_MAX and math.hypot(x - ox, y - oy) <= reach + walk * dt:
            return True
    return False


#: m/s: a tentative track walking faster than this counts for the contact limit (:func:`in_the_way`)
EMERGING_WALK = 0.3


def in_the_way(people: People, odom: tuple[float, float, float], now: float, *, echoes: np.ndarray | None = None,
               first_seen: bool = False, exclude: str | None = None, gone: str | None = None) -> np.ndarray:
    """(K, 4) robot-frame centres and velocities of everyone the contact limit
    (:func:`robot.footprint.contact_speed_limit`) reckons with: every confirmed track, the partner's too
    (she may turn back into its way), those lost standing where the laser still has an echo (``echoes``),
    and the tentative tracks that walk, freshly measured (:meth:`People.emerging`: a child running out of
    a side door is a few scans old when he is in the robot's lane); and, once more, those who stopped dead
    a moment ago, walking on as they walked (:meth:`People.stopped`: the limit is the least over both).
    ``first_seen`` (the follower's): also whoever is seen for the first time close ahead, as running at it
    (:meth:`People.newborn`; ``exclude``: the partner's track id, left out of those). ``gone``: a track id left out
    altogether (the follower's: its partner's coasting track where the laser looks and sees nobody)."""
    born = people.newborn(odom, now, exclude=exclude) if first_seen else np.zeros((0, 4))
    rows = [a for a in (people.around(odom, now, exclude=gone, echoes=echoes, velocity=True),
                        people.emerging(odom, now, moving=EMERGING_WALK, reach=REACH),
                        people.stopped(odom, now, exclude=gone), born)
            if len(a)]
    return np.concatenate(rows) if rows else np.zeros((0, 4))


def closing_in(people: np.ndarray, *, near: float, speed: float) -> bool:
    """Whether someone within ``near`` m, ahead of the robot's rear, walks toward its centre faster
    than ``speed`` m/s (``people``: (K, 4) robot-frame centres and velocities, :meth:`People.around`).

    A robot that drives on while a person walks at it meets them half way, at twice the closing
    speed; one that stands lets them pass, or stop, at a distance of their choosing.
    """
    if not len(people):
        return False
    x, y, vx, vy = people[:, 0], people[:, 1], people[:, 2], people[:, 3]
    d = np.hypot(x, y)
    toward = -(x * vx + y * vy) / np.maximum(d, 1e-6)
    return bool(np.any((d < near) & (x > -0.3) & (toward > speed)))


def nearest(centres: np.ndarray) -> float:
    """Distance (m) from the robot's centre to the nearest of ``centres`` (robot frame; inf: none)."""
    if not len(centres):
        return math.inf
    return float(np.min(np.hypot(centres[:, 0], centres[:, 1])))


#: m: a person's body, as a disc round the track's centre (for the clearance behind the robot).
BODY_RADIUS = 0.25
#: m: nobody may be left closer than this to the footprint after a back-off (personal space,
#: the ~0.45 m of the social-navigation metrics).
BACK_GAP = 0.45


def behind_clear(people: np.ndarray, *, length: float, width: float, reach: float,
                 gap: float = BACK_GAP, radius: float = BODY_RADIUS) -> bool:
    """Whether backing straight up to ``reach`` m keeps every person behind the robot's centre
    at least ``gap`` m from the footprint (``length`` x ``width``, centred on the robot;
    ``people``: robot-frame centres, (K, >=2), :meth:`People.around`).

    The laser does not look behind, but the attention's tracks do know who stands there (a
    bystander the robot drove past): reversing toward a tracked person is how one is touched.
    People ahead of the centre are the forward controllers' business (backing takes the robot off them).
    """
    if not len(people):
        return True
    x, y = people[:, 0], people[:, 1]
    # distance from each centre to the region the footprint sweeps backing ``reach`` m
    dx = np.maximum(np.maximum(-length / 2 - reach - x, x - length / 2), 0.0)
    dy = np.maximum(np.abs(y) - width / 2, 0.0)
    clearance = np.hypot(dx, dy) - radius
    return not bool(np.any((x < 0.0) & (clearance < gap)))


def standing_in_the_way(people: np.ndarray, *, half_length: float, half_width: float, travel: float,
                        gap: float = BACK_GAP, radius: float = BODY_RADIUS, speed: float = GHOST_SPEED) -> bool:
    """Whether driving straight on ``travel`` m would bring the front of the footprint (``half_length`` x
    ``half_width`` round the centre) within ``gap`` m of the body of someone standing (slower than
    ``speed``) in front of it, in its lane (``people``: (K, 4) robot-frame centres and velocities,
    :meth:`People.around`).

    Someone standing in the way is waited for outside their personal space (the ~0.45 m of the
    social-navigation metrics), not at the 0.25-0.30 m of air the window keeps to people it passes
    (goto_blocked, hall_goto_doorway_person: 13-14 s of a go-to inside the blocker's space). People
    beside the lane, passed, and people walking are the window's business.
    """
    if not len(people):
        return False
    x, y, vx, vy = people[:, 0], people[:, 1], people[:, 2], people[:, 3]
    lane = (x > 0.0) & (np.abs(y) < half_width + radius) & (np.hypot(vx, vy) < speed)
    ahead = x - half_length - radius  # air between the front and the body
    return bool(np.any(lane & (ahead - travel < gap)))


def passing_close(people: np.ndarray, gaps: np.ndarray, *, gap: float, speed: float, rear: float = -0.3) -> bool:
    """Whether someone walking (faster than ``speed`` m/s), ahead of the robot's rear (``rear`` m),
    passes with less than ``gap`` m of air to the footprint (the player: inside their personal space) (``people``: (K, 4) robot-frame centres
    and velocities, :meth:`People.around`; ``gaps``: (K,) their air to the footprint now).

    A robot that drives on while someone walks by it within arm's length crowds them (goto_standing_
    person seeds 1, 8, 9: it crept on at 0.1 m/s beside Max, 0.17-0.24 m off his body); one that stands lets them pass.
    """
    if not len(people):
        return False
    walking = np.hypot(people[:, 2], people[:, 3]) > speed
    return bool(np.any(walking & (people[:, 0] > rear) & (gaps < gap)))


def waits_for(seen: np.ndarray, ghosts: np.ndarray, *, half_length: float, half_width: float, travel: float,
              gap: float = BACK_GAP, radius: float = BODY_RADIUS) -> bool:
    """Whether the go-to waits for someone standing in its lane (:func:`standing_in_the_way`): a person
    the attention tracks now (``seen``) in the lane as wide as the footprint and their body; one only
    remembered where the tracker lost them (``ghosts``, :class:`People`: where the track was last, which
    may lie a few decimetres off the person) only squarely ahead, within the footprint's own width.
    Both (K, 4) robot-frame centres and velocities. A ghost beside the front held the robot for good
    while the man it stood for was 0.8 m to its side (goto_u_flat seed 2: 14 s blocked, then a help
    request); the dynamic window still keeps its social gap to every ghost."""
    return (standing_in_the_way(seen, half_length=half_length, half_width=half_width, travel=travel, gap=gap, radius=radius)
            or standing_in_the_way(ghosts, half_length=half_length, half_width=half_width - radius, travel=travel, gap=gap,
                                   radius=radius))
