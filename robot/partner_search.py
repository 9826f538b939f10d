"""How long a partner may be out of view while the robot follows her (issue 26 item 1).

Following, she leads: out of view a moment (a door frame, someone crossing between, walking
past the robot's side) is no evidence that she left. The follower searches where she was
heading meanwhile and the attention's leaving rule waits as long. A robot that yielded to people
crossing its way falls behind a partner who walks at its own top speed; when she then turns a
corner or goes through a door it needs longer than a near follower to come where she was. So the
time allowed grows with the distance at which she was last seen: the base time, plus the time
to drive the gap beyond the following band at the search speed (or the robot's own top speed,
from its configuration, when that is lower: a robot that does 0.3 m/s needs a third longer to
drive the gap than one that searches at 0.4 m/s), at most a cap (a partner unseen that long has
gone, wherever she was). Both the follower (its search) and the attention (its
``partner_lost``) read this one rule, so the robot never stops searching before the attention
lets her go, nor the other way round. Time spent yielding to someone near it (:func:`yielding`)
is not search time: held up by a person crossing its way, the robot does not search, and both
clocks stand still meanwhile. Nor is the time it spends on its way to where she was last seen
(:class:`Closing`): a leader faster than the robot may be far ahead when she goes out of view, and
the search proper, looking round where she went, begins when it gets there; so the search ends on
evidence (it came there and did not find her, or it could not come nearer), not on a clock set at
the moment she went out of view.
"""

from __future__ import annotations

import math
from typing import Any

#: s: unseen this long a near partner (within :data:`SEARCH_NEAR`) is lost
SEARCH_BASE = 6.0
#: m: the following band's far end: a partner seen this near needs no extra time
SEARCH_NEAR = 1.5
#: m/s: the follower's search speed (it drives at most this fast where she was heading)
SEARCH_SPEED = 0.4
#: s: a partner walking faster than the robot when last seen is taken to walk on this long out of view
#: (the gap she opens meanwhile is searched for too; :func:`follow_search_time`)
PULL_AWAY = 4.0
#: s: the follower has stood by the partner track this long (its status ``waiting``: she stopped and it came
#: up to her): her walk is over, and she will say "stop". A voice from elsewhere while that track stays silent
#: may be hers (the track it followed was someone she walked past): the person attention listens to it and the
#: dialog takes a stop from it (one rule for both; docs/subsystems.md, "never deaf by the followed track")
STOOD_FOR = 2.0
#: s: the longest a partner may be unseen while following, however far she was last seen
SEARCH_CAP = 15.0
#: m: while someone other than the partner is this near the robot (a person crossing its way, walking
#: past it), it yields to them (slows, stops, waits) instead of searching: that time does not count
#: as time she was unseen (issue 26 item 1, sq_cross_pair: it yielded to two people crossing, she
#: went through the next door meanwhile, and the search ran out at that door)
YIELD_NEAR = 1.2


#: m/s: searching, the robot comes nearer where she was last seen at least this fast: it is still on its way
#: there (it lagged behind a leader faster than itself), not yet searching; that time is not search time
CLOSING_SPEED = 0.1
#: m: ... until it is this near that place (there it looks for her, and the search clock runs)
CLOSING_NEAR = 1.0
#: s: at most this much time on the way there is not counted (a way round that never ends is no way there)
CLOSING_CAP = 30.0


class Closing:
    """Time spent on the way to where the partner was last seen (issue 26 item 10, fresh7
    corr_fast_walker_goto: a leader at 1.3 m/s went through a door 6 m ahead of a 0.45 m/s robot and
    stopped in the next room, out of its earshot; the search clock ran out while the robot was still
    driving along the hallway toward that door, one second before it would have heard and seen him).
    A search ends on evidence: the robot has come where it looks for her (where she was last seen, carried
    on along her way: the follower's search point, within :data:`CLOSING_NEAR`) and looked there, or it
    could not come nearer. So the time in which the robot's distance to that point fell at
    :data:`CLOSING_SPEED` or faster, while it was still further than :data:`CLOSING_NEAR`, is not search
    time (at most :data:`CLOSING_CAP` s in all). The follower (its search) and the attention (its
    ``partner_lost``) each keep one, fed with the same distances (the follower's, which its status
    ``searching`` carries), so both clocks stand still by the same rule while it drives there; reset when
    she is seen."""

    __slots__ = ("total", "_last")

    def __init__(self) -> None:
        self.total = 0.0  # s not counted as search time since she was last seen
        self._last: tuple[float, float] | None = None  # (time, distance) of the last update

    def reset(self) -> None:
        self.total, self._last = 0.0, None

    def update(self, t: float, distance: float) -> float:
        """The robot is ``distance`` m from where it looks for her at ``t``: the time not counted so far."""
        last, self._last = self._last, (t, distance)
        if last is not None and distance == distance and last[1] == last[1]:
            dt = t - last[0]
            if (0.0 < dt <= 1.0 and last[1] > CLOSING_NEAR and last[1] - distance >= CLOSING_SPEED * dt
                    and self.total < CLOSING_CAP):
                self.total = min(CLOSING_CAP, self.total + dt)
        return self.total


