"""Following through people crossing and a door (issue 26 item 1, fresh2/sq_cross_pair): the robot
yields to two people crossing its way, she walks on through the next door meanwhile, and on main the
search ran out at that door and she was declared lost while she stood in view a step further on.

* Yielding is not searching: the time someone other than the partner is near the robot does not count
  as time she was unseen (``robot.partner_search.yielding``), for the attention's leaving rule and the
  follower's search alike.
* She walks on: following, a track in her clothes (its colour seen, the same as hers) up to where she
  can have walked since she was last measured is hers again (``PersonAttention._reacquire_walking``);
  never one in other clothes, nor one of two in her clothes, nor one whose clothes are not yet seen
  (the camera looks at that one meanwhile: ``PersonAttention._candidate``).
"""

from __future__ import annotations

import math

from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from robot.attention.appearance import Colours
from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import Track, Tracks, TrackerSpec
from robot.partner_search import YIELD_NEAR, follow_search_time, yielding

RED, GREEN, YELLOW = (0.85, 0.1, 0.1), (0.1, 0.65, 0.2), (0.9, 0.85, 0.1)
SEEN = 20.0  # she was last measured then, at the origin (odom), walking 0.5 m/s along +x


def _following(others: list[tuple[float, float, tuple[float, float, float] | None]], t: float,
               state: str = "Follow") -> PersonAttention:
    """The attention following partner 1 (red), her track dormant since SEEN; ``others``: confirmed
    tracks 2.. at (x, y) with the colour the camera saw on them just before ``t`` (None: not seen)."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.state = state
    a.tracks = Tracks(TrackerSpec())
    a.colours = Colours()
    her = Track(1, [0.5, 0.0, 0.5, 0.0], [1.0, 0, 0, 0, 1.0, 0, 0, 0.1, 0, 0.1], 0.0)
    her.confirmed, her.dormant, her.last_seen, her.last_z = True, True, SEEN, (0.0, 0.0)
    a.tracks.tracks.append(her)
    for k, (x, y, colour) in enumerate(others):
        tk = Track(k + 2, [x, y, 0.0, 0.0], [0.01, 0, 0, 0, 0.01, 0, 0, 1.0, 0, 1.0], t - 1.0)
        tk.confirmed = True
        a.tracks.tracks.append(tk)
        if colour is not None:
            for j in range(3):
                a.colours.observe(tk.id, colour, t - 0.3 + 0.1 * j)
    a.partner, a.partner_lost_sent = 1, False
    a._partner_last = (SEEN, 0.0, 0.0, 0.5, 0.0, -2.0, 0.0)
    a._partner_colour = RED
    a._follow_stopped = None  # (the follower has not said its search is over)
    a._pose_at = lambda t: (-1.0, 0.0, 0.0)  # the robot 1 m behind where she went out of view
    return a


def test_she_is_found_again_in_her_clothes_where_she_walked_on_but_nobody_else_is():
    t = SEEN + 8.0  # 0.5 m/s for 8 s: up to 1 + 4 = 5 m on
    a = _following([(3.8, 1.2, RED)], t)
    assert a._reacquire(t) == 1 and a.partner == 2  # (main: 2.5 m at most, nobody)
    # two in her clothes, or one whose clothes are unseen: the one on her way on is hers (doors9's rule,
    # position history: she walked on along +x; PersonAttention._her_way) ...
    for others in ([(3.8, 0.3, RED), (3.0, -2.9, RED)], [(3.8, 0.3, None)]):
        a = _following(others, t)
        assert a._reacquire(t) == 1 and a.partner == 2, others
    # ... off her way (more than the reacquisition radius from it) the clothes decide alone: two in her
    # clothes, which one? clothes not yet seen: nobody
    for others in ([(3.8, 1.2, GREEN)],  # other clothes
                   [(3.8, 2.9, RED), (3.0, -2.9, RED)],  # two in her clothes off her way: which one?
                   [(3.8, 2.9, None)],  # clothes not yet seen, off her way
                   [(6.5, 0.0, RED)]):  # further than she can have walked, on her way or not
        a = _following(others, t)
        assert a._reacquire(t) == -1 and a.partner == 1, others
    a = _following([(3.8, 1.2, RED)], t, state="Interaction")  # standing with it, a step aside is not 4 m
    assert a._reacquire(t) == -1


def test_the_camera_looks_at_whoever_she_could_be_while_his_clothes_are_unseen():
    t = SEEN + 8.0
    a = _following([(3.8, 1.2, None), (1.0, -0.5, GREEN), (9.0, 0.0, None)], t)
    assert a._candidate(t) == 1  # the unseen one within her walking reach, not the green man, not the far one
    a = _following([(3.8, 1.2, RED)], t)
    assert a._candidate(t) == -1  # seen: nothing left to look at


@settings(max_examples=120, deadline=None)
@given(x=st.floats(-6, 6), y=st.floats(-6, 6), unseen=st.floats(0.5, 15.0), speed=st.floats(0.0, 2.0),
       same=st.booleans())
def test_taken_following_exactly_when_in_her_clothes_and_within_her_walking_reach(x, y, unseen, speed, same):
    t = SEEN + unseen
    a = _following([(x, y, RED if same else YELLOW)], t)
    a._partner_last = (SEEN, 0.0, 0.0, speed, 0.0, -2.0, 0.0)
    p = a.params
    reach = min(p.follow_reacquire_cap, p.reacquire_radius + min(p.follow_walk_speed, max(p.reacquire_speed, speed)) * unseen)
    d = math.hypot(x, y)
    if abs(d - reach) < 1e-6:
        return
    row = a._reacquire(t)
    assert (row == 1) == (same and d <= reach)
    assert reach <= p.follow_reacquire_cap


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.floats(-5, 5), st.floats(-5, 5)), max_size=5))
def test_the_robot_yields_exactly_while_someone_is_within_reach_of_it(others):
    assert yielding(others) == any(math.hypot(x, y) < YIELD_NEAR for x, y in others)


def test_time_spent_yielding_to_a_crosser_is_not_time_she_was_unseen():
    a = _following([(-0.5, 0.8, GREEN)], SEEN)  # a man crossing right beside the robot (robot frame (0.5, 0.8))
    a._yield_t, a._yielded = None, 0.0
    # her pace when last seen lengthens the search as it does the follower's (robot.partner_search, follow17)
    search = follow_search_time(2.0, base=a.params.follow_lost_after, top_speed=a.params.robot_top_speed,
                                pace=math.hypot(*a._partner_last[3:5]))
    a._driven, a._drive_start = 0.0, None
    t = SEEN
    while t < SEEN + 3.0:  # he stands beside it for 3 s
        a._count_yield(t)
        t += 0.1
    a.tracks.tracks[1].x[0] = 10.0  # then he has gone on
    while t < SEEN + search + 2.0:
        a._count_yield(t)
        t += 0.1
    assert 2.8 <= a._yielded <= 3.1
    assert not a.partner_left(SEEN + search + 2.0)  # unseen search + 2 s, 3 of them yielding: still searching
    assert a.partner_left(SEEN + search + 3.2)


@settings(max_examples=60, deadline=None)
@given(vx=st.floats(-1.0, 1.0), vy=st.floats(-1.0, 1.0), duration=st.floats(0.0, 5.0), wall=st.floats(0.5, 3.0))
def test_the_search_walks_on_at_her_pace_and_never_through_a_wall(vx, vy, duration, wall):
    """Her track gone quiet, the search point walks on along her last seen velocity (a quarter second at
    a time) for the time given, never through a wall (here the line x = ``wall``; the floor plan's
    ``in_sight`` in the follower): straight on while the way is free, along the wall once it reaches it
    (she walks along a passage), never back the way she came and never further than her pace carries her."""
    from robot.navigation.follow import WALL_BODY, Follower

    f = Follower.__new__(Follower)

    class _Plan:
        @staticmethod
        def in_sight(a, b):
            return (a[0] < wall) == (b[0] < wall)

        @staticmethod
        def clearance(p):
            return abs(wall - p[0])

    f.route = _Plan()
    x, y = f._walk_on((0.0, 0.0), (vx, vy), duration)
    steps = int(duration / 0.25)
    # a step ending on the wall to the last bit (vx 1/3, wall 0.5: 6 steps sum to 0.5 or to 0.49999999999999994)
    # is on either side by rounding, in the search as in this test
    near = wall - WALL_BODY  # a person's centre keeps this far off the wall
    assume(vx <= 0 or all(abs((k + 1) * 0.25 * vx - near) > 1e-9 for k in range(steps + 1)))
    free = steps if vx <= 0 else min(steps, next((k for k in range(steps + 1) if (k + 1) * 0.25 * vx > near), steps))
    assert x < wall  # never through the wall
    speed = math.hypot(vx, vy)
    assert math.hypot(x, y) <= speed * 0.25 * steps + 1e-9  # never further than her pace carries her
    if free == steps:  # the way straight on free: straight on
        assert math.isclose(x, vx * 0.25 * free, abs_tol=1e-9) and math.isclose(y, vy * 0.25 * free, abs_tol=1e-9)
    else:  # the wall reached: on along it, her way along it (never back)
        assert y * vy >= -1e-9 and abs(y) >= abs(vy) * 0.25 * free - 1e-9


def _l_corridor():
    """A 1.0 m corridor east along y in [0, 1] up to x = 3, then north in x in [2, 3] (an L bend), as the
    floor plan's ``in_sight`` would say (a segment crosses a wall when it leaves the corridor)."""

    def inside(p):
        x, y = p
        return (0.0 <= y <= 1.0 and -5.0 <= x <= 3.0) or (2.0 <= x <= 3.0 and 0.0 <= y <= 6.0)

    class _Plan:
        @staticmethod
        def clearance(p):
            x, y = p
            if not inside(p):
                return 0.0
            legs = [min(y, 1.0 - y, 3.0 - x) if y <= 1.0 else 0.0, min(x - 2.0, 3.0 - x, y) if x >= 2.0 else 0.0]
            return max(legs)

        @staticmethod
        def in_sight(a, b):
            return all(inside((a[0] + (b[0] - a[0]) * t / 8, a[1] + (b[1] - a[1]) * t / 8)) for t in range(9))

    return _Plan()


