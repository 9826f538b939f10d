"""Tracks of people the laser cannot see (issue 26 item 1): behind a wall's edge, behind someone,
behind the robot. No leg candidate is evidence of absence only where the laser looks; a person
hidden keeps their track (dormant: not reported as seen) and is found again under the same id,
so a crossing or a door frame is not an identity switch. A dormant track is gated narrowly: long
unseen, a pair metres away is somebody else."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robot.attention.legs import PAIR, SINGLE
from robot.attention.tracker import Tracks, TrackerSpec
from robot.attention.visibility import MARGIN, hidden_points

BEARINGS = np.radians(-90 + 0.5 * np.arange(361))
MIN_ANGLE, RES = float(BEARINGS[0]), float(BEARINGS[1] - BEARINGS[0])
EMPTY, NONE = np.zeros((0, 2)), np.zeros(0, dtype=np.int8)


def _hidden(points, ranges, offset=0.0):
    return hidden_points(points, ranges, MIN_ANGLE, RES, max_range=6.5, offset=offset)


# ------------------------------------------------------------------ visibility
def test_a_point_in_open_view_is_seen_one_behind_a_wall_or_the_robot_or_far_is_hidden():
    open_room = np.full(361, 8.19)
    assert _hidden([(2.0, 0.5)], open_room) == [False]
    assert _hidden([(-1.0, 0.2)], open_room) == [True]  # behind the robot: outside the half circle
    assert _hidden([(7.0, 0.0)], open_room) == [True]  # beyond the range legs are trusted
    wall = open_room.copy()
    wall[150:211] = 1.5  # something 1.5 m away straight ahead (-15 .. +15 deg)
    assert _hidden([(3.0, 0.0)], wall) == [True]
    assert _hidden([(1.4, 0.0)], wall) == [False]  # in front of it: in view
    assert _hidden([(3.0, 2.0)], wall) == [False]  # beside it (34 deg): in view


def test_bad_scans_are_refused():
    with pytest.raises(ValueError):
        hidden_points([(1.0, 0.0)], [], MIN_ANGLE, RES, max_range=6.5)
    with pytest.raises(ValueError):
        hidden_points([(1.0, 0.0)], [1.0, 2.0], MIN_ANGLE, 0.0, max_range=6.5)


@settings(max_examples=200, deadline=None)
@given(d=st.floats(0.4, 6.4), bearing=st.floats(-1.5, 1.5), reach=st.floats(0.0, 8.19))
def test_hidden_exactly_when_the_beams_at_the_point_end_well_in_front_of_it(d, bearing, reach):
    """With every beam ending at ``reach``, a point inside the field of view and range is hidden
    iff the beams end more than the margin in front of it. Exactly at the margin (a set of measure
    zero) float rounding of the point's distance decides, so that boundary is left out."""
    assume(abs(reach - (d - MARGIN)) > 1e-9)
    ranges = np.full(361, reach)
    (h,) = _hidden([(d * math.cos(bearing), d * math.sin(bearing))], ranges)
    assert h == (reach < d - MARGIN)


# ------------------------------------------------------------------ tracker
def _confirmed(tr: Tracks, xy=(2.0, 0.0)) -> int:
    for k in range(3):
        tr.step(k * 0.1, np.array([xy]), np.array([PAIR], dtype=np.int8))
    assert len(tr) == 1 and tr.confirmed[0]
    return int(tr.ids[0])


def test_a_hidden_person_keeps_the_track_and_is_found_again_under_the_same_id():
    """Blocker of cross_u_pair: the partner behind the kitchen door's wall for 3 s, a bystander behind
    the robot for 20 s: the track outlives the death timeout while hidden and takes the legs back."""
    spec = TrackerSpec()
    tr = Tracks(spec)
    tid = _confirmed(tr)
    t = 0.2
    while t < 20.0:
        t += 0.1
        tr.step(t, EMPTY, NONE, lambda pts: [True] * len(pts))
        assert len(tr) == 1
        if t - 0.2 > spec.death_timeout + 0.15:
            assert tr.tracks[0].dormant  # kept, but not a person seen
    tr.step(t + 0.1, np.array([[2.1, 0.05]]), np.array([PAIR], dtype=np.int8), lambda pts: [True] * len(pts))
    assert int(tr.ids[0]) == tid and not tr.tracks[0].dormant


def test_hidden_tracks_still_die_after_the_hidden_timeout_and_seen_ones_after_the_death_timeout():
    spec = TrackerSpec()
    for hide, limit in ((True, spec.hidden_timeout), (False, spec.death_timeout)):
        tr = Tracks(spec)
        _confirmed(tr)
        t = 0.2
        while len(tr) and t < 60:
            t += 0.1
            tr.step(t, EMPTY, NONE, lambda pts: [hide] * len(pts))
        assert t == pytest.approx(0.2 + limit + 0.1, abs=0.11)