def yielding(others: Any, near: float = YIELD_NEAR) -> bool:
    """Whether the robot yields now: someone other than the partner (``others``: their positions
    in the robot frame, rows of at least x and y) stands or walks within ``near`` m of it. The
    follower (its people) and the attention (its tracks) read this one rule, each with the time it
    holds subtracted from the time she is unseen."""
    return any(math.hypot(float(o[0]), float(o[1])) < near for o in others)


def robot_top_speed(config: Any) -> float | None:
    """The robot's top speed (m/s) from its own configuration (``run.config``: ``max_speed``), None
    when it does not say (the base's default, above :data:`SEARCH_SPEED`, then applies)."""
    get = config.get if isinstance(config, dict) else (lambda k, d=None: getattr(config, k, d))
    speed = get("max_speed", None)
    return None if speed is None else float(speed)


def follow_search_time(distance: float, *, base: float = SEARCH_BASE, near: float = SEARCH_NEAR,
                       speed: float = SEARCH_SPEED, top_speed: float | None = None, cap: float = SEARCH_CAP,
                       pace: float = 0.0) -> float:
    """Seconds a partner last seen ``distance`` m from the robot may stay unseen while it follows
    her: ``base``, plus the time to drive the gap beyond ``near`` at ``speed`` (no faster than the
    robot's ``top_speed`` when given), at most ``cap`` (never less than ``base``). The cap bounds how
    far behind a partner may be last seen and still be searched for: a robot slower than ``speed``
    gets the time to drive that same distance at its own top speed (:func:`search_cap`). A partner
    who walked faster than the robot searches (``pace``, m/s, her speed when last seen) pulled away
    further while out of view: the gap counts what she gains on it in :data:`PULL_AWAY` s more (a fast
    leader who went through a door and stopped in the next room was declared lost while the robot was
    still in the passage 1.2 m short of that door: follow17, fresh7 corr_fast_walker_goto)."""
    cap = search_cap(speed, top_speed, cap)
    if top_speed is not None and 0.0 < top_speed < speed:
        speed = top_speed
    if pace == pace and pace > speed:
        distance = distance + (pace - speed) * PULL_AWAY
    extra = max(0.0, distance - near) / speed if distance == distance else 0.0  # NaN: no extra time
    return max(base, min(cap, base + extra))


def search_cap(speed: float = SEARCH_SPEED, top_speed: float | None = None, cap: float = SEARCH_CAP) -> float:
    """The longest search (s): ``cap`` for a robot as fast as ``speed``; for a slower one, the cap's
    time beyond :data:`SEARCH_BASE` is the time to drive the same gap (3.6 m at the defaults) at its top
    speed. A 0.3 m/s robot whose partner (0.8 m/s) went into the next room 5 m ahead was 15 s at the
    cap and still short of the door when the search ran out (u_catch_up_slow)."""
    if top_speed is None or not 0.0 < top_speed < speed:
        return cap
    return cap + max(0.0, cap - SEARCH_BASE) * (speed / top_speed - 1.0)


def way_distance(point: tuple[float, float], last: tuple[float, float], velocity: tuple[float, float],
                 unseen: float, *, walking: float = 0.3, horizon: float = SEARCH_CAP) -> float:
    """Metres from ``point`` to the way a partner who led the robot went while unseen: the segment from
    where she was last measured (``last``) to where her last velocity (``velocity``, m/s) carried on
    for ``unseen`` s (at most ``horizon``) takes her; just ``last`` when she was slower than ``walking``
    (a standing person's velocity is noise). A partner who walks on out of view is found again where
    she went, not only where she disappeared: at 0.8 m/s she is 4 m on after 5 s, and a robot slower
    than her sees her there, far beyond any radius round the point where it lost her (issue 26 item 10)."""
    px, py = point
    x, y = last
    vx, vy = velocity
    h = min(max(unseen, 0.0), horizon)
    if vx * vx + vy * vy < walking * walking or h <= 0.0:
        return math.hypot(px - x, py - y)
    ex, ey = vx * h, vy * h
    u = max(0.0, min(1.0, ((px - x) * ex + (py - y) * ey) / (ex * ex + ey * ey)))
    return math.hypot(px - x - u * ex, py - y - u * ey)
