"""Top-down plots of the flat at one moment: the only module that imports matplotlib.

Pure drawing functions (py_trees' ``display`` style): each takes a
matplotlib ``Axes`` and plain data or a world, draws, and changes nothing
else. :func:`plot_moment` composes them into a figure: walls, furniture
(raised pieces hatched: the laser passes under them), objects, the robot
with its camera's field of view and the laser scan, people with legs,
heading, gaze, speech and pointing arms, and sound directions (both
front and back candidates, since the microphone pair cannot tell them
apart). Used by ``homesim scenario plot`` and by notebooks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Wedge

from .world.bodies import HUMAN_RADIUS, LEG_RADIUS, ROBOT_LENGTH, ROBOT_WIDTH
from .world.geometry import polygon_centroid, to_world
from .world.world import World

WALL = "#333333"
FURNITURE = "#c8b89a"
ROBOT = "#1f5fbf"
SCAN = "#d62728"
SOUND = "#9467bd"


def draw_flat(ax: Axes, world: World) -> None:
    """Rooms (labelled), walls and furniture."""
    for room in world.scenario.rooms:
        poly = np.array(room.polygon)
        ax.add_patch(Polygon(poly, closed=True, facecolor="#f7f7f2", edgecolor="none", zorder=0))
        cx, cy = polygon_centroid(poly)
        ax.text(cx, cy, room.name, ha="center", va="center", fontsize=9, color="#999999", zorder=1)
    for ob in world.obstacles:
        if ob.kind == "wall":
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor=WALL, edgecolor=WALL, zorder=3))
        elif ob.kind == "furniture":
            raised = ob.bottom > 0
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor=FURNITURE, edgecolor="#8c7b5e", hatch="//" if raised else None, alpha=0.8, zorder=2))
            cx, cy = polygon_centroid(ob.polygon)
            ax.text(cx, cy, ob.name, ha="center", va="center", fontsize=7, color="#5a4a30", zorder=4)
        else:
            ax.add_patch(Polygon(ob.polygon, closed=True, facecolor="#8c7b5e", edgecolor="none", zorder=3))


def draw_objects(ax: Axes, world: World) -> None:
    """Objects as coloured squares with their names."""
    for name, o in world.objects.items():
        h = max(o.size, 0.08) / 2
        ax.add_patch(Polygon([(o.x - h, o.y - h), (o.x + h, o.y - h), (o.x + h, o.y + h), (o.x - h, o.y + h)], closed=True, facecolor=o.colour, edgecolor="black", linewidth=0.5, zorder=5))
        ax.text(o.x, o.y - h - 0.05, name, ha="center", va="top", fontsize=6, zorder=5)


def draw_robot(ax: Axes, pose: Sequence[float], *, pan: float = 0.0, hfov: float = math.radians(48.8), view: float = 4.0) -> None:
    """The PeopleBot's footprint, heading and the camera's field of view."""
    x, y, th = pose
    hl, hw = ROBOT_LENGTH / 2, ROBOT_WIDTH / 2
    foot = to_world(pose, np.array([[-hl, -hw], [hl, -hw], [hl, hw], [-hl, hw]]))
    ax.add_patch(Polygon(foot, closed=True, facecolor=ROBOT, edgecolor="black", alpha=0.85, zorder=6))
    nose = to_world(pose, np.array([[hl + 0.1, 0.0]]))[0]
    ax.annotate("", xy=nose, xytext=(x, y), arrowprops={"arrowstyle": "->", "color": "white"}, zorder=7)
    centre = math.degrees(th + pan)
    half = math.degrees(hfov) / 2
    ax.add_patch(Wedge((x, y), view, centre - half, centre + half, facecolor=ROBOT, alpha=0.08, edgecolor=ROBOT, linewidth=0.5, zorder=1))


def draw_scan(ax: Axes, origin: Sequence[float], heading: float, bearings: np.ndarray, ranges: np.ndarray, *, max_range: float = 8.19) -> None:
    """Laser end points (hits only) and faint rays."""
    hit = ranges < max_range - 1e-6
    ang = heading + bearings[hit]
    xs = origin[0] + ranges[hit] * np.cos(ang)
    ys = origin[1] + ranges[hit] * np.sin(ang)
    ax.scatter(xs, ys, s=2, color=SCAN, zorder=8, label="laser")
    for xe, ye in zip(xs[::6], ys[::6]):
        ax.plot([origin[0], xe], [origin[1], ye], color=SCAN, alpha=0.06, linewidth=0.5, zorder=1)


def draw_people(ax: Axes, world: World, *, t: float | None = None) -> None:
    """People: body, legs, heading, gaze (dashed), pointing arm, what they say."""
    now = world.time if t is None else t
    for name, h in world.humans.items():
        if not h.present:
            continue
        x, y = h.position
        ax.add_patch(Circle((x, y), HUMAN_RADIUS, facecolor=h.torso, edgecolor="black", alpha=0.35, zorder=6))
        for lx, ly in h.leg_centres():
            ax.add_patch(Circle((lx, ly), LEG_RADIUS, facecolor="black", zorder=7))
        hx, hy = x + 0.4 * math.cos(h.heading), y + 0.4 * math.sin(h.heading)
        ax.annotate("", xy=(hx, hy), xytext=(x, y), arrowprops={"arrowstyle": "->", "color": "black"}, zorder=7)
        gx, gy = x + 0.9 * math.cos(h.gaze), y + 0.9 * math.sin(h.gaze)
        ax.plot([x, gx], [y, gy], linestyle="--", color="#ff7f0e", linewidth=1, zorder=7)
        hand = h.hand_point()
        if hand is not None and h.pointing is not None:
            tx, ty, _ = h.pointing.target
            ax.plot([x, tx], [y, ty], color="#2ca02c", linewidth=1.5, zorder=7)
        label = name
        u = world.sound.speaking(name, now)
        if u is not None:
            label += f': "{u.text}"'
        ax.text(x, y + HUMAN_RADIUS + 0.08, label, ha="center", va="bottom", fontsize=7, zorder=9)
    for name, (sx, sy, _) in world.sources.items():
        u = world.sound.speaking(name, now)
        ax.plot([sx], [sy], marker="s", color=SOUND, zorder=7)
        ax.text(sx, sy + 0.12, name + (f': "{u.text}"' if u else ""), ha="center", fontsize=6, color=SOUND, zorder=9)


def draw_sound_directions(ax: Axes, origin: Sequence[float], heading: float, bearings: Sequence[float], *, length: float = 2.5) -> None:
    """Sound directions from the microphones: solid front, dotted mirrored back candidate."""
    for b in bearings:
        for ang, style in ((b, "-"), (math.pi - b, ":")):
            a = heading + ang
            ax.plot([origin[0], origin[0] + length * math.cos(a)], [origin[1], origin[1] + length * math.sin(a)], linestyle=style, color=SOUND, linewidth=1.2, zorder=8)


def plot_moment(
    world: World,
    *,
    scan: tuple[np.ndarray, np.ndarray] | None = None,
    sound_bearings: Sequence[float] = (),
    title: str | None = None,
    size: float = 8.0,
) -> Figure:
    """A complete top-down figure of the world now (scan = (bearings, ranges))."""
    x0, y0, x1, y1 = world.bounds()
    w, h = x1 - x0, y1 - y0
    fig = Figure(figsize=(size, size * h / w + 0.6))
    ax = fig.add_subplot(1, 1, 1)
    draw_flat(ax, world)
    draw_objects(ax, world)
    pose = world.robot.pose
    draw_robot(ax, pose, pan=world.ptu[0])
    if scan is not None:
        bearings, ranges = scan
        off = world.robot.world_point(0.13)
        draw_scan(ax, off, pose[2], bearings, ranges)
    if sound_bearings:
        draw_sound_directions(ax, world.robot.world_point(0.10), pose[2], sound_bearings)
    draw_people(ax, world)
    ax.set_xlim(x0 - 0.5, x1 + 0.5)
    ax.set_ylim(y0 - 0.5, y1 + 0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title or f"{world.scenario.name} at t = {world.time:.2f} s", fontsize=10)
    fig.tight_layout()
    return fig
