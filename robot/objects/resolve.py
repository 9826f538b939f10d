"""Reference resolution: which seen object the partner means.

Pure functions, no bus and no time. The object attention collects the
camera's object detections into :class:`Candidate` s (one per physical
object: detections within ``MERGE`` metres of each other in the map frame
and of the same reported type), then :func:`resolve` scores every candidate
against what was said (the speech frame's type, name, colour) and shown
(the pointing ray from :mod:`robot.objects.gestures`):

- type: the detector confuses types now and then, so a candidate whose
  detections mostly say another type is only scored down; one seen
  ``TYPE_EVIDENCE`` times or more and as the named type in fewer than
  ``TYPE_SHARE`` of them does not fit (a lamp that the detector once took
  for glasses is not the glasses she named);
- colour: the distance between the candidate's mean colour and the named
  colour's RGB (the robot's own colour vocabulary, :data:`COLOURS`); a
  candidate clearly of another colour does not fit;
- gesture: the angle between the pointing direction and the direction from
  the hand to the candidate, against the ray's own uncertainty: the person's
  aim (``AIM_SIGMA``) and the camera's estimate of the arm's direction
  (the spread of its detections over their number, :attr:`Pointing.sigma`);
  far off the ray does not fit; along the ray, the arm's elevation says how
  far out it comes down (:meth:`Pointing.elevation_likelihood`, with the
  object's height measured from the image: two plants one behind the other on
  the floor, the arm points down more steeply at the nearer one's middle), as
  evidence that only scores down;
- distance: nearer to the hand (or to the robot without a gesture) is
  slightly preferred.

The result is ``one`` (a clear best), ``ambiguous`` (two or more fit and the
best is not clearly better: ask) or ``none`` (nothing fits). :func:`option_texts`
words the clarification options ("the red cup", "the blue one").
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from homesim.colours import COLOURS as NAMED_COLOURS

#: The robot's colour vocabulary (RGB in [0, 1]), as people name colours (the scenario format's words).
COLOURS: dict[str, tuple[float, float, float]] = NAMED_COLOURS
COLOUR_ALIASES = {"gray": "grey"}

MERGE = 0.2  # metres: detections closer than this are one object (without a viewpoint)
MERGE_BEARING = math.radians(4.0)  # seen from the robot: 4x the camera's bearing noise
BEARING_NOISE = math.radians(1.0)  # the camera's bearing noise (its data sheet)
SPLIT_SPREAD = 1.5  # a candidate whose bearings spread more than this many times the noise ...
SPLIT_APART = 2.5  # ... and fall in two groups this many noises apart is two objects
MERGE_RANGE = 0.25  # of the range: 4x the camera's relative distance noise
RANGE_NOISE = 0.06  # the camera's relative distance noise (its data sheet)
COLOUR_FIT = 0.3  # RGB distance under which a colour "is" the named one
AIM_SIGMA = math.radians(6.0)  # a person's aim at an object within a few metres (the arm is not a laser)
GESTURE_SIGMA = math.radians(12.0)  # a ray whose own uncertainty is not known (Pointing.sigma None)
GESTURE_FIT = math.radians(30.0)  # further off the pointing ray: not the object pointed at
# m along the ray: an object nearer the hand than this is judged as if it stood this far out (its
# sideways offset, not its angle seen from the fingertip: a cup 0.2 m past her hand and 0.15 m to
# the side is 37 deg off the ray, and is what she points at; at 0.5 m, 30 deg is 0.29 m sideways)
NEAR_HAND = 0.5
TYPE_EVIDENCE = 3  # detections, none of the named type, that rule a candidate out
TYPE_SHARE = 0.25  # with TYPE_EVIDENCE or more detections, a candidate seen as the named type less often does not fit
CLEAR = 3.0  # the best candidate's score ratio over the second to decide without asking
SIDE_APART = math.radians(3.0)  # rad: options this far apart, seen from the robot, are told apart by side too (3x the camera's bearing noise)
SPLIT_MIN = 8  # detections: fewer are never taken for two objects by depth
CO_SEEN = 0.5  # two parts are two objects only if seen together in this share of the frames of the one seen less
ANSWER_CLEAR = 1.5  # ... and after asking, with her answer's gesture and the request's together (she has been asked once)
# Along the ray: the arm's elevation says how far out it comes down. She points at an object's middle
# (its surface plus half the height the camera measured, Candidate.tall); ELEVATION_OUTLIER is the share
# of rays whose elevation says nothing (an object placed on the wrong surface, an arm held lazily), so a
# miss only scores down. Without a measured height the elevation is not used.
ELEVATION_OUTLIER = 0.1
ALONG_RAY = 0.25  # m: two options this much farther apart along her arm than across it are told apart by depth


def colour_name(rgb: tuple[float, float, float] | np.ndarray) -> str:
    """The nearest name in :data:`COLOURS` for an RGB colour."""
    c = np.asarray(rgb, dtype=float)
    return min(COLOURS, key=lambda n: float(np.sum((np.asarray(COLOURS[n]) - c) ** 2)))


@dataclass
class Candidate:
    """One object seen by the camera, its detections merged (map frame)."""

    x: float
    y: float
    z: float
    types: dict[str, int] = field(default_factory=dict)
    rgb_sum: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rgb_sq: np.ndarray = field(default_factory=lambda: np.zeros(3))
    n: int = 0
    size_sum: float = 0.0  # metres, over the detections that measured it
    size_n: int = 0
    tall_sum: float = 0.0  # metres from its surface to its top, over the detections that measured it
    tall_n: int = 0
    #: two objects the camera saw in most of its frames but could not tell apart (one behind the
    #: other on its line of sight, closer in depth than it resolves): a position between them
    two: bool = False
    #: with ``two``: the front and the back one, each the mean of the detections nearer (farther) to the
    #: camera in each frame that saw both (:func:`_front_back`), the options of a which-one question
    parts: tuple = ()

    @property
    def tall(self) -> float | None:
        """The mean height measured from the image (metres from its surface up), or None if not measured."""
        return self.tall_sum / self.tall_n if self.tall_n else None

    @property
    def size(self) -> float | None:
        """The mean size measured from the image (metres across), or None if no detection measured it."""
        return self.size_sum / self.size_n if self.size_n else None

    def add(self, type_: str, x: float, y: float, z: float, rgb: tuple[float, float, float], size: float | None = None,
            tall: float | None = None) -> None:
        """Merge one detection (running mean of the position, colour sums, type votes, size, height)."""
        if size is not None:
            self.size_sum += size
            self.size_n += 1
        if tall is not None:
            self.tall_sum += tall
            self.tall_n += 1
        k = self.n + 1
        self.x += (x - self.x) / k
        self.y += (y - self.y) / k
        self.z += (z - self.z) / k
        c = np.asarray(rgb, dtype=float)
        self.rgb_sum += c
        self.rgb_sq += c * c
        self.types[type_] = self.types.get(type_, 0) + 1
        self.n = k

    def absorb(self, other: Candidate) -> None:
        """Take in another candidate's detections (weighted mean position, summed colours and votes)."""
        k = self.n + other.n
        if k == 0:
            return
        self.x = (self.x * self.n + other.x * other.n) / k
        self.y = (self.y * self.n + other.y * other.n) / k
        self.z = (self.z * self.n + other.z * other.n) / k
        self.size_sum += other.size_sum
        self.size_n += other.size_n
        self.tall_sum += other.tall_sum
        self.tall_n += other.tall_n
        self.rgb_sum = self.rgb_sum + other.rgb_sum
        self.rgb_sq = self.rgb_sq + other.rgb_sq
        for t, v in other.types.items():
            self.types[t] = self.types.get(t, 0) + v
        self.n = k

    @property
    def type(self) -> str:
        """The type most detections reported (ties: alphabetical, for determinism)."""
        return max(sorted(self.types), key=lambda t: self.types[t])

    @property
    def rgb(self) -> np.ndarray:
        return self.rgb_sum / max(1, self.n)

    @property
    def colour(self) -> str:
        return colour_name(self.rgb)

    def features(self) -> np.ndarray:
        """Visual features: mean RGB, RGB standard deviation, and an 8-bin hue/brightness
        signature (soft votes of the mean colour), float64 (14,)."""
        mean = self.rgb
        std = np.sqrt(np.maximum(self.rgb_sq / max(1, self.n) - mean * mean, 0.0))
        r, g, b = mean
        mx, mn = float(max(mean)), float(min(mean))
        hue = 0.0
        if mx - mn > 1e-6:
            if mx == r:
                hue = ((g - b) / (mx - mn)) % 6
            elif mx == g:
                hue = (b - r) / (mx - mn) + 2
            else:
                hue = (r - g) / (mx - mn) + 4
        bins = np.zeros(8)
        sat = 0.0 if mx < 1e-6 else (mx - mn) / mx
        bins[int(hue / 6 * 6) % 6] += sat  # six hue sectors weighted by saturation
        bins[6] += (1 - sat) * mx  # grey-white
        bins[7] += (1 - sat) * (1 - mx)  # grey-black
        return np.concatenate([mean, std, bins / max(bins.sum(), 1e-9)])


