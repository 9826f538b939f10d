"""Exact 2D grid operations in numpy: Euclidean distance transform, 4-connected labels, 3x3 dilation.

Why not ``scipy.ndimage``: importing it pulls in ``scipy.special`` through its array-API layer,
~0.2 s of CPU at every ``homesim run`` before the first simulated step, for three functions the
flat's grids (navigation clearance, the likelihood field, the walkers' regions) call a few times.
These give the same arrays as ``scipy.ndimage.distance_transform_edt``, ``label`` (default
structure) and ``binary_dilation`` (3x3 ones, one iteration) on 2D boolean grids, bit for bit:
``tests/test_ndgrid.py`` compares them with SciPy (still a test-time dependency) on random grids.

- the distance transform is exact: squared distances are integers (the column distance, then the
  smallest ``g**2 + d**2`` over row offsets ``d``, stopping once ``d**2`` exceeds every cell's best),
  and the square root of an exact integer is what SciPy's ``sqrt(di**2 + dj**2)`` gives too;
  ``distance_transform_edt`` is Python-level numpy, ~5x SciPy's C: it runs a few times at start-up
  (the likelihood field) and at a navigation grid's build, not per step;
- labels propagate the smallest cell index of each region (minima over horizontal and vertical
  runs of cells, and pointer jumping),
  so a region's label is its first cell in row-major order, numbered 1, 2, ... in that order,
  which is SciPy's numbering.

The distance transform and the labels run in the optional compiled kernel
``homesim/_gridkernels.c`` when it is built (the same integers: exact arithmetic both ways; the
numpy paths here stay the reference, ``tests/test_ndgrid.py`` checks all three against each other).
"""

from __future__ import annotations

from types import ModuleType

import numpy as np

_K: list[ModuleType | None] = []


def _kernel() -> ModuleType | None:
    """The compiled grid kernel, or None (not built, stale, ``HOMESIM_PURE_PYTHON``); looked up once."""
    if not _K:
        from .kernels import load

        _K.append(load("homesim._gridkernels", 2))
    return _K[0]


def distance_transform_edt(grid: np.ndarray) -> np.ndarray:
    """Per cell of ``grid`` (2D), the Euclidean distance in cells to the nearest zero cell (0 on zeros).

    As ``scipy.ndimage.distance_transform_edt(grid)``. A grid with no zero cell has no distances:
    then SciPy's own result is returned (imported only in that case).
    """
    fg = np.asarray(grid, dtype=bool)
    if fg.ndim != 2:
        raise ValueError(f"a 2D grid is needed, not {fg.ndim}D")
    if fg.all():
        from scipy import ndimage  # no background: whatever SciPy defines

        return ndimage.distance_transform_edt(grid)  # type: ignore[no-any-return]
    nx, ny = fg.shape
    k = _kernel()
    if k is not None:
        sq = np.empty((nx, ny), dtype=np.int64)
        k.edt_sq(np.ascontiguousarray(fg).view(np.uint8), nx, ny, sq)
        return np.sqrt(sq.astype(np.float64))
    return _edt_numpy(fg)


def _edt_numpy(fg: np.ndarray) -> np.ndarray:
    """The numpy path of :func:`distance_transform_edt` (the reference) on a 2D bool grid with a false cell."""
    nx, ny = fg.shape
    cap = nx + ny  # more than any distance along a column: "no zero in this column"
    far = cap * cap  # more than any squared distance in the grid
    dtype = np.int32 if 2 * far < 2**31 else np.int64
    # pass 1: distance along axis 0 to the nearest zero in the same column
    g = np.empty((nx, ny), dtype=dtype)
    run = np.full(ny, cap, dtype=dtype)
    for i in range(nx):
        run = np.where(fg[i], np.minimum(run + 1, cap), 0).astype(dtype, copy=False)
        g[i] = run
    for i in range(nx - 2, -1, -1):
        np.minimum(g[i], g[i + 1] + 1, out=g[i])
    g2 = np.where(g >= cap, far, g * g).astype(dtype, copy=False)
    # pass 2: along axis 1, the smallest g2 + d**2 over offsets d, until d**2 can no longer win;
    # rows are dropped once every cell in them is nearer than d (a few rows hold the far cells)
    best = g2.copy()
    rows = np.arange(nx)
    d = 1
    while d < ny:
        rows = rows[best[rows].max(axis=1) > d * d]
        if rows.size == 0:
            break
        b, src = best[rows], g2[rows]
        for dd in range(d, min(d + 8, ny)):
            sq = dtype(dd * dd)
            np.minimum(b[:, dd:], src[:, :-dd] + sq, out=b[:, dd:])
            np.minimum(b[:, :-dd], src[:, dd:] + sq, out=b[:, :-dd])
        best[rows] = b
        d += 8
    return np.sqrt(best.astype(np.float64))


