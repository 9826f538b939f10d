/* Compiled inner loops of homesim.world.raycast (the laser's fan caster, the camera's 3D sight
 * lines), the laser's noise step and the sonar rings' cast (robot.hardware.sonar). Optional: the package installs and runs without it, through
 * the pure-Python/numpy paths in raycast.py, which give the same floats.
 *
 * Why these and why bit for bit. Every float here is computed with exactly the operations, in
 * exactly the order, of the numpy/Python path it replaces (the comments name them): + - * / and
 * sqrt are IEEE correctly rounded, and setup.py compiles with -ffp-contract=off so that no
 * multiply-add is fused. The only libm calls (atan2, asin, floor, ceil, fmod, hypot) decide which
 * beams are *candidates* for a test (with a beam of margin each side, so an ulp there changes no
 * range) or are the very functions CPython's math module and numpy's hypot call (glibc's);
 * tests/test_raykernels.py checks kernel == fallback on random geometry and on recorded scans.
 *
 * Arrays come through the buffer protocol (float64, C-contiguous); the Python wrapper checks
 * shapes and dtypes before calling, so these functions only check what they must not trust.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#define KERNEL_VERSION 2 /* 2: sonar_ranges */
/* The SHA-256 of this file as built, set by setup.py (homesim.kernels.load compares it with the
 * file on disk: a build older than its source is not used). */
#ifndef KERNEL_SOURCE_SHA256
#define KERNEL_SOURCE_SHA256 ""
#endif

static const double TWO_PI = 2.0 * 3.14159265358979323846;
static const double PI = 3.14159265358979323846;

/* numpy's minimum/maximum (checked against numpy 2.x): NaN propagates from either side, and on a
 * tie (0.0 and -0.0) the second operand is returned. */
static inline double np_min(double a, double b) { return (a < b || a != a) ? a : b; }
static inline double np_max(double a, double b) { return (a > b || a != a) ? a : b; }
/* np.clip(x, lo, hi) on floats: NaN propagates, and a tie keeps the bound (numpy's _NPY_CLIP). */
static inline double np_clip(double x, double lo, double hi) {
    if (x != x) return x;
    x = x > lo ? x : lo;
    return x < hi ? x : hi;
}

/* Python's float % (and numpy's remainder): the result takes the divisor's sign. */
static inline double py_mod(double x, double y) {
    double mod = fmod(x, y);
    if (mod != 0.0) {
        if ((y < 0.0) != (mod < 0.0)) mod += y;
    } else {
        mod = copysign(0.0, y);
    }
    return mod;
}

/* Buffer helpers ---------------------------------------------------------------------------- */
typedef struct {
    Py_buffer view;
    int held;
} Buf;

static int get_doubles(PyObject *obj, Buf *b, Py_ssize_t n, int writable, const char *what) {
    b->held = 0;
    if (PyObject_GetBuffer(obj, &b->view, (writable ? PyBUF_WRITABLE : 0) | PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        return -1;
    b->held = 1;
    if (b->view.itemsize != 8 || b->view.format == NULL || strcmp(b->view.format, "d") != 0) {
        PyErr_Format(PyExc_TypeError, "%s: expected float64 values", what);
        return -1;
    }
    if (n >= 0 && b->view.len != n * 8) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd values, got %zd", what, n, b->view.len / 8);
        return -1;
    }
    return 0;
}

static int get_bytes(PyObject *obj, Buf *b, Py_ssize_t n, int writable, const char *what) {
    b->held = 0;
    if (PyObject_GetBuffer(obj, &b->view, (writable ? PyBUF_WRITABLE : 0) | PyBUF_C_CONTIGUOUS) < 0)
        return -1;
    b->held = 1;
    if (b->view.itemsize != 1 || (n >= 0 && b->view.len != n)) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd one-byte values", what, n);
        return -1;
    }
    return 0;
}

