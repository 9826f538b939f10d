"""The simulated home's fast paths give the answers of the plain ways (issue 9: speed without changing behaviour).

Each fast path (the sound field's bounded window, the planner's cached and batched A*
and smoothing, the room look-up grid, the physics step's no-contact test) is checked
against the straightforward computation it replaces, kept here as the reference.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.world.acoustics import SoundField, Utterance, first_words, speech_duration, words_spoken
from homesim.geometry import point_in_polygon
from homesim import ndgrid
from homesim.scenario.pathplan import Grid, NoPathError, scenario_bounds
from homesim.world.world import World
from tests.conftest import examples
from tests.world_helpers import EXAMPLE, room, scenario


# ----------------------------------------------------------------- sound field
class LogField:
    """The reference: every utterance in one list, every question a scan of all of it."""

    def __init__(self) -> None:
        self.log: list[Utterance] = []

    def say(self, source: str, text: str, t: float, duration: float | None = None) -> None:
        dur = speech_duration(text) if duration is None else duration
        for i in range(len(self.log) - 1, -1, -1):
            u = self.log[i]
            if u.source == source and u.end > t:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                self.log[i] = Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True)
                break
        self.log.append(Utterance(len(self.log), source, text, t, t + dur, 60.0))

    def cut(self, source: str, t: float) -> None:
        for i in range(len(self.log) - 1, -1, -1):
            u = self.log[i]
            if u.source == source and u.start <= t < u.end:
                said = first_words(u.text, words_spoken(u.text, u.end - u.start, t - u.start))
                self.log[i] = Utterance(u.n, u.source, said, u.start, max(u.start, t), u.loudness, cut=True)
                return

    def active(self, t: float) -> list[Utterance]:
        return [u for u in self.log if u.start <= t < u.end]

    def ended(self, t0: float, t1: float) -> list[Utterance]:
        return sorted((u for u in self.log if t0 < u.end <= t1), key=lambda u: (u.end, u.n))


events = st.lists(
    st.tuples(st.sampled_from(["ann", "bob", "robot", "radio"]), st.sampled_from(["say", "cut", "wait"]),
              st.floats(0.0, 4.0), st.integers(1, 8), st.one_of(st.none(), st.floats(0.2, 25.0))),
    min_size=1, max_size=60,
)


@settings(max_examples=examples(60, 200), deadline=None)
@given(events=events)
def test_the_bounded_sound_field_answers_as_the_whole_log(events):
    """What listeners ask (now, what ended since their last look 0.1 s back, the recent past)
    is answered exactly as from the whole log, while the window stays small."""
    ref, field = LogField(), SoundField(horizon=5.0, history=False)
    t = last = said_at = longest = 0.0
    for source, what, gap, words, duration in events:
        t += gap
        text = " ".join(f"w{k}" for k in range(words))
        if what == "say":
            ref.say(source, text, t, duration)
            field.say(source, text, t, duration=duration)
            said_at, longest = t, max(longest, speech_duration(text) if duration is None else duration)
        elif what == "cut":
            ref.cut(source, t)
            field.cut(source, t)
        assert field.active(t) == ref.active(t)
        assert field.ended(last, t) == ref.ended(last, t)
        assert field.speaking(source, t) == next((u for u in reversed(ref.active(t)) if u.source == source), None)
        assert field.by(source, since=t - 5.0) == [u for u in ref.log if u.source == source and u.start >= t - 5.0]
        assert len(field) == len(ref.log)
        # The window: nothing that ended longer ago than the horizon (or the longest utterance) before the last say.
        assert all(u.end >= said_at - max(5.0, longest) for u in field._live)
        last = t


@settings(max_examples=examples(40, 150), deadline=None)
@given(events=events, spool=st.sampled_from([1, 64, 100_000]))
def test_the_transcript_on_disk_is_the_whole_log(events, spool):
    """The transcript (what left the window goes to a temporary file once it outgrows
    ``spool`` characters) reads back as the whole log: every utterance, cuts included, in
    order, with the same floats; questions further back than the window answer from it."""
    import homesim.world.acoustics as acoustics

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(acoustics, "SPOOL_CHARS", spool)
        ref, field = LogField(), SoundField(horizon=2.0)
    t = 0.0
    for source, what, gap, words, duration in events:
        t += gap
        text = " ".join(f"w{k}" for k in range(words))
        if what == "say":
            ref.say(source, text, t, duration)
            field.say(source, text, t, duration=duration)
        elif what == "cut":
            ref.cut(source, t)
            field.cut(source, t)
    if spool == 1 and len(field._live) < len(ref.log):
        assert field._history._file._rolled  # on disk
    assert field.all() == ref.log
    assert field.ended(0.0, t + 100.0) == ref.ended(0.0, t + 100.0)
    assert field.since(0) == ref.log and field.since(len(ref.log) // 2) == ref.log[len(ref.log) // 2:]
    assert field.by("ann") == [u for u in ref.log if u.source == "ann"]


def test_a_sound_field_without_history_refuses_questions_about_the_forgotten_past():
    field = SoundField(horizon=2.0, history=False)
    field.say("ann", "hello", 0.0)
    field.say("ann", "hello again", 10.0)
    assert [u.text for u in field.active(10.5)] == ["hello again"]
    with pytest.raises(ValueError, match="window"):
        field.ended(0.0, 10.0)
    with pytest.raises(ValueError, match="history"):
        field.all()
    assert field.said_by() == {"ann": 2}


def test_a_sound_field_with_history_keeps_the_transcript_with_cuts():
    field = SoundField(horizon=2.0)
    field.say("robot", "one two three four five", 0.0)
    field.cut("robot", 1.0)
    field.say("ann", "hello", 30.0)
    first, second = field.all()
    assert first.cut and first.text == "one two" and second.text == "hello"
    assert field.ended(0.0, 30.5) == [first]  # further back than the window: from the transcript
    assert field.since(0) == [first, second] and field.since(1) == [second]


# ----------------------------------------------------------------- path planning
def reference_plan(grid: Grid, start, goal, avoid=()):
    """The textbook A* (dict costs, a closed set, per-node neighbour lists) and one-by-one smoothing."""
    avoid = list(avoid)
    blocked = grid.with_discs(avoid) if avoid else grid.blocked
    s = grid.nearest_free(grid.cell_of(start), blocked=blocked)
    g = grid.nearest_free(grid.cell_of(goal), blocked=blocked)
    if s is None or g is None:
        raise NoPathError("no free space")
    end = goal if grid.free(grid.cell_of(goal), blocked) else grid.centre(g)
    if grid.free(grid.cell_of(start), blocked) and grid.line_free(start, end, blocked):
        return [end]
    ny = grid.ny
    free = (~blocked).ravel().tolist()
    s0, g0 = s[0] * ny + s[1], g[0] * ny + g[1]
    sq2 = math.sqrt(2.0)
    straight = ((ny, 1.0), (-ny, 1.0), (1, 1.0), (-1, 1.0))
    diagonal = ((ny + 1, ny, 1), (ny - 1, ny, -1), (-ny + 1, -ny, 1), (-ny - 1, -ny, -1))
    cost, came, counter, frontier, closed = {s0: 0.0}, {}, 0, [(0.0, 0, s0)], set()
    while frontier:
        _, _, c = heapq.heappop(frontier)
        if c == g0:
            path = [c]
            while path[-1] != s0:
                path.append(came[path[-1]])
            cells = [divmod(q, ny) for q in reversed(path)]
            break
        if c in closed:
            continue
        closed.add(c)
        steps = [(c + d, w) for d, w in straight if free[c + d]]
        steps += [(c + d, sq2) for d, o1, o2 in diagonal if free[c + d] and free[c + o1] and free[c + o2]]
        for n, w in steps:
            nc = cost[c] + w
            if nc < cost.get(n, math.inf):
                cost[n], came[n] = nc, c
                ni, nj = divmod(n, ny)
                dx, dy = abs(ni - g[0]), abs(nj - g[1])
                counter += 1
                heapq.heappush(frontier, (nc + (dx + dy + ((sq2 - 1.0) - 1.0) * min(dx, dy)), counter, n))
    else:
        raise NoPathError("no path")
    pts = [grid.centre(c) for c in cells[1:-1]] + [end]
    out, here, i = [], start, 0
    while i < len(pts):
        j = len(pts) - 1
        while j > i and not grid.line_free(here, pts[j], blocked):
            j -= 1
        out.append(pts[j])
        here, i = pts[j], j + 1
    return out


HOME = scenario(EXAMPLE)
HOME_GRID = Grid.for_scenario(HOME)
X0, Y0, X1, Y1 = scenario_bounds(HOME)
xs, ys = st.floats(X0, X1), st.floats(Y0, Y1)


@settings(max_examples=examples(8, 30), deadline=None)
@given(sx=xs, sy=ys, gx=xs, gy=ys, robot=st.one_of(st.none(), st.tuples(xs, ys)))
def test_plans_are_the_textbook_plans(sx, sy, gx, gy, robot):
    avoid = [] if robot is None else [(robot[0], robot[1], 0.35)]
    try:
        want = reference_plan(HOME_GRID, (sx, sy), (gx, gy), avoid)
    except NoPathError:
        with pytest.raises(NoPathError):
            HOME_GRID.plan((sx, sy), (gx, gy), avoid=avoid)
        return
    assert HOME_GRID.plan((sx, sy), (gx, gy), avoid=avoid) == want
    again = HOME_GRID.plan((sx, sy), (gx, gy), avoid=avoid)  # from the cache: the same, and a list of its own
    assert again == want
    again.pop()
    assert HOME_GRID.plan((sx, sy), (gx, gy), avoid=avoid) == want


@pytest.mark.skipif(ndgrid._kernel() is None, reason="homesim._gridkernels not built")
@settings(max_examples=examples(60, 300), deadline=None)
@given(shape=st.tuples(st.integers(3, 30), st.integers(3, 30)), density=st.floats(0.0, 0.6), seed=st.integers(0, 2**32 - 1),
       ends=st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)))
def test_the_compiled_search_is_the_python_search(shape, density, seed, ends):
    """The grid kernel's A* returns the Python loop's path cell for cell (or both find none) on random
    grids with blocked borders: open ones (many equal-cost ties), mazes, walled-off goals."""
    nx, ny = shape
    blocked = np.random.default_rng(seed).random(shape) < density
    blocked[0, :] = blocked[-1, :] = blocked[:, 0] = blocked[:, -1] = True
    s = (1 + int(ends[0] * (nx - 3)), 1 + int(ends[1] * (ny - 3)))
    g = (1 + int(ends[2] * (nx - 3)), 1 + int(ends[3] * (ny - 3)))
    blocked[s] = blocked[g] = False
    grid = object.__new__(Grid)
    grid.nx, grid.ny, grid.blocked, grid._free, grid._free_u8 = nx, ny, blocked, None, None
    grid.x0 = grid.y0 = 0.0
    grid.cell = 0.05
    try:
        want = grid._astar_python(blocked, s, g)
    except NoPathError:
        with pytest.raises(NoPathError):
            grid._astar(blocked, s, g)
        return
    assert grid._astar(blocked, s, g) == want
    assert grid._astar(blocked.copy(), s, g) == want  # a grid with discs: its own bytes


@settings(max_examples=examples(30, 100), deadline=None)
@given(ax=xs, ay=ys, ends=st.lists(st.tuples(xs, ys), min_size=1, max_size=30))
def test_lines_checked_together_are_lines_checked_one_by_one(ax, ay, ends):
    together = HOME_GRID.lines_free((ax, ay), ends).tolist()
    assert together == [HOME_GRID.line_free((ax, ay), e) for e in ends]


def flood_fill_regions(blocked: np.ndarray) -> np.ndarray:
    """The reference: 4-connected regions of the free cells, numbered in row-major order of their first cell."""
    nx, ny = blocked.shape
    labels = np.zeros((nx, ny), dtype=np.int32)
    n = 0
    for i in range(nx):
        for j in range(ny):
            if blocked[i, j] or labels[i, j]:
                continue
            n += 1
            labels[i, j] = n
            todo = [(i, j)]
            while todo:
                a, b = todo.pop()
                for c, d in ((a + 1, b), (a - 1, b), (a, b + 1), (a, b - 1)):
                    if 0 <= c < nx and 0 <= d < ny and not blocked[c, d] and not labels[c, d]:
                        labels[c, d] = n
                        todo.append((c, d))
    return labels


@settings(max_examples=examples(40, 150), deadline=None)
@given(cells=st.lists(st.booleans(), min_size=12 * 9, max_size=12 * 9), density=st.integers(0, 3))
def test_free_regions_are_numbered_as_a_flood_fill_numbers_them(cells, density):
    blocked = np.array(cells, dtype=bool).reshape(12, 9)
    if density:  # sparser walls too: big regions winding around each other
        blocked &= np.array(cells[density:] + cells[:density], dtype=bool).reshape(12, 9)
    blocked[0, :] = blocked[-1, :] = blocked[:, 0] = blocked[:, -1] = True
    grid = Grid.for_scenario(HOME)
    grid.blocked = blocked
    got = grid._label()
    assert got.dtype == np.int32 and got.tolist() == flood_fill_regions(blocked).tolist()


def test_the_flats_regions_are_numbered_as_a_flood_fill_numbers_them():
    assert HOME_GRID._label().tolist() == flood_fill_regions(HOME_GRID.blocked).tolist()


# ----------------------------------------------------------------- rooms
WORLD = World(HOME)


@settings(max_examples=examples(150, 600), deadline=None)
@given(x=st.floats(X0 - 1, X1 + 1), y=st.floats(Y0 - 1, Y1 + 1), snap=st.booleans())
def test_the_room_grid_answers_as_the_room_polygons(x, y, snap):
    if snap:  # on the polygons' own corners and edges too
        corners = [p for r in HOME.rooms for p in r.polygon]
        x, y = corners[int(abs(x) * 1000) % len(corners)]
        x, y = float(x), float(y) + (0.0 if int(abs(y) * 100) % 2 else 1e-12)
    want = next((r.name for r in HOME.rooms if point_in_polygon((x, y), r.polygon)), None)
    assert WORLD.room_of(x, y) == want


# ----------------------------------------------------------------- contacts
@settings(max_examples=examples(60, 200), deadline=None)
@given(x=st.floats(0.0, 9.0), y=st.floats(0.0, 7.0), heading=st.floats(-math.pi, math.pi),
       px=st.floats(0.0, 9.0), py=st.floats(0.0, 7.0))
def test_no_contact_is_said_only_where_the_robot_overlaps_nothing(x, y, heading, px, py):
    world = room()
    world.place_robot(x, y, heading)
    world.humans["ann"].teleport(px, py)
    if world._no_contact():
        assert world._overlaps() == (None, None)


def test_the_robot_still_meets_walls_and_people():
    world = room()
    world.place_robot(6.0, 3.0, 0.0)
    world.humans["ann"].teleport(2.0, 3.0)
    assert world._no_contact()
    world.place_robot(7.8, 3.0, 0.0)  # into the east wall
    assert not world._no_contact() and world._overlaps()[0] is not None
    world.place_robot(2.3, 3.0, 0.0)  # onto ann
    assert not world._no_contact() and world._overlaps()[1] is not None
    assert np.isfinite(world.robot.pose).all()


def test_a_robot_in_the_only_doorway_is_no_path_at_once_and_the_same_refusal():
    """The planner asks the free regions before searching: a disc closing the only door is
    refused as A* would refuse it (same error), and a path around it as A* finds it."""
    from homesim.scenario.pathplan import door_frame, door_sides

    wall, door = next((w, d) for w in HOME.walls for d in w.doors if not d.exit)
    (cx, cy), _ = door_frame(wall, door)
    inside, outside = door_sides(wall, door)
    grid = Grid.for_scenario(HOME)
    closed = [(cx, cy, door.width)]
    try:
        reference_plan(grid, inside, outside, closed)
        refused = False
    except NoPathError:
        refused = True
    if refused:
        with pytest.raises(NoPathError, match="no path from"):
            grid.plan(inside, outside, avoid=closed)
        with pytest.raises(NoPathError, match="no path from"):  # the refusal is kept too
            grid.plan(inside, outside, avoid=closed)
    else:
        assert grid.plan(inside, outside, avoid=closed) == reference_plan(grid, inside, outside, closed)
    open_ = [(cx + 3.0, cy + 3.0, 0.35)]
    assert grid.plan(inside, outside, avoid=open_) == reference_plan(grid, inside, outside, open_)


@settings(max_examples=examples(40, 150), deadline=None)
@given(x=xs, y=ys, th=st.floats(-math.pi, math.pi), pts=st.lists(st.tuples(xs, ys), max_size=12))
def test_visibility_tested_on_the_points_in_view_only_is_the_same(x, y, th, pts):
    from homesim.tour.metrics.tracking import visible_region, wall_edges
    from homesim.geometry import segments_intersect, wrap_angle

    walls = wall_edges(WORLD)
    xy = np.array(pts, dtype=float).reshape(-1, 2)
    ox, oy = x + 0.13 * math.cos(th), y + 0.13 * math.sin(th)
    dx, dy = xy[:, 0] - ox, xy[:, 1] - oy
    want = (np.abs(np.asarray(wrap_angle(np.arctan2(dy, dx) - th))) <= math.pi / 2) & (np.hypot(dx, dy) <= 6.5)
    if xy.shape[0]:
        want &= ~segments_intersect(np.broadcast_to(np.array([ox, oy]), xy.shape), xy, *walls).any(axis=1)
    assert visible_region(walls, (x, y, th), xy).tolist() == want.tolist()


# ----------------------------------------------------------------- pymunk's private binding
def _chipmunk_module(monkeypatch, binding):
    """homesim/world/chipmunk.py loaded afresh with ``pymunk._chipmunk_cffi`` replaced by ``binding``
    (None: absent, as in a pymunk that stopped shipping it)."""
    import importlib.util
    import sys

    from homesim.world import chipmunk

    monkeypatch.setitem(sys.modules, "pymunk._chipmunk_cffi", binding)
    spec = importlib.util.spec_from_file_location("chipmunk_fallback", chipmunk.__file__)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    monkeypatch.delitem(sys.modules, "pymunk._chipmunk_cffi")
    return mod


def _walk(world: World, steps: int) -> list[tuple[float, ...]]:
    """The robot driving and turning into ann's way while she walks towards it: poses each step."""
    world.place_robot(4.0, 3.0, 0.3)
    world.humans["ann"].teleport(6.5, 3.2)
    world.humans["ann"].walk_velocity(-0.8, -0.05)
    out = []
    for _ in range(steps):
        world.robot.command(0.4, 0.3)
        world.step()
        out.append((*world.robot.pose, *world.humans["ann"].position, *world.humans["ann"].leg_centres().ravel()))
    return out