def label(grid: np.ndarray) -> tuple[np.ndarray, int]:
    """The 4-connected regions of ``grid``'s true cells, numbered 1.. in row-major order of their
    first cell (0 elsewhere), and how many: as ``scipy.ndimage.label(grid)`` (int32 labels)."""
    fg = np.asarray(grid, dtype=bool)
    if fg.ndim != 2:
        raise ValueError(f"a 2D grid is needed, not {fg.ndim}D")
    nx, ny = fg.shape
    n = nx * ny
    out = np.zeros((nx, ny), dtype=np.int32)
    if n == 0 or not fg.any():
        return out, 0
    k = _kernel()
    if k is not None:
        count = k.label(np.ascontiguousarray(fg).view(np.uint8), nx, ny, out)
        return out, int(count)
    return _label_numpy(fg, out)


def _label_numpy(fg: np.ndarray, out: np.ndarray) -> tuple[np.ndarray, int]:
    """The numpy path of :func:`label` (the reference): ``out`` zeros of ``fg``'s shape, filled in."""
    nx, ny = fg.shape
    n = nx * ny
    flat = fg.ravel()
    cells = np.flatnonzero(flat)  # the true cells, row-major: label = a cell's flat index
    rank = np.zeros(n, dtype=np.int64)
    rank[cells] = np.arange(cells.size)
    # horizontal runs are contiguous in row-major order, vertical runs in column-major order
    left = np.zeros((nx, ny), dtype=bool)
    left[:, 1:] = fg[:, :-1]
    row_starts = np.flatnonzero(~left.ravel()[cells])
    row_run = np.cumsum(~left.ravel()[cells]) - 1
    up = np.zeros((nx, ny), dtype=bool)
    up[1:] = fg[:-1]
    by_col = rank[np.flatnonzero(fg.T.ravel()) % nx * ny + np.flatnonzero(fg.T.ravel()) // nx]
    col_first = ~up.ravel()[cells][by_col]
    col_starts = np.flatnonzero(col_first)
    col_run = np.cumsum(col_first) - 1
    lab = cells.copy()
    while True:
        # each run takes its smallest label, then each cell its label's cell's label (pointer jump)
        new = np.minimum.reduceat(lab, row_starts)[row_run]
        new[by_col] = np.minimum.reduceat(new[by_col], col_starts)[col_run]
        new = new[rank[new]]
        if np.array_equal(new, lab):
            break
        lab = new
    roots = cells[lab == cells]  # each region's first cell, ascending = row-major order
    out[fg] = (np.searchsorted(roots, lab) + 1).astype(np.int32)
    return out, int(roots.size)


def dilate3x3(grid: np.ndarray) -> np.ndarray:
    """``grid`` (2D) grown by one cell in all eight directions (outside counts as false):
    ``scipy.ndimage.binary_dilation(grid, structure=np.ones((3, 3)))``."""
    fg = np.asarray(grid, dtype=bool)
    if fg.ndim != 2:
        raise ValueError(f"a 2D grid is needed, not {fg.ndim}D")
    nx, ny = fg.shape
    p = np.zeros((nx + 2, ny + 2), dtype=bool)
    p[1:-1, 1:-1] = fg
    out = np.zeros((nx, ny), dtype=bool)
    for di in range(3):
        for dj in range(3):
            out |= p[di : di + nx, dj : dj + ny]
    return out
