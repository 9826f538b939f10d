"""Top-down plots of the flat at one moment, with the robot's percepts over the truth.

Pure drawing functions (py_trees' ``display`` style): each takes a
matplotlib ``Axes`` and plain data or a world, draws, and returns the
legend entries for what it drew (a :class:`Legend` collects them, so every
mark on the figure is explained). :func:`plot_moment` composes them: walls,
furniture (raised pieces hatched: the laser passes under them), objects,
the robot with its camera's field of view clipped by the walls, the laser
scan, people with legs, heading, gaze, speech and pointing arms, sound
directions (front candidate solid, its front/back mirror dotted: two
microphones cannot tell them apart) and, when given :class:`Percepts`, what
the robot believed: its tracks (id, 2-sigma covariance ellipse), the legs
it detected, faces seen, the selected person and partner, its pose
estimate and attention state. Labels are placed last so that none covers
another (:func:`place_labels`, with adjustText).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Ellipse, Patch, Polygon
from matplotlib.text import Text

from ..world.bodies import CAMERA_HEIGHT, HUMAN_RADIUS, LASER_OFFSET, LEG_RADIUS, MIC_OFFSET, ROBOT_LENGTH, ROBOT_WIDTH
from ..geometry import polygon_centroid, polygon_edges, to_world
from ..world.world import World
from .percepts import Percepts

WALL = "#333333"
FURNITURE = "#c8b89a"
ROBOT = "#1f5fbf"
SCAN = "#d62728"
SOUND = "#9467bd"
GAZE = "#ff7f0e"
POINT = "#2ca02c"
TRACK = "#17becf"
FACE = "#e377c2"
HFOV = math.radians(48.8)
#: Legs the robot detected: laser end points within this distance of a track.
LEG_GATE = 0.35


class Legend:
    """Legend entries in drawing order, each label once."""

    def __init__(self) -> None:
        self.handles: dict[str, object] = {}

    def add(self, label: str, handle: object) -> None:
        self.handles.setdefault(label, handle)

    def draw(self, ax: Axes) -> None:
        if self.handles:
            ax.legend(list(self.handles.values()), list(self.handles.keys()), loc="upper left",
                      bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False, borderaxespad=0.0)


def line(color: str, style: str = "-", width: float = 1.2, marker: str | None = None) -> Line2D:
    return Line2D([], [], color=color, linestyle=style, linewidth=width, marker=marker)


def dot(color: str, marker: str = "o", size: float = 5, face: str | None = None) -> Line2D:
    return Line2D([], [], color=color, linestyle="none", marker=marker, markersize=size,
                  markerfacecolor=face if face is not None else color)


def draw_flat(ax: Axes, world: World, legend: Legend, labels: list[Text]) -> None:
    """Rooms (labelled), walls and furniture."""
    for room in world.scenario.rooms:
        poly = np.array(room.polygon)
        ax.add_patch(Polygon(poly, closed=True, facecolor="#f7f7f2", edgecolor="none", zorder=0))
        cx, cy = polygon_centroid(poly)
        labels.append(ax.text(cx, cy, room.name, ha="center", va="center", fontsize=9, color="#999999", zorder=1))
    for ob in world.obstacles:
        if ob.kind == "wall":
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor=WALL, edgecolor=WALL, zorder=3))
            legend.add("wall", Patch(facecolor=WALL))
        elif ob.kind == "furniture":
            raised = ob.bottom > 0
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor=FURNITURE, edgecolor="#8c7b5e", hatch="//" if raised else None, alpha=0.8, zorder=2))
            legend.add("furniture (hatched: raised, the laser passes under)" if raised else "furniture",
                       Patch(facecolor=FURNITURE, edgecolor="#8c7b5e", hatch="//" if raised else None))
            cx, cy = polygon_centroid(ob.polygon)
            labels.append(ax.text(cx, cy, ob.name, ha="center", va="center", fontsize=7, color="#5a4a30", zorder=4))
        else:
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor="#8c7b5e", edgecolor="none", zorder=3))
            legend.add("table leg / post", Patch(facecolor="#8c7b5e"))


def draw_objects(ax: Axes, world: World, legend: Legend, labels: list[Text], marks: list[object] | None = None) -> None:
    """Objects as coloured squares with their names (the squares go to ``marks``: labels keep off them)."""
    for name, o in world.objects.items():
        h = max(o.size, 0.08) / 2
        (marks if marks is not None else []).append(ax.add_patch(Polygon([(o.x - h, o.y - h), (o.x + h, o.y - h), (o.x + h, o.y + h), (o.x - h, o.y + h)], closed=True,
            facecolor=o.colour, edgecolor="black", linewidth=0.5, zorder=5)))
        labels.append(ax.text(o.x, o.y - h - 0.05, name, ha="center", va="top", fontsize=6, zorder=5))
        legend.add("object (true place)", dot("black", "s", 5, face="white"))


def ray_lengths(a: np.ndarray, b: np.ndarray, origin: Sequence[float], angles: np.ndarray, max_len: float) -> np.ndarray:
    """How far each ray from ``origin`` at ``angles`` goes before the first segment (a[i], b[i]), at most ``max_len``."""
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)  # (R, 2)
    o = np.asarray(origin[:2], dtype=float)
    t = np.full(len(angles), float(max_len))
    if len(a):
        e = b - a  # (S, 2)
        w = a - o  # (S, 2)
        den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]  # (R, S)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # parallel rays: refused below
            tr = (w[None, :, 0] * e[None, :, 1] - w[None, :, 1] * e[None, :, 0]) / den
            us = (w[None, :, 0] * d[:, None, 1] - w[None, :, 1] * d[:, None, 0]) / den
        ok = (np.abs(den) > 1e-12) & (tr > 1e-9) & (us >= 0) & (us <= 1)
        tr = np.where(ok, tr, np.inf)
        t = np.minimum(t, tr.min(axis=1))
    return t


def view_polygon(world: World, origin: Sequence[float], centre: float, *, hfov: float = HFOV, view: float = 4.0,
                 z: float = CAMERA_HEIGHT, rays: int = 64) -> np.ndarray:
    """The camera's field of view as a polygon, each ray cut at the first wall or obstacle at height ``z``."""
    ang = centre + np.linspace(-hfov / 2, hfov / 2, rays)
    a, b = world.segments_at(z)
    t = ray_lengths(a, b, origin, ang, view)
    o = np.asarray(origin[:2], dtype=float)
    return np.vstack([o, o + np.stack([np.cos(ang), np.sin(ang)], axis=1) * t[:, None]])


