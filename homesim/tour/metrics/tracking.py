"""Person tracking and attention scored against ground truth (streaming, constant memory).

``tracking`` (:class:`TrackingMetric`) reads every ``/robot/attention/tracks``
message and compares the confirmed tracks with where the people really are
at that moment:

- CLEAR-MOT (Bernardin and Stiefelhagen 2008), computed exactly as
  py-motmetrics' ``MOTAccumulator`` does (:class:`StreamingMOT`: keep last
  frame's correspondences that are still within ``max_d``, assign the rest
  with ``scipy.optimize.linear_sum_assignment``, a switch when a person's
  match changes), but with running counts instead of an event table, so a
  run's memory does not grow with its length: MOTA, MOTP in metres (plain
  Euclidean distances), matches, misses, false positives, identity
  switches; the tests check every count against motmetrics itself;
- IDF1 (Ristani et al. 2016) from a gt-id x track-id co-occurrence count
  (bounded by the number of ids, not of frames) and the global id
  assignment, again as motmetrics computes it.

What counts: a person is a ground-truth object when the laser could see
them: present, in front of the laser (within ``fov``), closer than
``max_range`` and with no wall on the line from the laser (people and
furniture occluding them do count: the tracker must coast through that),
once one of the robot's sensors has had them in view, computed from the
world and the robot's true pose (:meth:`TrackingMetric._first_sightings`):
the laser their legs (:func:`legs_in_view`: a beam reaches one of their
legs, at leg height, past walls, furniture and other people's legs), or the
camera their face or torso (:func:`camera_sightings`: what the camera model
reports at the pan-tilt's true pan and tilt, with no noise: a frontal face
0.5-4 m away or a torso 0.5-5 m away, in the image and on a clear 3D sight
line). The tracker starts tracks from laser legs and from faces (a person
behind a coffee table), so either is a first sighting; before any, no
tracker could know they are there: a flatmate behind a bar stool, out of
the camera's image, is not a miss. MOT benchmarks annotate a person once
they become visible in the sensor data and keep them through occlusion
(MOT16, Milan et al. 2016: a trajectory starts when the person becomes
visible in the images; a person never visible is not annotated), and lidar benchmarks drop a box no lidar point
hits (nuScenes), which would not ask a tracker to coast at all. Here the
first sighting alone decides: hidden again after it, behind the pillar or a
passer-by, a person counts, as in CLEAR-MOT's annotations of people known
to be in the scene. ``mota`` and every count in the summary are by this
rule. ``mota_all_present`` (with ``idf1_all_present``,
``objects_all_present``, ``misses_all_present``) is the rule before
5596f11: every present person in the laser's region counts from the start,
seen or not (issue 26's target "MOTA >= 0.9" was set by it). A run whose
two figures differ had people in the region that no sensor had yet seen
(fresh4/loft_pillar_cross: a man behind a bar stool, out of the camera's
image, for up to 34 s).
A confirmed track is a hypothesis when it lies in the same region and is
not within ``max_d`` of a person outside it (those are "don't care").
Positions come from the message's robot-frame ``bearing`` and ``distance``
placed with the robot's true pose, so odometry drift does not count
against the tracker.

``attention`` in the same summary: while the supervisor is in an
interaction state, the share of scans on which the attention system's
partner track is on the right person (the one who spoke while facing the
robot when the interaction began) within ``max_d``.

:func:`detection_scores` scores a leg detector's candidates (precision and
recall per scan) for the benchmark and tests, which run the robot's
detector themselves (the kernel never imports the robot).
"""

from __future__ import annotations

import copy
import math
from bisect import bisect_right
from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np
from ...lsap import linear_sum_assignment  # SciPy's solver, without importing scipy.optimize

from ...geometry import TWO_PI, polygon_edges, wrap_angle
from ...world.bodies import LASER_HEIGHT, LEG_RADIUS
from ...world.raycast import RayCaster
from robot.hardware.camera import CameraSpec, PanTilt, detect_faces, detect_torsos
from . import Observer

INTERACTION_STATES = frozenset({"Interacting", "Following", "ObjectTeaching"})
FACING = math.radians(30)