@pytest.mark.parametrize("binding", ["absent", "incomplete"])
def test_without_pymunks_private_binding_the_world_steps_the_same(monkeypatch, binding):
    """The step's direct Chipmunk calls have the public pymunk API as fallback: if pymunk drops
    or changes its private cffi module, the world loads and moves exactly as before."""
    import types

    import homesim.world.bodies as bodies
    import homesim.world.world as world_mod
    from homesim.world import chipmunk

    fake = None if binding == "absent" else types.SimpleNamespace(lib=types.SimpleNamespace(cpBodyGetPosition=None))
    fallback = _chipmunk_module(monkeypatch, fake)
    assert chipmunk.DIRECT and not fallback.DIRECT
    want = _walk(room(), 150)
    monkeypatch.setattr(bodies, "cp", fallback)
    monkeypatch.setattr(world_mod, "cp", fallback)
    assert _walk(room(), 150) == want


@pytest.mark.parametrize("x, y", [(math.nan, 3.0), (3.0, math.nan), (math.inf, 3.0), (3.0, -math.inf), (1.7e308, 3.0)])
def test_the_room_grid_answers_points_off_the_grid_as_the_polygons(x, y):
    """A point no grid cell holds (not finite, or too far to number its cell) is in no room,
    as the polygons answer, not a ValueError or OverflowError from the look-up."""
    want = next((r.name for r in HOME.rooms if point_in_polygon((x, y), r.polygon)), None)
    assert WORLD.room_of(x, y) == want is None