def merge(
    detections: list[tuple[str, float, float, float, tuple[float, float, float]]] | list[tuple[str, float, float, float, tuple[float, float, float], float | None]],
    origin: tuple[float, float] | None = None,
    *,
    min_share: float = 0.25,
    eye_height: float | None = None,
    frames: list[float] | None = None,
) -> list[Candidate]:
    """Detections (type, x, y, z, rgb[, size]) -> candidates, in order of first sight.

    The camera measures bearings well (~1 degree) and distances poorly (~6 %), so two
    detections are one object when, seen from ``origin`` (the robot), their bearings differ by
    less than ``MERGE_BEARING`` and their ranges by less than ``MERGE_RANGE`` of the range, and
    their colours are alike; without an origin, when they lie within ``MERGE`` metres.
    With ``eye_height`` (the camera's height above the floor) the range is the camera's own
    slant distance to the point at its height ``z``, the quantity the camera's ~6 % noise is
    on: seen from above, the floor range of an object low down spreads far more (1.8x for a
    floor object 2 m from a camera 1.41 m high), and a gate on it split one object in two.
    Candidates whose means then pass the same gate are joined (an outlier seen first would
    otherwise start a second candidate for the same object).
    Candidates seen in fewer than ``min_share`` of the frames the best was seen in are
    dropped (a stray reading, a glimpse while the camera turned). With an origin, a candidate whose
    bearings fall in two groups is split (:func:`_split`), and a weak candidate between two
    stronger ones is dissolved into them (:func:`_dissolve_between`): every candidate's position is
    the mean of its own detections, never a point between two objects.
    With ``frames`` (each detection's capture time, one camera frame per time), the camera's own
    evidence of two things decides: it reports each object once per frame, so two objects side by
    side are seen together in most frames, and one object's detections never are. Parts of a
    split that were not seen together in ``CO_SEEN`` of the frames of the one seen less are one
    object (a noisy bearing or two, not a second cup), and so are two candidates close by
    (bearings within ``2 * MERGE_BEARING``, ranges within the gate, colours alike) never seen
    together: the partner is never asked to choose between two detections of one thing.
    """
    def gate(c: Candidate, x: float, y: float, z: float, rgb: np.ndarray) -> float | None:
        """How far a point is from a candidate (None: not the same object)."""
        if float(np.linalg.norm(c.rgb - rgb)) > 0.35:
            return None
        if origin is None:
            d = math.hypot(c.x - x, c.y - y)
            return d if d < MERGE else None
        r1, r2 = math.hypot(c.x - origin[0], c.y - origin[1]), math.hypot(x - origin[0], y - origin[1])
        if eye_height is not None:
            r1, r2 = math.hypot(r1, eye_height - c.z), math.hypot(r2, eye_height - z)
        da = abs(math.remainder(math.atan2(c.y - origin[1], c.x - origin[0]) - math.atan2(y - origin[1], x - origin[0]), 2 * math.pi))
        return da if da < MERGE_BEARING and abs(r1 - r2) < MERGE_RANGE * max(r1, r2) else None

    out: list[Candidate] = []
    members: dict[int, list[int]] = {}  # id(candidate) -> its detections' indices
    for k, det in enumerate(detections):
        type_, x, y, z, rgb = det[:5]
        size = det[5] if len(det) > 5 else None  # type: ignore[misc]
        tall = det[6] if len(det) > 6 else None  # type: ignore[misc]
        best, bd = None, math.inf
        for c in out:
            d = gate(c, x, y, z, np.asarray(rgb, dtype=float))
            if d is not None and d < bd:
                best, bd = c, d
        if best is None:
            best = Candidate(x, y, z)
            out.append(best)
            members[id(best)] = []
        best.add(type_, x, y, z, rgb, size, tall)
        members[id(best)].append(k)
    # A first sight that was an outlier splits one object in two: join candidates whose means
    # (far better than single detections) pass the same gate, the earlier one absorbing.
    joined = True
    while joined:
        joined = False
        for i, a in enumerate(out):
            for b in out[i + 1:]:
                if gate(a, b.x, b.y, b.z, b.rgb) is not None:
                    a.absorb(b)
                    members[id(a)] += members.pop(id(b))
                    out.remove(b)
                    joined = True
                    break
            if joined:
                break
    if origin is not None:
        split: list[tuple[Candidate, list[int]]] = []
        for c in out:
            for part, own in _split(c, members[id(c)], detections, origin, frames):
                split += _split_depth(part, own, detections, origin, frames, eye_height)
        split = _dissolve_between(split, detections, origin)
        if frames is not None:
            split = _join_apart(split, detections, origin, frames, eye_height)
            split = _split_counted(split, detections, origin, frames, eye_height)
            for c, idx in split:
                c.two = _holds_two(idx, frames)
                if c.two:
                    c.parts = _front_back(idx, detections, origin, frames, eye_height)
        out = [c for c, _ in split]
    top = max((c.n for c in out), default=0)
    return [c for c in out if c.n >= min_share * top]