@settings(max_examples=60, deadline=None)
@given(y0=st.floats(0.2, 0.8), x0=st.floats(0.0, 1.5), drift=st.floats(-0.3, 0.3), pace=st.floats(0.8, 1.2))
# search25: the longest free run was the way back down the first leg, not on up the other one beside its wall
@example(y0=0.21875, x0=0.25, drift=-0.0625, pace=1.0)
@example(y0=0.22, x0=0.25, drift=-0.06, pace=1.0)
@example(y0=0.5, x0=1.5, drift=-0.06, pace=1.19)
def test_the_search_point_follows_her_round_the_blind_bend_of_a_passage(y0, x0, drift, pace):
    """bend23, fresh11 twin_passage_chat: last seen walking east along a 1.0 m passage (her track's heading a
    little off the passage's, as a tracker's is), she turned north round its bend out of view; the search
    point walks on along the passage and round the bend into its other leg, not stopping on a wall short of
    it (where the robot stood until it declared her lost); inside the corridor all the way."""
    from robot.navigation.follow import Follower

    f = Follower.__new__(Follower)
    f.route = _l_corridor()
    assume(pace * 5.0 >= 1.3 * (3.0 - x0) + 1.0)  # her pace takes her past the bend (a third more: along the walls)
    c, s = math.cos(drift), math.sin(drift)
    x, y = f._walk_on((x0, y0), (pace * c, pace * s), 5.0)
    assert f.route.in_sight((x, y), (x, y))
    assert y > 1.0 and 2.0 <= x <= 3.0  # round the bend, on north in its other leg