class StreamingMOT:
    """CLEAR-MOT and IDF1 over a stream of frames, in memory bounded by the number of ids."""

    def __init__(self, max_d: float = 1.0) -> None:
        self.max_d = max_d
        self.frames = 0
        self.objects = 0  # ground-truth objects summed over frames
        self.hyps = 0
        self.matches = 0
        self.misses = 0
        self.false_positives = 0
        self.switches = 0
        self.distance = 0.0
        self._m: dict[Hashable, Hashable] = {}  # current correspondences gt -> hyp
        self._gt_frames: dict[Hashable, int] = {}
        self._hyp_frames: dict[Hashable, int] = {}
        self._co: dict[tuple[Hashable, Hashable], int] = {}

    def update(
        self, gt_ids: Sequence[Hashable], gt_xy: np.ndarray | Sequence[Sequence[float]], hyp_ids: Sequence[Hashable], hyp_xy: np.ndarray | Sequence[Sequence[float]]
    ) -> None:
        """One frame: ground-truth ids and positions (N, 2), hypothesis ids and positions (M, 2) (arrays or lists of pairs).

        Raises ValueError when the positions are not one pair per id.

        Plain floats (a frame has a few people and tracks); distances are numpy's ``hypot``; the
        assignment solver runs only when the valid pairs leave a choice (else the minimum-distance
        assignment is every valid pair).
        """
        self.frames += 1
        n, m = len(gt_ids), len(hyp_ids)
        self.objects += n
        self.hyps += m
        gt = np.asarray(gt_xy, dtype=float).reshape(n, 2).tolist() if isinstance(gt_xy, np.ndarray) else gt_xy
        hy = np.asarray(hyp_xy, dtype=float).reshape(m, 2).tolist() if isinstance(hyp_xy, np.ndarray) else hyp_xy
        if len(gt) != n or len(hy) != m:  # lists are not reshaped: a position missing or extra is refused as an array's is
            raise ValueError(f"StreamingMOT.update: {n} ids with {len(gt)} positions, {m} hypothesis ids with {len(hy)} positions")
        for o in gt_ids:
            self._gt_frames[o] = self._gt_frames.get(o, 0) + 1
        for h in hyp_ids:
            self._hyp_frames[h] = self._hyp_frames.get(h, 0) + 1
        if not (n and m):  # nobody to match: every person missed, every track false, correspondences kept
            self.misses += n
            self.false_positives += m
            return
        d: list[float] = []  # row-major, gt x hyp
        if n and m:
            d = np.hypot([gx - hx for gx, _ in gt for hx, _ in hy], [gy - hy_ for _, gy in gt for _, hy_ in hy]).tolist()
        max_d = self.max_d
        valid = [k for k in range(len(d)) if d[k] <= max_d]
        co = self._co
        for k in valid:
            key = (gt_ids[k // m], hyp_ids[k % m])
            co[key] = co.get(key, 0) + 1
        ok = set(valid)
        gi = {o: i for i, o in enumerate(gt_ids)}
        hj = {h: j for j, h in enumerate(hyp_ids)}
        used_g = [False] * n
        used_h = [False] * m
        # 1. Last frame's correspondences that still hold.
        for o, h in list(self._m.items()):
            i, j = gi.get(o), hj.get(h)
            if i is not None and j is not None and i * m + j in ok and not used_h[j]:
                used_g[i] = used_h[j] = True
                self.matches += 1
                self.distance += d[i * m + j]
        # 2. The rest: minimum total distance among valid pairs.
        rest = [k for k in valid if not used_g[k // m] and not used_h[k % m]]
        if rest:
            rows = {k // m for k in rest}
            cols = {k % m for k in rest}
            if len(rows) < len(rest) or len(cols) < len(rest):  # a choice: the solver
                ri = [i for i in range(n) if not used_g[i]]
                cj = [j for j in range(m) if not used_h[j]]
                sub = np.full((len(ri), len(cj)), 1e9)
                for a_, i in enumerate(ri):
                    for b_, j in enumerate(cj):
                        if i * m + j in ok:
                            sub[a_, b_] = d[i * m + j]
                r, c = linear_sum_assignment(sub)
                rest = [ri[a_] * m + cj[b_] for a_, b_ in zip(r.tolist(), c.tolist()) if ri[a_] * m + cj[b_] in ok]
            for k in rest:  # in ascending gt order, as the solver returns them
                i, j = k // m, k % m
                o, h = gt_ids[i], hyp_ids[j]
                if o in self._m and self._m[o] != h:
                    self.switches += 1  # a switch is a correspondence too, but not counted a match (as motmetrics)
                else:
                    self.matches += 1
                self._m[o] = h
                used_g[i] = used_h[j] = True
                self.distance += d[k]
        self.misses += used_g.count(False)
        self.false_positives += used_h.count(False)

    def idf1(self) -> tuple[float, int]:
        """IDF1 and the identity true positives of the best global id assignment."""
        if not self._co:
            return (0.0, 0) if self.objects + self.hyps else (1.0, 0)
        gts = sorted(self._gt_frames, key=str)
        hyps = sorted(self._hyp_frames, key=str)
        gi = {o: i for i, o in enumerate(gts)}
        hj = {h: j for j, h in enumerate(hyps)}
        c = np.zeros((len(gts), len(hyps)))
        for (o, h), k in self._co.items():
            c[gi[o], hj[h]] = k
        r, cc = linear_sum_assignment(-c)
        idtp = int(c[r, cc].sum())
        return 2.0 * idtp / (self.objects + self.hyps), idtp

    def summary(self) -> dict[str, Any]:
        mota = 1.0 - (self.misses + self.false_positives + self.switches) / self.objects if self.objects else None
        idf1, idtp = self.idf1()
        return {
            "frames": self.frames,
            "objects": self.objects,
            "mota": None if mota is None else round(mota, 4),
            "motp_m": round(self.distance / (self.matches + self.switches), 4) if self.matches + self.switches else None,
            "idf1": round(idf1, 4),
            "idtp": idtp,
            "matches": self.matches,
            "misses": self.misses,
            "false_positives": self.false_positives,
            "id_switches": self.switches,
            "gt_ids": len(self._gt_frames),
            "track_ids": len(self._hyp_frames),
        }


def detection_scores(det_xy: np.ndarray, truth_xy: np.ndarray, radius: float = 0.35) -> tuple[int, int, int]:
    """(true positives, false positives, false negatives) of one scan's person candidates (world frame).

    One-to-one: candidates and people paired by minimum distance within ``radius``.
    """
    det_xy = np.asarray(det_xy, dtype=float).reshape(-1, 2)
    truth_xy = np.asarray(truth_xy, dtype=float).reshape(-1, 2)
    if det_xy.shape[0] == 0 or truth_xy.shape[0] == 0:
        return 0, det_xy.shape[0], truth_xy.shape[0]
    d = np.hypot(det_xy[:, None, 0] - truth_xy[None, :, 0], det_xy[:, None, 1] - truth_xy[None, :, 1])
    r, c = linear_sum_assignment(np.where(d <= radius, d, 1e9))
    tp = int((d[r, c] <= radius).sum())
    return tp, det_xy.shape[0] - tp, truth_xy.shape[0] - tp


def visible_region(walls: tuple[np.ndarray, np.ndarray], pose: tuple[float, float, float], xy: np.ndarray, *, fov: float = math.pi, max_range: float = 6.5,
    offset: float = 0.13) -> np.ndarray:
    """Which points (N, 2) the laser could see: in its field of view and range, no wall in between.

    :class:`SightLines` for ``walls`` (a caller that asks every frame keeps one).
    """
    pts = [(px, py) for px, py in np.asarray(xy, dtype=float).reshape(-1, 2).tolist()]
    return np.array(SightLines(walls).visible(pose, pts, fov=fov, max_range=max_range, offset=offset), dtype=bool)


class SightLines:
    """Visibility from the laser past the walls, with the walls prepared once.

    Plain floats per point (a frame has a few people and tracks; numpy's per-call cost was most of
    a frame's scoring), the arithmetic of :func:`~homesim.geometry.segments_intersect`
    operation for operation, and only against the walls whose box meets the sight line's box:
    each wall is kept as its box and its segment (start, direction) in floats, sorted by the box's
    left edge, so the walls starting right of a sight line's box are never looked at. An answer
    is remembered while the laser stays where it is (a robot standing still sees a standing
    person, and a track the message puts at the same place, the same way every scan): the same
    inputs, the same arithmetic, so the same answer; at most ``memory`` points are kept.
    """

    def __init__(self, walls: tuple[np.ndarray, np.ndarray], *, memory: int = 64) -> None:
        a, e = walls
        prepared = [
            (min(ax, bx), max(ax, bx), min(ay, by), max(ay, by), ax, ay, bx - ax, by - ay)
            for (ax, ay), (bx, by) in zip(np.asarray(a, dtype=float).reshape(-1, 2).tolist(), np.asarray(e, dtype=float).reshape(-1, 2).tolist())
        ]
        prepared.sort(key=lambda w: w[0])
        self._walls = prepared
        self._left = [w[0] for w in prepared]
        self._memory = memory
        self._origin: tuple[float, ...] | None = None  # laser pose, fov, range of the remembered answers
        self._known: dict[tuple[float, float], bool] = {}

    def visible(self, pose: tuple[float, float, float], pts: Sequence[tuple[float, float]], *, fov: float = math.pi, max_range: float = 6.5, offset: float = 0.13) -> list[bool]:
        """Which points (a list of (x, y) tuples) the laser at ``pose`` could see (see :func:`visible_region`)."""
        if not pts:
            return []
        x, y, th = pose
        ox, oy = x + offset * math.cos(th), y + offset * math.sin(th)
        origin = (ox, oy, th, fov, max_range)
        known = self._known
        if origin != self._origin or len(known) > self._memory:
            known.clear()
            self._origin = origin
        todo = [p for p in pts if p not in known]
        if todo:
            dx = [px - ox for px, _ in todo]
            dy = [py - oy for _, py in todo]
            dist = np.hypot(dx, dy).tolist()
            walls, left = self._walls, self._left
            half = fov / 2
            for p, r0, r1, d in zip(todo, dx, dy, dist):
                ok = abs((math.atan2(r1, r0) - th + math.pi) % TWO_PI - math.pi) <= half and d <= max_range
                if ok:
                    # A wall outside the sight line's box cannot cross it (margin for rounding).
                    px, py = p
                    lo_x, hi_x = ((ox, px) if ox <= px else (px, ox))
                    lo_y, hi_y = ((oy, py) if oy <= py else (py, oy))
                    lo_x, hi_x, lo_y, hi_y = lo_x - 1e-6, hi_x + 1e-6, lo_y - 1e-6, hi_y + 1e-6
                    for k in range(bisect_right(left, hi_x)):  # the others start right of the box
                        x0, x1, y0, y1, ax, ay, s0, s1 = walls[k]
                        if x1 < lo_x or y1 < lo_y or y0 > hi_y:
                            continue
                        den = r0 * s1 - r1 * s0
                        if abs(den) > 1e-12:
                            ap0, ap1 = ax - ox, ay - oy
                            t = (ap0 * s1 - ap1 * s0) / den
                            u = (ap0 * r1 - ap1 * r0) / den
                            if 0 <= t <= 1 and 0 <= u <= 1:
                                ok = False
                                break
                known[p] = ok
        return [known[p] for p in pts]


#: m: a beam that ends this far short of a leg's near side still counts as reaching it (rounding; a beam grazing the leg's edge)
_GRAZE = 0.02


def legs_in_view(
    caster: RayCaster, origin: tuple[float, float], legs: Sequence[tuple[float, float]],
    seg: tuple[np.ndarray, np.ndarray], circles: tuple[np.ndarray, np.ndarray], *, max_range: float = 6.5, leg_radius: float = LEG_RADIUS,
) -> bool:
    """Does a beam from the laser at ``origin`` reach one of ``legs`` (world centres) first?

    One beam towards each leg's centre is cast against ``seg`` (the flat's segments at leg height: walls
    and furniture) and ``circles`` (every person's legs, these included); the leg is in view when that
    beam ends on its near side (within ``_GRAZE``), not on something nearer: a bar stool, another
    person's leg, a wall's end.
    """
    ox, oy = origin
    near = [(math.hypot(lx - ox, ly - oy), math.atan2(ly - oy, lx - ox)) for lx, ly in legs]
    near = [(d, a) for d, a in near if d - leg_radius <= max_range]
    if not near:
        return False
    ranges = caster.cast(origin, np.array([a for _, a in near]), seg[0], seg[1], circles[0], circles[1], max_range).tolist()
    return any(r >= d - leg_radius - _GRAZE for (d, _), r in zip(near, ranges))


def camera_sightings(world: Any, pose: tuple[float, float, float], spec: CameraSpec | None = None) -> set[str]:
    """Who the camera could report now: a frontal face or a torso in the image, in range, on a clear sight line.

    The camera model's own detection (:func:`robot.hardware.camera.detect_faces`, ``detect_torsos``) at the
    pan-tilt's true pan and tilt (``world.ptu``) from the robot's true ``pose``, without noise: the names, not
    the percepts (scoring only).
    """
    spec = spec or CameraSpec()
    pan, tilt = world.ptu
    ptu = PanTilt(pan, tilt, pan, tilt)
    occ = world.person_cylinders()
    faces = detect_faces(world, pose, ptu, spec, None, occluders=occ)
    torsos = detect_torsos(world, pose, ptu, spec, None, occluders=occ)
    return {d.truth for d in faces} | {d.truth for d in torsos}


def wall_edges(world: Any) -> tuple[np.ndarray, np.ndarray]:
    """Edges (a, b) of every wall piece of the world (door gaps are not walls)."""
    polys = [o.polygon for o in world.obstacles if o.kind == "wall"]
    if not polys:
        return np.zeros((0, 2)), np.zeros((0, 2))
    pairs = [polygon_edges(p) for p in polys]
    return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])


class TrackingMetric(Observer):
    """CLEAR-MOT, IDF1 and attention-on-the-right-person for ``person_attention`` (module docstring)."""

    channels = ("/robot/attention/",)

    def __init__(self, run: Any, *, max_d: float = 1.0) -> None:
        super().__init__(run)
        self.mot = StreamingMOT(max_d)
        # the same scores with every present person in the laser's region counted (the rule before 5596f11);
        # None while its frames have been the same as ``mot``'s (then ``mot`` is its state)
        self.mot_all: StreamingMOT | None = None
        self.max_d = max_d
        self.walls = wall_edges(run.world)
        self.sight = SightLines(self.walls)
        # people a sensor has had in view at least once (legs by the laser, face or torso by the camera): only they are ground truth
        self.perceived: set[str] = set()
        self._caster = RayCaster()
        self.partner: str | None = None  # the attention system's partner track
        self.right: str | None = None  # who the partner really is (ground truth)
        self.on_right = 0
        self.in_interaction = 0
        self.interactions = 0

    def on_message(self, m: Any) -> None:
        if m.channel == "/robot/attention/state":
            self.partner = m.xml.get("partner") or None
        elif m.channel == "/robot/attention/tracks":
            self._frame(m)

    def _frame(self, m: Any) -> None:
        world = self.run.world
        pose = world.robot.pose
        people = [(n, h.position) for n, h in world.humans.items() if h.present]
        gt = [(float(px), float(py)) for _, (px, py) in people]
        ids, hyp = [], []
        x, y, th = pose
        data = getattr(m, "data", None)
        if data is not None:  # the typed record: its fields as the contract's XML carries them (3 decimals)
            for t in data.tracks:
                if not t.confirmed:
                    continue
                b = math.radians(round(t.bearing, 3)) + th
                d = round(t.distance, 3)
                ids.append(t.id)
                hyp.append((x + d * math.cos(b), y + d * math.sin(b)))
        else:
            for t in m.xml:
                if t.get("confirmed") != "true":
                    continue
                b = math.radians(float(t.get("bearing"))) + th
                d = float(t.get("distance"))
                ids.append(t.get("id"))
                hyp.append((x + d * math.cos(b), y + d * math.sin(b)))
        # People and tracks in one visibility test (each point's answer is its own).
        n = len(gt)
        both = self.sight.visible(pose, gt + hyp)
        region, hvis = both[:n], both[n:]
        vis = region
        if not all(p[0] in self.perceived for p in people):
            vis = self._first_sightings(pose, people, region)
        gt_ids = [people[i][0] for i in range(n) if vis[i]]
        gt_xy = [gt[i] for i in range(n) if vis[i]]
        hyp_ids, hyp_xy = self._hypotheses(ids, hyp, hvis, [p for p, v in zip(gt, vis) if not v])
        if self.mot_all is None and vis == region:  # both rules count the same people, and have so far
            self.mot.update(gt_ids, gt_xy, hyp_ids, hyp_xy)
        else:
            if self.mot_all is None:
                self.mot_all = copy.deepcopy(self.mot)
            self.mot.update(gt_ids, gt_xy, hyp_ids, hyp_xy)
            all_ids, all_xy = self._hypotheses(ids, hyp, hvis, [p for p, v in zip(gt, region) if not v])
            self.mot_all.update([people[i][0] for i in range(n) if region[i]], [gt[i] for i in range(n) if region[i]], all_ids, all_xy)
        self._attention(ids, hyp, people)

    def _hypotheses(self, ids: list[str], hyp: list[tuple[float, float]], hvis: list[bool], hidden: list[tuple[float, float]]) -> tuple[list[str], list[tuple[float, float]]]:
        """The confirmed tracks that are hypotheses: in the laser's region and not within ``max_d`` of a person
        who does not count (``hidden``: outside the region, or not yet seen); a track on such a person is
        "don't care", not a false positive."""
        if hidden and hyp:
            k = len(hidden)
            dd = np.hypot([hx - gx for hx, _ in hyp for gx, _ in hidden], [hy - gy for _, hy in hyp for _, gy in hidden]).tolist()
            hvis = [v and min(dd[j * k : j * k + k]) > self.max_d for j, v in enumerate(hvis)]
        keep = [j for j in range(len(ids)) if hvis[j]]
        return [ids[j] for j in keep], [hyp[j] for j in keep]

    def _first_sightings(self, pose: tuple[float, float, float], people: list[tuple[str, Any]], region: list[bool]) -> list[bool]:
        """``region`` with the people no sensor has yet had in view set False; those one sees now become perceived.

        The laser: legs in view (:func:`legs_in_view`) of a person in its region (which holds its field of view
        and range). The camera: a face or torso it could report (:func:`camera_sightings`), anywhere its pan
        turns it: seen there, she counts once she is in the laser's region.
        """
        world = self.run.world
        x, y, th = pose
        origin = (x + 0.13 * math.cos(th), y + 0.13 * math.sin(th))  # the laser, as SightLines places it
        seg = circles = None
        camera: set[str] | None = None
        out = []
        for (name, _), v in zip(people, region):
            if name not in self.perceived:
                if v:
                    if seg is None:
                        seg, circles = world.segments_at(LASER_HEIGHT), world.leg_circles()
                    legs = [(float(a), float(b)) for a, b in world.humans[name].leg_centres().tolist()]
                    if legs_in_view(self._caster, origin, legs, seg, circles):
                        self.perceived.add(name)
                if name not in self.perceived:
                    if camera is None:
                        camera = camera_sightings(world, pose)
                    if name in camera:
                        self.perceived.add(name)
            out.append(v and name in self.perceived)
        return out

    def _attention(self, ids: list[str], hyp_xy: list[tuple[float, float]], people: list[tuple[str, tuple[float, float]]]) -> None:
        if self.run.es_state not in INTERACTION_STATES:
            self.right = None
            return
        if self.right is None:
            self.right = self._greeter()
            self.interactions += 1
        if self.right is None:
            return
        self.in_interaction += 1
        if self.partner in ids:
            px, py = hyp_xy[ids.index(self.partner)]
            where = dict(people).get(self.right)
            if where is not None and math.hypot(where[0] - px, where[1] - py) <= self.max_d:
                self.on_right += 1

    def _greeter(self) -> str | None:
        """The person who spoke (now or in the last 3 s) while facing the robot, nearest first."""
        world = self.run.world
        now = self.run.sim.now
        rx, ry, _ = world.robot.pose
        best: tuple[float, str] | None = None
        for name, h in world.humans.items():
            if not h.present:
                continue
            said = [u for u in world.sound.by(name, since=now - 10.0) if u.start <= now and u.end >= now - 3.0]
            hx, hy = h.position
            facing = abs(float(wrap_angle(h.gaze - math.atan2(ry - hy, rx - hx)))) <= FACING
            if said and facing:
                d = math.hypot(hx - rx, hy - ry)
                if best is None or d < best[0]:
                    best = (d, name)
        return best[1] if best else None

    def summary(self) -> dict[str, Any]:
        out = self.mot.summary()
        every = (self.mot_all or self.mot).summary()  # the rule before 5596f11 (module docstring)
        out["mota_all_present"] = every["mota"]
        out["idf1_all_present"] = every["idf1"]
        out["objects_all_present"] = every["objects"]
        out["misses_all_present"] = every["misses"]
        out["attention_on_partner_share"] = round(self.on_right / self.in_interaction, 4) if self.in_interaction else None
        out["attention_scans_in_interaction"] = self.in_interaction
        out["interactions"] = self.interactions
        return out


OBSERVERS = {"tracking": TrackingMetric}