def _bearing(origin: tuple[float, float], x: float, y: float) -> float:
    return math.atan2(y - origin[1], x - origin[0])


def _dissolve_between(parts: list[tuple[Candidate, list[int]]], detections: list, origin: tuple[float, float]) -> list[tuple[Candidate, list[int]]]:
    """A weak candidate lying between two stronger ones of its colour is their stray detections.

    Two objects a few bearing noises apart each throw a few detections towards the other; those
    that land in the middle can gate together into a weak third candidate whose mean lies between
    the two objects, a point where nothing stands. When a candidate holds fewer than half the
    detections of each of two stronger candidates of its colour whose bearings enclose its own,
    and lies within ``2 * MERGE_BEARING`` of both, it is dissolved: each of its detections goes to
    the nearer (in bearing) of the two, and their positions are again the means of their own
    detections. A real third object in the middle is seen in about as many frames as the others
    and is kept.
    """
    changed = True
    while changed:
        changed = False
        bearings = [_bearing(origin, c.x, c.y) for c, _ in parts]
        for i, (c, idx) in enumerate(parts):
            left = [j for j, (o, _) in enumerate(parts) if j != i and o.n >= 2 * c.n and float(np.linalg.norm(o.rgb - c.rgb)) <= 0.35
                    and 0 < math.remainder(bearings[j] - bearings[i], 2 * math.pi) <= 2 * MERGE_BEARING]
            right = [j for j, (o, _) in enumerate(parts) if j != i and o.n >= 2 * c.n and float(np.linalg.norm(o.rgb - c.rgb)) <= 0.35
                     and 0 < math.remainder(bearings[i] - bearings[j], 2 * math.pi) <= 2 * MERGE_BEARING]
            if not left or not right:
                continue
            a = min(left, key=lambda j: math.remainder(bearings[j] - bearings[i], 2 * math.pi))
            b = min(right, key=lambda j: math.remainder(bearings[i] - bearings[j], 2 * math.pi))
            groups = {a: list(parts[a][1]), b: list(parts[b][1])}
            for k in idx:
                d = detections[k]
                bk = _bearing(origin, d[1], d[2])
                near = a if abs(math.remainder(bk - bearings[a], 2 * math.pi)) <= abs(math.remainder(bk - bearings[b], 2 * math.pi)) else b
                groups[near].append(k)
            rebuilt = {j: (_from_detections(sorted(g), detections), sorted(g)) for j, g in groups.items()}
            parts = [rebuilt.get(j, p) for j, p in enumerate(parts) if j != i]
            changed = True
            break
    return parts


def _seen_together(a: list[int], b: list[int], frames: list[float]) -> bool:
    """Were the detections ``a`` and ``b`` seen in the same frames (``CO_SEEN`` of the frames of the
    one seen in fewer)? The camera reports an object once per frame: one object's detections are
    never seen together, two objects in view are seen together in nearly every frame."""
    fa, fb = {frames[k] for k in a}, {frames[k] for k in b}
    return len(fa & fb) >= CO_SEEN * min(len(fa), len(fb))


