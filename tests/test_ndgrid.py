"""homesim.ndgrid gives SciPy's arrays bit for bit (the flat's grids, the likelihood field and
the walkers' regions are built with it at start-up instead of scipy.ndimage)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from homesim import ndgrid

ndimage = pytest.importorskip("scipy.ndimage")

grids = st.tuples(st.integers(1, 24), st.integers(1, 24)).flatmap(
    lambda shape: arrays(np.bool_, shape, elements=st.booleans()))


@settings(max_examples=200, deadline=None)
@given(grids)
def test_distance_transform_is_scipys(g: np.ndarray) -> None:
    a, b = ndgrid.distance_transform_edt(g), ndimage.distance_transform_edt(g)
    assert a.dtype == b.dtype and a.shape == b.shape
    assert a.tobytes() == b.tobytes()


@settings(max_examples=200, deadline=None)
@given(grids)
def test_labels_are_scipys(g: np.ndarray) -> None:
    (a, na), (b, nb) = ndgrid.label(g), ndimage.label(g)
    assert na == nb and a.dtype == b.dtype
    assert a.tobytes() == b.tobytes()


@settings(max_examples=200, deadline=None)
@given(grids)
def test_dilation_is_scipys(g: np.ndarray) -> None:
    b = ndimage.binary_dilation(g, structure=np.ones((3, 3), dtype=bool))
    assert ndgrid.dilate3x3(g).tobytes() == b.tobytes()


def test_a_flat_sized_grid_with_walls_and_a_long_corridor() -> None:
    """Regions that wind (a long corridor) and distances far from any wall, at the flats' size."""
    g = np.ones((240, 200), dtype=bool)
    g[0] = g[-1] = g[:, 0] = g[:, -1] = False
    g[100, :150] = False
    g[50:, 80] = False
    for k in range(10, 230, 20):  # a comb: one region that snakes through every tooth
        g[k, 20 if k % 40 == 10 else 0 : 180 if k % 40 == 10 else 160] = False
    assert ndgrid.distance_transform_edt(g).tobytes() == ndimage.distance_transform_edt(g).tobytes()
    (a, na), (b, nb) = ndgrid.label(g), ndimage.label(g)
    assert na == nb and a.tobytes() == b.tobytes()


def test_only_2d_grids() -> None:
    with pytest.raises(ValueError, match="2D"):
        ndgrid.label(np.ones((2, 2, 2), dtype=bool))


kernel = ndgrid._kernel()
needs_kernel = pytest.mark.skipif(kernel is None, reason="homesim._gridkernels not built")
# wider than tall and the other way, sparse and dense false cells: the envelope's breaking points
shaped = st.tuples(st.integers(1, 40), st.integers(1, 40), st.floats(0.0, 1.0)).flatmap(
    lambda t: arrays(np.bool_, t[:2], elements=st.booleans()).map(lambda g: g | (np.arange(g.size).reshape(g.shape) % 97 > t[2] * 97)))


@needs_kernel
@settings(max_examples=300, deadline=None)
@given(st.one_of(grids, shaped))
def test_the_compiled_transform_and_labels_are_the_numpy_paths(g: np.ndarray) -> None:
    """The kernel gives the numpy reference's integers (so SciPy's arrays): squared distances, labels, count."""
    assert ndgrid._kernel() is kernel
    if not g.all():
        assert ndgrid.distance_transform_edt(g).tobytes() == ndgrid._edt_numpy(g).tobytes()
    (a, na) = ndgrid.label(g)
    b, nb = ndgrid._label_numpy(g, np.zeros(g.shape, dtype=np.int32))
    assert na == nb and a.tobytes() == b.tobytes()


@needs_kernel
def test_the_compiled_transform_on_the_flats_grids() -> None:
    """A flat-sized grid with one far corner and a single false cell: long envelopes, large distances."""
    rng = np.random.default_rng(3)
    for shape in ((356, 607), (607, 356), (1, 900), (900, 1)):
        g = rng.random(shape) > 0.002
        g2 = np.ones(shape, dtype=bool)
        g2[-1, -1] = False
        for grid in (g, g2):
            assert ndgrid.distance_transform_edt(grid).tobytes() == ndgrid._edt_numpy(grid).tobytes()
            assert ndgrid.label(grid)[0].tobytes() == ndgrid._label_numpy(grid, np.zeros(shape, dtype=np.int32))[0].tobytes()
