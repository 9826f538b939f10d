"""Label placement that keeps every label off the other labels and off what is drawn (lines, outlines, points).

A label is a box on the figure; what it must not cover is read from the axes
in pixels once the layout is fixed: the edges of patches (walls, furniture,
the robot, people, track ellipses, the selected-person ring), every line
(gaze, sound directions, pointing arms, arrows), every marker and every
scatter point (laser hits). Background is not a mark: artists whose gid is in
:data:`BACKGROUND` (room floors, the camera's field of view) and near-invisible
lines (alpha under :data:`FAINT`, the laser's rays). Each label, in the order
given, takes the free place nearest to where it was asked for, searching
rings of offsets (deterministic: no time limit, no randomness); a moved label
gets a thin leader line to its anchor. A label with no free place within
reach stays where it was asked for (never hidden).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import Collection
from matplotlib.lines import Line2D
from matplotlib.text import Annotation, Text

#: Artists with one of these gids are background (floors, the field of view): labels may lie over them.
BACKGROUND = {"background", "leader"}
#: Lines fainter than this are background (the laser's rays).
FAINT = 0.1
#: Pixels kept free around a label.
PAD = 2.0


def _alpha(artist: object) -> float:
    a = getattr(artist, "get_alpha", lambda: None)()
    return 1.0 if a is None else float(a)


def _segments_of_path(path, transform) -> np.ndarray:  # noqa: ANN001 (matplotlib Path, Transform)
    """The polyline(s) of a path in pixels as (S, 4) segments (x0, y0, x1, y1); curves are flattened."""
    segs = []
    for poly in path.to_polygons(transform=transform, closed_only=False):
        if len(poly) >= 2:
            segs.append(np.hstack([poly[:-1], poly[1:]]))
    return np.vstack(segs) if segs else np.zeros((0, 4))


def marks(ax: Axes, only: Sequence[Artist] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """What labels must keep off, in pixels: segments (S, 4) and points with a radius (P, 3); of the
    artists ``only`` when given (e.g. the rules between a timeline's host bands), else of everything drawn."""
    renderer = ax.figure.canvas.get_renderer()  # type: ignore[attr-defined]
    segs: list[np.ndarray] = []
    pts: list[np.ndarray] = []
    dpi = ax.figure.dpi
    if only is not None:
        chosen = {id(a) for a in only}
        patches = [p for p in ax.patches if id(p) in chosen]
        lines = [ln for ln in ax.lines if id(ln) in chosen]
        collections = [c for c in ax.collections if id(c) in chosen]
        texts = [t for t in ax.texts if id(t) in chosen]
    else:
        patches, lines, collections, texts = list(ax.patches), list(ax.lines), list(ax.collections), list(ax.texts)
    for p in patches:
        if p.get_gid() in BACKGROUND or not p.get_visible():
            continue
        if p.get_linewidth() > 0 and p.get_edgecolor()[3] > 0:
            segs.append(_segments_of_path(p.get_path(), p.get_transform()))
    for ln in lines:
        if ln.get_gid() in BACKGROUND or not ln.get_visible() or _alpha(ln) < FAINT:
            continue
        xy = ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]).astype(float))
        if ln.get_linestyle() not in ("None", "none", "", " ") and len(xy) >= 2:
            segs.append(np.hstack([xy[:-1], xy[1:]]))
        if ln.get_marker() not in (None, "None", "none", "", " "):
            r = ln.get_markersize() * dpi / 72 / 2
            pts.append(np.column_stack([xy, np.full(len(xy), r)]))
    for c in collections:
        if c.get_gid() in BACKGROUND or not c.get_visible() or not isinstance(c, Collection):
            continue
        off = c.get_offsets()
        if len(off):
            xy = c.get_offset_transform().transform(np.asarray(off, dtype=float))
            sizes = c.get_sizes() if len(c.get_sizes()) else np.array([4.0])
            r = np.sqrt(np.resize(sizes, len(xy))) * dpi / 72 / 2
            pts.append(np.column_stack([xy, r]))
    for t in texts:
        if isinstance(t, Annotation) and t.arrow_patch is not None and t.get_gid() not in BACKGROUND:
            t.update_positions(renderer)
            ap = t.arrow_patch
            segs.append(_segments_of_path(ap.get_path(), ap.get_transform()))
    s = np.vstack(segs) if segs else np.zeros((0, 4))
    p_ = np.vstack(pts) if pts else np.zeros((0, 3))
    return s, p_