def _join_apart(parts: list[tuple[Candidate, list[int]]], detections: list, origin: tuple[float, float], frames: list[float],
                eye_height: float | None) -> list[tuple[Candidate, list[int]]]:
    """Join candidates close by (bearings within ``2 * MERGE_BEARING``, ranges within
    ``2 * MERGE_RANGE``, colours alike) that were never seen together: one object, not two.
    Both gates are twice the merge gate (8 noises): a lone detection 4.4 range noises off its
    cup (one in some 10 000) gated into a candidate of its own, and a second cup was offered
    where one stands (cup25); two objects in view are seen together in nearly every frame."""
    joined = True
    while joined:
        joined = False
        for i, (a, ia) in enumerate(parts):
            for j in range(i + 1, len(parts)):
                b, ib = parts[j]
                if float(np.linalg.norm(a.rgb - b.rgb)) > 0.35 or _seen_together(ia, ib, frames):
                    continue
                ra, rb = math.hypot(a.x - origin[0], a.y - origin[1]), math.hypot(b.x - origin[0], b.y - origin[1])
                if eye_height is not None:
                    ra, rb = math.hypot(ra, eye_height - a.z), math.hypot(rb, eye_height - b.z)
                da = abs(math.remainder(_bearing(origin, a.x, a.y) - _bearing(origin, b.x, b.y), 2 * math.pi))
                if da <= 2 * MERGE_BEARING and abs(ra - rb) < 2 * MERGE_RANGE * max(ra, rb):
                    own = sorted(ia + ib)
                    parts = [p for k, p in enumerate(parts) if k != j]
                    parts[i] = (_from_detections(own, detections), own)
                    joined = True
                    break
            if joined:
                break
    return parts


COUNT_MIN = 3  # objects: a group the camera sees this many of in one frame is re-cut by its count (two: _split, _split_depth)
POOL_BEARING = 3 * MERGE_BEARING  # candidates this close in bearing (and within the range gate) are counted together
COUNT_MAX = 6  # ... up to this many (a frame's one-to-one assignment tries every order)
COUNT_APART = 2.0  # noises: a re-cut's groups this far apart are told apart (one spot cut in three by the one-to-one rule: about 1)
COUNT_ROUNDS = 20  # the re-cut's rounds at most (it stops when no detection changes its object)


def _pools(parts: list[tuple[Candidate, list[int]]], origin: tuple[float, float], eye_height: float | None) -> list[list[int]]:
    """Indices of ``parts`` in groups: alike colours, bearings within ``POOL_BEARING`` and ranges
    within ``MERGE_RANGE`` of a neighbour in the group (what the camera may have blurred together: two
    objects merged into one candidate stand 1.5 spacings from the third's, 8.2 deg for three cups 5.5
    deg apart)."""
    def rng_(c: Candidate) -> float:
        r = math.hypot(c.x - origin[0], c.y - origin[1])
        return math.hypot(r, eye_height - c.z) if eye_height is not None else r

    owner = list(range(len(parts)))

    def root(i: int) -> int:
        while owner[i] != i:
            i = owner[i]
        return i

    for i, (a, _) in enumerate(parts):
        for j in range(i + 1, len(parts)):
            b = parts[j][0]
            if float(np.linalg.norm(a.rgb - b.rgb)) > 0.35:
                continue
            ra, rb = rng_(a), rng_(b)
            da = abs(math.remainder(_bearing(origin, a.x, a.y) - _bearing(origin, b.x, b.y), 2 * math.pi))
            if da <= POOL_BEARING and abs(ra - rb) < MERGE_RANGE * max(ra, rb):
                owner[max(root(i), root(j))] = min(root(i), root(j))
    groups: dict[int, list[int]] = {}
    for i in range(len(parts)):
        groups.setdefault(root(i), []).append(i)
    return [groups[k] for k in sorted(groups)]


def _counted(idx: list[int], frames: list[float]) -> int:
    """How many objects the camera saw among these detections: the largest count it reported in one
    frame in ``CO_SEEN`` of their frames (it reports each object once per frame)."""
    by_frame: dict[float, int] = {}
    for k in idx:
        by_frame[frames[k]] = by_frame.get(frames[k], 0) + 1
    counts = sorted(by_frame.values(), reverse=True)
    need = math.ceil(CO_SEEN * len(counts))
    return counts[need - 1] if need >= 1 else 0


def _split_counted(parts: list[tuple[Candidate, list[int]]], detections: list, origin: tuple[float, float], frames: list[float],
                   eye_height: float | None) -> list[tuple[Candidate, list[int]]]:
    """Three or more like objects close together, fewer candidates than the camera saw, cut again by count.

    The splits above cut two at a time, on one axis each (bearing, :func:`_split`; depth,
    :func:`_split_depth`). Three like books 0.25 m apart on a sideboard seen at a slant, 2 m away,
    lie 1.5 bearing noises and 2 range noises apart: neither axis alone separates them, the first
    cut took the near one off and kept the middle and the far one as one candidate marked ``two``,
    and the robot asked "the book on the left or the one on the right?" for three books
    (fresh11/rail_three_books). The camera reports each object once per frame: a group of
    candidates (:func:`_pools`) whose frames hold ``m`` >= ``COUNT_MIN`` detections (in ``CO_SEEN``
    of them) holds ``m`` objects. Such a group with no more than ``m`` candidates is cut into ``m``
    again (the cuts two at a time also crossed two books now and then, each part half of each):
    each detection placed by its bearing and log slant range, each in its own noise; the ``m``
    groups start as the quantiles along the detections' main axis, and each frame's detections go
    one to each group (the assignment of least squared distance; extra ones to the nearest group),
    the groups' means moved, until no detection changes group. The cut is kept when every two
    groups' means lie ``COUNT_APART`` noises apart (one spot's detections cut by the same rule lie
    about one noise apart, at most 1.65 in 1200 simulated looks); each is the mean of its own
    detections, never a point between two objects, in the place of the pool's first candidate.
    Otherwise, or when the cut finds the same groups, the candidates stay as they were."""
    put: dict[int, list[tuple[Candidate, list[int]]]] = {}  # a pool's first part -> what stands in the pool's place
    gone: set[int] = set()
    for pool in _pools(parts, origin, eye_height):
        idx = sorted(k for i in pool for k in parts[i][1])
        m = _counted(idx, frames)
        if m < COUNT_MIN or m > COUNT_MAX or m < len(pool) or len(idx) < SPLIT_MIN:
            continue
        cut = _cut_by_count(idx, m, detections, origin, frames, eye_height)
        if cut is None or sorted(cut) == sorted(sorted(parts[i][1]) for i in pool):
            continue  # (the same objects as the cuts above found: left as they are, in their order)
        put[pool[0]] = [(_from_detections(own, detections), own) for own in cut]
        gone.update(pool)
    out: list[tuple[Candidate, list[int]]] = []
    for i, part in enumerate(parts):
        if i in put:
            out += put[i]
        elif i not in gone:
            out.append(part)
    return out