def test_once_the_walked_on_point_is_seen_empty_the_robot_come_up_to_it_looks_further_on_not_back_at_it():
    """search25, fresh11 twin_passage_chat seed 1: last seen walking east along the first leg of an L passage, she went
    on round its bend and up the other leg; the robot saw the 5 s point (round the bend) empty and made for where her
    pace carried her since, but come up beside that point it no longer saw it (not in the laser's view) and took it
    as her place again: it stood there, facing it, until it declared her lost. Seen empty once for this sighting,
    the point stays so: the search goes on up the other leg, whatever the scan now shows of it."""
    from robot.navigation.follow import SEARCH_WALK_ON, Follower

    plan = _l_corridor()
    plan.inside = staticmethod(lambda p: plan.clearance(p) > 0.0)

    class _Scan:
        empty = True  # whether the latest scan looks at a point and finds it empty

        def sees_through(self, x, y, radius=0.25):
            return self.empty

    class _Sim:
        now = 10.0  # unseen 10 s: the 5 s point is round the bend, her pace has taken her 2.5 m further up

    f = Follower.__new__(Follower)
    f.sim, f.route, f.scan = _Sim(), plan, _Scan()
    f._seen_pos, f._seen_v, f._walked_far = (0.5, 0.5, 0.0), (0.5, 0.0), None
    near = f._walk_on((0.5, 0.5), (0.5, 0.0), SEARCH_WALK_ON)
    assert near[0] > 2.0 and near[1] < 1.5  # (round the bend: the point the robot makes for first)
    f.odom = (1.5, 0.5, 0.0)  # in the first leg, the 5 s point in view and empty: on up the other leg
    first = f._not_there(*near)
    assert first[1] > near[1] + 2.0
    f.odom, f.scan.empty = (near[0] - 0.3, near[1], math.pi / 2), False  # come up beside it: out of the laser's view
    f.sim.now = 11.0
    assert f._not_there(*near)[1] > first[1]  # further on still, never back to the point seen empty


