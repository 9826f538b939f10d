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
 * astar(free, ny, start, goal) -> list of flat cell indices from start to goal, or None (no path):
 * homesim/scenario/pathplan.py's PathGrid._astar (the reference) step for step: the same moves in
 * the same order (east, west, north, south, then the diagonals, none cutting a corner), the same
 * costs and priorities in the same float operations, and the same pops: the frontier is ordered by
 * (priority, push counter), a total order, so a binary heap here pops what heapq pops there. The
 * grids' borders are blocked, so no neighbour leaves the grid; one that would is refused here
 * (IndexError) where the reference would index outside its list.
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

#include <math.h>

#define VERSION 2
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

typedef struct {
    double prio;
    int64_t counter;
    Py_ssize_t cell;
} Entry;

static int entry_less(const Entry *a, const Entry *b)
{
    return a->prio < b->prio || (a->prio == b->prio && a->counter < b->counter);
}

typedef struct {
    Entry *items;
    Py_ssize_t size, cap;
} Heap;

static int heap_push(Heap *h, double prio, int64_t counter, Py_ssize_t cell)
{
    if (h->size == h->cap) {
        Py_ssize_t cap = h->cap ? 2 * h->cap : 1024;
        Entry *items = realloc(h->items, sizeof(Entry) * (size_t)cap);
        if (items == NULL) {
            return -1;
        }
        h->items = items;
        h->cap = cap;
    }
    Py_ssize_t i = h->size++;
    Entry e = {prio, counter, cell};
    while (i > 0) {
        Py_ssize_t parent = (i - 1) / 2;
        if (!entry_less(&e, &h->items[parent])) {
            break;
        }
        h->items[i] = h->items[parent];
        i = parent;
    }
    h->items[i] = e;
    return 0;
}

static Py_ssize_t heap_pop(Heap *h)
{
    Py_ssize_t top = h->items[0].cell;
    Entry last = h->items[--h->size];
    Py_ssize_t i = 0, n = h->size;
    while (1) {
        Py_ssize_t l = 2 * i + 1, best = i;
        const Entry *b = &last;
        if (l < n && entry_less(&h->items[l], b)) {
            best = l;
            b = &h->items[l];
        }
        if (l + 1 < n && entry_less(&h->items[l + 1], b)) {
            best = l + 1;
        }
        if (best == i) {
            break;
        }
        h->items[i] = h->items[best];
        i = best;
    }
    if (n > 0) {
        h->items[i] = last;
    }
    return top;
}

static PyObject *astar(PyObject *self, PyObject *args)
{
    PyObject *free_obj;
    Py_ssize_t ny, start, goal;
    if (!PyArg_ParseTuple(args, "Onnn", &free_obj, &ny, &start, &goal)) {
        return NULL;
    }
    Py_buffer fb;
    if (PyObject_GetBuffer(free_obj, &fb, PyBUF_C_CONTIGUOUS) < 0) {
        return NULL;
    }
    const unsigned char *free_ = (const unsigned char *)fb.buf;
    const Py_ssize_t n = fb.len;
    if (ny <= 0 || start < 0 || start >= n || goal < 0 || goal >= n) {
        PyBuffer_Release(&fb);
        PyErr_SetString(PyExc_ValueError, "astar: start, goal or ny outside the grid");
        return NULL;
    }
    double *cost = malloc(sizeof(double) * (size_t)n);
    Py_ssize_t *came = malloc(sizeof(Py_ssize_t) * (size_t)n);
    unsigned char *closed = calloc((size_t)n, 1);
    Heap heap = {NULL, 0, 0};
    int status = 0; /* 0 no path, 1 found, -1 out of memory, -2 index past the end */
    if (cost == NULL || came == NULL || closed == NULL) {
        status = -1;
        goto done;
    }
    for (Py_ssize_t c = 0; c < n; c++) {
        cost[c] = INFINITY;
    }
    cost[start] = 0.0;
    const double sq2 = sqrt(2.0);
    const double km1 = (sq2 - 1.0) - 1.0;
    const Py_ssize_t gi = goal / ny, gj = goal % ny;
    int64_t counter = 0;
    if (heap_push(&heap, 0.0, 0, start) < 0) {
        status = -1;
        goto done;
    }
    /* the eight moves in the reference's order: offsets in cells (di, dj) */
    static const int mdi[8] = {1, -1, 0, 0, 1, 1, -1, -1};
    static const int mdj[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    while (heap.size > 0) {
        Py_ssize_t c = heap_pop(&heap);
        if (c == goal) {
            status = 1;
            break;
        }
        if (closed[c]) {
            continue;
        }
        closed[c] = 1;
        double base = cost[c];
        Py_ssize_t ci = c / ny, cj = c % ny;
        Py_ssize_t ex = ci - gi, ey = cj - gj;
        int f4[4];
        for (int m = 0; m < 4; m++) {
            Py_ssize_t q = c + mdi[m] * ny + mdj[m];
            if (q < 0 || q >= n) {
                status = -2;
                goto done;
            }
            f4[m] = free_[q] != 0;
        }
        for (int m = 0; m < 8; m++) {
            if (m < 4) {
                if (!f4[m]) {
                    continue;
                }
            }
            else if (!(f4[m < 6 ? 0 : 1] && f4[(m % 2) ? 3 : 2])) { /* no corner cutting: both orthogonals free */
                continue;
            }
            Py_ssize_t q = c + mdi[m] * ny + mdj[m];
            if (q < 0 || q >= n) {
                status = -2;
                goto done;
            }
            if (m >= 4 && !free_[q]) {
                continue;
            }
            double nc = base + (m < 4 ? 1.0 : sq2);
            if (nc < cost[q]) {
                cost[q] = nc;
                came[q] = c;
                Py_ssize_t dx = ex + mdi[m], dy = ey + mdj[m];
                dx = dx < 0 ? -dx : dx;
                dy = dy < 0 ? -dy : dy;
                counter++;
                double h = (double)(dx + dy) + km1 * (double)(dx < dy ? dx : dy);
                if (heap_push(&heap, nc + h, counter, q) < 0) {
                    status = -1;
                    goto done;
                }
            }
        }
    }
done:
    free(heap.items);
    free(closed);
    PyBuffer_Release(&fb);
    PyObject *result = NULL;
    if (status == 1) {
        Py_ssize_t len = 1;
        for (Py_ssize_t q = goal; q != start; q = came[q]) {
            len++;
        }
        result = PyList_New(len);
        if (result != NULL) {
            Py_ssize_t q = goal;
            for (Py_ssize_t k = len - 1; k >= 0; k--) {
                PyObject *v = PyLong_FromSsize_t(q);
                if (v == NULL) {
                    Py_CLEAR(result);
                    break;
                }
                PyList_SET_ITEM(result, k, v);
                if (k > 0) {
                    q = came[q];
                }
            }
        }
    }
    else if (status == 0) {
        result = Py_NewRef(Py_None);
    }
    else if (status == -1) {
        PyErr_NoMemory();
    }
    else {
        PyErr_SetString(PyExc_IndexError, "astar: a neighbour outside the grid (its border is not blocked)");
    }
    free(cost);
    free(came);
    return result;
}

static PyMethodDef methods[] = {
    {"astar", astar, METH_VARARGS, "astar(free, ny, start, goal) -> cells or None: pathplan's A* (see the file's comment)."},
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
