/* The leg detector's per-scan pass in C: segments, their sums, the rules, the candidates' centres.
 *
 * robot/attention/legs.py (LegDetector) is the reference and stays the fallback; this computes
 * the same floats operation for operation:
 *  - a segment's sums are numpy's np.add.reduceat: the first element plus numpy's pairwise sum of
 *    the rest (pairwise_sum below is numpy's algorithm: eight accumulators in blocks of up to 128,
 *    halves beyond, -0.0 to start a short run);
 *  - hypotenuses are the C library's hypot, which numpy's np.hypot calls for float64;
 *  - sqrt is correctly rounded (as Python's math.sqrt);
 *  - built with -ffp-contract=off (setup.py): no fused multiply-add, every product rounded.
 * tests/test_attention_kernel.py checks candidates and flags bit for bit against the Python path.
 *
 * candidates(ranges, cos, sin, params) -> (cx, cy, flags): lists of the leg-like segments' centres
 * (robot frame, pushed back by a leg radius, laser offset added) and per centre 1 (a leg), 2 (a
 * blob: both legs as one segment) or 3 (both), in scan order; what LegDetector._rules has before
 * the furniture filter and the pairing. params is a tuple of 13 floats, in this order:
 * max_range, jump, spacing, min_width, max_width, blob_lo, blob_hi, max_linearity, background,
 * sparse_range, hidden_lo, hidden_hi, offset.
 *
 * pair(legs, blobs, pair_distance, near) -> (points, kinds): the pairing (legs.py's _pair).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

#define VERSION 2
/* The SHA-256 of this file as built, set by setup.py (homesim.kernels.load compares it with the
 * file on disk: a build older than its source is not used). */
#ifndef KERNEL_SOURCE_SHA256
#define KERNEL_SOURCE_SHA256 ""
#endif
#define MAX_BEAMS 4096

static double pairwise_sum(const double *a, Py_ssize_t n)
{
    if (n < 8) {
        double res = -0.0;
        for (Py_ssize_t i = 0; i < n; i++) {
            res += a[i];
        }
        return res;
    }
    else if (n <= 128) {
        double r[8], res;
        Py_ssize_t i;
        for (int j = 0; j < 8; j++) {
            r[j] = a[j];
        }
        for (i = 8; i < n - (n % 8); i += 8) {
            for (int j = 0; j < 8; j++) {
                r[j] += a[i + j];
            }
        }
        res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for (; i < n; i++) {
            res += a[i];
        }
        return res;
    }
    else {
        Py_ssize_t n2 = n / 2;
        n2 -= n2 % 8;
        return pairwise_sum(a, n2) + pairwise_sum(a + n2, n - n2);
    }
}

/* np.add.reduceat's value for a[0:n] (n >= 1). */
static double segment_sum(const double *a, Py_ssize_t n)
{
    return a[0] + pairwise_sum(a + 1, n - 1);
}

/* Python's max(v, 0.0): v unless 0.0 is larger. */
static double max0(double v)
{
    return 0.0 > v ? 0.0 : v;
}

/* LegDetector._linearity for the points x[0:n], y[0:n]. */
static double linearity(const double *x, const double *y, Py_ssize_t n, double *scratch)
{
    double *xx = scratch, *yy = scratch + n, *xy = scratch + 2 * n;
    for (Py_ssize_t i = 0; i < n; i++) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    double sx = segment_sum(x, n), sy = segment_sum(y, n);
    double sxx = segment_sum(xx, n), syy = segment_sum(yy, n), sxy = segment_sum(xy, n);
    double dn = (double)n;
    double mx = sx / dn, my = sy / dn;
    double cxx = sxx / dn - mx * mx, cyy = syy / dn - my * my, cxy = sxy / dn - mx * my;
    double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
    return sqrt(max0(tr / 2 - sqrt(max0(tr * tr / 4 - det))));
}