# ----------------------------------------------------------------- kept poses
_ops = st.lists(st.one_of(
    st.tuples(st.just("place"), st.floats(0.5, 7.5), st.floats(0.5, 5.5), st.floats(-4.0, 4.0)),
    st.tuples(st.just("teleport"), st.floats(0.5, 7.5), st.floats(0.5, 5.5), st.just(0.0)),
    st.tuples(st.just("command"), st.floats(-1.0, 1.0), st.floats(-3.0, 3.0), st.just(0.0)),
    st.tuples(st.just("walk"), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.just(0.0)),
    st.tuples(st.just("step"), st.integers(1, 12), st.sampled_from([0.0, 0.2, 0.37]), st.just(0.0)),
    st.tuples(st.just("leave"), st.just(0.0), st.just(0.0), st.just(0.0)),
    st.tuples(st.just("squeeze"), st.floats(0.2, 0.5), st.just(0.0), st.just(0.0)),
), min_size=1, max_size=25)


@settings(max_examples=examples(25, 100), deadline=None)
@given(ops=_ops)
def test_kept_poses_are_chipmunks_after_any_move(ops):
    """RobotBody.pose and HumanBody.position are read from Chipmunk once per move and kept:
    after any mix of placements, teleports, commands, walks, steps (one or several sub-steps,
    pushes at walls and people) and a person leaving, what they answer is the bodies' state now."""
    from homesim.geometry import wrap_angle

    world = room()
    ann = world.humans["ann"]
    for op, a, b, c in ops:
        if op == "place":
            world.place_robot(a, b, c)
        elif op == "teleport":
            ann.teleport(a, b)
        elif op == "command":
            world.robot.command(a, b)
        elif op == "walk":
            ann.walk_velocity(a, b)
        elif op == "leave":
            ann.remove()
        elif op == "squeeze":  # ann onto the robot at the east wall: the step moves her, not it
            world.place_robot(7.55, 3.0, 0.0)
            ann.teleport(7.55 - a, 3.0)
            world.step()
        else:
            for _ in range(int(a)):
                world.step(b or None)
        rb = world.robot
        p = rb.body.position
        assert rb.pose == (p.x, p.y, float(wrap_angle(rb.body.angle)))
        assert ann.position == tuple(ann.body.position)
        if op == "step" and ann.present:  # legs placed after the step: on the shapes as the world reports them
            assert [tuple(leg.offset) for leg in ann.legs] == list(ann.leg_offsets)
            assert ann.body.angle == ann.heading
