"""Go-to that recovers (issue 26 item 4): the pieces the go-to's recovery is built of.

- The planner's watch question (:func:`robot.navigation.planner.in_view`): a way is known to be clear
  only where the laser looks.
- The sequencer watches the way of a go-to that failed ``blocked`` and sends ``way_clear`` after
  two clear answers in a row, at most ``max_resumes`` times per goal (end to end:
  tests/test_nav_goto.py).
- The player arrives beside someone standing on the place itself (:func:`robot.navigation.player.goal_taken`).
- A ghost (a person only remembered where the tracker lost them) holds the go-to only when squarely
  ahead (:func:`robot.navigation.people.waits_for`).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings, strategies as st
from lxml import etree

from robot.navigation.people import BODY_RADIUS, waits_for
from robot.navigation.planner import WATCH_FIELD, in_view
from robot.navigation.player import GOAL_TAKEN, goal_taken, in_sight, local_goal
from robot.navigation.sequencer import Sequencer
from robot.navigation.local import HALF_LENGTH, HALF_WIDTH


# ------------------------------------------------------------------ the planner's watch
@settings(max_examples=60, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-1.3, 1.3), st.floats(0.5, 6.0))
def test_a_straight_way_is_in_view_exactly_when_it_leaves_within_the_lasers_field(heading, off, length):
    """A straight path from the robot: in view iff its direction lies within WATCH_FIELD of the heading."""
    d = heading + off
    path = [(0.0, 0.0), (length * math.cos(d), length * math.sin(d))]
    if abs(abs(off) - WATCH_FIELD) < 1e-3:
        return  # (the boundary itself)
    assert in_view(path, (0.0, 0.0, heading), reach=3.0) == (abs(off) <= WATCH_FIELD)


def test_a_way_that_turns_back_behind_the_robot_within_reach_is_not_in_view():
    # ahead 1 m, then round behind the robot (a door behind it): the laser does not see that ground
    path = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (-1.5, 1.0)]
    assert not in_view(path, (0.0, 0.0, 0.0), reach=3.0)
    # the same turn beyond reach is not looked at
    far = [(0.0, 0.0), (3.5, 0.0), (3.5, 1.0), (-1.5, 1.0)]
    assert in_view(far, (0.0, 0.0, 0.0), reach=3.0)


# ------------------------------------------------------------------ the sequencer's watch
class _Bus:
    def __init__(self) -> None:
        self.sent: list[tuple[str, etree._Element]] = []

    def publish(self, channel: str, el: etree._Element, **_: object) -> None:
        self.sent.append((channel, el))

    def subscribe(self, *_: object) -> None:
        return None

    def declare_channel(self, *_: object) -> None:
        return None


class _Sim:
    def __init__(self) -> None:
        self.bus = _Bus()
        self.now = 0.0


class _Seq(Sequencer):
    """The sequencer's own logic on a clock and a bus the test holds (no simulation runs)."""

    @property
    def now(self) -> float:  # type: ignore[override]
        return self._sim.now


def _sequencer(max_resumes: int = 2) -> tuple[Sequencer, _Sim]:
    sim = _Sim()
    seq = _Seq.__new__(_Seq)
    seq.__dict__.update(dict(_sim=sim, bus=sim.bus, blocked_timeout=10.0, start_timeout=3.0, replan_after=3.0, max_replans=3,
                             watch_time=60.0, watch_every=1.0, max_resumes=max_resumes, resumes=0, watching=None,
                             _watch_asked=-math.inf, _clear=0, _resumed=False, replans=0, _asked=False, goal="", steps=[],
                             index=-1, sent_at=0.0, started=False, blocked_since=None, _beside=False))
    return seq, sim


def _plan(goal: str, *, failed: str | None = None, watch: bool = False, replan: bool = False) -> etree._Element:
    el = etree.Element("plan", goal=goal, length="0" if failed else "3.0")
    if failed:
        el.set("failed", failed)
    if watch:
        el.set("watch", "true")
    if replan or watch:
        el.set("replan", "true")
    if not failed:
        etree.SubElement(el, "waypoint", x="0", y="0")
        etree.SubElement(el, "waypoint", x="3", y="0", theta="0")
    return el