def wall_segments(world: World) -> tuple[np.ndarray, np.ndarray]:
    """The edges of the walls alone (sound goes over furniture, not through walls)."""
    walls = [polygon_edges(o.polygon) for o in world.obstacles if o.kind == "wall"]
    if not walls:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.concatenate([w[0] for w in walls]), np.concatenate([w[1] for w in walls])


def draw_robot(ax: Axes, world: World, legend: Legend, *, view: float = 4.0, marks: list[object] | None = None) -> None:
    """The PeopleBot's footprint, heading and the camera's field of view (clipped by walls); the footprint goes to ``marks``."""
    pose = world.robot.pose
    x, y, th = pose
    hl, hw = ROBOT_LENGTH / 2, ROBOT_WIDTH / 2
    foot = to_world(pose, np.array([[-hl, -hw], [hl, -hw], [hl, hw], [-hl, hw]]))
    body = ax.add_patch(Polygon(foot, closed=True, facecolor=ROBOT, edgecolor="black", alpha=0.85, zorder=6))
    if marks is not None:
        marks.append(body)
    legend.add("robot (true pose)", Patch(facecolor=ROBOT, edgecolor="black"))
    nose = to_world(pose, np.array([[hl + 0.1, 0.0]]))[0]
    ax.annotate("", xy=nose, xytext=(x, y), arrowprops={"arrowstyle": "->", "color": "white"}, zorder=7)
    fov = view_polygon(world, (x, y), th + world.ptu[0], view=view)
    ax.add_patch(Polygon(fov, closed=True, facecolor=ROBOT, alpha=0.08, edgecolor=ROBOT, linewidth=0.5, zorder=1))
    legend.add("camera field of view (cut at walls)", Patch(facecolor=ROBOT, alpha=0.15, edgecolor=ROBOT))


def draw_scan(ax: Axes, origin: Sequence[float], heading: float, bearings: np.ndarray, ranges: np.ndarray,
              legend: Legend, *, max_range: float = 8.19) -> np.ndarray:
    """Laser end points (hits only) and faint rays; returns the hit points (N, 2)."""
    hit = ranges < max_range - 1e-6
    ang = heading + bearings[hit]
    xs = origin[0] + ranges[hit] * np.cos(ang)
    ys = origin[1] + ranges[hit] * np.sin(ang)
    ax.scatter(xs, ys, s=2, color=SCAN, zorder=8)
    for xe, ye in zip(xs[::6], ys[::6]):
        ax.plot([origin[0], xe], [origin[1], ye], color=SCAN, alpha=0.06, linewidth=0.5, zorder=1)
    legend.add("laser hits", dot(SCAN, "o", 3))
    return np.stack([xs, ys], axis=1)