def test_searching_her_coasting_track_on_a_wall_or_seen_empty_is_nobody_in_its_way_but_never_while_she_is_seen():
    """search25 (own L passage scene): unseen round a blind bend, her track stood where she was last measured, its
    centre at the passage's wall, kept by the wall's echo; the contact limit took it for her standing 0.7 m ahead and
    halted the robot until the search ran out while she walked on up the other leg. Searching, her coasting track is
    left out of the contact limit where nobody can stand (centre within WALL_BODY of the floor plan) or where the
    laser looks and sees nobody; never while she is seen (following), nor where the laser does not look."""
    from robot.navigation.follow import Follower

    plan = _l_corridor()

    class _Scan:
        empty = False

        def sees_through(self, x, y, radius=0.25):
            return self.empty

    class _Sim:
        now = 12.0

    f = Follower.__new__(Follower)
    f.sim, f.route, f.scan, f.partner_id, f.odom = _Sim(), plan, _Scan(), "t1", (1.8, 0.5, 0.0)
    on_wall = {"t": 11.9, "x": 2.5, "y": 0.05, "vx": 0.0, "vy": 0.0}  # 5 cm off the passage's wall
    mid = {"t": 11.9, "x": 2.5, "y": 0.5, "vx": 0.0, "vy": 0.0}  # in the passage's middle
    assert f._nobody_there(on_wall, True) == "t1"
    assert f._nobody_there(on_wall, False) is None  # following: she is seen, her track is her
    assert f._nobody_there(mid, True) is None  # the laser does not look there (or sees someone): she may stand there
    f.scan.empty = True
    assert f._nobody_there(mid, True) == "t1"  # looked at and empty: nobody there


