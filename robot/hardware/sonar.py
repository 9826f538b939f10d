"""The PeopleBot's sonar rings: sixteen ultrasonic range readings all round the base.

The laser looks ahead only (180 degrees from 0.13 m ahead of the centre); the robot's sides and
back are seen by the Pioneer base's two rings of eight Polaroid-type transducers, front and rear,
at about 0.2 m above the floor (the PeopleBot's base ring). The layout follows the Pioneer's:
each ring at -90, -50, -30, -10, 10, 30, 50, 90 degrees (front) and the mirror of it (rear),
the transducers on the footprint's edge.

A reading is the nearest echo within the transducer's cone (``cone`` wide, sampled by ``rays``
rays): walls and furniture that reach the sonar's height and people's legs (a sonar does not
tell a leg from a wall). Each ring fires one transducer every ``fire_interval`` s (the Pioneer's
25 Hz per ring, a whole ring in 0.32 s); the base reports the readings fired since its last
packet at ``rate`` Hz, as the Pioneer's server information packets do. Noise: Gaussian with a
standard deviation of ``noise + noise_per_m * range``; a reading is lost now and then
(``dropout``: a specular reflection that never comes back, crosstalk), which reads
``max_range``, the "no echo" value, like a cone that met nothing. An echo nearer than
``min_range`` (inside the transducer's ring-down) reads ``min_range``: "something this close
or closer". All randomness comes from the module's generator.

Published on ``/robot/sonar`` as ``<sonar seq time min_range max_range cone height>`` with one
``<echo id x y bearing range/>`` per new reading (the transducer's place and bearing in the robot
frame, so a receiver needs no table of them), sent as a typed record
(:class:`~robot.sonar_packet.SonarPacket`: its readers share it, the XML is built when read).
"""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from homesim.kernels import load
from homesim.module import Module
from homesim.world.raycast import RayCaster
from robot.contract import SONAR
from robot.sonar_packet import SonarPacket

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World

__all__ = ["SonarSpec", "Sonar", "PEOPLEBOT_RING", "SegmentRanges", "sonar_readings", "sonar_packet", "sonar_element", "noisy", "SONAR"]

#: (x, y, bearing deg) of the sixteen transducers, robot frame: the front ring right to left, then
#: the rear ring left to right (the Pioneer's numbering), on the 0.51 x 0.43 m footprint's edge.
PEOPLEBOT_RING: tuple[tuple[float, float, float], ...] = (
    (0.10, -0.215, -90.0), (0.215, -0.17, -50.0), (0.255, -0.10, -30.0), (0.255, -0.035, -10.0),
    (0.255, 0.035, 10.0), (0.255, 0.10, 30.0), (0.215, 0.17, 50.0), (0.10, 0.215, 90.0),
    (-0.10, 0.215, 90.0), (-0.215, 0.17, 130.0), (-0.255, 0.10, 150.0), (-0.255, 0.035, 170.0),
    (-0.255, -0.035, -170.0), (-0.255, -0.10, -150.0), (-0.215, -0.17, -130.0), (-0.10, -0.215, -90.0),
)


@dataclass(frozen=True)
class SonarSpec:
    """Geometry, timing and noise of the rings (defaults: the PeopleBot's Pioneer sonars)."""

    transducers: tuple[tuple[float, float, float], ...] = PEOPLEBOT_RING
    rings: int = 2  # fired in parallel, each in turn through its share of ``transducers``
    cone: float = math.radians(30.0)  # full width of a transducer's main lobe
    rays: int = 7  # rays sampling the cone
    min_range: float = 0.10
    max_range: float = 5.0
    noise: float = 0.01  # m
    noise_per_m: float = 0.01  # m per m of range
    dropout: float = 0.03  # probability that a reading is lost (reads max_range)
    height: float = 0.20
    fire_interval: float = 0.04  # s between two firings of one ring
    rate: float = 10.0  # packets per second
    offsets: tuple[float, ...] = field(init=False, default=())
    #: per transducer: x, y and bearing (radians, ``math.radians``' floats), as arrays for one pass over a packet
    _tx: np.ndarray = field(init=False, repr=False, compare=False, default=None)  # type: ignore[assignment]
    _ty: np.ndarray = field(init=False, repr=False, compare=False, default=None)  # type: ignore[assignment]
    _tb: np.ndarray = field(init=False, repr=False, compare=False, default=None)  # type: ignore[assignment]
    #: the message's fixed attribute texts: the packet's (min_range, max_range, cone, height), each transducer's (id, x, y, bearing)
    _head: tuple[str, str, str, str] = field(init=False, repr=False, compare=False, default=("", "", "", ""))
    _text: tuple[tuple[str, str, str, str], ...] = field(init=False, repr=False, compare=False, default=())

    def __post_init__(self) -> None:
        if self.rays < 1 or self.rings < 1 or len(self.transducers) % self.rings:
            raise ValueError("a sonar needs at least one ray and ring, and rings of equal size")
        half = self.cone / 2
        offs = (0.0,) if self.rays == 1 else tuple(float(a) for a in np.linspace(-half, half, self.rays))
        object.__setattr__(self, "offsets", offs)
        object.__setattr__(self, "_tx", np.array([t[0] for t in self.transducers], dtype=float))
        object.__setattr__(self, "_ty", np.array([t[1] for t in self.transducers], dtype=float))
        object.__setattr__(self, "_tb", np.array([math.radians(t[2]) for t in self.transducers], dtype=float))
        object.__setattr__(self, "_head", (f"{self.min_range:.3f}", f"{self.max_range:.3f}", f"{math.degrees(self.cone):.3f}", f"{self.height:.3f}"))
        object.__setattr__(self, "_text", tuple((str(i), f"{tx:.3f}", f"{ty:.3f}", f"{tb:.3f}") for i, (tx, ty, tb) in enumerate(self.transducers)))

    @property
    def per_ring(self) -> int:
        return len(self.transducers) // self.rings

    def firing(self, k: int) -> tuple[int, ...]:
        """The transducers fired at the ``k``-th firing (one per ring, each ring in its own order)."""
        i = k % self.per_ring
        return tuple(r * self.per_ring + i for r in range(self.rings))


