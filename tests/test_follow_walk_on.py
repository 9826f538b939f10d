"""The follower's search walks her on past furniture, never through a wall (issue 26 item 1).

fresh5/row_fast_then_waits seed 8: the partner walked diagonally across the living room, round an
armchair, to the study door and out of view; her track's coasting stopped at the armchair, the search
point stayed there, and the robot stood silent 0.8 m from it until she was declared lost, while she
waited in the study door. People walk round furniture; the search point now does too (within her
room), and still stops at a wall.
"""

from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.navigation.follow import walk_on_past

# two rooms side by side, a wall between them at x = 5 (no door), an armchair in room A
WALL = (4.9, 5.1)
CHAIR = ((2.0, 3.0), (1.0, 2.0))
ROOM_A, ROOM_B = "A", "B"


def _occupied(p: tuple[float, float]) -> bool:
    x, y = p
    if not (0.0 <= x <= 10.0 and 0.0 <= y <= 4.0):
        return True
    if WALL[0] <= x <= WALL[1]:
        return True
    (x0, x1), (y0, y1) = CHAIR
    return x0 <= x <= x1 and y0 <= y <= y1


def sight(a: tuple[float, float], b: tuple[float, float]) -> bool:
    n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.02) + 2)
    return not any(_occupied((a[0] + (b[0] - a[0]) * k / (n - 1), a[1] + (b[1] - a[1]) * k / (n - 1))) for k in range(n))


def room(p: tuple[float, float]) -> str | None:
    x, y = p
    if not (0.0 <= x <= 10.0 and 0.0 <= y <= 4.0):
        return None
    return ROOM_A if x < 5.0 else ROOM_B


def free(p: tuple[float, float]) -> bool:
    return not any(_occupied((p[0] + dx, p[1] + dy)) for dx in (-0.3, 0.0, 0.3) for dy in (-0.3, 0.0, 0.3))


def test_she_walks_round_an_armchair() -> None:
    """Walking at the armchair at 1.2 m/s for 3 s, she is beyond it, not stopped in front of it."""
    end = walk_on_past((1.0, 1.5), (1.2, 0.0), 3.0, sight=sight, room=room, free=free)
    assert end[0] > CHAIR[0][1] + 0.3 and free(end)


def test_a_wall_ends_the_walk() -> None:
    """Walking at the wall between the rooms, she stops before it (she is not in the next room)."""
    end = walk_on_past((3.5, 3.0), (1.0, 0.0), 5.0, sight=sight, room=room, free=free)
    assert room(end) == ROOM_A and end[0] < WALL[0]


def test_open_floor_is_a_straight_walk() -> None:
    """Nothing in the way: the point is where her velocity takes her (the search as before)."""
    end = walk_on_past((5.5, 0.5), (0.5, 0.5), 4.0, sight=sight, room=room, free=free)
    assert math.isclose(end[0], 7.5) and math.isclose(end[1], 2.5)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(0.4, 4.6), y=st.floats(0.4, 3.6), speed=st.floats(0.0, 2.0), heading=st.floats(-math.pi, math.pi),
       duration=st.floats(0.0, 6.0))
def test_never_through_a_wall_and_where_the_robot_can_stand(x: float, y: float, speed: float, heading: float,
                                                            duration: float) -> None:
    """From anywhere in room A, in any direction: the point never lies in room B (the wall has no door)
    nor outside the flat, and past furniture it is a point where the robot can stand."""
    start = (x, y)
    assume(not _occupied(start))  # she stands on the floor, not on the armchair
    end = walk_on_past(start, (speed * math.cos(heading), speed * math.sin(heading)), duration,
                       sight=sight, room=room, free=free)
    assert room(end) == ROOM_A
    straight = sight(start, end)
    assert straight or free(end)