class _Msg:
    def __init__(self, xml: etree._Element) -> None:
        self.xml = xml


def _names(sim: _Sim) -> list[str]:
    return [el.get("name") for ch, el in sim.bus.sent if el.tag == "event"]


def test_the_sequencer_sends_way_clear_after_two_clear_answers_in_a_row_and_only_after_a_blocked_failure():
    seq, sim = _sequencer()
    seq._on_plan(_Msg(_plan("kitchen")))
    seq._fail("blocked")
    assert seq.watching is not None
    seq._on_plan(_Msg(_plan("kitchen", watch=True)))
    seq._on_plan(_Msg(_plan("kitchen", failed="no_path", watch=True)))  # he stepped back in: start again
    seq._on_plan(_Msg(_plan("kitchen", watch=True)))
    assert "way_clear" not in _names(sim)
    seq._on_plan(_Msg(_plan("kitchen", watch=True)))
    assert _names(sim).count("way_clear") == 1 and seq.watching is None
    # an unknown place is no blockage: nothing to watch
    seq2, _ = _sequencer()
    seq2._on_plan(_Msg(_plan("garage", failed="unknown_place")))
    assert seq2.watching is None


def test_the_sequencer_resumes_a_goal_at_most_max_resumes_times_and_a_new_request_starts_the_count_again():
    seq, sim = _sequencer(max_resumes=2)
    seq._on_plan(_Msg(_plan("kitchen")))
    for _ in range(3):
        seq._fail("blocked")
        for _ in range(2):
            seq._on_plan(_Msg(_plan("kitchen", watch=True)))
        seq._on_plan(_Msg(_plan("kitchen")))  # the ES's navigate after way_clear: the resumed plan
    assert _names(sim).count("way_clear") == 2
    # she asks again herself: a new request, the robot may go on by itself again
    seq._fail("blocked")
    seq._on_plan(_Msg(_plan("kitchen")))
    seq._fail("blocked")
    assert seq.watching is not None


def test_a_cancel_ends_the_watch_and_the_watch_asks_once_a_second_for_its_time():
    seq, sim = _sequencer()
    seq._on_plan(_Msg(_plan("kitchen")))
    seq._fail("blocked")
    for k in range(25):
        sim.now = k * 0.1
        seq.check()
    told = [el for ch, el in sim.bus.sent if el.tag == "replan" and el.get("blocked") == "true"]
    assert len(told) == 1 and told[0].get("goal") == "kitchen"  # the planner remembers where it was blocked (goto17)
    asked = [el for ch, el in sim.bus.sent if el.tag == "replan" and el.get("blocked") is None]
    assert len(asked) == 3 and all(el.get("watch") == "true" and el.get("goal") == "kitchen" for el in asked)
    sim.now = 61.0
    seq.check()
    assert seq.watching is None  # watched long enough
    seq._fail("blocked")
    seq._on_order(_Msg(etree.Element("order", name="cancel")))
    assert seq.watching is None


# ------------------------------------------------------------------ the player at a taken place
@settings(max_examples=80, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3), st.floats(0.0, 1.5), st.floats(-math.pi, math.pi))
def test_a_place_is_taken_exactly_by_someone_standing_within_goal_taken_of_it(gx, gy, px, py, speed, heading):
    people = np.array([[px, py, speed * math.cos(heading), speed * math.sin(heading)]])
    d = math.hypot(px - gx, py - gy)
    if abs(d - GOAL_TAKEN) < 1e-6 or abs(speed - 0.3) < 1e-6:
        return
    assert goal_taken(people, (gx, gy)) == (d < GOAL_TAKEN and speed < 0.3)


def test_a_goal_behind_a_wall_or_a_table_is_not_in_sight():
    wall = np.array([[0.8, y] for y in np.arange(-2.0, 2.0, 0.05)])  # a wall across, 0.8 m ahead
    assert not in_sight((1.2, 0.1), wall) and in_sight((0.6, 0.1), wall)
    assert in_sight((1.2, 0.1), np.zeros((0, 2)))
    assert in_sight((-1.0, 0.0), wall)  # the wall is not between the robot and a goal behind it


def test_local_goal_is_the_goal_in_the_robots_frame():
    x, y = local_goal((1.0, 2.0, math.pi / 2), (1.0, 3.0))
    assert math.isclose(x, 1.0, abs_tol=1e-9) and math.isclose(y, 0.0, abs_tol=1e-9)


