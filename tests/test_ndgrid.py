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