def draw_people(ax: Axes, world: World, legend: Legend, labels: list[Text], *, t: float | None = None) -> None:
    """People: body, legs, heading, gaze (dashed), pointing arm, what they say; other sound sources."""
    now = world.time if t is None else t
    for name, h in world.humans.items():
        if not h.present:
            continue
        x, y = h.position
        ax.add_patch(Circle((x, y), HUMAN_RADIUS, facecolor=h.torso, edgecolor="black", alpha=0.35, zorder=6))
        legend.add("person (true; torso colour)", Patch(facecolor="#bbbbbb", edgecolor="black", alpha=0.5))
        for lx, ly in h.leg_centres():
            ax.add_patch(Circle((lx, ly), LEG_RADIUS, facecolor="black", zorder=7))
        legend.add("true legs", dot("black", "o", 4))
        hx, hy = x + 0.4 * math.cos(h.heading), y + 0.4 * math.sin(h.heading)
        ax.annotate("", xy=(hx, hy), xytext=(x, y), arrowprops={"arrowstyle": "->", "color": "black"}, zorder=7)
        legend.add("heading", line("black", marker=">"))
        gx, gy = x + 0.9 * math.cos(h.gaze), y + 0.9 * math.sin(h.gaze)
        ax.plot([x, gx], [y, gy], linestyle="--", color=GAZE, linewidth=1.6, zorder=9)  # over the sound directions
        legend.add("gaze", line(GAZE, "--", 1.6))
        if h.hand_point() is not None and h.pointing is not None:
            tx, ty, _ = h.pointing.target
            ax.plot([x, tx], [y, ty], color=POINT, linewidth=1.5, zorder=7)
            legend.add("pointing arm", line(POINT, "-", 1.5))
        label = name
        u = world.sound.speaking(name, now)
        if u is not None:
            label += f': "{u.text}"'
            legend.add('"words": being said now', line("black", "none"))
        labels.append(ax.text(x, y + HUMAN_RADIUS + 0.08, label, ha="center", va="bottom", fontsize=7, zorder=9))
    for name, (sx, sy, _) in world.sources.items():
        u = world.sound.speaking(name, now)
        ax.plot([sx], [sy], marker="s", color=SOUND, zorder=7)
        legend.add("other sound source", dot(SOUND, "s", 5))
        labels.append(ax.text(sx, sy + 0.12, name + (f': "{u.text}"' if u else ""), ha="center", fontsize=6, color=SOUND, zorder=9))


def draw_sound_directions(ax: Axes, origin: Sequence[float], heading: float, bearings: Sequence[float], legend: Legend,
                          *, length: float = 2.5, world: World | None = None) -> None:
    """Sound directions from the microphones: solid front, dotted mirrored back candidate.

    With ``world`` each line stops at the first wall and at the flat's edge
    (a direction, not a sound leaving the flat). They are drawn thin and under
    the people, so a gaze along the same line stays visible.
    """
    segs = wall_segments(world) if world is not None else None
    box = world.bounds() if world is not None else None
    for b in bearings:
        for ang, style in ((b, "-"), (math.pi - b, ":")):
            a = heading + ang
            n = length
            if segs is not None:
                n = float(ray_lengths(segs[0], segs[1], origin, np.array([a]), length)[0])
            if box is not None:  # the flat's bounding box (a door opening does not let it out)
                c, s_ = math.cos(a), math.sin(a)
                for lo, hi, o, d in ((box[0], box[2], origin[0], c), (box[1], box[3], origin[1], s_)):
                    if d > 1e-12:
                        n = min(n, (hi - o) / d)
                    elif d < -1e-12:
                        n = min(n, (lo - o) / d)
                n = max(n, 0.0)
            ax.plot([origin[0], origin[0] + n * math.cos(a)], [origin[1], origin[1] + n * math.sin(a)], linestyle=style, color=SOUND,
                    linewidth=1.0, alpha=0.7, zorder=5)
    if bearings:
        legend.add("sound direction heard", line(SOUND, "-"))
        legend.add("its front/back mirror (cut at walls)", line(SOUND, ":"))


