"""The vectorised 2D raycast kernel (the laser, and line-of-sight checks).

Why our own kernel and not pymunk's segment queries: one pymunk query per
beam costs about 1.4 ms for a 361-beam scan, a numpy pass over all
(beam, segment) pairs about 0.3 ms. The kernel is a pure function of the
geometry (IR-SIM's ``cast_rays``): segments (polygon edges of walls and
furniture) and circles (legs, bodies). :class:`RayCaster` does the same
with scratch buffers it keeps between calls, so a running laser allocates
nothing per scan. A test checks both against pymunk's segment queries.

A ray that starts inside a circle hits it at range 0. A ray parallel to a
segment never hits that segment (its end points are caught by the
neighbouring edges of the closed polygon). Rays that hit nothing return
``max_range``, as a SICK scanner does.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from homesim.kernels import load

FloatArray = np.ndarray
# The compiled inner loops (homesim/world/_raykernels.c), same floats as the Python paths below;
# None where not built (or HOMESIM_PURE_PYTHON is set): the Python paths run.
_K = load("homesim.world._raykernels", 2)

_EMPTY2 = np.zeros((0, 2))
_EMPTY1 = np.zeros(0)
TWO_PI = 2.0 * math.pi
_FAR = 1e12  # beam indices: beyond every fan (finite, so it casts to an integer)
_CULL = 1e-6  # metres: culling margin, far above rounding, far below any geometry


def cast_rays(
    origin: Sequence[float],
    angles: FloatArray,
    seg_a: FloatArray = _EMPTY2,
    seg_b: FloatArray = _EMPTY2,
    circ_c: FloatArray = _EMPTY2,
    circ_r: FloatArray = _EMPTY1,
    max_range: float = np.inf,
) -> FloatArray:
    """Range along each world-frame angle (N,) from ``origin`` to the first hit.

    Pure and allocating; for repeated scans use :class:`RayCaster`.
    """
    return RayCaster().cast(origin, angles, seg_a, seg_b, circ_c, circ_r, max_range)


class RayCaster:
    """:func:`cast_rays` with scratch buffers reused from call to call.

    Buffers grow when a call needs more beams or obstacles and are never
    shrunk, so after the first scans a laser allocates nothing. One instance
    per sensor: calls are not re-entrant (the simulation is single-threaded).
    """

    __slots__ = ("_seg_shape", "_circ_shape", "_den", "_u", "_t", "_mask", "_cb", "_ck", "_ck2", "_dx", "_dy")

    def __init__(self) -> None:
        self._seg_shape = (0, 0)
        self._circ_shape = (0, 0)
        self._dx = self._dy = np.empty(0)

    def _buffers(self, n: int, m: int, k: int) -> None:
        if self._dx.shape[0] < n:
            self._dx = np.empty(n)
            self._dy = np.empty(n)
        sn, sm = self._seg_shape
        if m and (n > sn or m > sm):
            shape = (max(n, sn), max(m, sm))
            self._den = np.empty(shape)
            self._u = np.empty(shape)
            self._t = np.empty(shape)
            self._mask = np.empty(shape, dtype=bool)
            self._seg_shape = shape
        cn, ck = self._circ_shape
        if k and (n > cn or k > ck):
            shape = (max(n, cn), max(k, ck))
            self._cb = np.empty(shape)
            self._ck = np.empty(shape)
            self._ck2 = np.empty(shape, dtype=bool)
            self._circ_shape = shape

    def cast(
        self,
        origin: Sequence[float],
        angles: FloatArray,
        seg_a: FloatArray = _EMPTY2,
        seg_b: FloatArray = _EMPTY2,
        circ_c: FloatArray = _EMPTY2,
        circ_r: FloatArray = _EMPTY1,
        max_range: float = np.inf,
        *,
        out: FloatArray | None = None,
        backfaces: bool = True,
    ) -> FloatArray:
        """Ranges (N,) to the first segment or circle hit along each angle.

        ``seg_a``/``seg_b`` are segment end points (M, 2), ``circ_c``/``circ_r``
        circle centres (K, 2) and radii (K,). Segments and circles wholly
        beyond ``max_range`` are culled first. ``out`` receives the result
        when given (shape (N,)). ``backfaces=False`` drops segments whose
        right-hand side faces the origin: correct (and about twice as fast)
        when the segments are edges of counter-clockwise closed polygons and
        the origin lies outside all of them.
        """
        ox, oy = float(origin[0]), float(origin[1])
        angles = np.asarray(angles, dtype=float)
        n = angles.shape[0]
        result = np.empty(n) if out is None else out
        result.fill(max_range)
        seg_a = np.asarray(seg_a, dtype=float).reshape(-1, 2)
        seg_b = np.asarray(seg_b, dtype=float).reshape(-1, 2)
        circ_c = np.asarray(circ_c, dtype=float).reshape(-1, 2)
        circ_r = np.asarray(circ_r, dtype=float).reshape(-1)
        if not backfaces and seg_a.shape[0]:
            # Outward normal of a CCW edge is (ey, -ex); keep edges facing the origin.
            facing = (seg_b[:, 1] - seg_a[:, 1]) * (ox - seg_a[:, 0]) - (seg_b[:, 0] - seg_a[:, 0]) * (oy - seg_a[:, 1]) > 0
            seg_a, seg_b = seg_a[facing], seg_b[facing]
        if np.isfinite(max_range):
            seg_a, seg_b = _cull_segments(ox, oy, seg_a, seg_b, max_range)
            if circ_c.shape[0]:
                keep = np.hypot(circ_c[:, 0] - ox, circ_c[:, 1] - oy) - circ_r <= max_range
                circ_c, circ_r = circ_c[keep], circ_r[keep]
        m, k = seg_a.shape[0], circ_c.shape[0]
        if n == 0 or (m == 0 and k == 0):
            return result
        self._buffers(n, m, k)
        dx, dy = self._dx[:n], self._dy[:n]
        np.cos(angles, out=dx)
        np.sin(angles, out=dy)
        if m:
            self._segments(ox, oy, dx, dy, seg_a, seg_b, result)
        if k:
            self._circles(ox, oy, dx, dy, circ_c, circ_r, result)
        return result

    def _segments(self, ox: float, oy: float, dx: FloatArray, dy: FloatArray, a: FloatArray, b: FloatArray, result: FloatArray) -> None:
        n, m = dx.shape[0], a.shape[0]
        ex = b[:, 0] - a[:, 0]
        ey = b[:, 1] - a[:, 1]
        fx = a[:, 0] - ox
        fy = a[:, 1] - oy
        den, u, t, mask = self._den[:n, :m], self._u[:n, :m], self._t[:n, :m], self._mask[:n, :m]
        dxc, dyc = dx[:, None], dy[:, None]
        # den = d x e ; t = (f x e) / den ; u = (f x d) / den
        np.multiply(dxc, ey, out=den)
        np.multiply(dyc, ex, out=t)
        np.subtract(den, t, out=den)
        np.multiply(fx, dyc, out=u)
        np.multiply(fy, dxc, out=t)
        np.subtract(u, t, out=u)
        tnum = fx * ey - fy * ex  # (m,)
        # Multiply through by sign(den) instead of dividing everywhere.
        sign = np.sign(den)
        np.multiply(u, sign, out=u)
        np.abs(den, out=den)
        np.multiply(tnum, sign, out=t)  # t * |den|
        np.greater_equal(t, 0.0, out=mask)
        mask &= u >= 0.0
        mask &= u <= den
        mask &= den > 1e-15
        # Parameter along the ray where valid, inf elsewhere.
        np.divide(t, den, out=t, where=mask)
        t[~mask] = np.inf
        np.minimum(result, t.min(axis=1), out=result)

    def _circles(self, ox: float, oy: float, dx: FloatArray, dy: FloatArray, c: FloatArray, r: FloatArray, result: FloatArray) -> None:
        n, k = dx.shape[0], c.shape[0]
        fx = c[:, 0] - ox
        fy = c[:, 1] - oy
        ff = fx * fx + fy * fy
        rr = r * r
        tca, disc, hit = self._cb[:n, :k], self._ck[:n, :k], self._ck2[:n, :k]
        np.multiply(dx[:, None], fx, out=tca)
        tca += dy[:, None] * fy
        # disc = r^2 - (|f|^2 - tca^2)
        np.multiply(tca, tca, out=disc)
        disc += rr - ff
        np.greater_equal(disc, 0.0, out=hit)
        np.sqrt(disc, out=disc, where=hit)
        np.subtract(tca, disc, out=disc, where=hit)
        hit &= disc >= 0.0
        disc[~hit] = np.inf
        inside = ff <= rr
        if inside.any():
            disc[:, inside] = 0.0
        np.minimum(result, disc.min(axis=1), out=result)


class FanCaster:
    """:meth:`RayCaster.cast` for a scanner's fan of beams, bit for bit, meeting each obstacle only
    with the beams that can reach it.

    A laser's beams are evenly spaced: a segment or circle subtends an interval of angles from the
    origin, and only the beams inside it (plus a beam of margin each side) can hit it. Those
    (beam, obstacle) pairs are computed with exactly the dense kernel's operations, so every range
    is the same float: a scan of walls and furniture meets some hundreds of pairs instead of every
    beam with every edge, and a leg (a circle) a dozen beams, in plain floats. The fan (cosines,
    sines, spacing) and the segments (edge vectors, lengths) are prepared once per distinct array
    and kept, so a laser on static geometry prepares them once.

    Angles that are not evenly spaced, or that span so much of a turn that a widened interval
    could wrap onto beams at both ends, fall back to the dense :class:`RayCaster` (same results).
    Not re-entrant, like :class:`RayCaster`.
    """

    __slots__ = ("_dense", "_angles", "_key", "_fan", "_segs", "_static")

    def __init__(self) -> None:
        self._dense = RayCaster()
        self._angles: FloatArray | None = None
        self._key = b""
        self._fan: _Fan | None = None
        self._segs: _Segments | None = None
        # (origin x, origin y, max range), the angles and segments it was cast with, the ranges.
        self._static: tuple[tuple[float, float, float], FloatArray, _Segments, FloatArray] | None = None

    def fan(self, angles: FloatArray) -> "_Fan | None":
        """The prepared fan for ``angles`` (None: not an even fan narrower than a turn).

        Recognised by their bytes (a laser passes a new array of the same angles each scan).
        """
        key = angles.tobytes()
        if key != self._key:
            self._angles = np.array(angles, dtype=float)
            self._key = key
            self._fan = _Fan.of(self._angles)
        return self._fan

    def _segments(self, a: FloatArray, b: FloatArray) -> "_Segments":
        """The prepared segments: the same read-only arrays as last time, or equal ones, or new."""
        got = self._segs
        if got is not None and got.source[0] is a and got.source[1] is b and _frozen(a) and _frozen(b):
            return got
        sa = np.asarray(a, dtype=float).reshape(-1, 2)
        sb = np.asarray(b, dtype=float).reshape(-1, 2)
        if got is None or got.a.shape != sa.shape or got.b.shape != sb.shape or not (np.array_equal(got.a, sa) and np.array_equal(got.b, sb)):
            got = self._segs = _Segments(sa, sb)
        got.source = (a, b)
        return got

    def cast(
        self,
        origin: Sequence[float],
        angles: FloatArray,
        seg_a: FloatArray = _EMPTY2,
        seg_b: FloatArray = _EMPTY2,
        circ_c: FloatArray = _EMPTY2,
        circ_r: FloatArray = _EMPTY1,
        max_range: float = np.inf,
        *,
        out: FloatArray | None = None,
        backfaces: bool = True,
    ) -> FloatArray:
        """Exactly :meth:`RayCaster.cast` (same arguments, same floats)."""
        angles = np.asarray(angles, dtype=float)
        fan = self.fan(angles)
        if fan is None:
            return self._dense.cast(origin, angles, seg_a, seg_b, circ_c, circ_r, max_range, out=out, backfaces=backfaces)
        result = np.empty(fan.n) if out is None else out
        result.fill(max_range)
        ox, oy, max_range = float(origin[0]), float(origin[1]), float(max_range)
        segs = self._segments(seg_a, seg_b)
        if segs.m:
            fan.segments(ox, oy, segs, backfaces, max_range, result)
        circ_c = np.asarray(circ_c, dtype=float).reshape(-1, 2)
        if circ_c.shape[0]:
            fan.circles(ox, oy, circ_c, np.asarray(circ_r, dtype=float).reshape(-1), max_range, result)
        return result

    def scan(
        self,
        origin: Sequence[float],
        angles: FloatArray,
        seg_a: FloatArray,
        seg_b: FloatArray,
        circ_c: FloatArray,
        circ_r: FloatArray,
        max_range: float,
        *,
        out: FloatArray | None = None,
    ) -> FloatArray:
        """A laser scan: :meth:`cast` with ``backfaces=False``, the segments' ranges kept per origin.

        The segments are static geometry (walls, furniture) seen from outside; their ranges are
        cast once per origin, angles and segments and kept, so while the scanner stands still
        only the circles (people's legs) are cast. A range is the minimum over everything hit
        and a minimum is exact, so the result is bit for bit that of casting all together.
        Pass the segments as read-only arrays (the world's are) and they are recognised by
        identity; writeable ones, and read-only views of writeable ones, are compared value by value.
        """
        angles = np.asarray(angles, dtype=float)
        fan = self.fan(angles)
        segs = self._segments(seg_a, seg_b)
        ox, oy, max_range = float(origin[0]), float(origin[1]), float(max_range)
        key = (ox, oy, max_range)
        kept = self._static
        if kept is None or kept[0] != key or kept[1] is not self._angles or kept[2] is not segs:
            if fan is None:
                static = self._dense.cast(origin, angles, segs.a, segs.b, max_range=max_range, backfaces=False)
            else:
                static = np.full(fan.n, max_range)
                if segs.m:
                    fan.segments(ox, oy, segs, False, max_range, static)
            kept = self._static = (key, self._angles, segs, static)
        static = kept[3]
        circ_c = np.asarray(circ_c, dtype=float).reshape(-1, 2)
        if fan is None and circ_c.shape[0]:
            result = self._dense.cast(origin, angles, circ_c=circ_c, circ_r=circ_r, max_range=max_range, out=out)
            np.minimum(result, static, out=result)
            return result
        if out is None:
            result = static.copy()
        else:
            result = out
            result[:] = static
        if circ_c.shape[0]:
            fan.circles(ox, oy, circ_c, np.asarray(circ_r, dtype=float).reshape(-1), max_range, result)
        return result


class _Segments:
    """Segments prepared for :meth:`_Fan.segments`: edge vectors as the dense kernel computes
    them, both end points packed, and how near the origin may come to a segment's line before
    the angle it subtends is too close to half a turn to trust."""

    __slots__ = ("a", "b", "m", "ex", "ey", "vx", "vy", "near", "both", "source")

    def __init__(self, a: FloatArray, b: FloatArray) -> None:
        self.a, self.b = a.copy(), b.copy()
        self.m = a.shape[0]
        self.ex = b[:, 0] - a[:, 0]
        self.ey = b[:, 1] - a[:, 1]
        self.vx = np.concatenate((a[:, 0], b[:, 0]))
        self.vy = np.concatenate((a[:, 1], b[:, 1]))
        length = np.hypot(self.ex, self.ey)
        # |f x e| = distance to the line * length; within 1e-6 m (scaled for long segments)
        # the subtended angle is within about 1e-6 rad of pi: every beam is a candidate then.
        self.near = 1e-6 * length * np.maximum(length, 1.0)
        self.both = np.concatenate((np.arange(self.m), np.arange(self.m)))
        self.source: tuple[object, object] = (a, b)  # the arrays it was last asked with (recognised while read-only)


class _Fan:
    """Evenly spaced beam angles, prepared: beam i points at ``centre - half + step * i``."""

    __slots__ = ("n", "step", "half", "centre", "dx", "dy", "dxl", "dyl", "_base", "_k0", "_kturn", "_khalf")

    def __init__(self, angles: FloatArray, step: float) -> None:
        self.n = angles.shape[0]
        self.step = step
        self.half = step * (self.n - 1) / 2.0
        self.centre = float(angles[0]) + self.half
        # The dense kernel's np.cos/np.sin over the whole array: the same floats it uses.
        self.dx, self.dy = np.cos(angles), np.sin(angles)
        self.dxl, self.dyl = self.dx.tolist(), self.dy.tolist()
        # Directions as beam indices: k = ((angle - base) mod 2 pi) / step - k0 puts beam i at k = i,
        # with the direction opposite the centre at the ends of [-k0, kturn - k0).
        self._base = self.centre - math.pi
        self._k0 = (math.pi - self.half) / step
        self._kturn = TWO_PI / step
        self._khalf = math.pi / step

    @classmethod
    def of(cls, angles: FloatArray) -> "_Fan | None":
        n = angles.shape[0]
        if angles.ndim != 1 or n < 2 or not np.isfinite(angles).all():
            return None
        step = (float(angles[-1]) - float(angles[0])) / (n - 1)
        # Even spacing to a nanoradian, beams far wider apart than that, and an interval widened
        # by the margin can never reach beams at both ends of the fan.
        if not step > 1e-6 or step * (n - 1) / 2.0 + 4.0 * step >= math.pi:
            return None
        if np.abs(angles - (float(angles[0]) + step * np.arange(n))).max() > 1e-9:
            return None
        return cls(angles, step)

    def circles(self, ox: float, oy: float, c: FloatArray, r: FloatArray, max_range: float, result: FloatArray) -> None:
        """The dense kernel's circle test on the beams each circle subtends, in plain floats.

        Measured against numpy over the gathered (beam, circle) pairs (about forty numpy calls,
        whatever the count) and the dense pass: plain floats are the cheapest from one person's
        legs (about a quarter of the dense pass) to ten people's (about the same as the dense
        pass), so they are the only path.
        """
        if _K is not None and _plain(result):
            _K.fan_circles(ox, oy, np.ascontiguousarray(c, dtype=float), np.ascontiguousarray(r, dtype=float), self.dx, self.dy,
                           self.centre, self.half, self.step, max_range, result)
            return
        self._circles_in_floats(ox, oy, c.tolist(), r.tolist(), max_range, result)

    def _circles_in_floats(self, ox: float, oy: float, centres: list[list[float]], radii: list[float], max_range: float, result: FloatArray) -> None:
        dxl, dyl, centre, fan_half, step, last = self.dxl, self.dyl, self.centre, self.half, self.step, self.n - 1
        finite = math.isfinite(max_range)
        for (cx, cy), r in zip(centres, radii):
            fx = cx - ox
            fy = cy - oy
            ff = fx * fx + fy * fy
            rr = r * r
            if finite:  # the dense kernel's cull, decided exactly where it is close
                lim = max_range + r
                if ff > lim * lim * (1.0 + 1e-12):
                    continue
                if ff >= lim * lim * (1.0 - 1e-12) and float(np.hypot(fx, fy)) - r > max_range:
                    continue
            if ff <= rr:  # the origin inside: every beam reads 0
                np.minimum(result, 0.0, out=result)
                continue
            rel = (math.atan2(fy, fx) - centre + math.pi) % TWO_PI - math.pi
            # ff == 0 here only with a NaN radius (which never hits): no ZeroDivisionError then.
            half = math.asin(min(1.0, r / math.sqrt(ff) if ff > 0.0 else math.inf))
            base = rr - ff
            lo, hi = rel - half, rel + half
            if -math.pi <= lo and hi <= math.pi:
                pieces: Sequence[tuple[float, float]] = ((lo, hi),)
            elif lo == lo and hi == hi:
                pieces = _unwrapped(lo, hi)
            else:  # NaN geometry (a NaN leg or origin): the dense test on every beam, which never hits
                pieces = ((-math.pi, math.pi),)
            for lo, hi in pieces:
                # Beams whose angle may lie in [lo, hi], with a beam of margin each side.
                i0 = max(0, math.floor((lo + fan_half) / step) - 1)
                i1 = min(last, math.ceil((hi + fan_half) / step) + 1)
                if i0 > i1:
                    continue
                ranges = result[i0 : i1 + 1].tolist()
                changed = False
                for j in range(i1 - i0 + 1):
                    tca = dxl[i0 + j] * fx + dyl[i0 + j] * fy
                    disc = tca * tca + base
                    if disc >= 0.0:
                        t = tca - math.sqrt(disc)
                        if t >= 0.0 and t < ranges[j]:
                            ranges[j] = t
                            changed = True
                if changed:
                    result[i0 : i1 + 1] = ranges

    def segments(self, ox: float, oy: float, s: _Segments, backfaces: bool, max_range: float, result: FloatArray) -> None:
        """The dense kernel's segment test on the (beam, segment) pairs where the beam lies within
        the angle the segment subtends (numpy over the pairs; the compiled kernel where built)."""
        if _K is not None and _plain(result):
            _K.fan_segments(ox, oy, s.a, s.b, s.ex, s.ey, s.near, self.dx, self.dy, self._base, self._k0, self._kturn, self._khalf,
                            self.step, backfaces, max_range, result)
            return
        m = s.m
        dvx = s.vx - ox
        dvy = s.vy - oy
        fx, fy = dvx[:m], dvy[:m]
        tnum = fx * s.ey
        tnum -= fy * s.ex  # f x e, as the dense kernel computes it
        # Both end points' directions as beam indices (see __init__).
        k = np.arctan2(dvy, dvx)
        k -= self._base
        k %= TWO_PI
        k *= 1.0 / self.step
        k -= self._k0
        ka, kb = k[:m], k[m:]
        lo = np.minimum(ka, kb)
        hi = np.maximum(ka, kb)
        # Less than half a turn: [lo, hi]; more: the segment lies across the direction behind the
        # centre and subtends [hi, lo + turn]. Each piece is also tried one turn lower.
        wrap = hi - lo > self._khalf
        start = np.where(wrap, hi, lo)
        end = np.where(wrap, lo + self._kturn, hi)
        unsure = ~(np.abs(tnum) >= s.near)  # the origin (almost) on the segment's line, or NaN geometry
        if unsure.any():
            start[unsure] = -_FAR
            end[unsure] = _FAR
        if not backfaces:
            # The dense kernel's "facing" test is (e_y (o_x - a_x) - e_x (o_y - a_y)) > 0, which
            # is -(f x e) > 0 exactly (negation commutes with rounding): drop back faces.
            start[tnum >= 0.0] = _FAR
        starts = np.concatenate((start, start - self._kturn))
        ends = np.concatenate((end, end - self._kturn))
        i0 = np.floor(starts)
        i0 -= 1.0
        np.maximum(i0, 0.0, out=i0)
        i1 = np.ceil(ends)
        i1 += 1.0
        np.minimum(i1, self.n - 1.0, out=i1)
        counts = i1 - i0
        counts += 1.0
        np.maximum(counts, 0.0, out=counts)
        counts = counts.astype(np.intp)
        total = int(counts.sum())
        if total == 0:
            return
        seg = np.repeat(s.both, counts)
        first = i0.astype(np.intp)
        first -= np.cumsum(counts)
        first += counts
        beam = np.arange(total)
        beam += np.repeat(first, counts)
        dx, dy = self.dx[beam], self.dy[beam]
        exs, eys = s.ex[seg], s.ey[seg]
        # den = d x e ; t = (f x e) / den ; u = (f x d) / den, as in RayCaster._segments
        den = dx * eys
        den -= dy * exs
        u = fx[seg] * dy
        u -= fy[seg] * dx
        sign = np.sign(den)
        u *= sign
        np.abs(den, out=den)
        t = tnum[seg]
        t *= sign
        mask = t >= 0.0
        mask &= u >= 0.0
        mask &= u <= den
        mask &= den > 1e-15
        beam, seg = beam[mask], seg[mask]
        t = t[mask]
        t /= den[mask]
        if math.isfinite(max_range):
            # The dense kernel first drops segments wholly beyond max_range; only a hit within
            # rounding of max_range can come from one of those: ask the same test for them.
            near = t >= max_range * (1.0 - 1e-9)
            near &= t < max_range  # farther hits never change a range
            if near.any():
                idx = np.unique(seg[near])
                culled = idx[~_within(ox, oy, s.a[idx], s.b[idx], max_range)]
                if culled.shape[0]:
                    ok = ~np.isin(seg, culled)
                    beam, t = beam[ok], t[ok]
        np.minimum.at(result, beam, t)


def _plain(a: FloatArray) -> bool:
    """Whether the compiled kernel can write into ``a`` in place: contiguous, writeable float64."""
    return a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable


def add_range_noise(ranges: FloatArray, noise: FloatArray, max_range: float) -> FloatArray:
    """A laser's noise, in place: ``ranges + noise`` clipped to [0, max_range], and a beam that hit
    nothing (at ``max_range`` or beyond) reads exactly ``max_range``. Returns ``ranges``."""
    if _K is not None and _plain(ranges) and noise.dtype == np.float64 and noise.flags.c_contiguous:
        _K.scan_noise(ranges, noise, float(max_range))
        return ranges
    miss = ranges >= max_range
    ranges += noise
    # np.clip's values without its Python-level wrapper (a third of a scan's noise cost)
    np.maximum(ranges, 0.0, out=ranges)
    np.minimum(ranges, max_range, out=ranges)
    ranges[miss] = max_range
    return ranges


def _frozen(a: object) -> bool:
    """Whether nobody can change ``a``'s values: an array that is read-only, and so is every array
    it views (a read-only view of a writeable array changes when that array does)."""
    while isinstance(a, np.ndarray):
        if a.flags.writeable:
            return False
        if a.base is None:
            return True
        a = a.base
    return False  # not an array, or a view of another buffer (bytes, mmap): compare by value


def _unwrapped(lo: float, hi: float) -> list[tuple[float, float]]:
    """[lo, hi] (relative angles, each end at most half a turn outside (-pi, pi]) as pieces within it."""
    pieces = [(lo, hi)]
    if lo < -math.pi:
        pieces.append((lo + TWO_PI, hi + TWO_PI))
    if hi > math.pi:
        pieces.append((lo - TWO_PI, hi - TWO_PI))
    return pieces


def _cull_segments(ox: float, oy: float, a: FloatArray, b: FloatArray, max_range: float) -> tuple[FloatArray, FloatArray]:
    """Drop segments whose closest point is farther than ``max_range``."""
    if a.shape[0] == 0:
        return a, b
    keep = _within(ox, oy, a, b, max_range)
    if keep.all():
        return a, b
    return a[keep], b[keep]


def _within(ox: float, oy: float, a: FloatArray, b: FloatArray, max_range: float) -> FloatArray:
    """Per segment (row): whether its closest point lies within ``max_range`` of the origin.
    Rows are independent, so asking for a subset gives the same answers."""
    ab = b - a
    ao = np.array([ox, oy]) - a
    denom = (ab * ab).sum(1)
    denom[denom < 1e-18] = 1.0
    t = np.clip((ao * ab).sum(1) / denom, 0.0, 1.0)
    cx = a[:, 0] + t * ab[:, 0] - ox
    cy = a[:, 1] + t * ab[:, 1] - oy
    return cx * cx + cy * cy <= max_range * max_range


def line_of_sight(
    origin: Sequence[float],
    targets: FloatArray,
    seg_a: FloatArray = _EMPTY2,
    seg_b: FloatArray = _EMPTY2,
    circ_c: FloatArray = _EMPTY2,
    circ_r: FloatArray = _EMPTY1,
    *,
    margin: float = 1e-6,
    caster: RayCaster | None = None,
) -> FloatArray:
    """For each target point (N, 2): True when nothing blocks the view from ``origin``.

    A hit counts as blocking only when it lies more than ``margin`` before
    the target (so the target's own surface, if it is in the circles, can be
    excluded by passing a margin of its radius).
    """
    targets = np.atleast_2d(np.asarray(targets, dtype=float))
    if targets.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    d = targets - np.asarray(origin, dtype=float)[:2]
    dist = np.hypot(d[:, 0], d[:, 1])
    ang = np.arctan2(d[:, 1], d[:, 0])
    rc = caster or RayCaster()
    hit = rc.cast(origin, ang, seg_a, seg_b, circ_c, circ_r, float(dist.max()) + 1.0)
    return hit >= dist - margin


# ----------------------------------------------------------- 3D sight lines
class Prisms:
    """Convex vertical prisms (a polygon footprint from ``bottom`` to ``top``), packed for
    :func:`sight_lines_clear`: every edge's start point and outward normal, grouped by prism,
    and each prism's bounding box (``lo``, ``hi``: (M, 2)) for culling."""

    __slots__ = ("a", "normal", "first", "bottom", "top", "lo", "hi", "count", "_edge_prism", "_boxes", "_packed")

    def __init__(self, polygons: Sequence[FloatArray], bottom: Sequence[float], top: Sequence[float]) -> None:
        starts, normals, first, lo, hi = [], [], [], [], []
        n = 0
        for poly in polygons:
            p = np.asarray(poly, dtype=float)
            if p.shape[0] >= 3 and _signed_area(p) < 0:
                p = p[::-1]
            e = np.roll(p, -1, axis=0) - p
            starts.append(p)
            normals.append(np.stack((e[:, 1], -e[:, 0]), axis=1))  # outward for a counter-clockwise polygon
            first.append(n)
            lo.append(p.min(axis=0) if p.shape[0] else (np.inf, np.inf))
            hi.append(p.max(axis=0) if p.shape[0] else (-np.inf, -np.inf))
            n += p.shape[0]
        self.a = np.concatenate(starts) if starts else _EMPTY2
        self.normal = np.concatenate(normals) if normals else _EMPTY2
        self.first = np.array(first, dtype=np.intp)
        self.bottom = np.asarray(bottom, dtype=float)
        self.top = np.asarray(top, dtype=float)
        self.lo = np.array(lo, dtype=float).reshape(-1, 2)
        self.hi = np.array(hi, dtype=float).reshape(-1, 2)
        self.count = np.diff(np.append(self.first, n)).astype(np.intp)
        self._edge_prism = np.repeat(np.arange(len(first), dtype=np.intp), self.count)

    def __len__(self) -> int:
        return int(self.first.shape[0])

    @property
    def packed(self) -> tuple[FloatArray, ...]:
        """(a, normal, first, count, bottom, top, lo, hi) as contiguous arrays, for the compiled kernel."""
        try:
            return self._packed
        except AttributeError:
            self._packed = tuple(np.ascontiguousarray(x, dtype=dt) for x, dt in (
                (self.a, float), (self.normal, float), (self.first, np.intp), (self.count, np.intp),
                (self.bottom, float), (self.top, float), (self.lo, float), (self.hi, float)))
            return self._packed

    @property
    def boxes(self) -> list[tuple[float, float, float, float, float, float]]:
        """Per prism (lo x, lo y, hi x, hi y, bottom, top) as plain floats, for culling."""
        try:
            return self._boxes
        except AttributeError:
            self._boxes = [tuple(row) for row in np.column_stack((self.lo, self.hi, self.bottom, self.top)).tolist()]
            return self._boxes

    def subset(self, keep: FloatArray) -> "Prisms":
        """The prisms at indices ``keep`` (sorted), packed the same way (no copies of the polygons)."""
        out = Prisms.__new__(Prisms)
        edges = np.isin(self._edge_prism, keep)
        out.a, out.normal = self.a[edges], self.normal[edges]
        out.count = self.count[keep]
        out.first = np.concatenate(([0], np.cumsum(out.count)[:-1])).astype(np.intp)
        out.bottom, out.top, out.lo, out.hi = self.bottom[keep], self.top[keep], self.lo[keep], self.hi[keep]
        out._edge_prism = np.repeat(np.arange(len(keep), dtype=np.intp), out.count)
        return out


def _signed_area(p: FloatArray) -> float:
    return 0.5 * float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))