static int get_intp(PyObject *obj, Buf *b, Py_ssize_t n, const char *what) {
    b->held = 0;
    if (PyObject_GetBuffer(obj, &b->view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        return -1;
    b->held = 1;
    if (b->view.itemsize != (Py_ssize_t)sizeof(Py_ssize_t) || b->view.format == NULL ||
        !(strcmp(b->view.format, "l") == 0 || strcmp(b->view.format, "q") == 0 || strcmp(b->view.format, "n") == 0)) {
        PyErr_Format(PyExc_TypeError, "%s: expected intp values", what);
        return -1;
    }
    if (n >= 0 && b->view.len != n * (Py_ssize_t)sizeof(Py_ssize_t)) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd values", what, n);
        return -1;
    }
    return 0;
}

static void release(Buf *bufs, int count) {
    for (int i = 0; i < count; i++)
        if (bufs[i].held) PyBuffer_Release(&bufs[i].view);
}

#define D(b) ((double *)(b).view.buf)
#define NLEN(b) ((b).view.len / 8)

/* Beam index range [i0, i1] of a piece (lo, hi) of relative angle, a beam of margin each side:
 * raycast._Fan._circles_in_floats. Returns 0 when empty. */
static int beam_range(double lo, double hi, double fan_half, double step, Py_ssize_t last, Py_ssize_t *i0, Py_ssize_t *i1) {
    double f0 = floor((lo + fan_half) / step) - 1.0;
    double f1 = ceil((hi + fan_half) / step) + 1.0;
    if (!(f0 == f0) || !(f1 == f1)) { /* cannot happen for finite pieces; all beams then */
        f0 = 0.0;
        f1 = (double)last;
    }
    if (f0 < 0.0) f0 = 0.0;
    if (f1 > (double)last) f1 = (double)last;
    if (f0 > f1) return 0;
    *i0 = (Py_ssize_t)f0;
    *i1 = (Py_ssize_t)f1;
    return 1;
}

static void circle_piece(double lo, double hi, double fan_half, double step, Py_ssize_t last, const double *dx, const double *dy,
                         double fx, double fy, double base, double *res) {
    Py_ssize_t i0, i1;
    if (!beam_range(lo, hi, fan_half, step, last, &i0, &i1)) return;
    for (Py_ssize_t j = i0; j <= i1; j++) {
        double tca = dx[j] * fx + dy[j] * fy;
        double disc = tca * tca + base;
        if (disc >= 0.0) {
            double t = tca - sqrt(disc);
            if (t >= 0.0 && t < res[j]) res[j] = t;
        }
    }
}

/* fan_circles(ox, oy, centres, radii, dx, dy, centre, fan_half, step, max_range, result)
 * raycast._Fan._circles_in_floats: the dense kernel's circle test on the beams each circle
 * subtends. */
static PyObject *fan_circles(PyObject *self, PyObject *args) {
    double ox, oy, centre, fan_half, step, max_range;
    PyObject *o_c, *o_r, *o_dx, *o_dy, *o_res;
    if (!PyArg_ParseTuple(args, "ddOOOOddddO", &ox, &oy, &o_c, &o_r, &o_dx, &o_dy, &centre, &fan_half, &step, &max_range, &o_res))
        return NULL;
    Buf b[5];
    memset(b, 0, sizeof b);
    if (get_doubles(o_res, &b[0], -1, 1, "result") < 0) goto fail;
    Py_ssize_t n = NLEN(b[0]);
    if (get_doubles(o_dx, &b[1], n, 0, "dx") < 0 || get_doubles(o_dy, &b[2], n, 0, "dy") < 0) goto fail;
    if (get_doubles(o_r, &b[3], -1, 0, "radii") < 0) goto fail;
    Py_ssize_t k = NLEN(b[3]);
    if (get_doubles(o_c, &b[4], 2 * k, 0, "centres") < 0) goto fail;
    {
        double *res = D(b[0]);
        const double *dx = D(b[1]), *dy = D(b[2]), *rad = D(b[3]), *cen = D(b[4]);
        Py_ssize_t last = n - 1;
        int finite = isfinite(max_range);
        for (Py_ssize_t c = 0; c < k; c++) {
            double fx = cen[2 * c] - ox, fy = cen[2 * c + 1] - oy, r = rad[c];
            double ff = fx * fx + fy * fy;
            double rr = r * r;
            if (finite) {
                double lim = max_range + r;
                if (ff > lim * lim * (1.0 + 1e-12)) continue;
                if (ff >= lim * lim * (1.0 - 1e-12) && hypot(fx, fy) - r > max_range) continue;
            }
            if (ff <= rr) {
                for (Py_ssize_t j = 0; j < n; j++) res[j] = np_min(res[j], 0.0);
                continue;
            }
            double rel = py_mod(atan2(fy, fx) - centre + PI, TWO_PI) - PI;
            double q = r / sqrt(ff);
            double half = asin(q < 1.0 ? q : 1.0); /* Python's min(1.0, q): 1.0 unless q < 1.0 */
            double base = rr - ff;
            double lo = rel - half, hi = rel + half;
            if (-PI <= lo && hi <= PI) {
                circle_piece(lo, hi, fan_half, step, last, dx, dy, fx, fy, base, res);
            } else if (lo == lo && hi == hi) {
                circle_piece(lo, hi, fan_half, step, last, dx, dy, fx, fy, base, res);
                if (lo < -PI) circle_piece(lo + TWO_PI, hi + TWO_PI, fan_half, step, last, dx, dy, fx, fy, base, res);
                if (hi > PI) circle_piece(lo - TWO_PI, hi - TWO_PI, fan_half, step, last, dx, dy, fx, fy, base, res);
            } else {
                circle_piece(-PI, PI, fan_half, step, last, dx, dy, fx, fy, base, res);
            }
        }
    }
    release(b, 5);
    Py_RETURN_NONE;
fail:
    release(b, 5);
    return NULL;
}

/* raycast._within for one segment: whether its closest point lies within max_range. */
static int within(double ox, double oy, double ax, double ay, double bx, double by, double max_range) {
    double abx = bx - ax, aby = by - ay;
    double aox = ox - ax, aoy = oy - ay;
    double denom = abx * abx + aby * aby;
    if (denom < 1e-18) denom = 1.0;
    double t = (aox * abx + aoy * aby) / denom;
    t = np_clip(t, 0.0, 1.0);
    double cx = ax + t * abx - ox;
    double cy = ay + t * aby - oy;
    return cx * cx + cy * cy <= max_range * max_range;
}

/* fan_segments(ox, oy, a, b, ex, ey, near, dx, dy, base, k0, kturn, khalf, step, backfaces, max_range, result)
 * raycast._Fan.segments: the dense kernel's segment test (RayCaster._segments) on the beams
 * within the angle each segment subtends (a beam of margin each side), the dense kernel's
 * max_range cull asked for a hit within rounding of max_range. */
static PyObject *fan_segments(PyObject *self, PyObject *args) {
    double ox, oy, base_angle, k0, kturn, khalf, step, max_range;
    int backfaces;
    PyObject *o_a, *o_b, *o_ex, *o_ey, *o_near, *o_dx, *o_dy, *o_res;
    if (!PyArg_ParseTuple(args, "ddOOOOOOOdddddpdO", &ox, &oy, &o_a, &o_b, &o_ex, &o_ey, &o_near, &o_dx, &o_dy, &base_angle, &k0, &kturn,
                          &khalf, &step, &backfaces, &max_range, &o_res))
        return NULL;
    Buf b[8];
    memset(b, 0, sizeof b);
    if (get_doubles(o_res, &b[0], -1, 1, "result") < 0) goto fail;
    Py_ssize_t n = NLEN(b[0]);
    if (get_doubles(o_dx, &b[1], n, 0, "dx") < 0 || get_doubles(o_dy, &b[2], n, 0, "dy") < 0) goto fail;
    if (get_doubles(o_ex, &b[3], -1, 0, "ex") < 0) goto fail;
    Py_ssize_t m = NLEN(b[3]);
    if (get_doubles(o_ey, &b[4], m, 0, "ey") < 0 || get_doubles(o_near, &b[5], m, 0, "near") < 0 || get_doubles(o_a, &b[6], 2 * m, 0, "a") < 0 ||
        get_doubles(o_b, &b[7], 2 * m, 0, "b") < 0)
        goto fail;
    {
        double *res = D(b[0]);
        const double *dx = D(b[1]), *dy = D(b[2]), *ex = D(b[3]), *ey = D(b[4]), *near = D(b[5]), *pa = D(b[6]), *pb = D(b[7]);
        const double FAR = 1e12, inv_step = 1.0 / step, last = (double)(n - 1);
        int finite = isfinite(max_range);
        double near_lo = max_range * (1.0 - 1e-9);
        /* Per segment: f x e, and the interval of beam indices it subtends (start > end: none). */
        double *work = PyMem_Malloc((size_t)(3 * m + 1) * sizeof(double));
        signed char *inside = PyMem_Malloc((size_t)m + 1);
        if (work == NULL || inside == NULL) {
            PyMem_Free(work);
            PyMem_Free(inside);
            PyErr_NoMemory();
            goto fail;
        }
        double *tnums = work, *starts = work + m, *ends = work + 2 * m;
        for (Py_ssize_t s = 0; s < m; s++) {
            double fx = pa[2 * s] - ox, fy = pa[2 * s + 1] - oy;
            double gx = pb[2 * s] - ox, gy = pb[2 * s + 1] - oy;
            double tnum = fx * ey[s] - fy * ex[s];
            double start, end;
            inside[s] = -1; /* not yet asked */
            tnums[s] = tnum;
            if (!(fabs(tnum) >= near[s])) { /* the origin (almost) on the segment's line, or NaN geometry */
                start = -FAR;
                end = FAR;
            } else {
                double ka = (py_mod(atan2(fy, fx) - base_angle, TWO_PI)) * inv_step - k0;
                double kb = (py_mod(atan2(gy, gx) - base_angle, TWO_PI)) * inv_step - k0;
                double lo = ka < kb ? ka : kb, hi = ka < kb ? kb : ka;
                if (hi - lo > khalf) {
                    start = hi;
                    end = lo + kturn;
                } else {
                    start = lo;
                    end = hi;
                }
                if (!(start == start) || !(end == end)) { /* all beams then: a superset is exact */
                    start = -FAR;
                    end = FAR;
                }
            }
            if (!backfaces && tnum >= 0.0) start = FAR; /* a back face: no beam */
            starts[s] = start;
            ends[s] = end;
        }
        /* The Python path's order (its np.minimum.at): each piece over all segments, beams ascending. */
        for (int piece = 0; piece < 2; piece++) {
            for (Py_ssize_t s = 0; s < m; s++) {
                double st = piece ? starts[s] - kturn : starts[s], en = piece ? ends[s] - kturn : ends[s];
                double f0 = floor(st) - 1.0, f1 = ceil(en) + 1.0;
                if (f0 < 0.0) f0 = 0.0;
                if (f1 > last) f1 = last;
                if (!(f0 <= f1)) continue;
                Py_ssize_t i0 = (Py_ssize_t)f0, i1 = (Py_ssize_t)f1;
                double fx = pa[2 * s] - ox, fy = pa[2 * s + 1] - oy, tnum = tnums[s];
                for (Py_ssize_t i = i0; i <= i1; i++) {
                    /* den = d x e ; u = f x d ; sign = np.sign(den) ; RayCaster._segments' mask */
                    double den = dx[i] * ey[s] - dy[i] * ex[s];
                    double u = fx * dy[i] - fy * dx[i];
                    double sign = den > 0.0 ? 1.0 : (den < 0.0 ? -1.0 : (den == 0.0 ? 0.0 : den));
                    u *= sign;
                    den = fabs(den);
                    double t = tnum * sign;
                    if (!(t >= 0.0 && u >= 0.0 && u <= den && den > 1e-15)) continue;
                    t /= den;
                    if (finite && t >= near_lo && t < max_range) {
                        if (inside[s] < 0) inside[s] = (signed char)within(ox, oy, pa[2 * s], pa[2 * s + 1], pb[2 * s], pb[2 * s + 1], max_range);
                        if (!inside[s]) continue;
                    }
                    res[i] = np_min(res[i], t);
                }
            }
        }
        PyMem_Free(work);
        PyMem_Free(inside);
    }
    release(b, 8);
    Py_RETURN_NONE;
fail:
    release(b, 8);
    return NULL;
}

/* scan_noise(ranges, noise, max_range): laser.simulate_scan's noise step in place:
 *   miss = ranges >= max_range; ranges += noise; np.maximum(ranges, 0); np.minimum(ranges, max_range);
 *   ranges[miss] = max_range */
static PyObject *scan_noise(PyObject *self, PyObject *args) {
    PyObject *o_r, *o_n;
    double max_range;
    if (!PyArg_ParseTuple(args, "OOd", &o_r, &o_n, &max_range)) return NULL;
    Buf b[2];
    memset(b, 0, sizeof b);
    if (get_doubles(o_r, &b[0], -1, 1, "ranges") < 0) goto fail;
    Py_ssize_t n = NLEN(b[0]);
    if (get_doubles(o_n, &b[1], n, 0, "noise") < 0) goto fail;
    {
        double *r = D(b[0]);
        const double *z = D(b[1]);
        for (Py_ssize_t i = 0; i < n; i++) {
            if (r[i] >= max_range) {
                r[i] = max_range;
            } else {
                double v = r[i] + z[i];
                v = np_max(v, 0.0);
                r[i] = np_min(v, max_range);
            }
        }
    }
    release(b, 2);
    Py_RETURN_NONE;
fail:
    release(b, 2);
    return NULL;
}

/* sight_lines(ox, oy, oz, targets, margin, cull, prism_a, prism_normal, first, count, bottom, top, lo, hi,
 *             cyl_c, cyl_r, cyl_top, skip, blocked)
 * raycast.sight_lines_clear for finite inputs: the same culling (boxes, all-skipped cylinders),
 * Cyrus-Beck clipping of every line against every kept prism and the cylinders' quadratic, each
 * with numpy's operation order; writes blocked[i] (1: something blocks line i). skip is None or
 * N*K bytes. Returns False (and decides nothing) when the origin or a target is not finite. */
static PyObject *sight_lines(PyObject *self, PyObject *args) {
    double ox, oy, oz, margin, cull;
    PyObject *o_tg, *o_a, *o_nrm, *o_first, *o_count, *o_bot, *o_top, *o_lo, *o_hi, *o_cc, *o_cr, *o_ct, *o_skip, *o_out;
    if (!PyArg_ParseTuple(args, "dddOddOOOOOOOOOOOOO", &ox, &oy, &oz, &o_tg, &margin, &cull, &o_a, &o_nrm, &o_first, &o_count, &o_bot, &o_top,
                          &o_lo, &o_hi, &o_cc, &o_cr, &o_ct, &o_skip, &o_out))
        return NULL;
    Buf b[15];
    memset(b, 0, sizeof b);
    if (get_bytes(o_out, &b[0], -1, 1, "blocked") < 0) goto fail;
    Py_ssize_t n = b[0].view.len;
    if (get_doubles(o_tg, &b[1], 3 * n, 0, "targets") < 0) goto fail;
    if (get_doubles(o_bot, &b[2], -1, 0, "bottom") < 0) goto fail;
    Py_ssize_t mp = NLEN(b[2]);
    if (get_doubles(o_top, &b[3], mp, 0, "top") < 0 || get_doubles(o_lo, &b[4], 2 * mp, 0, "lo") < 0 || get_doubles(o_hi, &b[5], 2 * mp, 0, "hi") < 0 ||
        get_intp(o_first, &b[6], mp, "first") < 0 || get_intp(o_count, &b[7], mp, "count") < 0)
        goto fail;
    if (get_doubles(o_a, &b[8], -1, 0, "prism a") < 0) goto fail;
    Py_ssize_t ne = NLEN(b[8]) / 2;
    if (get_doubles(o_nrm, &b[9], 2 * ne, 0, "prism normal") < 0) goto fail;
    if (get_doubles(o_cr, &b[10], -1, 0, "cylinder radii") < 0) goto fail;
    Py_ssize_t kc = NLEN(b[10]);
    if (get_doubles(o_cc, &b[11], 2 * kc, 0, "cylinder centres") < 0 || get_doubles(o_ct, &b[12], kc, 0, "cylinder tops") < 0) goto fail;
    if (o_skip != Py_None && get_bytes(o_skip, &b[13], n * kc, 0, "skip") < 0) goto fail;
    {
        unsigned char *blocked = (unsigned char *)b[0].view.buf;
        const double *tg = D(b[1]), *bot = D(b[2]), *top = D(b[3]), *plo = D(b[4]), *phi = D(b[5]);
        const Py_ssize_t *first = (const Py_ssize_t *)b[6].view.buf, *count = (const Py_ssize_t *)b[7].view.buf;
        const double *pa = D(b[8]), *nrm = D(b[9]), *cr = D(b[10]), *cc = D(b[11]), *ct = D(b[12]);
        const unsigned char *skip = o_skip != Py_None ? (const unsigned char *)b[13].view.buf : NULL;
        int finite = isfinite(ox) && isfinite(oy) && isfinite(oz);
        for (Py_ssize_t i = 0; i < 3 * n && finite; i++) finite = isfinite(tg[i]);
        if (!finite) { /* Python's min/max over NaNs depend on the order: the Python path decides */
            release(b, 15);
            Py_RETURN_FALSE;
        }
        /* The box around every line (Python's min/max over the origin and the targets, all finite). */
        double x0 = ox, x1 = ox, y0 = oy, y1 = oy, z0 = oz, z1 = oz;
        for (Py_ssize_t i = 0; i < n; i++) {
            double x = tg[3 * i], y = tg[3 * i + 1], z = tg[3 * i + 2];
            if (x < x0) x0 = x;
            if (x > x1) x1 = x;
            if (y < y0) y0 = y;
            if (y > y1) y1 = y;
            if (z < z0) z0 = z;
            if (z > z1) z1 = z;
        }
        x0 -= cull; x1 += cull; y0 -= cull; y1 += cull; z0 -= cull; z1 += cull;
        for (Py_ssize_t i = 0; i < n; i++) blocked[i] = 0;
        for (Py_ssize_t p = 0; p < mp; p++) {
            if (!(plo[2 * p] <= x1 && phi[2 * p] >= x0 && plo[2 * p + 1] <= y1 && phi[2 * p + 1] >= y0 && bot[p] <= z1 && top[p] >= z0)) continue;
            Py_ssize_t e0 = first[p], ec = count[p];
            if (ec <= 0 || e0 < 0 || e0 > ne || ec > ne - e0) { /* no e0 + ec: it could overflow */
                PyErr_SetString(PyExc_ValueError, "sight_lines: a prism without edges");
                goto fail;
            }
            for (Py_ssize_t i = 0; i < n; i++) {
                if (blocked[i]) continue;
                double dxl = tg[3 * i] - ox, dyl = tg[3 * i + 1] - oy, dz = tg[3 * i + 2] - oz;
                double length = hypot(dxl, dyl);
                double t_end = np_clip(1.0 - margin / np_max(length, 1e-12), 0.0, 1.0);
                double t_in = 0.0, t_out = 0.0;
                for (Py_ssize_t e = e0; e < e0 + ec; e++) {
                    double num = (pa[2 * e] - ox) * nrm[2 * e] + (pa[2 * e + 1] - oy) * nrm[2 * e + 1];
                    double den = dxl * nrm[2 * e] + dyl * nrm[2 * e + 1];
                    double t = num / den;
                    double enter = den < 0.0 ? t : -INFINITY;
                    if (den == 0.0 && num < 0.0) enter = INFINITY;
                    double leave = den > 0.0 ? t : INFINITY;
                    if (e == e0) {
                        t_in = enter;
                        t_out = leave;
                    } else {
                        t_in = np_max(t_in, enter);
                        t_out = np_min(t_out, leave);
                    }
                }
                t_in = np_max(t_in, 0.0);
                t_out = np_min(t_out, t_end);
                /* _height_span_blocks */
                int meet = t_in <= t_out;
                double za = oz + dz * (meet ? t_in : 0.0), zb = oz + dz * (meet ? t_out : 0.0);
                double lo = np_min(za, zb), hi = np_max(za, zb);
                if (meet && lo <= top[p] && hi >= bot[p]) blocked[i] = 1;
            }
        }
        for (Py_ssize_t c = 0; c < kc; c++) {
            double cx = cc[2 * c], cy = cc[2 * c + 1], rk = cr[c];
            if (skip) {
                int all = 1;
                for (Py_ssize_t i = 0; i < n && all; i++) all = skip[i * kc + c] != 0;
                if (all && n > 0) continue;
            }
            if (!(cx - rk <= x1 && cx + rk >= x0 && cy - rk <= y1 && cy + rk >= y0)) continue;
            double fx = ox - cx, fy = oy - cy;
            double ccq = (fx * fx + fy * fy) - rk * rk;
            for (Py_ssize_t i = 0; i < n; i++) {
                if (blocked[i] || (skip && skip[i * kc + c])) continue;
                double dxl = tg[3 * i] - ox, dyl = tg[3 * i + 1] - oy, dz = tg[3 * i + 2] - oz;
                double length = hypot(dxl, dyl);
                double t_end = np_clip(1.0 - margin / np_max(length, 1e-12), 0.0, 1.0);
                double a = dxl * dxl + dyl * dyl;
                double bq = 2.0 * (dxl * fx + dyl * fy);
                double disc = bq * bq - 4.0 * a * ccq;
                double root = sqrt(np_max(disc, 0.0));
                double t1 = disc >= 0.0 ? (-bq - root) / (2.0 * a) : INFINITY;
                double t2 = disc >= 0.0 ? (-bq + root) / (2.0 * a) : -INFINITY;
                double t_in = np_max(t1, 0.0), t_out = np_min(t2, t_end);
                int meet = t_in <= t_out;
                double za = oz + dz * (meet ? t_in : 0.0), zb = oz + dz * (meet ? t_out : 0.0);
                double lo = np_min(za, zb), hi = np_max(za, zb);
                if (meet && lo <= ct[c] && hi >= 0.0) blocked[i] = 1;
            }
        }
    }
    release(b, 15);
    Py_RETURN_TRUE;
fail:
    release(b, 15);
    return NULL;
}

/* hypots(x, y, out): out[i] = hypot(x[i], y[i]) with the C library's hypot, for the tests to check
 * it is numpy's (the kernel's length and cull decisions rely on that). */
static PyObject *hypots(PyObject *self, PyObject *args) {
    PyObject *o_x, *o_y, *o_out;
    if (!PyArg_ParseTuple(args, "OOO", &o_x, &o_y, &o_out)) return NULL;
    Buf b[3];
    memset(b, 0, sizeof b);
    if (get_doubles(o_out, &b[0], -1, 1, "out") < 0) goto fail;
    Py_ssize_t n = NLEN(b[0]);
    if (get_doubles(o_x, &b[1], n, 0, "x") < 0 || get_doubles(o_y, &b[2], n, 0, "y") < 0) goto fail;
    for (Py_ssize_t i = 0; i < n; i++) D(b[0])[i] = hypot(D(b[1])[i], D(b[2])[i]);
    release(b, 3);
    Py_RETURN_NONE;
fail:
    release(b, 3);
    return NULL;
}

/* sonar_ranges(ox, oy, dx, dy, k, which, a, b, c, r, max_range, out)
 * robot.hardware.sonar.sonar_readings' cast (its cast_from, walls' part and legs' part, then the
 * least range of each transducer's rays), for a packet in one call: the ring's rays at the pose
 * are rows of k (ox, oy: origins, dx, dy: np.cos and np.sin of the angles, so numpy's floats);
 * out[j] is the least range over row which[j]'s rays of the first wall segment (a, b) or leg
 * circle (c, r) hit, max_range where none. Each candidate is cast_from's float (its operations in
 * its order); the result is their minimum, which is exact (a hit at range zero may come out as
 * -0.0 here and 0.0 there: the caller clips to the sonar's min_range, so the readings agree). */
static PyObject *sonar_ranges(PyObject *self, PyObject *args) {
    PyObject *o_ox, *o_oy, *o_dx, *o_dy, *o_which, *o_a, *o_b, *o_c, *o_r, *o_out;
    Py_ssize_t k;
    double max_range;
    if (!PyArg_ParseTuple(args, "OOOOnOOOOOdO", &o_ox, &o_oy, &o_dx, &o_dy, &k, &o_which, &o_a, &o_b, &o_c, &o_r, &max_range, &o_out))
        return NULL;
    if (k < 1) {
        PyErr_SetString(PyExc_ValueError, "k: a transducer needs at least one ray");
        return NULL;
    }
    PyObject *which = PySequence_Fast(o_which, "which: expected a sequence of transducer indices");
    if (which == NULL) return NULL;
    Buf b[9];
    memset(b, 0, sizeof b);
    Py_ssize_t nw = PySequence_Fast_GET_SIZE(which);
    if (get_doubles(o_out, &b[0], nw, 1, "out") < 0 || get_doubles(o_ox, &b[1], -1, 0, "ox") < 0) goto fail;
    Py_ssize_t n = NLEN(b[1]);
    if (n % k) {
        PyErr_SetString(PyExc_ValueError, "ox: expected whole rows of k rays");
        goto fail;
    }
    if (get_doubles(o_oy, &b[2], n, 0, "oy") < 0 || get_doubles(o_dx, &b[3], n, 0, "dx") < 0 || get_doubles(o_dy, &b[4], n, 0, "dy") < 0) goto fail;
    if (get_doubles(o_a, &b[5], -1, 0, "a") < 0) goto fail;
    Py_ssize_t m = NLEN(b[5]) / 2;
    if (NLEN(b[5]) % 2 || get_doubles(o_b, &b[6], 2 * m, 0, "b") < 0) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_ValueError, "a: expected (m, 2) values");
        goto fail;
    }
    if (get_doubles(o_r, &b[7], -1, 0, "r") < 0) goto fail;
    Py_ssize_t p = NLEN(b[7]);
    if (get_doubles(o_c, &b[8], 2 * p, 0, "c") < 0) goto fail;
    {
        Py_ssize_t rows = n / k;
        PyObject **items = PySequence_Fast_ITEMS(which);
        double *out = D(b[0]);
        const double *OX = D(b[1]), *OY = D(b[2]), *DX = D(b[3]), *DY = D(b[4]), *pa = D(b[5]), *pb = D(b[6]), *rad = D(b[7]), *cen = D(b[8]);
        for (Py_ssize_t j = 0; j < nw; j++) {
            Py_ssize_t row = PyNumber_AsSsize_t(items[j], PyExc_IndexError);
            if (row == -1 && PyErr_Occurred()) goto fail;
            if (row < 0 || row >= rows) {
                PyErr_Format(PyExc_IndexError, "which: transducer %zd of %zd", row, rows);
                goto fail;
            }
            double least = INFINITY;
            for (Py_ssize_t i = row * k; i < (row + 1) * k; i++) {
                double ox = OX[i], oy = OY[i], dx = DX[i], dy = DY[i];
                double walls = INFINITY, legs = INFINITY;
                for (Py_ssize_t s = 0; s < m; s++) {
                    /* cast_from's segments: den = d x e ; u = f x d ; tnum = f x e ; the sign trick; its mask */
                    double ex = pb[2 * s] - pa[2 * s], ey = pb[2 * s + 1] - pa[2 * s + 1];
                    double fx = pa[2 * s] - ox, fy = pa[2 * s + 1] - oy;
                    double den = dx * ey - dy * ex;
                    double u = fx * dy - fy * dx;
                    double tnum = fx * ey - fy * ex;
                    double sign = den > 0.0 ? 1.0 : (den < 0.0 ? -1.0 : (den == 0.0 ? 0.0 : den));
                    u = u * sign;
                    den = fabs(den);
                    double t = tnum * sign;
                    if (t >= 0.0 && u >= 0.0 && u <= den && den > 1e-15) walls = np_min(walls, t / den);
                }
                for (Py_ssize_t c = 0; c < p; c++) {
                    /* cast_from's circles: ff, rr, tca = dx*fx + dy*fy, disc = tca*tca + (rr - ff), near = tca - sqrt(disc) */
                    double fx = cen[2 * c] - ox, fy = cen[2 * c + 1] - oy;
                    double ff = fx * fx + fy * fy;
                    double rr = rad[c] * rad[c];
                    double near = INFINITY;
                    if (ff <= rr) {
                        near = 0.0;
                    } else {
                        double tca = dx * fx;
                        tca += dy * fy;
                        double disc = tca * tca;
                        disc += rr - ff;
                        if (disc >= 0.0) {
                            double t = tca - sqrt(disc);
                            if (t >= 0.0) near = t;
                        }
                    }
                    legs = np_min(legs, near);
                }
                /* np.minimum(full(max_range), walls' least), the same for the legs, their np.minimum */
                double ray = np_min(np_min(max_range, walls), np_min(max_range, legs));
                least = np_min(least, ray);
            }
            out[j] = least;
        }
    }
    Py_DECREF(which);
    release(b, 9);
    Py_RETURN_NONE;