def covariance_ellipse(x: float, y: float, cov: np.ndarray, *, sigmas: float = 2.0, **kw: object) -> Ellipse:
    """The ``sigmas``-sigma ellipse of a 2x2 covariance at (x, y)."""
    vals, vecs = np.linalg.eigh(np.asarray(cov, dtype=float))
    vals = np.clip(vals, 0.0, None)
    angle = math.degrees(math.atan2(vecs[1, 1], vecs[0, 1]))
    return Ellipse((x, y), 2 * sigmas * math.sqrt(vals[1]), 2 * sigmas * math.sqrt(vals[0]), angle=angle, **kw)


def draw_percepts(ax: Axes, world: World, p: Percepts, legend: Legend, labels: list[Text], hits: np.ndarray | None) -> None:
    """What the robot believed: tracks, detected legs, faces, selection, partner, its pose estimate."""
    if p.estimate is not None:
        hl, hw = ROBOT_LENGTH / 2, ROBOT_WIDTH / 2
        foot = to_world(p.estimate, np.array([[-hl, -hw], [hl, -hw], [hl, hw], [-hl, hw]]))
        ax.add_patch(Polygon(foot, closed=True, facecolor="none", edgecolor=ROBOT, linestyle="--", linewidth=1, zorder=6))
        legend.add("robot's pose estimate (localiser)", Patch(facecolor="none", edgecolor=ROBOT, linestyle="--"))
    if hits is not None and len(hits) and p.tracks:
        centres = np.array([(t.x, t.y) for t in p.tracks])
        d = np.linalg.norm(hits[:, None, :] - centres[None, :, :], axis=2).min(axis=1)
        legs = hits[d < LEG_GATE]
        if len(legs):
            ax.scatter(legs[:, 0], legs[:, 1], s=14, facecolors="none", edgecolors=TRACK, linewidths=0.8, zorder=9)
            legend.add("legs detected (laser hits at a track)", dot(TRACK, "o", 5, face="none"))
    for t in p.tracks:
        ax.add_patch(covariance_ellipse(t.x, t.y, t.cov, facecolor=TRACK, alpha=0.25 if t.confirmed else 0.1,
                                        edgecolor=TRACK, linestyle="-" if t.confirmed else ":", zorder=8))
        ax.plot([t.x], [t.y], marker="+", color=TRACK, markersize=8, zorder=9)
        legend.add("track (+ mean, 2-sigma ellipse; dotted: unconfirmed)", dot(TRACK, "+", 8))
        tag = t.id + (" selected" if t.id == p.selected else "") + (" partner" if t.id == p.partner else "")
        if t.speaking:
            tag += " speaking"
        labels.append(ax.text(t.x + 0.15, t.y - 0.15, tag, fontsize=6, color="#0e7c87", ha="left", va="top", zorder=10))
        if t.id in (p.selected, p.partner):
            ax.add_patch(Circle((t.x, t.y), 0.45, facecolor="none", edgecolor="#d4a017", linewidth=2, zorder=9))
            legend.add("selected person / partner", Patch(facecolor="none", edgecolor="#d4a017", linewidth=2))
    for fx, fy in p.faces:
        ax.plot([fx], [fy], marker="*", color=FACE, markersize=9, zorder=10)
        legend.add("face seen by the camera", dot(FACE, "*", 9))


def _overlaps_any(bb, placed) -> bool:  # noqa: ANN001 (matplotlib Bboxes)
    return any(bb.overlaps(o) for o in placed)