def test_time_in_view_without_legs_counts_hidden_time_does_not():
    """In view 1.5 s, hidden 10 s, in view again: dead after another 1 s in view (2.5 s in view in all)."""
    spec = TrackerSpec()
    tr = Tracks(spec)
    _confirmed(tr)
    t, seen_for = 0.2, 0.0
    while len(tr) and t < 30:
        t += 0.1
        hide = 1.7 < t <= 11.7
        tr.step(t, EMPTY, NONE, lambda pts, hide=hide: [hide] * len(pts))
        seen_for += 0.0 if hide else 0.1
    assert seen_for == pytest.approx(spec.death_timeout + 0.1, abs=0.15)


@settings(max_examples=60, deadline=None)
@given(dx=st.floats(-3.0, 3.0), dy=st.floats(-3.0, 3.0), kind=st.sampled_from([PAIR, SINGLE]))
def test_a_dormant_track_takes_only_pairs_near_where_it_was(dx, dy, kind):
    """A dormant track (a standing person hidden 5 s) takes back a pair or blob within its narrow gate
    (3.03 sigma of ``dormant_gate_std`` and the measurement) and never a lone leg, nor anything further."""
    spec = TrackerSpec()
    tr = Tracks(spec)
    tid = _confirmed(tr)
    t = 0.2
    while t < 5.2:
        t += 0.1
        tr.step(t, EMPTY, NONE, lambda pts: [True] * len(pts))
    assert tr.tracks[0].dormant
    x, y = tr.tracks[0].x[0], tr.tracks[0].x[1]
    z = np.array([[2.0 + dx, dy]])
    tr.step(t + 0.1, z, np.array([kind], dtype=np.int8), lambda pts: [True] * len(pts))
    row = tr.row(tid)
    took = row >= 0 and tr.tracks[row].last_update == pytest.approx(t + 0.1)
    far = min(math.hypot(2.0 + dx - x, dy - y), math.hypot(dx, dy))
    if kind == SINGLE or far > 3.05 * math.hypot(spec.dormant_gate_std, spec.meas_std):
        assert not took
    if kind == PAIR and far < 0.3:
        assert took


def test_without_the_visibility_test_a_track_dies_as_before():
    spec = TrackerSpec()
    tr = Tracks(spec)
    _confirmed(tr)
    t = 0.2
    while len(tr) and t < 10:
        t += 0.1
        tr.step(t, EMPTY, NONE)
    assert t == pytest.approx(0.2 + spec.death_timeout + 0.1, abs=0.11)


def test_a_track_coasting_unseen_stops_at_a_wall_instead_of_walking_through_it():
    """Blocker of cross_u_pair seeds 4 and 7: she turned along a wall while unseen, her track coasted on
    through it and was metres off when she came back into view. With the floor plan's test (here: a
    wall at y >= 1), the track stops where it was before the step that would take it in."""
    spec = TrackerSpec()
    free, walled = Tracks(spec), Tracks(spec)
    for tr in (free, walled):
        for k in range(6):  # walking north at 1 m/s
            tr.step(k * 0.1, np.array([[2.0, 0.1 * k]]), np.array([PAIR], dtype=np.int8))
    wall = lambda pts: [y >= 1.0 for _, y in pts]  # noqa: E731
    t = 0.5
    for _ in range(15):
        t += 0.1
        free.step(t, EMPTY, NONE)
        walled.step(t, EMPTY, NONE, blocked=wall)
    assert free.x[0, 1] > 1.5  # through the wall
    assert 0.8 < walled.x[0, 1] < 1.0 and abs(walled.x[0, 3]) < 1e-9  # stopped before it
    # a measurement inside is taken as it is (the plan is for predictions, not for what the laser saw)
    walled.step(t + 0.1, np.array([[2.0, 1.05]]), np.array([PAIR], dtype=np.int8), blocked=wall)
    assert walled.x[0, 1] > 1.0


def _walker_past_a_hidden_bystander(spec: TrackerSpec) -> tuple[Tracks, int, int, float]:
    """Olaf stands at (2.5, 0.3), tracked, then hidden (behind Jana) until his track is dormant; Jana's
    track walks along y = 0 at 0.5 m/s towards him. Returns the tracks, Jana's id, Olaf's id and the
    time of the last scan (Jana at x = 1.95)."""
    tr = Tracks(spec)
    olaf = _confirmed(tr, (2.5, 0.3))

    def behind_her(pts):
        return [math.hypot(x - 2.5, y - 0.3) < 0.5 for x, y in pts]

    t, x = 0.2, 0.0
    while x < 1.95 - 1e-9:
        t = round(t + 0.1, 6)
        if t >= 3.0:  # his track dormant by now (she came from out of its gate while it still coasted)
            x = 0.5 + 0.5 * (t - 3.0)
            tr.step(t, np.array([[x, 0.0]]), np.array([PAIR], dtype=np.int8), behind_her)
        else:
            tr.step(t, EMPTY, NONE, behind_her)
    jana = [int(i) for i in tr.ids if int(i) != olaf]
    assert len(jana) == 1 and tr.confirmed[tr.row(jana[0])] and tr.tracks[tr.row(olaf)].dormant
    return tr, jana[0], olaf, t


