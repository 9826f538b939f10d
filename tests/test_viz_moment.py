"""``homesim plot TRACE --at T``: the flat with the robot's percepts, every mark explained, labels apart."""

from __future__ import annotations

import json

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from homesim.cli import main
from homesim.viz.moment import covariance_ellipse, place_labels, view_polygon
from homesim.viz.percepts import odom_to_world
from homesim.world.bodies import CAMERA_HEIGHT

from .conftest import examples
from .viz_helpers import tour_trace
from .world_helpers import room

def _cross(p, q, a, b) -> bool:
    """Do segments pq and ab properly cross (not merely touch)?"""
    def orient(u, v, w):
        return (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0])
    d1, d2, d3, d4 = orient(a, b, p), orient(a, b, q), orient(p, q, a), orient(p, q, b)
    return d1 * d2 < -1e-9 and d3 * d4 < -1e-9


WORLD = room()


@settings(max_examples=examples(30, 60))
@given(x=st.floats(0.5, 7.5), y=st.floats(0.5, 5.5), centre=st.floats(-math.pi, math.pi))
def test_the_field_of_view_stops_at_the_first_wall(x, y, centre):
    poly = view_polygon(WORLD, (x, y), centre, view=4.0)
    origin, ends = poly[0], poly[1:]
    a, b = WORLD.segments_at(CAMERA_HEIGHT)
    assert np.all(np.linalg.norm(ends - origin, axis=1) <= 4.0 + 1e-9)
    for e in ends:
        shortened = origin + (e - origin) * 0.999  # the ray up to just before its end point
        assert not any(_cross(origin, shortened, a[i], b[i]) for i in range(len(a)))


def test_a_wall_cuts_the_view_short():
    # the sensor room has a wall along y = 0: looking straight down from y = 1 the view ends there
    poly = view_polygon(WORLD, (4.0, 1.0), -math.pi / 2, view=4.0, rays=5)
    assert np.max(np.linalg.norm(poly[1:] - poly[0], axis=1)) < 1.2


@given(sx=st.floats(0.01, 1.0), sy=st.floats(0.01, 1.0), rho=st.floats(-0.95, 0.95))
def test_the_covariance_ellipse_is_the_two_sigma_contour(sx, sy, rho):
    cov = np.array([[sx * sx, rho * sx * sy], [rho * sx * sy, sy * sy]])
    e = covariance_ellipse(1.0, 2.0, cov)
    a = np.radians(e.angle)
    u = np.linspace(0, 2 * np.pi, 32)
    local = np.stack([e.width / 2 * np.cos(u), e.height / 2 * np.sin(u)], axis=1)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    pts = local @ rot.T + np.array(e.center)
    d = pts - np.array([1.0, 2.0])
    maha = np.einsum("ij,jk,ik->i", d, np.linalg.inv(cov), d)
    assert np.allclose(maha, 4.0, rtol=1e-3, atol=1e-3)


@given(true=st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi)),
       odom=st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi)),
       ahead=st.floats(0.1, 4.0))
def test_a_track_in_odom_lands_where_the_robot_truly_saw_it(true, odom, ahead):
    # a track `ahead` metres in front of the robot's odometry pose is that far in front of its true pose
    ox, oy, oth = odom
    T = odom_to_world(true, odom)
    got = T @ np.array([ox + ahead * math.cos(oth), oy + ahead * math.sin(oth), 1.0])
    tx, ty, tth = true
    assert np.allclose(got[:2], [tx + ahead * math.cos(tth), ty + ahead * math.sin(tth)], atol=1e-9)


@settings(max_examples=examples(15, 30))
@given(st.lists(st.tuples(st.floats(4.0, 5.0), st.floats(2.5, 3.5), st.text("abcdefgh ", min_size=1, max_size=12)), min_size=2, max_size=8))
def test_labels_placed_near_each_other_do_not_cover_each_other(anchors):
    fig = Figure(figsize=(8, 6))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 6)
    labels = [ax.text(x, y, s, fontsize=7, ha="center") for x, y, s in anchors]
    place_labels(ax, labels)
    r = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(r) for t in labels]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            assert not boxes[i].overlaps(boxes[j]), (anchors[i], anchors[j])


@pytest.fixture(scope="module")
def short_trace(tmp_path_factory):
    return tour_trace(tmp_path_factory.getbasetemp())