#: the compiled cast of a packet (``sonar_ranges`` in homesim/world/_raykernels.c), None: the numpy path
_K = load("homesim.world._raykernels", 2)

_NO_SEGS = np.zeros((0, 2))
_NO_LEGS = np.zeros((0, 2))
_NO_RADII = np.zeros(0)


def cast_from(ox: np.ndarray, oy: np.ndarray, angles: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, r: np.ndarray,
              max_range: float) -> np.ndarray:
    """Ranges (N,) along rays from their own origins (``ox``, ``oy``, ``angles``: (N,)) to the first wall
    segment (``a``, ``b``) or leg circle (``c``, ``r``) hit, ``max_range`` where none: what
    :class:`~homesim.world.raycast.RayCaster` computes ray by ray, float for float (the same operations
    on each element), for a packet's rays all at once: a packet's few dozen rays from a handful of
    transducers cost one pass instead of one cast per transducer."""
    n = angles.shape[0]
    result = np.full(n, max_range)
    dx, dy = np.cos(angles)[:, None], np.sin(angles)[:, None]
    ox, oy = ox[:, None], oy[:, None]
    if a.shape[0]:
        ex, ey = (b[:, 0] - a[:, 0])[None, :], (b[:, 1] - a[:, 1])[None, :]
        fx, fy = a[None, :, 0] - ox, a[None, :, 1] - oy
        den = dx * ey - dy * ex
        u = fx * dy - fy * dx
        tnum = fx * ey - fy * ex
        sign = np.sign(den)
        u = u * sign
        den = np.abs(den)
        t = tnum * sign
        mask = (t >= 0.0) & (u >= 0.0) & (u <= den) & (den > 1e-15)
        t = np.divide(t, den, out=np.full_like(t, np.inf), where=mask)
        np.minimum(result, t.min(axis=1), out=result)
    if c.shape[0]:
        fx, fy = c[None, :, 0] - ox, c[None, :, 1] - oy
        ff = fx * fx + fy * fy
        rr = (r * r)[None, :]
        tca = dx * fx
        tca += dy * fy
        disc = tca * tca
        disc += rr - ff
        hit = disc >= 0.0
        root = np.sqrt(disc, out=np.zeros_like(disc), where=hit)
        near = np.subtract(tca, root, out=np.full_like(tca, np.inf), where=hit)
        hit &= near >= 0.0
        near[~hit] = np.inf
        near[ff <= rr] = 0.0
        np.minimum(result, near.min(axis=1), out=result)
    return result