def _height_span_blocks(z0: float, dz: FloatArray, t_in: FloatArray, t_out: FloatArray, bottom: FloatArray, top: FloatArray) -> FloatArray:
    """Whether the line's heights over [t_in, t_out] meet [bottom, top] (where t_in <= t_out)."""
    meet = t_in <= t_out
    za, zb = z0 + dz * np.where(meet, t_in, 0.0), z0 + dz * np.where(meet, t_out, 0.0)
    lo, hi = np.minimum(za, zb), np.maximum(za, zb)
    return meet & (lo <= top) & (hi >= bottom)


def sight_lines_clear(
    origin: Sequence[float],
    targets: FloatArray,
    prisms: Prisms,
    cyl_c: FloatArray = _EMPTY2,
    cyl_r: FloatArray = _EMPTY1,
    cyl_top: FloatArray = _EMPTY1,
    *,
    skip: FloatArray | None = None,
    margin: float = 1e-6,
) -> FloatArray:
    """For each 3D target (N, 3): True when the straight line from the 3D ``origin`` reaches it.

    Obstacles have heights: ``prisms`` (walls, furniture, table legs, each
    from its bottom to its top) and upright cylinders standing on the
    floor (people: centres (K, 2), radii (K,), tops (K,)). An obstacle
    blocks a line only where the line, at its height there, passes
    through it: over a short cupboard, under a table top, past a child's
    head to an adult's face. ``skip`` (N, K) marks cylinders a target
    belongs to (a person's own body does not hide their face). The last
    ``margin`` metres before a target never block (its own surface).
    """
    tg = np.atleast_2d(np.asarray(targets, dtype=float))
    n = tg.shape[0]
    if n == 0:
        return np.zeros(0, dtype=bool)
    ox, oy, oz = float(origin[0]), float(origin[1]), float(origin[2])
    if _K is not None:
        c = np.ascontiguousarray(cyl_c, dtype=float).reshape(-1, 2)
        k = c.shape[0]
        blocked = np.zeros(n, dtype=bool)
        if _K.sight_lines(ox, oy, oz, np.ascontiguousarray(tg), margin, _CULL, *prisms.packed, c,
                          np.ascontiguousarray(cyl_r, dtype=float).reshape(k), np.ascontiguousarray(cyl_top, dtype=float).reshape(k),
                          None if skip is None else np.ascontiguousarray(skip, dtype=bool).reshape(n, k), blocked):
            return ~blocked
    # Cull first, in plain floats (a frame asks a few lines): an obstacle whose box misses the
    # box around every line, or whose height span misses every line's, cannot block; the
    # margin _CULL keeps rounding on the safe side. Often nothing is left to test.
    cols = tg.T.tolist()
    x0, x1 = min(ox, *cols[0]) - _CULL, max(ox, *cols[0]) + _CULL
    y0, y1 = min(oy, *cols[1]) - _CULL, max(oy, *cols[1]) + _CULL
    z0, z1 = min(oz, *cols[2]) - _CULL, max(oz, *cols[2]) + _CULL
    keep = [i for i, (lx, ly, hx, hy, bot, top) in enumerate(prisms.boxes)
            if lx <= x1 and hx >= x0 and ly <= y1 and hy >= y0 and bot <= z1 and top >= z0]
    c = np.asarray(cyl_c, dtype=float).reshape(-1, 2)
    ckeep: list[int] = []
    if c.shape[0]:
        r = np.asarray(cyl_r, dtype=float)
        all_skip = np.asarray(skip, dtype=bool).all(axis=0).tolist() if skip is not None else [False] * c.shape[0]
        ckeep = [k for k, ((cx, cy), rk, sk) in enumerate(zip(c.tolist(), r.tolist(), all_skip))
                 if not sk and cx - rk <= x1 and cx + rk >= x0 and cy - rk <= y1 and cy + rk >= y0]
    if not keep and not ckeep:
        return np.ones(n, dtype=bool)
    d = tg[:, :2] - (ox, oy)  # (N, 2): the line is origin + t d, t in [0, 1]
    dz = tg[:, 2] - oz
    length = np.hypot(d[:, 0], d[:, 1])
    t_end = np.clip(1.0 - margin / np.maximum(length, 1e-12), 0.0, 1.0)
    blocked = np.zeros(n, dtype=bool)
    if keep:
        prisms = prisms if len(keep) == len(prisms) else prisms.subset(np.array(keep, dtype=np.intp))
        # Cyrus-Beck clipping of every line against every convex prism footprint; the
        # products are elementwise, so a line's result never depends on the others asked.
        num = (prisms.a[:, 0] - ox) * prisms.normal[:, 0] + (prisms.a[:, 1] - oy) * prisms.normal[:, 1]  # (E,)
        den = d[:, 0:1] * prisms.normal[None, :, 0] + d[:, 1:2] * prisms.normal[None, :, 1]  # (N, E)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            t = num[None, :] / den
        enter = np.where(den < 0, t, -np.inf)
        enter = np.where((den == 0) & (num[None, :] < 0), np.inf, enter)  # parallel and outside this edge
        leave = np.where(den > 0, t, np.inf)
        t_in = np.maximum(np.maximum.reduceat(enter, prisms.first, axis=1), 0.0)  # (N, M)
        t_out = np.minimum(np.minimum.reduceat(leave, prisms.first, axis=1), t_end[:, None])
        blocked |= _height_span_blocks(oz, dz[:, None], t_in, t_out, prisms.bottom[None, :], prisms.top[None, :]).any(axis=1)
    if ckeep:
        sel = np.array(ckeep, dtype=np.intp)
        c, r, cyl_top = c[sel], r[sel], np.asarray(cyl_top, dtype=float)[sel]
        f = (ox, oy) - c  # (K, 2)
        a = (d * d).sum(axis=1)[:, None]  # (N, 1)
        b = 2.0 * (d[:, 0:1] * f[None, :, 0] + d[:, 1:2] * f[None, :, 1])  # (N, K), elementwise as above
        cc = (f * f).sum(axis=1) - r * r  # (K,)
        disc = b * b - 4.0 * a * cc[None, :]
        root = np.sqrt(np.maximum(disc, 0.0))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            t1 = np.where(disc >= 0, (-b - root) / (2.0 * a), np.inf)
            t2 = np.where(disc >= 0, (-b + root) / (2.0 * a), -np.inf)
        t_in = np.maximum(t1, 0.0)
        t_out = np.minimum(t2, t_end[:, None])
        hit = _height_span_blocks(oz, dz[:, None], t_in, t_out, np.zeros_like(r)[None, :], cyl_top[None, :])
        if skip is not None:
            hit &= ~np.asarray(skip, dtype=bool)[:, sel]
        blocked |= hit.any(axis=1)
    return ~blocked