static int as_doubles(PyObject *obj, Py_buffer *view, const char *what)
{
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        return -1;
    }
    if (view->itemsize != sizeof(double) || view->format == NULL || strcmp(view->format, "d") != 0) {
        PyErr_Format(PyExc_TypeError, "_legkernel: %s must be a contiguous float64 array", what);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static PyObject *candidates(PyObject *self, PyObject *args)
{
    PyObject *r_obj, *c_obj, *s_obj;
    double max_range, jump, spacing, min_width, max_width, blob_lo, blob_hi, max_linearity, background, sparse_range, hidden_lo, hidden_hi, offset;
    if (!PyArg_ParseTuple(args, "OOO(ddddddddddddd)", &r_obj, &c_obj, &s_obj, &max_range, &jump, &spacing, &min_width, &max_width, &blob_lo, &blob_hi,
                          &max_linearity, &background, &sparse_range, &hidden_lo, &hidden_hi, &offset)) {
        return NULL;
    }
    Py_buffer rv, cv, sv;
    if (as_doubles(r_obj, &rv, "ranges") < 0) {
        return NULL;
    }
    if (as_doubles(c_obj, &cv, "cos") < 0) {
        PyBuffer_Release(&rv);
        return NULL;
    }
    if (as_doubles(s_obj, &sv, "sin") < 0) {
        PyBuffer_Release(&rv);
        PyBuffer_Release(&cv);
        return NULL;
    }
    Py_ssize_t n = rv.len / (Py_ssize_t)sizeof(double);
    PyObject *result = NULL;
    if (n < 2 || n > MAX_BEAMS || cv.len != rv.len || sv.len != rv.len) {
        PyErr_Format(PyExc_ValueError, "_legkernel: need 2 to %d beams and one cos and sin per beam", MAX_BEAMS);
        goto done;
    }
    const double *r = (const double *)rv.buf, *co = (const double *)cv.buf, *si = (const double *)sv.buf;
    /* Per beam: x, y; per segment (at most n): first, last, features. */
    static double x[MAX_BEAMS], y[MAX_BEAMS], scratch[3 * MAX_BEAMS];
    static Py_ssize_t first[MAX_BEAMS], last[MAX_BEAMS];
    static double rng[MAX_BEAMS], wid[MAX_BEAMS], before[MAX_BEAMS], after[MAX_BEAMS];
    static Py_ssize_t size[MAX_BEAMS];
    static unsigned char leg[MAX_BEAMS], blob[MAX_BEAMS], hidden[MAX_BEAMS];
    const double inf = HUGE_VAL;
    for (Py_ssize_t i = 0; i < n; i++) {
        x[i] = r[i] * co[i];
        y[i] = r[i] * si[i];
    }
    /* 1. Segments: a break after beam i where the range jumps or either beam has no echo; beams
     * without echo are segments of their own, dropped. */
    Py_ssize_t count = 0;
    Py_ssize_t start = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        int brk = i == n - 1 || !(r[i] < max_range) || !(r[i + 1] < max_range) || fabs(r[i + 1] - r[i]) > jump;
        if (brk) {
            if (r[start] < max_range) {
                first[count] = start;
                last[count] = i;
                count++;
            }
            start = i + 1;
        }
    }
    /* 2.-3. Features and rules (LegDetector._rules). */
    double widest = blob_hi > max_width ? blob_hi : max_width; /* Python's max(max_width, blob_hi) */
    for (Py_ssize_t k = 0; k < count; k++) {
        Py_ssize_t s = first[k], e = last[k];
        double ch = hypot(x[e] - x[s], y[e] - y[s]);
        double b = s > 0 ? r[s - 1] : inf;
        double a = e < n - 1 ? r[e + 1] : inf;
        leg[k] = blob[k] = hidden[k] = 0;
        size[k] = 0;
        rng[k] = 0.0;
        before[k] = b;
        after[k] = a;
        if (ch > widest) {
            wid[k] = ch;
            continue;
        }
        Py_ssize_t cnt = e + 1 - s;
        double mean_r = segment_sum(r + s, cnt) / (double)cnt;
        double width = ch + mean_r * spacing;
        size[k] = cnt;
        rng[k] = mean_r;
        wid[k] = width;
        if (b >= max_range) {
            b = before[k] = inf;
        }
        if (a >= max_range) {
            a = after[k] = inf;
        }
        if (b > mean_r + background && a > mean_r + background) {
            if ((cnt >= 2 || mean_r > 3.0) && (width >= min_width || (cnt <= 2 && mean_r > sparse_range)) && width <= max_width) {
                leg[k] = 1;
            }
            if (cnt >= 4 && blob_lo < width && width <= blob_hi) {
                blob[k] = linearity(x + s, y + s, cnt, scratch) > max_linearity;
            }
        }
    }
    /* A leg half hidden behind the other. */
    for (Py_ssize_t k = 0; k < count; k++) {
        if (!leg[k]) {
            continue;
        }
        Py_ssize_t j = k + 1;
        if (j < count && last[k] + 1 == first[j] && !leg[j] && !blob[j] && wid[j] <= max_width) {
            double d = rng[j] - rng[k];
            if (hidden_lo < d && d < hidden_hi && after[j] > rng[j] + background) {
                hidden[j] = 1;
            }
        }
        j = k - 1;
        if (j >= 0 && last[j] + 1 == first[k] && !leg[j] && !blob[j] && wid[j] <= max_width) {
            double d = rng[j] - rng[k];
            if (hidden_lo < d && d < hidden_hi && before[j] > rng[j] + background) {
                hidden[j] = 1;
            }
        }
    }
    /* A leg partly hidden behind something well in front of it, standing out on its other side. */
    for (Py_ssize_t k = 0; k < count; k++) {
        if (leg[k] || hidden[k] || blob[k] || size[k] < 2 || !(min_width <= wid[k] && wid[k] <= max_width)) {
            continue;
        }
        double m = rng[k];
        if ((before[k] < m - hidden_hi && after[k] > m + background) || (after[k] < m - hidden_hi && before[k] > m + background)) {
            hidden[k] = 1;
        }
    }
    /* The candidates' centres, pushed back by about a leg radius. */
    PyObject *lx = PyList_New(0), *ly = PyList_New(0), *lf = PyList_New(0);
    if (lx == NULL || ly == NULL || lf == NULL) {
        goto fail;
    }
    for (Py_ssize_t k = 0; k < count; k++) {
        int isleg = leg[k] || hidden[k];
        if (!isleg && !blob[k]) {
            continue;
        }
        double dn = (double)size[k];
        double mx = segment_sum(x + first[k], size[k]) / dn;
        double my = segment_sum(y + first[k], size[k]) / dn;
        double norm = hypot(mx, my);
        if (1e-9 > norm) {
            norm = 1e-9;
        }
        PyObject *vx = PyFloat_FromDouble(mx + 0.05 * mx / norm + offset);
        PyObject *vy = PyFloat_FromDouble(my + 0.05 * my / norm);
        PyObject *vf = PyLong_FromLong((isleg ? 1 : 0) | (blob[k] ? 2 : 0));
        int bad = vx == NULL || vy == NULL || vf == NULL || PyList_Append(lx, vx) < 0 || PyList_Append(ly, vy) < 0 || PyList_Append(lf, vf) < 0;
        Py_XDECREF(vx);
        Py_XDECREF(vy);
        Py_XDECREF(vf);
        if (bad) {
            goto fail;
        }
    }
    result = PyTuple_Pack(3, lx, ly, lf);
fail:
    Py_XDECREF(lx);
    Py_XDECREF(ly);
    Py_XDECREF(lf);
done:
    PyBuffer_Release(&rv);
    PyBuffer_Release(&cv);
    PyBuffer_Release(&sv);
    return result;
}

