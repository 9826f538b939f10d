"""Could the laser have seen a track's person on this scan? (Negative evidence only where it looks.)

Issue 26 item 1: a track whose legs no scan reports dies after ``death_timeout`` s (the
tracker's rule), but no leg candidate is evidence of absence only where the laser looks.
A person hidden behind a wall's edge (she walked through a door the robot has not reached),
behind someone else, or outside the laser's half circle (people standing behind the robot
it drove past) is still there; their track dying there and a new one being born when they
come back into view is an identity switch (the tracking metric counts it, as CLEAR-MOT does),
and for the partner a gap in which her "stop" found no beam to be heard through.

The test is on the robot's own scan: a point is hidden when it lies outside the scan's
angular range, beyond the leg detector's ``max_range``, or when any of the scan's beams
within ``half_width`` either side of it ends more than ``margin`` in front of it (something
nearer is in the way: a door jamb, another person). The width is the track's uncertainty as
much as the body's: a partner walking on behind a jamb is predicted a few decimetres off
where she turned, and the jamb beside that prediction hides her (cross_u_pair seed 4). Where
all the beams reach the point, the laser looked and saw no legs: that is evidence the person
is not there, and the tracker's timeout runs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

#: m: half the width looked at: a body (two legs about 0.3 m across) and a few decimetres of prediction error
BODY_HALF_WIDTH = 0.35
#: m: beams ending this far in front of the point hit something in the way
MARGIN = 0.3


def hidden_points(
    points: Sequence[tuple[float, float]],
    ranges: Sequence[float],
    min_angle: float,
    resolution: float,
    *,
    max_range: float,
    offset: float = 0.0,
    half_width: float = BODY_HALF_WIDTH,
    margin: float = MARGIN,
) -> list[bool]:
    """Per robot-frame point, is it hidden from the laser (module docstring)?

    ``ranges`` are the scan's (one per beam, beam ``k`` at ``min_angle + k * resolution``, radians),
    the laser ``offset`` m ahead of the robot centre; ``max_range`` is how far legs are trusted.
    Raises ValueError for an empty scan or a resolution that is not positive.
    """
    n = len(ranges)
    if n == 0 or not resolution > 0:
        raise ValueError(f"hidden_points: a scan of {n} beams at resolution {resolution} rad")
    out = []
    for x, y in points:
        lx, ly = x - offset, y
        d = math.hypot(lx, ly)
        if d > max_range:
            out.append(True)
            continue
        b = math.atan2(ly, lx)
        k = (b - min_angle) / resolution
        if k < -0.5 or k > n - 0.5:
            out.append(True)  # outside the laser's field of view (behind the robot)
            continue
        w = math.atan2(half_width, max(d, 1e-6)) / resolution
        lo, hi = max(0, int(math.floor(k - w))), min(n - 1, int(math.ceil(k + w)))
        out.append(min(ranges[lo : hi + 1]) < d - margin)
    return out
