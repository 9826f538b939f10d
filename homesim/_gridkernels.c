/* The flat grids' exact distance transform and 4-connected labels in C (homesim/ndgrid.py).
 *
 * homesim/ndgrid.py's numpy functions are the reference and stay the fallback; both give
 * scipy.ndimage's arrays bit for bit (tests/test_ndgrid.py compares all three on random grids).
 * Why compiled: the likelihood field's two transforms and the rooms' labels are built before the
 * localiser's first step, ~50 ms of numpy on a 356 x 607 grid at every start (issue 25, start-up).
 *
 * edt_sq(fg, nx, ny, out): out (int64, nx*ny, row-major) receives per true cell of fg (uint8, nx*ny)
 * the squared Euclidean distance in cells to the nearest false cell (0 on false cells). Integers
 * throughout, so exact: the column pass as ndgrid's, then per row the lower envelope of the
 * parabolas (j - q)^2 + g(q)^2 (Felzenszwalb and Huttenlocher 2012) with the envelope's breaking
 * points compared as fractions by cross-multiplication (no division, no float). The caller takes
 * the square root of the float64 of each value (as ndgrid does). fg must hold a false cell.
 *
 * label(fg, nx, ny, out) -> count: out (int32, nx*ny) receives the 4-connected regions of fg's
 * true cells numbered 1.. in row-major order of their first cell, 0 elsewhere (SciPy's numbering):
 * union-find over the right and lower neighbours, then one row-major pass numbering each root at
 * its region's first cell.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <stdlib.h>

#define VERSION 1
/* The SHA-256 of this file as built, set by setup.py (homesim.kernels.load compares it). */
#ifndef KERNEL_SOURCE_SHA256
#define KERNEL_SOURCE_SHA256 ""
#endif

static int get_buffers(PyObject *fg_obj, PyObject *out_obj, Py_ssize_t n, Py_ssize_t item, Py_buffer *fg, Py_buffer *out)
{
    if (PyObject_GetBuffer(fg_obj, fg, PyBUF_C_CONTIGUOUS) < 0) {
        return -1;
    }
    if (PyObject_GetBuffer(out_obj, out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE) < 0) {
        PyBuffer_Release(fg);
        return -1;
    }
    if (fg->len != n || out->len != n * item) {
        PyErr_SetString(PyExc_ValueError, "buffer sizes do not match nx * ny");
        PyBuffer_Release(fg);
        PyBuffer_Release(out);
        return -1;
    }
    return 0;
}

static PyObject *edt_sq(PyObject *self, PyObject *args)
{
    PyObject *fg_obj, *out_obj;
    Py_ssize_t nx, ny;
    if (!PyArg_ParseTuple(args, "OnnO", &fg_obj, &nx, &ny, &out_obj)) {
        return NULL;
    }
    if (nx <= 0 || ny <= 0) {
        PyErr_SetString(PyExc_ValueError, "an empty grid");
        return NULL;
    }
    Py_buffer fb, ob;
    if (get_buffers(fg_obj, out_obj, nx * ny, (Py_ssize_t)sizeof(int64_t), &fb, &ob) < 0) {
        return NULL;
    }
    const unsigned char *fg = (const unsigned char *)fb.buf;
    int64_t *out = (int64_t *)ob.buf;
    const int64_t cap = (int64_t)nx + (int64_t)ny; /* "no false cell in this column" */
    int64_t *g = malloc(sizeof(int64_t) * (size_t)(nx * ny));
    int64_t *v = malloc(sizeof(int64_t) * (size_t)ny);
    int64_t *zn = malloc(sizeof(int64_t) * (size_t)(ny + 1));
    int64_t *zd = malloc(sizeof(int64_t) * (size_t)(ny + 1));
    if (g == NULL || v == NULL || zn == NULL || zd == NULL) {
        free(g);
        free(v);
        free(zn);
        free(zd);
        PyBuffer_Release(&fb);
        PyBuffer_Release(&ob);
        return PyErr_NoMemory();
    }
    Py_BEGIN_ALLOW_THREADS
    /* pass 1: distance along axis 0 to the nearest false cell of the same column (capped) */
    for (Py_ssize_t j = 0; j < ny; j++) {
        int64_t run = cap;
        for (Py_ssize_t i = 0; i < nx; i++) {
            run = fg[i * ny + j] ? (run + 1 < cap ? run + 1 : cap) : 0;
            g[i * ny + j] = run;
        }
        for (Py_ssize_t i = nx - 2; i >= 0; i--) {
            if (g[(i + 1) * ny + j] + 1 < g[i * ny + j]) {
                g[i * ny + j] = g[(i + 1) * ny + j] + 1;
            }
        }
    }
    /* pass 2: per row, the lower envelope of the parabolas of the columns that hold a false cell */
    for (Py_ssize_t i = 0; i < nx; i++) {
        const int64_t *gr = g + i * ny;
        int64_t *o = out + i * ny;
        Py_ssize_t k = -1;
        for (Py_ssize_t q = 0; q < ny; q++) {
            if (gr[q] >= cap) {
                continue;
            }
            int64_t fq = gr[q] * gr[q] + (int64_t)q * q;
            int64_t sn = 0, sd = 1;
            while (k >= 0) {
                int64_t p = v[k];
                sn = fq - (gr[p] * gr[p] + p * p); /* breaking point of p and q: sn / sd */
                sd = 2 * ((int64_t)q - p);
                /* drop p while the new breaking point is at or left of p's own (z[0] is -inf) */
                if (k > 0 && sn * zd[k] <= zn[k] * sd) {
                    k--;
                    continue;
                }
                break;
            }
            k++;
            v[k] = q;
            if (k > 0) {
                zn[k] = sn;
                zd[k] = sd;
            }
        }
        Py_ssize_t count = k + 1, at = 0;
        for (Py_ssize_t j = 0; j < ny; j++) {
            while (at + 1 < count && zn[at + 1] < (int64_t)j * zd[at + 1]) {
                at++;
            }
            int64_t p = v[at], d = (int64_t)j - p;
            o[j] = fg[i * ny + j] ? d * d + gr[p] * gr[p] : 0;
        }
    }
    Py_END_ALLOW_THREADS
    free(g);
    free(v);
    free(zn);
    free(zd);
    PyBuffer_Release(&fb);
    PyBuffer_Release(&ob);
    Py_RETURN_NONE;
}