@settings(max_examples=60, deadline=None)
@given(lx=st.floats(2.1, 2.6), ly=st.floats(0.2, 0.5), ahead=st.floats(-0.03, 0.03))
def test_a_dormant_track_never_takes_the_pair_a_seen_persons_track_predicts(lx, ly, ahead):
    """bystander_at_door with the half-hidden leg rule: Jana walks past Olaf, whose track is dormant (she
    hides him); the scan shows her pair where her track predicts it and one leg of Olaf's beside. The
    pair is hers: her track takes it, not his dormant track (which took it in one global assignment
    that makes as many pairs as it can, pushing her track onto his lone leg: her track then slid onto
    Olaf, her voice no longer came from her track's bearing, and the robot stopped listening to her)."""
    spec = TrackerSpec()
    tr, jana, olaf, t = _walker_past_a_hidden_bystander(spec)
    px = 2.0 + ahead
    z = np.array([[px, 0.0], [lx, ly]])
    got = tr.step(t + 0.1, z, np.array([PAIR, SINGLE], dtype=np.int8), lambda pts: [math.hypot(x - 2.5, y - 0.3) < 0.5 for x, y in pts])
    assert got[0] == tr.row(jana), (got, lx, ly)
    j = tr.tracks[tr.row(jana)]
    assert math.hypot(j.x[0] - px, j.x[1]) < 0.05
    assert tr.row(olaf) < 0 or tr.tracks[tr.row(olaf)].last_update < t + 0.05  # his track was not fed her pair


def test_a_dormant_track_still_takes_a_pair_no_seen_persons_track_wants():
    """The same scene, Olaf steps out from behind Jana: his pair, 0.1 m from where he stood and 0.6 m
    beside her, is his dormant track's again (found under his own id), hers stays on her."""
    spec = TrackerSpec()
    tr, jana, olaf, t = _walker_past_a_hidden_bystander(spec)
    got = tr.step(t + 0.1, np.array([[2.0, 0.0], [2.55, 0.38]]), np.array([PAIR, PAIR], dtype=np.int8))
    assert got == [tr.row(jana), tr.row(olaf)]
    assert not tr.tracks[tr.row(olaf)].dormant


@pytest.mark.slow
@pytest.mark.skipif(os.environ.get("HOMESIM_SLOW", "") in ("", "0"),
                    reason="a 27 s end-to-end run (about 30 s of CPU): set HOMESIM_SLOW=1")
def test_walked_past_a_hidden_flatmate_the_partner_is_still_heard():
    """End to end, tests/scenarios/follow/past_flatmate_at_shelf.xml seed 0 to 27 s: Mia leads the robot past
    Tom, whose track went dormant behind her; her "Stop" (24.1 s) is heard and answered. With one round of
    assignment his dormant track took her pair, her track slid onto him and the beam gate took her voice
    for a bystander's: never answered. Slow (her "Stop" comes at 24 s, so no shorter run shows it): run with
    the library's slow tests (HOMESIM_SLOW=1, review14 F3); in the fast suite the two Hypothesis properties
    above (a dormant track never takes the pair a seen person's track predicts, and still takes one nobody
    wants) fail on the one-round assignment."""
    from pathlib import Path

    from homesim.tour.runner import Run, RunOptions

    scene = Path(__file__).resolve().parent / "scenarios" / "follow" / "past_flatmate_at_shelf.xml"
    with Run.from_file(scene, RunOptions(seed=0, until=27)) as run:
        run.run()
        said = [u.text for u in run.world.sound.all() if u.source == "robot"]
        run.finish()
    assert any("stopped" in t.lower() for t in said), said


def test_a_half_hidden_persons_track_lives_on_one_leg_while_someone_stands_in_front():
    """A bystander half behind the partner shows one leg: while the laser cannot see the rest of him his
    track is not dropped after ``single_support`` (no track may start again beside hers); a lone leg in
    plain view (a table's) still holds a track only ``single_support`` s."""
    from robot.attention.legs import PAIR, SINGLE
    from robot.attention.tracker import Tracks, TrackerSpec

    spec = TrackerSpec()
    for half_hidden in (False, True):  # the half-hidden tracker last: the bound below runs on its live track
        tr = Tracks(spec)
        t = 0.0
        for k in range(6):  # a pair: born and confirmed
            t = 0.1 * k
            tr.step(t, [[2.3, -0.3]], [PAIR])
        assert tr.tracks and tr.tracks[0].confirmed
        while t < spec.single_support + 4.0:
            t += 0.1
            tr.step(t, [[2.32, -0.25]], [SINGLE], hidden=lambda pts: [half_hidden] * len(pts))
        assert (len(tr.tracks) == 1) is half_hidden
    assert half_hidden and len(tr.tracks) == 1
    while t < spec.hidden_timeout + 1.0:  # but not for ever: at most ``hidden_timeout`` after its last pair
        t += 0.1
        tr.step(t, [[2.32, -0.25]], [SINGLE], hidden=lambda pts: [True] * len(pts))
    assert not tr.tracks
