"""Blind corners: drive past what the laser cannot see round at a speed it can stop from.

A go-to entering a door or an opening sees the room behind it only through the
opening: whoever walks toward it behind the jamb appears at the jamb's corner,
about a metre ahead, when the robot is already there (ring_goto_other_way: Ben
came out of the kitchen through the 1.6 m dining opening the way the robot went in;
first seen 1.0 m off, 0.4 m of air, with the robot at 0.5 m/s; it stopped 0.02 m
from him). The tracker needs a few scans to give a new person a velocity; the
robot then brakes. So where the scan shows an occluding corner ahead (a jump
in range between neighbouring beams, :data:`JUMP`, whose near end lies on the
floor plan's walls or furniture: people and legs are the tracker's business), the
robot's speed is capped so that a person stepping out at that corner and walking
at it at :data:`WALK` while it reacts (:data:`REACT`) and brakes leaves it
:data:`GAP` of air when it stands (:func:`stop_speed`). Far from corners, and
where the far side is seen, it drives as fast as before. A real robot does the
same: it cannot know who comes round a corner it cannot see.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robot.footprint import HALF_LENGTH, footprint_distance

#: m: a range jump between neighbouring beams at least this large hides room for a person behind its near end
JUMP = 0.5
#: m: only corners this near the laser matter (beyond, the cap is the full speed anyway)
REACH = 2.0
#: m: the near end of a jump lies on the floor plan (a wall's or a piece of furniture's corner) within this
EXPLAINED = 0.12
#: m/s: how fast someone stepping out of the shadow may walk at the robot (an everyday indoor walk)
WALK = 0.8
#: s: from the first scan that shows them to braking (a fresh track's velocity takes a scan or two)
REACT = 0.3
#: m: air left between the footprint and their body when the robot stands (the go-to's social gap)
GAP = 0.30
#: m/s: the cap never goes below this crawl (it stops from it within a few centimetres): through a
#: door whose jamb it passes at arm's length it still moves on
CRAWL = 0.12
#: m: a beam without echo, as a range (far beyond any jump's near end)
FAR = 1e6
#: m: the occluder must be this wide to hide someone (a table's or a chair's leg, a person's own leg is not) ...
WIDE = 0.25
#: m: ... its echoes running on from the corner with neighbouring ranges this close (the leg filter's cluster jump)
SAME = 0.15


def corners(ranges: np.ndarray, min_angle: float, resolution: float, max_range: float, offset: float, *,
            jump: float = JUMP, reach: float = REACH) -> np.ndarray:
    """(K, 2) robot-frame points (laser ``offset`` m ahead of the centre; angles in radians) at the near end of
    every range jump of at least ``jump`` m between neighbouring beams whose near range is within ``reach`` and
    whose near side is an occluder at least :data:`WIDE` wide: the corners behind which the laser does not see
    (a beam without echo counts as far)."""
    r = np.asarray(ranges, dtype=float)
    r = np.where(r >= max_range - 1e-6, FAR, r)
    if len(r) < 2:
        return np.zeros((0, 2))
    a = min_angle + resolution * np.arange(len(r))
    d = r[1:] - r[:-1]
    near_left = d >= jump  # beam i near, i + 1 far
    near_right = -d >= jump  # beam i + 1 near, i far
    idx = np.concatenate((np.nonzero(near_left)[0], np.nonzero(near_right)[0] + 1))
    idx = idx[r[idx] <= reach]
    if not len(idx):
        return np.zeros((0, 2))
    idx = np.unique(idx)
    x, y = offset + r * np.cos(a), r * np.sin(a)
    keep = [i for i in idx if _occluder_width(x, y, r, int(i)) >= WIDE]
    return np.column_stack((x[keep], y[keep])) if keep else np.zeros((0, 2))


def _occluder_width(x: np.ndarray, y: np.ndarray, r: np.ndarray, i: int) -> float:
    """How wide (m, chord) the run of echoes is that beam ``i`` ends: its neighbours on the near side, as long as
    each is within :data:`SAME` m in range of the next (a leg or a table leg is a few centimetres; a wall's end
    runs on along the wall)."""
    n = len(r)
    lo = hi = i
    while lo > 0 and abs(r[lo - 1] - r[lo]) < SAME and r[lo - 1] < FAR:
        lo -= 1
        if math.hypot(x[lo] - x[i], y[lo] - y[i]) >= WIDE:
            return WIDE
    while hi < n - 1 and abs(r[hi + 1] - r[hi]) < SAME and r[hi + 1] < FAR:
        hi += 1
        if math.hypot(x[hi] - x[i], y[hi] - y[i]) >= WIDE:
            return WIDE
    return max(math.hypot(x[lo] - x[i], y[lo] - y[i]), math.hypot(x[hi] - x[i], y[hi] - y[i]))


def on_plan(points: np.ndarray, mapped: np.ndarray, *, tol: float = EXPLAINED) -> np.ndarray:
    """Those of ``points`` (robot frame) within ``tol`` m of the floor plan's outline ``mapped`` (robot frame)."""
    if not len(points) or not len(mapped):
        return np.zeros((0, 2))
    d = np.min(np.hypot(points[:, None, 0] - mapped[None, :, 0], points[:, None, 1] - mapped[None, :, 1]), axis=1)
    return points[d <= tol]