def _cut_by_count(idx: list[int], m: int, detections: list, origin: tuple[float, float], frames: list[float],
                  eye_height: float | None) -> list[list[int]] | None:
    """The detections ``idx`` cut into ``m`` objects (see :func:`_split_counted`), or None when the
    camera cannot tell them apart."""
    ox, oy = origin
    ref = math.atan2(sum(detections[k][2] for k in idx) / len(idx) - oy, sum(detections[k][1] for k in idx) / len(idx) - ox)
    pts = {}
    for k in idx:
        d = detections[k]
        r = math.hypot(d[1] - ox, d[2] - oy)
        if eye_height is not None:
            r = math.hypot(r, eye_height - d[3])
        pts[k] = np.array([math.remainder(math.atan2(d[2] - oy, d[1] - ox) - ref, 2 * math.pi) / BEARING_NOISE,
                           math.log(max(r, 1e-3)) / RANGE_NOISE])
    arr = np.array([pts[k] for k in idx])
    centre = arr.mean(axis=0)
    w, v = np.linalg.eigh(np.cov((arr - centre).T))
    main = v[:, int(np.argmax(w))]
    if main[0] < 0 or (main[0] == 0 and main[1] < 0):
        main = -main  # one sign, for determinism
    by_frame: dict[float, list[int]] = {}
    for k in idx:
        by_frame.setdefault(frames[k], []).append(k)
    best: tuple[float, list[list[int]], list[np.ndarray]] | None = None
    # three starts (the quantiles along the main axis, along the bearing, along the range): the one
    # of least squared distance wins (one start alone ends now and then with two groups crossed)
    for axis in (main, np.array([1.0, 0.0]), np.array([0.0, 1.0])):
        order = sorted(idx, key=lambda k: (float(pts[k] @ axis), k))
        means = [np.mean([pts[k] for k in chunk], axis=0) for chunk in np.array_split(np.array(order), m)]
        got = _assign_rounds(by_frame, pts, means, m)
        if got is not None and (best is None or got[0] < best[0] - 1e-9):
            best = got
    if best is None:
        return None
    _, groups, means = best
    for a, b in itertools.combinations(means, 2):
        if float(np.linalg.norm(a - b)) < COUNT_APART:
            return None
    return groups


def _assign_rounds(by_frame: dict[float, list[int]], pts: dict, means: list, m: int):
    """Rounds of one-to-one assignment per frame and new means, from ``means``, until no detection
    changes group: (squared distance summed, groups, means), or None when a group ends empty."""
    groups: list[list[int]] | None = None
    total = math.inf
    for _ in range(COUNT_ROUNDS):
        new: list[list[int]] = [[] for _ in range(m)]
        total = 0.0
        for t in sorted(by_frame):
            ks = by_frame[t]
            cost = [[float(np.sum((pts[k] - mu) ** 2)) for mu in means] for k in ks]
            head = ks[:m]
            least, pick = math.inf, ()
            for perm in itertools.permutations(range(m), len(head)):
                c = sum(cost[i][g] for i, g in enumerate(perm))
                if c < least:
                    least, pick = c, perm
            total += least
            for i, g in enumerate(pick):
                new[g].append(ks[i])
            for i in range(len(head), len(ks)):
                g = min(range(m), key=lambda g: cost[i][g])
                total += cost[i][g]
                new[g].append(ks[i])
        if any(not g for g in new):
            return None
        new = [sorted(g) for g in new]
        if new == groups:
            break
        groups = new
        means = [np.mean([pts[k] for k in g], axis=0) for g in groups]
    assert groups is not None
    return total, groups, means


def _from_detections(idx: list[int], detections: list) -> Candidate:
    """A candidate made of exactly these detections (in their order)."""
    first = detections[idx[0]]
    c = Candidate(first[1], first[2], first[3])
    c.x = c.y = c.z = 0.0
    for k in idx:
        d = detections[k]
        c.add(d[0], d[1], d[2], d[3], d[4], d[5] if len(d) > 5 else None, d[6] if len(d) > 6 else None)
    return c