def hits(box: Sequence[float], segs: np.ndarray, pts: np.ndarray) -> int:
    """How many segments cross and points fall in ``box`` (x0, y0, x1, y1, pixels)."""
    x0, y0, x1, y1 = box
    n = 0
    if len(pts):
        r = pts[:, 2]
        n += int(np.count_nonzero((pts[:, 0] + r >= x0) & (pts[:, 0] - r <= x1) & (pts[:, 1] + r >= y0) & (pts[:, 1] - r <= y1)))
    if len(segs):
        # Liang-Barsky: the part of each segment inside the box's x and y slabs
        px, py = segs[:, 0], segs[:, 1]
        dx, dy = segs[:, 2] - px, segs[:, 3] - py
        lo = np.zeros(len(segs))
        hi = np.ones(len(segs))
        ok = np.ones(len(segs), dtype=bool)
        for d, p, a, b in ((dx, px, x0, x1), (dy, py, y0, y1)):
            flat = np.abs(d) < 1e-12
            ok &= ~flat | ((p >= a) & (p <= b))
            with np.errstate(divide="ignore", invalid="ignore"):
                ta, tb = (a - p) / d, (b - p) / d
            t0 = np.where(flat, -np.inf, np.minimum(ta, tb))
            t1 = np.where(flat, np.inf, np.maximum(ta, tb))
            lo = np.maximum(lo, t0)
            hi = np.minimum(hi, t1)
        n += int(np.count_nonzero(ok & (lo <= hi)))
    return n


def _overlap(a: Sequence[float], b: Sequence[float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def place_clear(ax: Axes, labels: Sequence[Text], *, reach: float = 12.0, leader: str = "#999999",
                avoid_marks: bool | Sequence[Artist] = True, avoid: Sequence[Text] = ()) -> None:
    """Move each label (in the order given: the important first) to the nearest place that covers no other label
    (nor the fixed texts ``avoid``) and no drawn mark (``avoid_marks``: True every mark, False none, or the
    marks of the artists given), within ``reach`` label heights of where it was asked for, inside the axes."""
    labels = [t for t in labels if t.get_text()]
    if not labels:
        return
    fig = ax.figure
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)  # type: ignore[arg-type]
    renderer = canvas.get_renderer()
    ax.apply_aspect()  # an equal-aspect axes takes its drawn box only now: measure what will be drawn
    if avoid_marks is True:
        segs, pts = marks(ax)
    elif avoid_marks is False:
        segs, pts = np.zeros((0, 4)), np.zeros((0, 3))
    else:
        segs, pts = marks(ax, only=avoid_marks)
    frame = ax.get_window_extent(renderer)
    to_px, to_data = ax.transData, ax.transData.inverted()
    placed: list[tuple[float, float, float, float]] = [tuple(t.get_window_extent(renderer).extents) for t in avoid]  # type: ignore[misc]
    for txt in labels:
        bb = txt.get_window_extent(renderer)
        box = (bb.x0 - PAD, bb.y0 - PAD, bb.x1 + PAD, bb.y1 + PAD)
        h = max(bb.height, 6.0)
        ax_pos = to_px.transform(txt.get_position())
        best = None
        for r in np.arange(0.0, reach + 1e-9, 0.5):
            steps = [(0.0, 0.0)] if r == 0 else [(r * math.cos(a), r * math.sin(a))
                                                   for a in np.linspace(0, 2 * math.pi, max(8, int(8 * r)), endpoint=False)]
            for dx, dy in steps:
                cand = (box[0] + dx * h, box[1] + dy * h, box[2] + dx * h, box[3] + dy * h)
                if cand[0] < frame.x0 or cand[2] > frame.x1 or cand[1] < frame.y0 or cand[3] > frame.y1:
                    continue
                if any(_overlap(cand, o) for o in placed) or hits(cand, segs, pts):
                    continue
                best = (dx * h, dy * h, cand)
                break
            if best is not None:
                break
        if best is None:  # nowhere free within reach: it stays (never hidden)
            placed.append(box)
            continue
        dx, dy, cand = best
        placed.append(cand)
        if dx or dy:
            txt.set_position(to_data.transform((ax_pos[0] + dx, ax_pos[1] + dy)))
            # a leader from the anchor to the nearest point of the label's box (it does not cross the label)
            cx = min(max(ax_pos[0], cand[0] + PAD), cand[2] - PAD)
            cy = min(max(ax_pos[1], cand[1] + PAD), cand[3] - PAD)
            if math.hypot(cx - ax_pos[0], cy - ax_pos[1]) > 4:
                (a, b) = to_data.transform([ax_pos, (cx, cy)])
                ln = Line2D([a[0], b[0]], [a[1], b[1]], color=leader, linewidth=0.4, zorder=txt.get_zorder() - 0.5)
                ln.set_gid("leader")
                ax.add_line(ln)


__all__ = ["BACKGROUND", "FAINT", "hits", "marks", "place_clear"]