/* pair(legs, blobs, pair_distance, near) -> (points, kinds): legs.py's _pair. legs and blobs are lists
 * of (x, y) float tuples; near is (pair_distance * 1.01) ** 2 as Python computes it. Pairs of legs at
 * most pair_distance apart (hypot, as np.hypot), nearest first (a stable order: ties keep the
 * row-major order of (i, j)), each leg in one pair at most, at their midpoint; then the blobs; then
 * the legs left over. kinds: 0 pair, 1 blob, 2 single (PAIR, BLOB, SINGLE). */
static PyObject *pair(PyObject *self, PyObject *args)
{
    PyObject *legs, *blobs;
    double pair_distance, near;
    if (!PyArg_ParseTuple(args, "O!O!dd", &PyList_Type, &legs, &PyList_Type, &blobs, &pair_distance, &near)) {
        return NULL;
    }
    Py_ssize_t k = PyList_GET_SIZE(legs);
    if (k > 256) {
        PyErr_SetString(PyExc_ValueError, "_legkernel.pair: at most 256 legs");
        return NULL;
    }
    static double lx[256], ly[256], dd[256 * 255 / 2];
    static int pi[256 * 255 / 2], pj[256 * 255 / 2], order[256 * 255 / 2];
    static unsigned char used[256];
    for (Py_ssize_t i = 0; i < k; i++) {
        PyObject *t = PyList_GET_ITEM(legs, i);
        if (!PyTuple_Check(t) || PyTuple_GET_SIZE(t) != 2) {
            PyErr_SetString(PyExc_TypeError, "_legkernel.pair: legs must be (x, y) tuples");
            return NULL;
        }
        lx[i] = PyFloat_AsDouble(PyTuple_GET_ITEM(t, 0));
        ly[i] = PyFloat_AsDouble(PyTuple_GET_ITEM(t, 1));
        if (PyErr_Occurred()) {
            return NULL;
        }
        used[i] = 0;
    }
    PyObject *points = PyList_New(0), *kinds = PyList_New(0);
    PyObject *kind_pair = PyLong_FromLong(0), *kind_blob = PyLong_FromLong(1), *kind_single = PyLong_FromLong(2);
    if (points == NULL || kinds == NULL || kind_pair == NULL || kind_blob == NULL || kind_single == NULL) {
        goto fail;
    }
    int count = 0;
    for (int i = 0; i < k; i++) {
        for (int j = i + 1; j < k; j++) {
            double ex = lx[i] - lx[j], ey = ly[i] - ly[j];
            if (ex * ex + ey * ey <= near) {
                pi[count] = i;
                pj[count] = j;
                dd[count] = hypot(ex, ey);
                count++;
            }
        }
    }
    /* Stable insertion sort of the candidate pairs by distance (Python's sorted on the same keys). */
    for (int m = 0; m < count; m++) {
        int q = m;
        while (q > 0 && dd[m] < dd[order[q - 1]]) {
            order[q] = order[q - 1];
            q--;
        }
        order[q] = m;
    }
    for (int q = 0; q < count; q++) {
        int m = order[q];
        if (dd[m] > pair_distance) {
            break;
        }
        int i = pi[m], j = pj[m];
        if (used[i] || used[j]) {
            continue;
        }
        used[i] = used[j] = 1;
        PyObject *pt = Py_BuildValue("(dd)", (lx[i] + lx[j]) / 2, (ly[i] + ly[j]) / 2);
        if (pt == NULL || PyList_Append(points, pt) < 0 || PyList_Append(kinds, kind_pair) < 0) {
            Py_XDECREF(pt);
            goto fail;
        }
        Py_DECREF(pt);
    }
    for (Py_ssize_t b = 0; b < PyList_GET_SIZE(blobs); b++) {
        if (PyList_Append(points, PyList_GET_ITEM(blobs, b)) < 0 || PyList_Append(kinds, kind_blob) < 0) {
            goto fail;
        }
    }
    for (Py_ssize_t i = 0; i < k; i++) {
        if (!used[i] && (PyList_Append(points, PyList_GET_ITEM(legs, i)) < 0 || PyList_Append(kinds, kind_single) < 0)) {
            goto fail;
        }
    }
    Py_DECREF(kind_pair);
    Py_DECREF(kind_blob);
    Py_DECREF(kind_single);
    PyObject *result = PyTuple_Pack(2, points, kinds);
    Py_DECREF(points);
    Py_DECREF(kinds);
    return result;
fail:
    Py_XDECREF(points);
    Py_XDECREF(kinds);
    Py_XDECREF(kind_pair);
    Py_XDECREF(kind_blob);
    Py_XDECREF(kind_single);
    return NULL;
}

static PyMethodDef methods[] = {
    {"candidates", candidates, METH_VARARGS, "candidates(ranges, cos, sin, params) -> (cx, cy, flags): see the file's comment."},
    {"pair", pair, METH_VARARGS, "pair(legs, blobs, pair_distance, near) -> (points, kinds): legs.py's _pair."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_legkernel", "The leg detector's per-scan pass (see robot/attention/legs.py).", -1, methods};

PyMODINIT_FUNC PyInit__legkernel(void)
{
    PyObject *m = PyModule_Create(&module);
    if (m != NULL && (PyModule_AddIntConstant(m, "VERSION", VERSION) < 0 || PyModule_AddStringConstant(m, "SOURCE_SHA256", KERNEL_SOURCE_SHA256) < 0)) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