def stop_speed(air: float, *, decel: float, walk: float = WALK, react: float = REACT, gap: float = GAP) -> float:
    """The speed (m/s) from which the robot, reacting after ``react`` s and braking at ``decel`` m/s^2, still
    stands ``gap`` m off someone who appears ``air`` m from its footprint walking at it at ``walk`` m/s
    (0 when no speed does): (v + walk) react + v^2 / (2 decel) + walk v / decel <= air - gap."""
    budget = air - gap - walk * react
    if budget <= 0.0:
        return 0.0
    b = react + walk / decel
    return decel * (-b + math.sqrt(b * b + 2.0 * budget / decel))


def blind_speed_limit(hidden: np.ndarray, max_speed: float, *, decel: float, walk: float = WALK, react: float = REACT,
                      gap: float = GAP, crawl: float = CRAWL) -> float:
    """The speed cap (m/s) for the corners ``hidden`` (robot frame, :func:`corners` on the plan): the least
    :func:`stop_speed` (someone stepping out at ``walk`` m/s, seen ``react`` s before it brakes, ``gap`` m of air
    left) over those ahead of its centre (someone stepping out behind it is not driven at), never under
    ``crawl``, never over ``max_speed``."""
    if not len(hidden):
        return max_speed
    ahead = hidden[hidden[:, 0] > 0.0]
    if not len(ahead):
        return max_speed
    air = float(np.min(footprint_distance(ahead[:, 0], ahead[:, 1])))
    return min(max_speed, max(crawl, stop_speed(air, decel=decel, walk=walk, react=react, gap=gap)))


#: m/s: the follower's blind corners: someone stepping out of an opening it cannot see into at up to this is
#: never reached (an unhurried walk out of a door; the go-to's :data:`WALK` of 0.8 m/s held the follower so far
#: back along a 1.1 m hallway with a door every 2-4 m that its partner, who does not wait, was lost at the end:
#: fresh7 corr_hallway_crossing 0/4; a child running out faster is met slower, not always stopped for)
FOLLOW_WALK = 0.4
#: s: ... seen this long before it brakes (the scan shows their legs at once; the dynamic window stops for echoes)
FOLLOW_REACT = 0.2
#: m: ... and it stands this far off their body: not touched (their personal space is the tracks' business)
FOLLOW_GAP = 0.05
#: m/s: ... never slower than this (it must get past, and through the doors it follows through); from it the robot
#: stands short of someone stepping out at FOLLOW_WALK 0.335 m of air beside its flank (a 1.1 m hallway's side door:
#: (0.1 + 0.4) 0.2 + 0.1^2 / 2 + 0.4 x 0.1 = 0.145 m of closing)
FOLLOW_CRAWL = 0.10


def follow_blind_limit(hidden: np.ndarray, max_speed: float, *, decel: float) -> float:
    """The follower's cap (following, approaching, searching) for the blind corners ``hidden`` (robot frame):
    :func:`blind_speed_limit` for someone stepping out at :data:`FOLLOW_WALK` with :data:`FOLLOW_GAP` of air: a
    speed it can stand from short of anyone who steps out of an opening beside its way (a door of a hallway it
    passes, a corner), never under :data:`FOLLOW_CRAWL`. Only corners ahead of its front count: once its front
    is level with a jamb, someone stepping out there meets its flank, which no braking prevents, and crawling
    on only keeps it beside the opening longer (counted from its centre, as the go-to does, it crawled a
    quarter of a metre more at every jamb and fell back from its partner)."""
    ahead = hidden[hidden[:, 0] > HALF_LENGTH] if len(hidden) else hidden
    return blind_speed_limit(ahead, max_speed, decel=decel, walk=FOLLOW_WALK, react=FOLLOW_REACT, gap=FOLLOW_GAP,
                             crawl=FOLLOW_CRAWL)


def scan_corners(msg: Any, mapped: np.ndarray) -> np.ndarray:
    """The floor plan's corners the latest scan ``msg`` (a laser Message) does not see round (robot frame, (K, 2))."""
    if msg is None:
        return np.zeros((0, 2))
    x = msg.xml
    pts = corners(msg.attachments["ranges"], math.radians(float(x.get("min_angle"))), math.radians(float(x.get("resolution"))),
                  float(x.get("max_range")), float(x.get("offset")))
    return on_plan(pts, mapped)