static Py_ssize_t find(Py_ssize_t *parent, Py_ssize_t a)
{
    while (parent[a] != a) {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    return a;
}

static void unite(Py_ssize_t *parent, Py_ssize_t a, Py_ssize_t b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a < b) {
        parent[b] = a;
    }
    else if (b < a) {
        parent[a] = b;
    }
}

static PyObject *label(PyObject *self, PyObject *args)
{
    PyObject *fg_obj, *out_obj;
    Py_ssize_t nx, ny;
    if (!PyArg_ParseTuple(args, "OnnO", &fg_obj, &nx, &ny, &out_obj)) {
        return NULL;
    }
    if (nx < 0 || ny < 0) {
        PyErr_SetString(PyExc_ValueError, "a negative size");
        return NULL;
    }
    Py_buffer fb, ob;
    if (get_buffers(fg_obj, out_obj, nx * ny, (Py_ssize_t)sizeof(int32_t), &fb, &ob) < 0) {
        return NULL;
    }
    const unsigned char *fg = (const unsigned char *)fb.buf;
    int32_t *out = (int32_t *)ob.buf;
    Py_ssize_t n = nx * ny;
    Py_ssize_t *parent = malloc(sizeof(Py_ssize_t) * (size_t)(n > 0 ? n : 1));
    if (parent == NULL) {
        PyBuffer_Release(&fb);
        PyBuffer_Release(&ob);
        return PyErr_NoMemory();
    }
    long count = 0;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t c = 0; c < n; c++) {
        parent[c] = c;
    }
    for (Py_ssize_t i = 0; i < nx; i++) {
        for (Py_ssize_t j = 0; j < ny; j++) {
            Py_ssize_t c = i * ny + j;
            if (!fg[c]) {
                continue;
            }
            if (j + 1 < ny && fg[c + 1]) {
                unite(parent, c, c + 1);
            }
            if (i + 1 < nx && fg[c + ny]) {
                unite(parent, c, c + ny);
            }
        }
    }
    /* the root is each region's smallest cell index, its first cell in row-major order */
    for (Py_ssize_t c = 0; c < n; c++) {
        if (!fg[c]) {
            out[c] = 0;
        }
        else {
            Py_ssize_t r = find(parent, c);
            out[c] = (r == c) ? (int32_t)++count : out[r];
        }
    }
    Py_END_ALLOW_THREADS
    free(parent);
    PyBuffer_Release(&fb);
    PyBuffer_Release(&ob);
    return PyLong_FromLong(count);
}

static PyMethodDef methods[] = {
    {"edt_sq", edt_sq, METH_VARARGS, "edt_sq(fg, nx, ny, out): squared exact distance transform (see the file's comment)."},
    {"label", label, METH_VARARGS, "label(fg, nx, ny, out) -> count: 4-connected regions, SciPy's numbering."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_gridkernels", "Exact grid transforms (see homesim/ndgrid.py).", -1, methods};

PyMODINIT_FUNC PyInit__gridkernels(void)
{
    PyObject *m = PyModule_Create(&module);
    if (m != NULL && (PyModule_AddIntConstant(m, "VERSION", VERSION) < 0 || PyModule_AddStringConstant(m, "SOURCE_SHA256", KERNEL_SOURCE_SHA256) < 0)) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
