"""Backing off never reverses toward a tracked person (issue 26 review: the laser does not look
behind, but the attention's tracks know who stands there)."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from lxml import etree

from robot.navigation.follow import STUCK_TIME, Follower
from robot.navigation.local import LatestScan
from robot.navigation.people import BACK_GAP, BODY_RADIUS, People, behind_clear
from robot.navigation.seen import SeenGround
from tests.nav_helpers import start_run

L, W = 0.51, 0.43


@given(x=st.floats(-4.0, -0.01), y=st.floats(-3.0, 3.0), reach=st.floats(0.0, 0.6))
def test_a_person_behind_blocks_backing_exactly_when_the_back_off_would_bring_her_into_personal_space(x, y, reach):
    """The rule's invariant: blocked iff some point of the footprint backed 0..reach m comes closer than
    the gap to her body (checked here by sampling the backed footprint's outline)."""
    clear = behind_clear(np.array([[x, y]]), length=L, width=W, reach=reach)
    gaps = []
    for b in np.linspace(0.0, reach, 31):
        cx, cy = min(max(x, -L / 2 - b), L / 2 - b), min(max(y, -W / 2), W / 2)
        gaps.append(math.hypot(x - cx, y - cy) - BODY_RADIUS)
    g = min(gaps)
    if g < BACK_GAP - 0.01:
        assert not clear
    if g > BACK_GAP + 0.01:
        assert clear


def test_people_ahead_or_nobody_never_block_backing():
    assert behind_clear(np.zeros((0, 2)), length=L, width=W, reach=0.3)
    assert behind_clear(np.array([[0.6, 0.0], [0.3, 0.1]]), length=L, width=W, reach=0.3)


def _wedged_follower(track_x: float) -> Follower:
    f = Follower.__new__(Follower)
    f.odom = (2.0, 0.0, 0.0)  # facing +x, having driven along y = 0 (its crumbs: backing is "safe")
    f.crumbs = deque([(1.0 + 0.05 * k, 0.0) for k in range(21)], maxlen=200)
    f.seen = SeenGround()
    f.scan = LatestScan()
    f._stuck_since = 10.0 - STUCK_TIME - 0.1
    f._stuck_at = f.odom  # no progress since then (the wedge rule)
    f._unstick_until = -math.inf
    f.people = People()
    tracks = etree.Element("tracks", time="10.0", frame="odom")
    etree.SubElement(tracks, "track", id="t7", x=str(track_x), y="0.0", vx="0", vy="0", confirmed="true")
    f.people.update(tracks)
    return f


def test_a_wedged_follower_does_not_back_into_a_person_standing_behind_it(monkeypatch):
    monkeypatch.setattr(Follower, "now", property(lambda self: 10.0))
    near = _wedged_follower(1.45)  # her body's edge 0.045 m off the rear bumper
    assert not near.can_back_off()
    assert near._unstick(0.0, 0.0, np.zeros((0, 2))) == (0.0, 0.0)
    far = _wedged_follower(0.2)  # nobody within reach behind: it backs over its own trail
    v, _ = far._unstick(0.0, 0.0, np.zeros((0, 2)))
    assert v < 0.0


BYSTANDER = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="backbystander" seed="0" duration="60">
  <flat>
    <room name="hall" points="0,0 7,0 7,4 0,4"/>
    <walls thickness="0.1">
      <wall from="0 0" to="7 0"/><wall from="7 0" to="7 4"/><wall from="7 4" to="0 4"/><wall from="0 4" to="0 0"/>
    </walls>
  </flat>
  <robot x="1.0" y="2.0" heading="0"/>
  <humans>
    <human name="nina" x="2.3" y="2.0" heading="0" height="1.64" torso="yellow" speed="0.8">
      <script><wait for="1"/><walk-to point="4.6 2.0" speed="0.4"/><wait for="4"/><face angle="180"/>
        <walk-to point="3.7 2.0" speed="0.4"/><wait for="60"/></script>
    </human>
    <human name="olga" x="1.0" y="3.6" heading="0" height="1.70" torso="green" speed="0.8">
      <script><wait for="6"/><walk-to point="2.55 2.6" speed="0.5"/><walk-to point="2.55 2.0" speed="0.3"/>
        <face angle="0"/><wait for="60"/></script>
    </human>
  </humans>
</scenario>
"""


def test_the_follower_backing_off_from_its_partner_keeps_clear_of_a_bystander_standing_behind():
    """Nina turns back toward the robot that follows her; Olga has stepped in behind it. The
    follower's back-off from Nina must not bring Olga within reach (it touched her at 12.6 s)."""
    run = start_run("backbystander", tracks={"nina": "t1", "olga": "t2"}, text=BYSTANDER)
    gaps = []

    def watch(w):
        rx, ry, th = w.robot.pose
        hx, hy = w.humans["olga"].position
        c, s = math.cos(th), math.sin(th)
        dx, dy = hx - rx, hy - ry
        lx, ly = abs(c * dx + s * dy), abs(-s * dx + c * dy)
        gaps.append(math.hypot(max(lx - L / 2, 0), max(ly - W / 2, 0)) - BODY_RADIUS)

    run.world.add_listener(watch)
    run.at(0.3, lambda: run.oracle.follow("t1"))
    run.until(20.0)
    try:
        assert not run.world.contacts
        assert min(gaps) > 0.2
    finally:
        run.close()