def test_the_contact_limit_leaves_out_only_the_track_said_gone():
    """``in_the_way(gone=id)`` leaves that one track out of every row (its own, and as someone who stopped dead),
    and nobody else: a person standing in the way still limits the robot."""
    from robot.navigation.people import People, in_the_way

    people = People()
    xml = ('<tracks time="10.0" frame="odom"><track id="t1" x="1.0" y="0.0" vx="0.0" vy="0.0" cxx="30" cxy="0" '
           'cyy="30" confirmed="true"/><track id="t2" x="2.0" y="0.5" vx="0.0" vy="0.0" cxx="0.01" cxy="0" '
           'cyy="0.01" confirmed="true"/></tracks>')
    from homesim.xmlio import parse_bytes

    people.update(parse_bytes(xml))
    both = in_the_way(people, (0.0, 0.0, 0.0), 10.0)
    one = in_the_way(people, (0.0, 0.0, 0.0), 10.0, gone="t1")
    assert len(both) == 2 and len(one) == 1 and abs(one[0][0] - 2.0) < 1e-9


def test_she_turned_through_the_door_as_she_went_out_of_view_her_pace_not_her_last_speed_is_her_reach():
    """sq_cross_pair seed 0: turning through the hall door slowed her constant-velocity track to 0.3 m/s
    just before the jamb hid her, though she walked 0.5 m/s; 8.3 s later she came into view in the next
    room 4.1 m on. With her last speed she could be 3.5 m on (nobody looked at her, she was declared gone);
    with the fastest her track went in the last seconds (0.5 m/s) she is within reach: found again."""
    t = SEEN + 8.3
    a = _following([(3.3, 2.4, RED)], t)  # 4.08 m from where her legs were last measured
    a._partner_last = (SEEN, 0.0, 0.0, 0.3, 0.0, -2.0, 0.0)
    a._partner_pace = (SEEN - 5.0, 0.5)  # a pace from before this sighting is not hers now
    assert a._reacquire(t) == -1 and a.partner == 1
    a = _following([(3.3, 2.4, RED)], t)
    a._partner_last = (SEEN, 0.0, 0.0, 0.3, 0.0, -2.0, 0.0)
    a._partner_pace = (SEEN, 0.5)  # renewed with this sighting: her pace
    assert a._reacquire(t) == 1 and a.partner == 2
    assert a._candidate(t) == -1  # (her clothes seen: nothing left to look at)


@settings(max_examples=80, deadline=None)
@given(speeds=st.lists(st.tuples(st.floats(0.05, 1.0), st.floats(0.0, 1.5)), min_size=1, max_size=12))
def test_her_pace_is_never_below_her_last_speed_and_forgets_a_fast_step_within_seconds(speeds):
    """walking_pace over a run of sightings: at least the last speed, at most the fastest, and every
    earlier speed counts only faded by exp(-dt / PACE_MEMORY) (a quick step 10 s ago is no pace now)."""
    from robot.attention.module import PACE_MEMORY, walking_pace

    pace, t, history = None, SEEN, []
    for dt, v in speeds:
        t += dt
        pace = walking_pace(pace, t, v)
        history.append((t, v))
    when, p = pace
    assert when == t and history[-1][1] <= p <= max(v for _, v in history)
    assert p <= max(v * math.exp(-(t - s) / PACE_MEMORY) for s, v in history) + 1e-9



def test_following_a_track_whose_clothes_are_unseen_is_not_hers_for_being_first_seen_near_where_she_went():
    """fresh7 corr_fast_walker_goto seed 0: a door jamb 6 m ahead came out as a standing track 1.3 m behind where
    the leader went out of view (his way on leads away from it) and took his id by the origin exception; the
    search drove to the jamb and stood there. Following (she leads, walks on), such a track waits for its clothes
    (the camera looks at it: _candidate); standing with her (Interaction), the exception holds as before."""
    t = SEEN + 3.0  # unseen 3 s: the reacquisition radius is 1.0 + 0.3 * 3 = 1.9 m
    a = _following([(-1.3, 0.0, None)], t)
    assert a._reacquire(t) == -1 and a.partner == 1
    assert a._candidate(t) == 1  # the camera looks at it meanwhile
    a = _following([(-1.3, 0.0, RED)], t)  # seen in her clothes (and within her walking reach): hers
    assert a._reacquire(t) == 1 and a.partner == 2
    a = _following([(-1.3, 0.0, None)], t, state="Interaction")
    assert a._reacquire(t) == 1 and a.partner == 2
