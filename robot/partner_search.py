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
clocks stand still meanwhile.
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
#: s: the longest a partner may be unseen while following, however far she was last seen
SEARCH_CAP = 15.0
#: m: while someone other than the partner is this near the robot (a person crossing its way, walking
#: past it), it yields to them (slows, stops, waits) instead of searching: that time does not count
#: as time she was unseen (issue 26 item 1, sq_cross_pair: it yielded to two people crossing, she
#: went through the next door meanwhile, and the search ran out at that door)
YIELD_NEAR = 1.2


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
                       speed: float = SEARCH_SPEED, top_speed: float | None = None, cap: float = SEARCH_CAP) -> float:
    """Seconds a partner last seen ``distance`` m from the robot may stay unseen while it follows
    her: ``base``, plus the time to drive the gap beyond ``near`` at ``speed`` (no faster than the
    robot's ``top_speed`` when given), at most ``cap`` (never less than ``base``)."""
    if top_speed is not None and 0.0 < top_speed < speed:
        speed = top_speed
    extra = max(0.0, distance - near) / speed if distance == distance else 0.0  # NaN: no extra time
    return max(base, min(cap, base + extra))