# ------------------------------------------------------------------ ghosts in the lane
def _at(x: float, y: float) -> np.ndarray:
    return np.array([[x, y, 0.0, 0.0]])


def test_a_ghost_beside_the_front_does_not_hold_the_go_to_but_a_tracked_person_there_does():
    beside = _at(0.33, 0.37)  # goto_u_flat seed 2: the ghost the robot waited at for 14 s
    none = np.zeros((0, 4))
    kw = dict(half_length=HALF_LENGTH, half_width=HALF_WIDTH, travel=0.02)
    assert not waits_for(none, beside, **kw)
    assert waits_for(beside, none, **kw)
    # squarely ahead, a ghost is waited for as a person is
    assert waits_for(none, _at(0.9, 0.1), **kw) and waits_for(_at(0.9, 0.1), none, **kw)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.0, 2.0), st.floats(-1.0, 1.0))
def test_whatever_holds_the_go_to_as_a_ghost_holds_it_as_a_tracked_person(x, y):
    """A ghost's lane is the narrower one: nothing a ghost holds up is let pass when seen."""
    none = np.zeros((0, 4))
    kw = dict(half_length=HALF_LENGTH, half_width=HALF_WIDTH, travel=0.02)
    if waits_for(none, _at(x, y), **kw):
        assert waits_for(_at(x, y), none, **kw)
    if abs(y) >= HALF_WIDTH + BODY_RADIUS:
        assert not waits_for(_at(x, y), none, **kw)


def _status(state: str, x: str = "3", y: str = "0") -> _Msg:
    return _Msg(etree.Element("player", state=state, x=x, y=y))


def _replans(sim: _Sim) -> int:
    return sum(1 for ch, el in sim.bus.sent if el.tag == "replan" and el.get("watch") != "true")


def _blocked_for(seq: Sequencer, sim: _Sim, seconds: float) -> None:
    seq._on_player(_status("blocked"))
    for _ in range(int(seconds * 10)):
        sim.now += 0.1
        seq.check()


def test_a_blockage_after_progress_gets_its_own_replans_but_one_blockage_no_more_than_max_replans():
    """open_island_goto seed 1: three replans went while Ole stood in the bedroom door; he then stood beside
    the next corner, and the go-to, with none left, waited 10 s and asked for help though the way round him
    was free. A blockage the robot got out of (the player on again: 0.3 m of progress) is over."""
    seq, sim = _sequencer()
    seq._on_plan(_Msg(_plan("kitchen")))
    seq._on_player(_status("moving"))
    for _ in range(3):  # blocked, a replan asked, its way round begun, blocked again at once (no progress)
        _blocked_for(seq, sim, 3.5)
        seq._on_plan(_Msg(_plan("kitchen", replan=True)))
        seq._on_player(_status("moving"))  # (the new step's first status)
    assert _replans(sim) == 3
    _blocked_for(seq, sim, 3.5)
    assert _replans(sim) == 3  # no more for this blockage
    seq._on_player(_status("moving"))  # he stepped aside: on again, after 0.3 m of progress
    _blocked_for(seq, sim, 3.5)
    assert _replans(sim) == 4  # a new blockage further on: a way round is asked for again


def _reached(beside: bool = False) -> etree._Element:
    el = etree.Element("player", state="reached", x="3.0000", y="0.0000")
    if beside:
        el.set("beside", "true")
    return el


def _goal_place(sim: _Sim) -> etree._Element:
    (el,) = [el for ch, el in sim.bus.sent if el.tag == "event" and el.get("name") == "goal_reached"]
    return el.find("PLACE")


def test_a_go_to_that_ends_beside_someone_on_the_place_says_so_in_its_goal_reached_and_only_then():
    # goto25: the player stopped short beside someone standing on the place: the dialog is told (and says so)
    for beside in (True, False):
        seq, sim = _sequencer()
        seq._on_plan(_Msg(_plan("study")))
        seq._on_player(_Msg(_reached(beside)))
        place = _goal_place(sim)
        assert place.find("TITLE").get("name") == "study"
        assert (place.get("beside") == "true") is beside