class SegmentRanges:
    """The walls' and furniture's part of the readings, kept while the robot stands still.

    A reading is the minimum over everything its rays hit, and a minimum is exact, so the segments'
    per-ray ranges of a transducer cast at one pose serve every later packet at that same pose (the
    same floats): a robot standing still (talking, waiting, being shown a room) casts only the legs.
    Bounded: one (rays,) array per transducer, for one pose and one set of segments. The segments are
    recognised by identity and only when read-only (the world's are); anything else is cast anew."""

    __slots__ = ("_key", "_seg", "_rays", "_ring", "_ring_key")

    def __init__(self) -> None:
        self._key: tuple[float, float, float] | None = None
        self._seg: tuple[np.ndarray, np.ndarray] | None = None
        self._rays: dict[int, np.ndarray] = {}
        self._ring: tuple[np.ndarray, ...] | None = None  # every transducer's rays at _ring_key (origins, angles, directions)
        self._ring_key: tuple[SonarSpec, tuple[float, float, float]] | None = None

    def ring(self, spec: SonarSpec, pose: tuple[float, float, float]) -> tuple[np.ndarray, ...]:
        """Every transducer's ray origins, angles and directions at ``pose`` (:func:`_ring_at`), kept for as
        long as the pose stays the same."""
        if self._ring is None or self._ring_key is None or self._ring_key[1] != pose or self._ring_key[0] is not spec:
            self._ring = _ring_at(spec, pose)
            self._ring_key = (spec, pose)
        return self._ring

    def get(self, pose: tuple[float, float, float], a: np.ndarray, b: np.ndarray) -> dict[int, np.ndarray] | None:
        """The kept per-transducer ranges for ``pose`` and segments (``a``, ``b``), emptied when either
        changed; None when the segments cannot be recognised (writeable arrays)."""
        if a.flags.writeable or b.flags.writeable:
            return None
        seg = self._seg
        if self._key != pose or seg is None or seg[0] is not a or seg[1] is not b:
            self._key, self._seg = pose, (a, b)
            self._rays.clear()
        return self._rays


def _ring_at(spec: SonarSpec, pose: tuple[float, float, float]) -> tuple[np.ndarray, ...]:
    """Every transducer's rays at ``pose``: origins x, y, angles, and the angles' cosines and sines
    ((transducers, rays) each, :func:`_rays_of`'s floats; numpy's cos and sin, as :func:`cast_from` takes
    them, element by element)."""
    ox, oy, ang = _rays_of(spec, pose, tuple(range(len(spec.transducers))))
    k = len(spec.offsets)
    return (ox.reshape(-1, k), oy.reshape(-1, k), ang.reshape(-1, k), np.cos(ang).reshape(-1, k), np.sin(ang).reshape(-1, k))


