"""After following ends facing out of the flat, the follower turns back toward its room's middle
(:meth:`robot.navigation.follow.Follower._face_in`); that turn keeps every corner off everyone's body, the
partner's above all (fresh13 rail_wrong_corrections seeds 2 and 4, make25: held back in a door, she said
stop 0.54 m in front of it, and the full-rate turn swung a corner into her). And backing off from a partner who
walks back at it, with the straight reverse refused by the floor plan (turned toward her in a 1.0 m corridor), it
backs along its own trail instead (:meth:`Follower._trail_reverse`; fresh13 rail_walk_back_pass)."""

from __future__ import annotations

import math

import numpy as np

from robot.navigation.follow import Follower


class _Route:
    ready = True

    def __init__(self) -> None:
        self.room = np.array([(-4.0, -1.0), (-0.2, -1.0), (-0.2, 2.0), (-4.0, 2.0)])  # behind it, a little left

    def inside(self, p):  # the point ahead lies out of the flat: it faces out
        return False

    def room_at(self, p):
        return self.room

    def to_odom(self, p):
        return p

    def obstacles_near(self, odom):
        return np.zeros((0, 2))


class _People:
    def __init__(self, rows) -> None:
        self.rows = np.array(rows, dtype=float).reshape(-1, 2)

    def around(self, odom, now, **kw):
        return self.rows


class _Scan:
    def sees_through(self, x, y):
        return False


class _Limits:
    max_turn = math.radians(100)


def _follower(partner, others=()):
    class _F(Follower):
        now = 0.0

        def _command(self, v, w):
            self.sent.append((v, w))

    f = _F.__new__(_F)
    f.odom, f.route, f.limits, f.scan, f.sent = (0.0, 0.0, 0.0), _Route(), _Limits(), _Scan(), []
    f.people = _People(list(others))
    f.track = None if partner is None else {"x": partner[0], "y": partner[1], "vx": 0.0, "vy": 0.0, "t": 0.0}
    return f


def test_with_nobody_near_it_turns_back_toward_its_room():
    f = _follower(None)
    cmd = f._face_in()
    assert cmd is not None and cmd[0] == 0.0 and abs(cmd[1]) > 0.5
    assert f.sent == [cmd]


def test_it_never_swings_a_corner_into_the_partner_standing_close_in_front():
    for partner in ((0.5, 0.15), (0.54, 0.0), (0.35, 0.35)):  # (the turn is to the left)
        f = _follower(partner)
        assert f._face_in() is None and f.sent == []  # stands: the corner would reach her


def test_nor_into_anyone_else_standing_close_beside_it():
    f = _follower((3.0, 0.0), others=[(0.15, 0.48)])
    assert f._face_in() is None and f.sent == []


def test_someone_well_away_does_not_stop_the_turn():
    f = _follower((1.6, 0.0), others=[(0.0, 2.0)])
    assert f._face_in() is not None


# ----------------------------------------------------------------- backing off along its own trail (make25)

def _corridor_follower(heading: float, y: float):
    """A follower in a 1.0 m corridor (walls' faces at y 4.25 and 5.25) that drove east along y 4.75 and stands at
    x 6.7 turned ``heading`` off the corridor toward her (she walks back at it from the east)."""
    from collections import deque

    class _F(Follower):
        now = 0.0

    class _L:
        max_turn, max_reverse = math.radians(100), 0.3

    class _S:
        def points(self):
            return np.zeros((0, 2))

    f = _F.__new__(_F)
    f.odom, f.limits, f.scan, f.people = (6.7, y, heading), _L(), _S(), _People([])
    f.crumbs = deque([(x, 4.75) for x in np.arange(1.0, 9.2, 0.05)], maxlen=2000)
    xs = np.arange(4.0, 9.5, 0.05)
    walls = np.concatenate((np.stack((xs, np.full_like(xs, 4.25)), 1), np.stack((xs, np.full_like(xs, 5.25)), 1)))
    c, s = math.cos(heading), math.sin(heading)
    dx, dy = walls[:, 0] - 6.7, walls[:, 1] - y
    mapped = np.stack((c * dx + s * dy, -s * dx + c * dy), 1)
    return f, mapped


def test_turned_toward_her_in_a_corridor_it_backs_along_its_own_trail_where_straight_back_hits_the_wall():
    """fresh13 rail_walk_back_pass seed 0: turned 14 degrees toward her at y 4.63, straight back would bring its rear
    corner onto the corridor's wall; it stood there with her held back for the rest of the run."""
    f, mapped = _corridor_follower(0.25, 4.63)
    assert f._swept(-0.2, 0.0, mapped)[0] == 0.0  # straight back refused by the floor plan
    v, w = f._trail_reverse(0.0, 0.0, 0.55, 0.1, mapped)
    assert v < 0.0  # it backs ...
    assert w < 0.0  # ... steering its rear back onto the trail (heading back toward the corridor's axis)


def test_off_its_trail_it_does_not_back_blind():
    f, mapped = _corridor_follower(0.25, 4.63)
    f.crumbs.clear()
    f.crumbs.append((1.0, 4.75))  # it never drove here
    assert f._trail_reverse(0.0, 0.0, 0.55, 0.1, mapped) == (0.0, 0.0)