fail:
    Py_DECREF(which);
    release(b, 9);
    return NULL;
}

static PyMethodDef methods[] = {
    {"hypots", hypots, METH_VARARGS, "The C library's hypot over arrays (for the tests)."},
    {"fan_circles", fan_circles, METH_VARARGS, "The fan caster's circle test (raycast._Fan._circles_in_floats)."},
    {"fan_segments", fan_segments, METH_VARARGS, "The fan caster's segment test (raycast._Fan.segments)."},
    {"scan_noise", scan_noise, METH_VARARGS, "The laser's noise step in place (laser.simulate_scan)."},
    {"sight_lines", sight_lines, METH_VARARGS, "3D sight lines against prisms and cylinders (raycast.sight_lines_clear)."},
    {"sonar_ranges", sonar_ranges, METH_VARARGS, "The sonar rings' cast of a packet (robot.hardware.sonar.sonar_readings)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_raykernels", "Compiled inner loops of homesim.world.raycast (optional).", -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__raykernels(void) {
    PyObject *m = PyModule_Create(&module);
    if (m == NULL) return NULL;
    if (PyModule_AddIntConstant(m, "VERSION", KERNEL_VERSION) < 0 || PyModule_AddStringConstant(m, "SOURCE_SHA256", KERNEL_SOURCE_SHA256) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