def _rays_of(spec: SonarSpec, pose: tuple[float, float, float], which: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Origins and angles ((len(which) * rays,) each) of the transducers ``which``' rays, transducer by
    transducer: the ray-by-ray path's expressions (``x + c * tx - s * ty``, ``th + radians(tb) + offset``)
    element by element, so the same floats."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    idx = np.fromiter(which, dtype=np.intp, count=len(which))
    k = len(spec.offsets)
    tx, ty = spec._tx[idx], spec._ty[idx]
    ox = np.repeat(x + c * tx - s * ty, k)
    oy = np.repeat(y + s * tx + c * ty, k)
    ang = ((th + spec._tb[idx])[:, None] + np.asarray(spec.offsets)[None, :]).ravel()
    return ox, oy, ang


def sonar_readings(
    world: World,
    pose: tuple[float, float, float],
    spec: SonarSpec,
    which: tuple[int, ...],
    rng: np.random.Generator | None,
    *,
    caster: RayCaster | None = None,
    kept: SegmentRanges | None = None,
    compiled: bool = True,
) -> np.ndarray:
    """Ranges (len(which),) of the transducers ``which`` from robot pose ``pose``; noise from ``rng``
    (None: exact, no dropouts). The nearest echo among the cone's rays; none reads ``max_range``.
    All rays in one pass (:func:`cast_from`), the segments' part and the legs' part apart (a minimum
    of minima: the same floats); ``kept``: the segments' part kept
    while the pose stays the same (:class:`SegmentRanges`); ``caster``: ray by ray with it instead
    (the reference: the same floats). With the compiled kernel (``compiled``, and built) the whole packet
    is cast in one call (the rays' origins and directions kept per pose in ``kept``), the same floats
    again: everything then but the noise costs a few microseconds, so nothing else is kept."""
    if not which:
        return np.zeros(0)
    a, b = world.segments_at(spec.height)
    cc, cr = world.leg_circles()
    x, y, th = pose
    offs = np.asarray(spec.offsets)
    if caster is not None:  # ray by ray (the reference the packet's one pass is checked against)
        c, s = math.cos(th), math.sin(th)
        out = np.empty(len(which))
        for j, i in enumerate(which):
            tx, ty, tb = spec.transducers[i]
            origin = (x + c * tx - s * ty, y + s * tx + c * ty)
            out[j] = float(caster.cast(origin, th + math.radians(tb) + offs, a, b, cc, cr, spec.max_range).min())
    elif _K is not None and compiled:
        ring = kept.ring(spec, pose) if kept is not None else _ring_at(spec, pose)
        out = np.empty(len(which))
        _K.sonar_ranges(ring[0], ring[1], ring[3], ring[4], len(offs), which, np.ascontiguousarray(a, dtype=float),
                        np.ascontiguousarray(b, dtype=float), np.ascontiguousarray(cc, dtype=float),
                        np.ascontiguousarray(cr, dtype=float), float(spec.max_range), out)
    else:
        k = len(offs)
        rays = kept.get(pose, a, b) if kept is not None else None
        todo = which if rays is None else tuple(dict.fromkeys(i for i in which if i not in rays))
        got: dict[int, np.ndarray] = {} if rays is None else rays
        if kept is not None:
            ring = kept.ring(spec, pose)
            rows = np.fromiter(which, dtype=np.intp, count=len(which))
            rays_all = (ring[0][rows].ravel(), ring[1][rows].ravel(), ring[2][rows].ravel())
        else:
            rays_all = _rays_of(spec, pose, which)
        if todo:
            todo_rays = rays_all
            if todo != which:
                sub = np.repeat([which.index(i) for i in todo], k) * k + np.tile(np.arange(k), len(todo))
                todo_rays = (rays_all[0][sub], rays_all[1][sub], rays_all[2][sub])
            static = cast_from(*todo_rays, a, b, _NO_LEGS, _NO_RADII, spec.max_range).reshape(len(todo), k)
            for j, i in enumerate(todo):
                got[i] = static[j]
        ranges = static if todo == which else np.stack([got[i] for i in which])
        if cc.shape[0]:
            legs = cast_from(*rays_all, _NO_SEGS, _NO_SEGS, cc, cr, spec.max_range).reshape(len(which), k)
            ranges = np.minimum(ranges, legs)
        out = ranges.min(axis=1)
    if rng is None:
        return np.clip(out, spec.min_range, spec.max_range)
    return np.array(noisy(out.tolist(), rng.normal(0.0, 1.0, len(which)).tolist(), (rng.random(len(which)) < spec.dropout).tolist(), spec))


def noisy(exact: list[float], noise: list[float], lost: list[bool], spec: SonarSpec) -> list[float]:
    """The readings with their noise (standard normal draws ``noise``) and dropouts (``lost``), clipped
    to the sonar's range: ``np.where(hit, r + noise * (spec.noise + spec.noise_per_m * r), r)``, then
    ``max_range`` where lost, then ``np.clip``, in Python floats (the same IEEE operations in the same
    order, so the same floats; a packet's handful of readings cost less so than as arrays)."""
    lo, hi, a, b = spec.min_range, spec.max_range, spec.noise, spec.noise_per_m
    out = []
    for r, z, gone in zip(exact, noise, lost):
        if gone:
            r = hi
        elif r < hi:
            r = r + z * (a + b * r)
        out.append(lo if r < lo else (hi if r > hi else r))
    return out


def sonar_packet(t: float, spec: SonarSpec, seq: int, which: tuple[int, ...], ranges: np.ndarray) -> SonarPacket:
    """The ``<sonar>`` message for the readings ``ranges`` of transducers ``which``, as the typed record
    the module publishes (:class:`~robot.sonar_packet.SonarPacket`: its XML is built only when read)."""
    text = spec._text
    return SonarPacket(str(seq), f"{t:.6f}", spec._head,
                       tuple((*text[i], f"{r:.4f}") for i, r in zip(which, ranges.tolist())))


def sonar_element(t: float, spec: SonarSpec, seq: int, which: tuple[int, ...], ranges: np.ndarray) -> etree._Element:
    """The ``<sonar>`` message for the readings ``ranges`` of transducers ``which``, as XML."""
    return sonar_packet(t, spec, seq, which, ranges).to_xml()


class Sonar(Module):
    """Publishes the rings' new readings on ``/robot/sonar`` at ``spec.rate`` Hz (see the module docstring)."""

    def __init__(self, sim: Simulation, world: World, spec: SonarSpec | None = None, *, name: str = "sonar") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or SonarSpec()
        self.seq = 0
        self._fired = 0  # firings so far (each fires one transducer per ring)
        self._kept = SegmentRanges()  # the walls' part of the readings while the robot stands still

    def due(self, seq: int) -> int:
        """How many firings fall in packet ``seq``'s period (the firing clock runs on its own)."""
        per = 1.0 / self.spec.rate / self.spec.fire_interval
        return int(math.floor((seq + 1) * per + 1e-9)) - int(math.floor(seq * per + 1e-9))

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            which: tuple[int, ...] = ()
            for _ in range(self.due(self.seq)):
                which += self.spec.firing(self._fired)
                self._fired += 1
            ranges = sonar_readings(self.world, self.world.robot.pose, self.spec, which, self.rng, kept=self._kept)
            self.bus.publish(SONAR, sonar_packet(self.now, self.spec, self.seq, which, ranges))
            self.seq += 1
            await asyncio.sleep(period)