def place_labels(ax: Axes, labels: Sequence[Text], *, avoid: Sequence[object] = (), pad: float = 1.0,
                 only_move: str = "xy", iterations: int = 300) -> None:
    """Move labels so that none covers another (nor the ``avoid`` artists), with a thin leader line to a moved one's anchor.

    Labels that cover nothing stay. adjustText (a force-directed label placer) moves the others apart for a fixed
    number of ``iterations`` (never a time limit: the same figure gives the
    same picture). What it leaves overlapping (it minimises overlaps, it does
    not promise none) gets the first free offset around where it ended, in the
    order given (put the important labels first); a label that finds no free
    place stays (never hidden). ``only_move``: "xy", "x" or "y" (a timeline's
    labels keep their time).
    """
    from adjustText import adjust_text

    labels = list(labels)
    if not labels:
        return
    fig = ax.figure
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)  # type: ignore[arg-type]
    renderer = canvas.get_renderer()
    anchors = [t.get_position() for t in labels]
    # Only labels that cover another (or an avoided mark) move; the others stay where they were asked for, as obstacles.
    boxes = [t.get_window_extent(renderer).padded(pad) for t in labels]
    marks = [a.get_window_extent(renderer).padded(pad) for a in avoid]  # type: ignore[attr-defined]
    crowded = [i for i, bb in enumerate(boxes)
               if _overlaps_any(bb, marks) or any(bb.overlaps(o) for j, o in enumerate(boxes) if j != i)]
    if crowded:
        still = [labels[i] for i in range(len(labels)) if i not in crowded]
        adjust_text([labels[i] for i in crowded], ax=ax, objects=[*avoid, *still] or None, iter_lim=iterations, ensure_inside_axes=True,
                    expand=(1.1, 1.3), only_move={"text": only_move, "static": only_move, "explode": only_move, "pull": only_move})
    placed: list = [a.get_window_extent(renderer).padded(pad) for a in avoid]  # type: ignore[attr-defined]
    steps = [(0, 0)] + [(dx, dy) for r in (1, 2, 3, 4, 6) for dx, dy in
                        ((0, r), (0, -r), (r, 0), (-r, 0), (r, r), (-r, r), (r, -r), (-r, -r))
                        if (only_move != "x" or dy == 0) and (only_move != "y" or dx == 0)]
    to_px = ax.transData
    to_data = ax.transData.inverted()
    for txt, anchor in zip(labels, anchors):
        x0, y0 = txt.get_position()
        px, py = to_px.transform((x0, y0))
        h = txt.get_window_extent(renderer).height or 8.0
        for dx, dy in steps:
            txt.set_position(to_data.transform((px + dx * h * 0.9, py + dy * h * 0.9)))
            bb = txt.get_window_extent(renderer).padded(pad)
            if not _overlaps_any(bb, placed):
                break
        else:
            txt.set_position((x0, y0))
            bb = txt.get_window_extent(renderer).padded(pad)
        placed.append(bb)
        nx, ny = txt.get_position()
        if math.hypot(*(to_px.transform((nx, ny)) - to_px.transform(anchor))) > 4:  # moved: a leader line to its anchor
            ax.plot([anchor[0], nx], [anchor[1], ny], color="#aaaaaa", linewidth=0.4, zorder=txt.get_zorder() - 0.5)


def plot_moment(
    world: World,
    *,
    scan: tuple[np.ndarray, np.ndarray] | None = None,
    sound_bearings: Sequence[float] = (),
    percepts: Percepts | None = None,
    title: str | None = None,
    size: float = 8.0,
) -> Figure:
    """A complete top-down figure of the world now (scan = (bearings, ranges); ``percepts`` overrides both)."""
    if percepts is not None:
        scan = percepts.scan if percepts.scan is not None else scan
        sound_bearings = percepts.sound_bearings or sound_bearings
    x0, y0, x1, y1 = world.bounds()
    w, h = x1 - x0, y1 - y0
    fig = Figure(figsize=(size + 3.2, size * h / w + 0.6))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    legend = Legend()
    flat: list[Text] = []
    things: list[Text] = []
    people: list[Text] = []
    marks: list[object] = []
    draw_flat(ax, world, legend, flat)
    draw_objects(ax, world, legend, things, marks)
    draw_robot(ax, world, legend, marks=marks)
    pose = world.robot.pose
    hits = None
    if scan is not None:
        bearings, ranges = scan
        hits = draw_scan(ax, world.robot.world_point(LASER_OFFSET), pose[2], bearings, ranges, legend)
    if sound_bearings:
        draw_sound_directions(ax, world.robot.world_point(MIC_OFFSET), pose[2], sound_bearings, legend, world=world)
    draw_people(ax, world, legend, people)
    if percepts is not None:
        draw_percepts(ax, world, percepts, legend, people, hits)
    ax.set_xlim(x0 - 0.5, x1 + 0.5)
    ax.set_ylim(y0 - 0.5, y1 + 0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    head = title or f"{world.scenario.name} at t = {world.time:.2f} s"
    if percepts is not None and percepts.attention:
        head += f"   attention: {percepts.attention}" + (f", partner {percepts.partner}" if percepts.partner else "")
    ax.set_title(head, fontsize=10)
    legend.draw(ax)
    fig.tight_layout()
    place_labels(ax, people + things + flat, avoid=marks)  # who says what first, room names last
    return fig