def _split(c: Candidate, idx: list[int], detections: list, origin: tuple[float, float],
           frames: list[float] | None = None) -> list[tuple[Candidate, list[int]]]:
    """Two objects side by side, merged into one candidate, made two again.

    The camera's bearings of one object spread by its noise (``BEARING_NOISE``); those of two
    objects a few noises apart (two cups 0.1 m apart 2 m away are 2.9 degrees apart) spread
    more. When a candidate's bearings spread more than ``SPLIT_SPREAD`` noises, they are cut
    in two at the largest gap of the sorted bearings' two-means split; if both groups hold a
    quarter of the detections and their means lie ``SPLIT_APART`` noises apart, they are two
    candidates, each the mean of its own detections (never a position between two objects),
    and each is split again the same way (three objects side by side).
    With ``frames``, the two groups must also have been seen together (:func:`_seen_together`):
    an outlier or two of one object's bearings fall apart from the rest, but never in the same frame.
    ``idx``: the candidate's detections (indices into ``detections``); returns each part with its own.
    """
    n = len(idx)
    if n < 8:
        return [(c, idx)]
    ox, oy = origin
    ref = math.atan2(c.y - oy, c.x - ox)
    b = sorted((math.remainder(math.atan2(detections[k][2] - oy, detections[k][1] - ox) - ref, 2 * math.pi), k) for k in idx)
    vals = [v for v, _ in b]
    mean = sum(vals) / n
    if math.sqrt(sum((v - mean) ** 2 for v in vals) / (n - 1)) <= SPLIT_SPREAD * BEARING_NOISE:
        return [(c, idx)]
    best, cut = math.inf, -1
    for i in range(max(2, n // 4), n - max(2, n // 4) + 1):  # each side at least a quarter
        lo, hi = vals[:i], vals[i:]
        ml, mh = sum(lo) / len(lo), sum(hi) / len(hi)
        sse = sum((v - ml) ** 2 for v in lo) + sum((v - mh) ** 2 for v in hi)
        if sse < best:
            best, cut = sse, i
    if cut < 0:
        return [(c, idx)]
    lo, hi = vals[:cut], vals[cut:]
    if sum(hi) / len(hi) - sum(lo) / len(lo) < SPLIT_APART * BEARING_NOISE:
        return [(c, idx)]
    if frames is not None and not _seen_together([k for _, k in b[:cut]], [k for _, k in b[cut:]], frames):
        return [(c, idx)]
    parts = []
    for group in (b[:cut], b[cut:]):  # each part may itself be two objects (three side by side)
        own = sorted(k for _, k in group)
        parts += _split(_from_detections(own, detections), own, detections, origin, frames)
    return parts


def _holds_two(idx: list[int], frames: list[float]) -> bool:
    """The camera reports an object once per frame: detections of one candidate seen two (or
    more) in one frame in ``CO_SEEN`` of its frames, ``SPLIT_MIN`` or more, are two objects the
    splits could not tell apart (:func:`_split_depth` keeps them one when their ranges are closer
    than the camera resolves)."""
    if len(idx) < SPLIT_MIN:
        return False
    by_frame: dict[float, int] = {}
    for k in idx:
        by_frame[frames[k]] = by_frame.get(frames[k], 0) + 1
    return sum(1 for n in by_frame.values() if n >= 2) >= CO_SEEN * len(by_frame)


def _front_back(idx: list[int], detections: list, origin: tuple[float, float], frames: list[float],
                eye_height: float | None) -> tuple:
    """The two objects of a ``two`` candidate as (front, back): in each frame that saw two or more, the
    nearer detection (the camera's own distance) goes to the front one, the others to the back one; each
    the mean of its own detections (their ranges are too close for the camera to place them well, but
    neither is the point between them). Empty when no frame saw two."""
    ox, oy = origin

    def rng_(k: int) -> float:
        d = detections[k]
        r = math.hypot(d[1] - ox, d[2] - oy)
        return math.hypot(r, eye_height - d[3]) if eye_height is not None else r

    by_frame: dict[float, list[int]] = {}
    for k in idx:
        by_frame.setdefault(frames[k], []).append(k)
    front: list[int] = []
    back: list[int] = []
    for t in sorted(by_frame):
        ks = sorted(by_frame[t], key=lambda k: (rng_(k), k))
        if len(ks) >= 2:
            front.append(ks[0])
            back += ks[1:]
    if not front or not back:
        return ()
    return (_from_detections(sorted(front), detections), _from_detections(sorted(back), detections))


def _split_depth(c: Candidate, idx: list[int], detections: list, origin: tuple[float, float], frames: list[float] | None,
                 eye_height: float | None) -> list[tuple[Candidate, list[int]]]:
    """Two objects one behind the other along the camera's line of sight, merged, made two again.

    Their bearings agree, so :func:`_split` cannot tell them apart, and the range gate
    (``MERGE_RANGE``) is measured from a running mean that drifts between them: two mugs 0.3 m
    apart 1.5 m away became one candidate at the point between them, where nothing stands.
    The camera reports each object once per frame, so a candidate that holds two detections in
    ``CO_SEEN`` of its frames holds two objects: in each frame the nearer detection (by the
    camera's own distance, slant with ``eye_height``) goes to the front part, the others to the
    back part, and a lone detection to the part whose mean range (log: the noise is relative) is
    nearer. If the parts' mean ranges lie ``SPLIT_APART`` range noises apart, they are two
    candidates, each the mean of its own detections, and each is split again (three in a row).
    Closer than that, pairs of one range ordered by their noise alone drift apart by about one
    noise: the camera cannot resolve them, and they stay one, marked ``two`` (:func:`_holds_two`):
    the object attention then looks from another side before it stores either. Needs ``frames``."""
    if frames is None or len(idx) < SPLIT_MIN:
        return [(c, idx)]
    ox, oy = origin

    def rng_(k: int) -> float:
        d = detections[k]
        r = math.hypot(d[1] - ox, d[2] - oy)
        if eye_height is not None:
            r = math.hypot(r, eye_height - d[3])
        return math.log(max(r, 1e-3))

    by_frame: dict[float, list[int]] = {}
    for k in idx:
        by_frame.setdefault(frames[k], []).append(k)
    if sum(1 for ks in by_frame.values() if len(ks) >= 2) < CO_SEEN * len(by_frame):
        return [(c, idx)]
    front: list[int] = []
    back: list[int] = []
    single: list[int] = []
    for t in sorted(by_frame):
        ks = sorted(by_frame[t], key=lambda k: (rng_(k), k))
        if len(ks) == 1:
            single.append(ks[0])
        else:
            front.append(ks[0])
            back += ks[1:]
    mf = sum(rng_(k) for k in front) / len(front)
    mb = sum(rng_(k) for k in back) / len(back)
    if mb - mf < SPLIT_APART * RANGE_NOISE:
        return [(c, idx)]
    for k in single:
        (front if abs(rng_(k) - mf) <= abs(rng_(k) - mb) else back).append(k)
    parts = []
    for group in (front, back):
        own = sorted(group)
        parts += _split_depth(_from_detections(own, detections), own, detections, origin, frames, eye_height)
    return parts


@dataclass(frozen=True)
class Pointing:
    """A pointing ray in the map frame: the hand (x, y, z) and the arm's direction and elevation (rad);
    ``sigma``: the standard error of the measured direction (rad; None: unknown)."""

    x: float
    y: float
    z: float
    direction: float
    elevation: float
    sigma: float | None = None

    @property
    def spread(self) -> float:
        """How far off the ray (1 sigma, rad) the object pointed at may lie: aim and measurement."""
        return GESTURE_SIGMA if self.sigma is None else math.hypot(AIM_SIGMA, self.sigma)

    def angle_to(self, x: float, y: float, z: float) -> float:
        """Angle (rad) between the ray and the direction from the hand to a point."""
        d = np.array([x - self.x, y - self.y, z - self.z])
        n = float(np.linalg.norm(d))
        if n < 1e-9:
            return 0.0
        u = np.array([math.cos(self.elevation) * math.cos(self.direction), math.cos(self.elevation) * math.sin(self.direction), math.sin(self.elevation)])
        return math.acos(max(-1.0, min(1.0, float(d @ u) / n)))

    def elevation_off(self, c: Candidate) -> float | None:
        """How far (rad) the ray's elevation passes above or below the candidate's middle, seen from
        the hand; None without its measured height (:attr:`Candidate.tall`), or within ``NEAR_HAND``
        of the hand along the floor (there a few centimetres' difference is a large angle)."""
        r = math.hypot(c.x - self.x, c.y - self.y)
        if c.tall is None or r < NEAR_HAND:
            return None
        middle = c.z - 0.05 + c.tall / 2  # candidates stand 0.05 m above their surface
        return abs(self.elevation - math.atan2(middle - self.z, r))

    def elevation_likelihood(self, c: Candidate) -> float:
        """The ray's elevation as evidence for a candidate (1 on it, down to ``ELEVATION_OUTLIER`` far off)."""
        off = self.elevation_off(c)
        if off is None:
            return 1.0
        return (1.0 - ELEVATION_OUTLIER) * math.exp(-0.5 * (off / self.spread) ** 2) + ELEVATION_OUTLIER

    def angle_horizontal(self, x: float, y: float) -> float:
        """Angle (rad) between the ray's heading and the hand-to-point heading, on the floor plan."""
        return abs(math.remainder(math.atan2(y - self.y, x - self.x) - self.direction, 2 * math.pi))

    def angle_off(self, x: float, y: float) -> float:
        """How far off the ray a point lies, as an angle on the floor plan: seen from the hand, but
        for a point nearer the hand along the ray than ``NEAR_HAND`` from that far out (its sideways
        offset over ``NEAR_HAND``): just past her hand a few centimetres are a large angle."""
        dx, dy = x - self.x, y - self.y
        c, s = math.cos(self.direction), math.sin(self.direction)
        along, side = dx * c + dy * s, abs(-dx * s + dy * c)
        if 0.0 < along < NEAR_HAND:
            return math.atan2(side, NEAR_HAND)
        return self.angle_horizontal(x, y)


@dataclass(frozen=True)
class Wanted:
    """What the speech frame says of the object (lower case; empty: not said)."""

    type: str = ""
    name: str = ""
    colour: str = ""
    owner: str = ""
    attribute: str = ""


@dataclass(frozen=True)
class Scored:
    candidate: Candidate
    score: float
    fits: bool
    why: str


@dataclass(frozen=True)
class Resolution:
    kind: str  # "one", "ambiguous", "none"
    ranked: tuple[Scored, ...]
    reason: str = ""

    @property
    def best(self) -> Candidate | None:
        return self.ranked[0].candidate if self.ranked and self.ranked[0].fits else None

    def fitting(self) -> list[Candidate]:
        return [s.candidate for s in self.ranked if s.fits]


def learned_type(c: Candidate, wanted: Wanted) -> str:
    """The type an object is stored as: the user's own word when the camera saw the object as just
    that (most of its detections), else the speech frame's type, else what the camera saw most.

    The lexicon maps a word to the class it is understood by ("toaster", "microwave" and "grill"
    are all understood as a ``stove``), so that a request finds the object; but her toaster is a
    toaster: the class must not replace the thing she named by another appliance when the
    camera itself tells them apart. A word the camera has no class for ("lemon tree": a plant)
    keeps the frame's type, and her word stays the object's name either way."""
    word = "_".join(wanted.name.split())
    if word and word != wanted.type and c.n and c.types.get(word, 0) * 2 > c.n:
        return word
    return wanted.type or c.type


def score(c: Candidate, wanted: Wanted, pointing: Pointing | None, origin: tuple[float, float]) -> Scored:
    """How well one candidate fits what was said and shown (a likelihood, up to a constant)."""
    s, fits, why = 1.0, True, []
    kinds = {t for t in (wanted.type, wanted.name) if t}
    if kinds:
        share = sum(v for t, v in c.types.items() if t in kinds) / max(1, c.n)
        s *= 0.1 + 0.9 * share  # a confused detector: other types only score down
        if share < TYPE_SHARE:
            why.append(f"seen as {c.type}")
            if share == 0.0:
                s *= 0.5
            if c.n >= TYPE_EVIDENCE:  # confusion is rare: this many detections, (almost) none of the type
                fits = False
    if wanted.colour:
        ref = COLOURS.get(COLOUR_ALIASES.get(wanted.colour, wanted.colour))
        if ref is not None:
            d = float(np.linalg.norm(c.rgb - np.asarray(ref)))
            s *= math.exp(-0.5 * (d / 0.15) ** 2) + 1e-3
            if d > COLOUR_FIT:
                fits = False
                why.append(f"{c.colour}, not {wanted.colour}")
    if pointing is not None:
        a = pointing.angle_off(c.x, c.y)
        s *= (math.exp(-0.5 * (a / pointing.spread) ** 2) + 1e-3) * pointing.elevation_likelihood(c)
        if a > GESTURE_FIT:
            fits = False
            why.append(f"{math.degrees(a):.0f} deg off the pointing")
        dist = math.hypot(c.x - pointing.x, c.y - pointing.y)
    else:
        dist = math.hypot(c.x - origin[0], c.y - origin[1])
    s *= 1.0 / (1.0 + 0.2 * dist)
    if kinds and all(t not in c.types for t in kinds) and not wanted.colour and pointing is None:
        fits = False  # nothing but the type to go by, and the type is wrong
    return Scored(c, s, fits, "; ".join(why))


def resolve(candidates: list[Candidate], wanted: Wanted, pointing: Pointing | None, origin: tuple[float, float]) -> Resolution:
    """Rank the candidates; decide one, ambiguous (ask) or none (see the module docstring)."""
    if not candidates:
        return Resolution("none", (), "nothing_seen")
    ranked = sorted((score(c, wanted, pointing, origin) for c in candidates), key=lambda r: -r.score)
    fit = [r for r in ranked if r.fits]
    # Fitting candidates first, each group best first (sorted is stable).
    ranked = sorted(ranked, key=lambda r: not r.fits)
    if not fit:
        return Resolution("none", tuple(ranked), "no_match")
    if len(fit) == 1 or fit[0].score >= CLEAR * fit[1].score:
        return Resolution("one", tuple(ranked))
    return Resolution("ambiguous", tuple(ranked))


def choose_pointed(cands: list[Candidate], gestures: list[Pointing]) -> Candidate | None:
    """Of candidates she was asked to choose from, the one several gestures at the same object
    point at: each gesture's aim errs on its own, so their likelihoods (as in :func:`score`: across the
    ray and, by the arm's elevation, along it) multiply. The best when it is ``ANSWER_CLEAR`` times as likely as the next and within
    ``GESTURE_FIT`` of every gesture; else None."""
    if not cands or not gestures:
        return None
    ranked = []
    for c in cands:
        like, fits = 1.0, True
        for g in gestures:
            a = g.angle_off(c.x, c.y)
            like *= (math.exp(-0.5 * (a / g.spread) ** 2) + 1e-6) * g.elevation_likelihood(c)
            fits = fits and a <= GESTURE_FIT
        ranked.append((like, fits, c))
    ranked.sort(key=lambda r: -r[0])
    best = ranked[0]
    if not best[1] or (len(ranked) > 1 and best[0] < ANSWER_CLEAR * ranked[1][0]):
        return None
    return best[2]


def along_ray(cands: list[Candidate], pointing: Pointing | None) -> list[int] | None:
    """The candidates' order from her hand outwards (indices) when they stand one behind the other
    along her arm: each next one at least ``ALONG_RAY`` farther out and farther out than twice its
    offset across the arm from the one before (two plants by a wardrobe, in line with her arm: left
    and right tell them apart badly, "the one in front" well); None otherwise."""
    if pointing is None or len(cands) < 2:
        return None
    c, s = math.cos(pointing.direction), math.sin(pointing.direction)
    along = [(k.x - pointing.x) * c + (k.y - pointing.y) * s for k in cands]
    across = [-(k.x - pointing.x) * s + (k.y - pointing.y) * c for k in cands]
    order = sorted(range(len(cands)), key=lambda i: along[i])
    for a, b in zip(order, order[1:]):
        gap = along[b] - along[a]
        if gap < ALONG_RAY or gap <= 2 * abs(across[b] - across[a]):
            return None
    return order


#: The words of an option by its place along her arm (index: from her hand outwards).
DEPTH_WORDS = {2: ("in front", "behind it"), 3: ("in front", "in the middle", "at the back")}


def option_texts(cands: list[Candidate], wanted: Wanted, robot_pose: tuple[float, float, float],
                 pointing: Pointing | None = None) -> list[str]:
    """Words that tell the candidates apart: "the red cup", "the blue one"; by side or distance
    when the colours are the same ("the cup on the left", "the one on the right"). Different colours
    are said with their side too when the sides differ by ``SIDE_APART`` or more ("the green book on
    the right", "the brown one on the left"): people answer "which one?" by colour or by side alike,
    and the answer is matched to the words of the options.
    Options one behind the other along her arm (:func:`along_ray`, with ``pointing``) are told apart by
    depth: "the plant in front", "the one behind it" when they stand in the same order from her and
    from the robot; two that do not (the robot sees them from the other side) are "the plant nearer to
    you" and "the one nearer to me" (the robot speaking). Two the robot sees ``SIDE_APART`` apart say
    their side after it ("the plant in front on the right"): she may answer by either."""
    noun = wanted.name or wanted.type or cands[0].type
    colours = [c.colour for c in cands]
    x, y, th = robot_pose
    side = [math.remainder(math.atan2(c.y - y, c.x - x) - th, 2 * math.pi) for c in cands]
    order = sorted(range(len(cands)), key=lambda i: -side[i])  # leftmost first
    words = {}
    depth = along_ray(cands, pointing) if len(cands) in DEPTH_WORDS else None
    if len(cands) == 2:
        words[order[0]], words[order[1]] = "on the left", "on the right"
    else:
        for rank, i in enumerate(order):
            words[i] = "on the left" if rank == 0 else "on the right" if rank == len(cands) - 1 else "in the middle"
    if depth is not None:
        from_robot = sorted(range(len(cands)), key=lambda i: math.hypot(cands[i].x - x, cands[i].y - y))
        if from_robot == depth:
            deep = dict(zip(depth, DEPTH_WORDS[len(cands)]))
        elif len(cands) == 2 and from_robot == depth[::-1]:
            deep = {depth[0]: "nearer to you", depth[1]: "nearer to me"}
        else:
            deep = None
        if deep is not None:
            # their sides too when the robot sees them apart: she may answer by side as well
            sides = len(cands) == 2 and abs(side[order[0]] - side[order[1]]) >= SIDE_APART
            words = {i: deep[i] + (f" {words[i]}" if sides else "") for i in range(len(cands))}
        else:
            depth = None
    if len(set(colours)) == len(colours):
        apart = depth is not None or all(abs(side[a] - side[b]) >= SIDE_APART for a, b in zip(order, order[1:]))
        return [(f"the {col} {noun}" if i == 0 else f"the {col} one") + (f" {words[i]}" if apart else "") for i, col in enumerate(colours)]
    return [f"the {noun} {words[i]}" if i == 0 else f"the one {words[i]}" for i in range(len(cands))]