def test_plot_at_a_moment_shows_percepts_with_a_legend_for_every_mark(short_trace, tmp_path, capsys):
    out = tmp_path / "m.svg"
    assert main(["plot", str(short_trace), "--at", "11.5", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "at t = 11.50 s" in said and "attention: Interaction" in said
    svg = out.read_text(encoding="utf-8")
    for entry in ("laser hits", "camera field of view", "gaze", "track (+ mean", "selected person / partner",
                  "face seen by the camera", "legs detected", "robot's pose estimate", "t1 selected partner"):
        assert entry in svg, entry


def test_the_track_is_drawn_on_the_person_it_follows(short_trace):
    from homesim.tour.plot_cli import plot_moment_of_trace  # the figure, to read its marks back

    fig = plot_moment_of_trace(short_trace, 11.5)
    ax = fig.axes[0]
    tags = [t for t in ax.texts if t.get_text().startswith("t1")]
    people = [t for t in ax.texts if t.get_text().startswith("anna")]
    assert tags and people
    from matplotlib.patches import Ellipse
    ellipses = [p for p in ax.patches if isinstance(p, Ellipse)]
    assert ellipses
    # anna's body circle: the track's mean must be within half a metre of her
    from matplotlib.patches import Circle
    bodies = [c for c in ax.patches if isinstance(c, Circle) and abs(c.radius - 0.25) < 0.1]
    assert any(np.hypot(*(np.array(e.center) - np.array(b.center))) < 0.5 for e in ellipses for b in bodies)


def test_plot_refuses_a_moment_after_the_recorded_run(short_trace, tmp_path, capsys):
    assert main(["plot", str(short_trace), "--at", "30", "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "after the end of the recorded run" in err and err.startswith(f"homesim: error: {short_trace}: t = 30 s")


def test_plot_refuses_a_trace_that_the_run_does_not_reproduce(short_trace, tmp_path, capsys):
    lines = short_trace.read_text(encoding="utf-8").split("\n")
    lines[5] = lines[5].replace('"seq":5', '"seq":55')
    bad = tmp_path / "bad.jsonl"
    bad.write_text("\n".join(lines), encoding="utf-8")
    assert main(["plot", str(bad), "--at", "1", "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:6: the re-run departs from the trace" in err
    assert not (tmp_path / "x.png").exists()


def test_a_departing_or_truncated_trace_is_one_plain_line_with_the_first_differing_line(short_trace, tmp_path, capsys):
    """Not the loop's wrapper ('simulation failed at ...: HomesimError(...)'), and the first departure, not a later one."""
    text = short_trace.read_text(encoding="utf-8")
    header, rest = text.split("\n", 1)
    head = json.loads(header)
    head["run"]["seed"] += 1  # another run from the first message on
    cases = {"seed.jsonl": (json.dumps(head) + "\n" + rest, ":3: the re-run departs from the trace"),
             "cut.jsonl": (text[: len(text) // 3], "(truncated?)")}
    for name, (body, says) in cases.items():
        bad = tmp_path / name
        bad.write_text(body, encoding="utf-8")
        assert main(["plot", str(bad), "--at", "11", "--out", str(tmp_path / "x.png")]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"homesim: error: {bad}:") and says in err and "HomesimError(" not in err, err
        assert len(err.strip().splitlines()) == 1


def test_plot_wants_a_picture_format(short_trace, tmp_path, capsys):
    assert main(["plot", str(short_trace), "--out", str(tmp_path / "x.pdf")]) == 2
    assert ".png or .svg" in capsys.readouterr().err


@settings(max_examples=examples(30, 60))
@given(x=st.floats(0.5, 7.5), y=st.floats(0.5, 5.5), heading=st.floats(-math.pi, math.pi),
       bearings=st.lists(st.floats(-math.pi / 2, math.pi / 2), min_size=1, max_size=3))
def test_sound_directions_and_their_mirrors_stay_inside_the_flat(x, y, heading, bearings):
    """Neither a heard direction nor its front/back mirror is drawn through a wall or past the flat's edge."""
    from homesim.viz.moment import Legend, draw_sound_directions, wall_segments

    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    draw_sound_directions(ax, (x, y), heading, bearings, Legend(), length=20.0, world=WORLD)
    x0, y0, x1, y1 = WORLD.bounds()
    a, b = wall_segments(WORLD)
    lines = ax.get_lines()
    assert len(lines) == 2 * len(bearings)
    for ln in lines:
        (px, qx), (py, qy) = ln.get_xdata(), ln.get_ydata()
        assert x0 - 1e-9 <= qx <= x1 + 1e-9 and y0 - 1e-9 <= qy <= y1 + 1e-9
        p, q = np.array([px, py]), np.array([qx, qy])
        shortened = p + (q - p) * 0.999
        assert not any(_cross(p, shortened, a[i], b[i]) for i in range(len(a)))


def test_the_gaze_is_drawn_over_the_sound_direction(short_trace):
    from homesim.tour.plot_cli import plot_moment_of_trace
    from homesim.viz.moment import GAZE, SOUND

    ax = plot_moment_of_trace(short_trace, 9.5).axes[0]  # anna asks "what can you do", facing the robot
    gaze = [ln for ln in ax.get_lines() if ln.get_color() == GAZE]
    sound = [ln for ln in ax.get_lines() if ln.get_color() == SOUND]
    assert gaze and sound and min(g.get_zorder() for g in gaze) > max(s.get_zorder() for s in sound)


def test_an_svg_moment_keeps_its_words_as_text(short_trace, tmp_path):
    out = tmp_path / "m.svg"
    assert main(["plot", str(short_trace), "--at", "11.5", "--out", str(out)]) == 0
    svg = out.read_text(encoding="utf-8")
    assert ">living room</text>" in svg and ">laser hits</text>" in svg  # searchable, editable words, not glyph outlines
