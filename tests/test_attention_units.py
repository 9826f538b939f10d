"""Person attention parts: selection rules (Hypothesis), the FSM, the batched Kalman filter against
filterpy, the leg detector on synthetic scans, cue matching and hysteresis."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.cues import Hysteresis, match_sounds
from robot.attention.fsm import AttentionFSM, OrderRefused
from robot.attention.legs import PAIR, SINGLE, LegDetector, LegSpec, detect
from robot.attention.selection import SelectionParams, Selector
from robot.attention.tracker import GATE_99, Tracks, TrackerSpec, _assign, cv_model
from tests.attention_reference import reference_detect

P = SelectionParams(max_selection=5.0, inhibition=3.0)

# ------------------------------------------------------------------ selection
frames = st.lists(
    st.tuples(st.floats(0.05, 1.5), st.dictionaries(st.integers(1, 5), st.integers(1, 3), max_size=5)),
    min_size=1, max_size=60,
)


@settings(max_examples=200, deadline=None)
@given(seq=frames)
def test_selection_rules_hold_at_every_step(seq):
    """Category 3 at once; otherwise the highest category among the unblocked; a category 1/2
    selection ends after max_selection when someone else is there; a released person stays blocked."""
    sel = Selector(P)
    now = 0.0
    for dt, cats in seq:
        now += dt
        prev, prev_since = sel.selected, sel.since
        got = sel.update(now, cats)
        if not cats:
            assert got is None
            continue
        assert got in cats
        if 3 in cats.values():
            assert cats[got] == 3  # a potential partner is selected at once
            continue
        free = [i for i in cats if sel.blocked_until.get(i, -math.inf) <= now]
        pool = free or list(cats)
        assert cats[got] == max(cats[i] for i in pool)  # the highest category wins
        assert got in pool  # a blocked person only when nobody else is free
        if got == prev and len(cats) > 1:
            assert now - prev_since < P.max_selection + 1e-9  # the time limit


@settings(max_examples=100, deadline=None)
@given(ids=st.lists(st.integers(1, 9), min_size=2, max_size=5, unique=True), cat=st.integers(1, 2), order=st.permutations(range(5)))
def test_ties_go_to_the_one_not_selected_for_the_longest_time(ids, cat, order):
    sel = Selector(P)
    cats = {i: cat for i in ids}
    history = [ids[k % len(ids)] for k in order]
    for t, i in enumerate(history):  # select each in turn (everyone else absent)
        sel.update(float(t * 10), {i: cat})
    t = 100.0
    got = sel.update(t, cats)
    never = [i for i in ids if i not in history]
    if never:
        assert got == min(never)
    else:
        last = {i: max(k for k, h in enumerate(history) if h == i) for i in ids}
        assert got == min(ids, key=lambda i: last[i])


@settings(max_examples=200, deadline=None)
@given(seq=frames)
def test_someone_who_starts_speaking_gets_the_look_from_an_equal_talker_at_once(seq):
    """When a free person starts speaking (rises into category 2) while the selected person speaks
    without facing the robot (category 2, the best there is), the tie is decided there and then:
    the selection moves to one of the equals not selected for longer. (Category 3 keeps its
    selection: rule 1.) And starting to speak lifts a block (inhibition of return)."""
    sel = Selector(P)
    now = 0.0
    before: dict[int, int] = {}
    for dt, cats in seq:
        now += dt
        prev = sel.selected
        got = sel.update(now, cats)
        if prev is not None and prev in cats and got is not None:
            c = cats[prev]
            free = {i for i in cats if sel.blocked_until.get(i, -math.inf) <= now}
            risen = [i for i in cats if i != prev and i in free and cats[i] == c and before.get(i, 0) < c]
            if c == 2 and prev in free and c == max(cats[i] for i in free) and risen:
                assert got != prev and cats[got] == c
        # Starting to speak lifts the inhibition of return (the selected one may reach its time limit).
        for i, c in cats.items():
            if c >= 2 and before.get(i, 0) < 2 and i != prev:
                assert sel.blocked_until.get(i, -math.inf) <= now
        before = dict(cats)


@settings(max_examples=200, deadline=None)
@given(seq=frames)
def test_a_potential_partner_keeps_the_selection_while_in_category_3_and_threes_tie_by_longest_unselected(seq):
    """Rule 1 with several potential partners: the selected one keeps the focus as long as they stay
    in category 3 (another category-3 person does not take it, however long they waited); a new
    category-3 selection goes to the one not selected for the longest time."""
    sel = Selector(P)
    now = 0.0
    for dt, cats in seq:
        now += dt
        prev = sel.selected
        last = dict(sel.last_selected)
        got = sel.update(now, cats)
        if prev is not None and cats.get(prev) == 3:
            assert got == prev
        elif 3 in cats.values():
            threes = [i for i, c in cats.items() if c == 3]
            assert got == min(threes, key=lambda i: (last.get(i, -math.inf) if i != prev else now, i))


def test_inhibition_of_return_then_the_other_then_back():
    sel = Selector(P)
    cats = {1: 1, 2: 1}
    picks = [(t / 10, sel.update(t / 10, cats)) for t in range(0, 200)]
    first = picks[0][1]
    switch = next(t for t, i in picks if i != first)
    assert switch == pytest.approx(P.max_selection)
    back = next(t for t, i in picks if t > switch and i == first)
    assert back == pytest.approx(2 * P.max_selection)  # the other one had its full time meanwhile


def test_a_speaking_person_takes_the_focus_from_a_silent_one_and_category_3_from_both():
    sel = Selector(P)
    assert sel.update(0.0, {1: 1, 2: 1}) == 1
    assert sel.update(0.1, {1: 1, 2: 2}) == 2
    assert sel.update(0.2, {1: 3, 2: 2}) == 1
    assert sel.update(60.0, {1: 3, 2: 2}) == 1  # no time limit for a potential partner


# ------------------------------------------------------------------ FSM
def test_top_down_states_only_by_orders_and_unknown_orders_refused():
    fsm = AttentionFSM()
    assert fsm.bottom_up(0.0, True, 1) == "Alertness"
    assert fsm.bottom_up(0.1, True, 2) == "Listen"
    assert fsm.order("interact") == "Interaction"
    assert fsm.bottom_up(0.2, False, None) == "Interaction"  # tracks never leave a top-down state
    assert fsm.order("follow") == "Follow"
    assert fsm.order("focus_object") == "Object"
    assert fsm.order("look_around") == "Alertness"
    assert fsm.bottom_up(0.3, False, None) == "Alertness"
    assert fsm.bottom_up(2.4, False, None) == "Sleeping"  # nobody for sleep_after seconds
    assert fsm.order("sleep") == "Sleeping" and fsm.bottom_up(3.0, True, 3) == "Sleeping"
    with pytest.raises(OrderRefused, match="'dance'.*known: focus_object, follow, interact, look_around, look_for_help, pause, sleep"):
        fsm.order("dance")


# ------------------------------------------------------------------ Kalman
@settings(max_examples=50, deadline=None)
@given(
    n=st.integers(1, 4),
    dt=st.floats(0.02, 0.5),
    seed=st.integers(0, 2**31 - 1),
)
def test_the_filter_equals_one_filterpy_kalman_filter_per_track(n, dt, seed):
    rng = np.random.default_rng(seed)
    spec = TrackerSpec()
    tr = Tracks(spec)
    tr._birth(0.0, rng.uniform(-3, 3, (n, 2)), np.full(n, spec.meas_std**2))
    tr._t = 0.0
    for tk, v in zip(tr.tracks, rng.uniform(-1, 1, (n, 2)).tolist()):
        tk.x[2:] = v
        tk.last_update = dt  # not coasting: no damping
    kfs = [tr.filterpy(i) for i in range(n)]
    F, Q = cv_model(dt, spec.accel_noise)
    tr.predict(dt)
    z = rng.uniform(-3, 3, (n, 2))
    for i, kf in enumerate(kfs):
        kf.predict(F=F, Q=Q)
        assert np.allclose(tr.x[i], kf.x.ravel(), atol=1e-9)
        assert np.allclose(tr.P[i], kf.P, atol=1e-9)
        tr.tracks[i].update(z[i, 0], z[i, 1], spec.meas_std**2)
        kf.update(z[i], R=np.eye(2) * spec.meas_std**2)
        assert np.allclose(tr.x[i], kf.x.ravel(), atol=1e-9)
        assert np.allclose(tr.P[i], kf.P, atol=1e-9)
        assert np.array_equal(tr.P[i], tr.P[i].T)  # kept symmetric by construction


@settings(max_examples=100, deadline=None)
@given(n=st.integers(1, 6), m=st.integers(1, 8), seed=st.integers(0, 2**31 - 1))
def test_when_the_gate_leaves_no_choice_the_optimal_assignment_is_every_gated_pair(n, m, seed):
    """The tracker skips linear_sum_assignment when no track has two candidates in its gate and no
    candidate is in two tracks' gates: the solver's answer is then exactly the gated pairs."""
    rng = np.random.default_rng(seed)
    rows = rng.permutation(n)[: min(n, m)]
    cols = rng.permutation(m)[: min(n, m)]
    keep = rng.random(rows.size) < 0.7
    pairs = [(int(i), int(j), float(rng.uniform(0, GATE_99))) for i, j, k in zip(rows, cols, keep) if k]
    assert sorted(_assign(pairs, n, m)) == sorted(pairs)


def test_a_track_is_born_on_repeated_evidence_and_dies_after_the_timeout():
    spec = TrackerSpec()
    tr = Tracks(spec)
    for k in range(3):
        tr.step(k * 0.1, np.array([[2.0 + 0.05 * k, 0.0]]), np.array([PAIR], dtype=np.int8))
    assert len(tr) == 1 and tr.confirmed[0]
    tr.step(0.3, np.array([[5.0, 5.0]]), np.array([SINGLE], dtype=np.int8))  # a lone leg elsewhere: no birth
    assert len(tr) == 1
    t = 0.3
    while len(tr) and t < 10:
        t += 0.1
        tr.step(t, np.zeros((0, 2)), np.zeros(0, dtype=np.int8))
    assert t == pytest.approx(0.2 + spec.death_timeout + 0.1, abs=0.11)


def test_a_person_the_camera_sees_outlives_missing_legs_and_a_bearing_cue_only_until_the_single_allowance():
    """Blocker of home_tour: a standing partner whose legs stop associating for a few seconds is
    kept by frontal faces or their torso (strong) and by their voice from their bearing (weak, bounded)."""
    spec = TrackerSpec()
    empty, none = np.zeros((0, 2)), np.zeros(0, dtype=np.int8)
    faced, weak = Tracks(spec), Tracks(spec)
    for tr in (faced, weak):
        for k in range(3):
            tr.step(k * 0.1, np.array([[2.0, 0.0]]), np.array([PAIR], dtype=np.int8))
    t = 0.2
    while t < 20.0:
        t += 0.1
        faced.step(t, empty, none)
        weak.step(t, empty, none)
        if len(faced):
            faced.support([0], t)
        if len(weak):
            weak.seen([0], t)
    assert len(faced) == 1 and faced.last_seen[0] == pytest.approx(t)  # legs gone 20 s, face seen: kept
    assert len(weak) == 0  # a voice alone does not hold a track past single_support


def test_two_crossing_walkers_keep_their_tracks():
    tr = Tracks()
    ids = None
    for k in range(40):
        t = k * 0.1
        a = (1.0 + 0.9 * t, 0.0 + 0.9 * t)  # ... crossing at (2.8, 1.8) about t = 2
        b = (1.0 + 0.9 * t, 3.6 - 0.9 * t)
        tr.step(t, np.array([a, b]), np.array([PAIR, PAIR], dtype=np.int8))
        if k == 5:
            ids = (int(tr.ids[np.argmin(tr.x[:, 1])]), int(tr.ids[np.argmax(tr.x[:, 1])]))
    assert ids is not None
    # After the crossing the one that started low is high: the same id follows each walker.
    assert int(tr.ids[np.argmax(tr.x[:, 1])]) == ids[0]


# ------------------------------------------------------------------ leg detector
BEARINGS = np.radians(-90 + 0.5 * np.arange(361))


def _scan(circles=(), squares=(), wall=6.0):
    """Exact ranges against a wall at x=wall and some circles (cx, cy, r) / squares (cx, cy, side) in the laser frame."""
    d = np.stack([np.cos(BEARINGS), np.sin(BEARINGS)], 1)
    r = np.where(d[:, 0] > 1e-6, wall / np.maximum(d[:, 0], 1e-6), 8.19)
    r = np.minimum(r, 8.19)
    for cx, cy, rad in circles:
        b = d @ np.array([cx, cy])
        disc = b * b - (cx * cx + cy * cy - rad * rad)
        hit = (disc >= 0) & (b > 0)
        r = np.where(hit, np.minimum(r, b - np.sqrt(np.maximum(disc, 0))), r)
    for cx, cy, side in squares:
        h = side / 2
        for x0 in (cx - h,):  # the face towards the laser
            t = x0 / np.maximum(d[:, 0], 1e-9)
            y = t * d[:, 1]
            hit = (np.abs(y - cy) <= h) & (d[:, 0] > 0)
            r = np.where(hit, np.minimum(r, t), r)
    return r


def test_two_legs_make_a_pair_a_lone_leg_a_single_and_table_legs_no_pair():
    spec = LegSpec(offset=0.0)
    person = detect(_scan(circles=[(2.5, 0.1, 0.06), (2.5, -0.1, 0.06)]), BEARINGS, spec)
    assert list(person.kind) == [PAIR] and np.allclose(person.xy[0], [2.55, 0.0], atol=0.05)
    table = detect(_scan(squares=[(3.0, 0.5, 0.05), (3.0, -0.4, 0.05)]), BEARINGS, spec)
    assert PAIR not in table.kind  # 0.9 m apart: never one person
    wall_only = detect(_scan(), BEARINGS, spec)
    assert len(wall_only) == 0


def test_known_furniture_legs_are_dropped_before_pairing():
    spec = LegSpec(offset=0.0)
    ranges = _scan(circles=[(2.5, 0.1, 0.06)], squares=[(2.5, -0.16, 0.11)])  # a thick post as wide as a leg
    without = detect(ranges, BEARINGS, spec)
    assert PAIR in without.kind  # a person's leg next to a table leg looks like a pair...
    with_map = detect(ranges, BEARINGS, spec, reject=lambda xy: xy[:, 1] < -0.05)
    assert list(with_map.kind) == [SINGLE]  # ... unless the map says the table leg is furniture


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    people=st.integers(0, 4),
    posts=st.integers(0, 5),
    together=st.booleans(),
    no_echo=st.floats(0.0, 0.3),
)
def test_the_leg_detector_computes_what_the_vectorised_rules_say_bit_for_bit(seed, people, posts, together, no_echo):
    """The plain-float detector against the rules written as numpy expressions (tests/attention_reference.py):
    random people (legs apart, or together as one blob), table legs, 1 cm range noise, beams without echo,
    with and without a furniture filter: the same candidates, kinds and legs, to the last bit."""
    rng = np.random.default_rng(seed)
    circles, squares = [], []
    for _ in range(people):
        cx, cy = rng.uniform(0.5, 5.5), rng.uniform(-3.0, 3.0)
        spread = rng.uniform(0.10, 0.14) if together else rng.uniform(0.15, 0.45)
        a = rng.uniform(0, math.pi)
        for sgn in (-1, 1):
            circles.append((cx + sgn * spread / 2 * math.cos(a), cy + sgn * spread / 2 * math.sin(a), rng.uniform(0.05, 0.07)))
    for _ in range(posts):
        squares.append((rng.uniform(0.5, 5.5), rng.uniform(-3.0, 3.0), rng.uniform(0.03, 0.06)))
    ranges = _scan(circles, squares, wall=rng.uniform(2.0, 7.0)) + rng.normal(0.0, 0.01, BEARINGS.shape[0])
    ranges[rng.random(BEARINGS.shape[0]) < no_echo] = 8.19
    spec = LegSpec(offset=float(rng.uniform(0.0, 0.2)))
    for reject in (None, lambda xy: xy[:, 1] < -1.0):
        want = reference_detect(ranges, BEARINGS, spec, reject)
        got = detect(ranges, BEARINGS, spec, reject)
        assert got.xy.shape == want.xy.shape and np.array_equal(got.xy, want.xy)
        assert np.array_equal(got.kind, want.kind)
        assert got.legs.shape == want.legs.shape and np.array_equal(got.legs, want.legs)
    # The module's form of the filter: a test on a list of (x, y) tuples.
    want = reference_detect(ranges, BEARINGS, spec, lambda xy: xy[:, 1] < -1.0)
    got = LegDetector(BEARINGS, spec)(ranges, reject_points=lambda pts: [y < -1.0 for _, y in pts])
    assert np.array_equal(got.xy, want.xy) and np.array_equal(got.kind, want.kind) and np.array_equal(got.legs, want.legs)


@pytest.mark.parametrize("side", [1.0, -1.0])
@pytest.mark.parametrize("compiled", [True, False])
def test_a_person_half_hidden_behind_another_is_a_pair_not_a_lone_leg(side, compiled):
    """Bea stands 1.2 m behind Al, her near leg's edge behind his leg: what shows of it is still a whole
    leg's width standing out of the wall behind. Both her legs make a pair, so a track can start on her
    (a lone leg never starts one: tour-3000-03's Paul stood so, untracked, for 61 s). Either side, either path."""
    al = [(2.0, side * 0.1, 0.06), (2.0, side * -0.1, 0.06)]
    bea = [(3.2, side * 0.29, 0.06), (3.2, side * 0.49, 0.06)]
    det = LegDetector(BEARINGS, compiled=compiled)(_scan(al + bea, wall=5.0))
    pairs = [p for p, k in zip(det.points, det.kinds) if k == PAIR]
    assert any(math.hypot(x - 3.2 - 0.05, y - side * 0.39) < 0.1 for x, y in pairs), (det.points, det.kinds)
    assert any(math.hypot(x - 2.0 - 0.05, y) < 0.1 for x, y in pairs)
    assert SINGLE not in det.kinds


@settings(max_examples=150, deadline=None)
@given(d=st.floats(1.0, 2.5), gap=st.floats(0.6, 1.5), shown=st.floats(0.0, 1.0), side=st.sampled_from([1.0, -1.0]),
       compiled=st.booleans())
def test_a_leg_half_hidden_behind_someone_nearer_counts_iff_a_leg_width_of_it_shows(d, gap, shown, side, compiled):
    """Al stands ``d`` m away; Bea ``gap`` m behind him, her near leg behind his outer leg's edge with a
    fraction ``shown`` of its angular width in view. Al is always a pair. Bea is a pair (not a lone
    leg) whenever what shows of her near leg is 2+ points a leg's width (``min_width``, with a beam's
    spacing to spare) wide, standing out of the wall on its other side; when nothing of it shows she
    is one lone leg. Either path (compiled kernel, Python)."""
    r, spec = 0.06, LegSpec()
    al = [(d, 0.1, r), (d, -0.1, r)]
    depth = d + gap
    edge = math.atan2(0.1 + r, d)  # Al's outer leg's edge, as the laser sees it
    half = math.asin(r / depth)
    a = edge + (2 * shown - 1) * half  # bearing of Bea's near leg's centre
    near = (depth * math.cos(a), depth * math.sin(a))
    far = (near[0], near[1] + 0.2)  # her other leg, further out
    mirror = [(x, side * y, q) for x, y, q in al + [(near[0], near[1], r), (far[0], far[1], r)]]
    ranges = _scan(mirror, wall=6.0)
    alone = _scan([mirror[2]], wall=6.0)  # her near leg alone: which beams end on it
    on_leg = np.flatnonzero(np.isclose(ranges, alone) & (alone < _scan([], wall=6.0) - 1e-6))
    pts = np.column_stack((ranges[on_leg] * np.cos(BEARINGS[on_leg]), ranges[on_leg] * np.sin(BEARINGS[on_leg])))
    width = float(np.hypot(*(pts[-1] - pts[0]))) if len(pts) >= 2 else 0.0
    det = LegDetector(BEARINGS, spec, compiled=compiled)(ranges)
    pairs = [p for p, k in zip(det.points, det.kinds) if k == PAIR]
    bea = (depth * math.cos(a) + 0.05, side * (near[1] + 0.1))
    assert any(math.hypot(x - d - 0.05, y) < 0.1 for x, y in pairs), (det.points, det.kinds)  # Al
    bea_pair = any(math.hypot(x - bea[0], y - bea[1]) < 0.15 for x, y in pairs)
    spacing = depth * math.radians(0.5)
    if len(pts) >= 2 and width >= spec.min_width + spacing:
        assert bea_pair, (width, len(pts), det.points, det.kinds)
    if len(pts) == 0:
        assert not bea_pair and SINGLE in det.kinds, (det.points, det.kinds)


def test_the_leg_detector_refuses_a_scan_of_the_wrong_size():
    with pytest.raises(ValueError, match=r"scan of shape \(360,\), expected \(361,\)"):
        detect(np.ones(360), BEARINGS)
    with pytest.raises(ValueError, match="at least two beam bearings"):
        detect(np.ones(1), BEARINGS[:1])


# ------------------------------------------------------------------ cues
def test_a_sound_direction_speaks_for_the_track_in_front_or_behind_and_only_one():
    tracks = np.radians([20.0, 160.0, -60.0])
    assert match_sounds(tracks, np.radians([21.0]), math.radians(9)) == [0]  # nearest of the two mirror images
    assert match_sounds(tracks, np.radians([-62.0]), math.radians(9)) == [2]
    assert match_sounds(tracks, np.radians([45.0]), math.radians(9)) == []


def test_hysteresis_needs_two_frames_on_and_a_pause_to_go_off():
    h = Hysteresis(on_frames=2, off_after=0.7)
    ids = np.array([7])
    h.feed(0.0, ids, {7})
    assert not h.on(7)
    h.feed(0.1, ids, {7})
    assert h.on(7)
    h.feed(0.5, ids, set())  # a pause between words
    assert h.on(7)
    h.feed(0.9, ids, set())
    assert not h.on(7)
