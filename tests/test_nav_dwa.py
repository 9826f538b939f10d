"""The dynamic window's fast path (echo prefilter + one matrix product) decides exactly as the
elementwise reference did, on random scans, windows and goals."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.navigation.config import Limits
from robot.navigation.local import dwa
from tests.nav_dwa_reference import reference_dwa


@settings(max_examples=120, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 200), v0=st.floats(-0.2, 0.5), w0=st.floats(-1.5, 1.5),
       gx=st.floats(-4, 4), gy=st.floats(-4, 4), v_pref=st.floats(-0.2, 0.5), spread=st.floats(0.3, 5.0))
def test_dwa_matches_reference(seed: int, n: int, v0: float, w0: float, gx: float, gy: float, v_pref: float,
                               spread: float) -> None:
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.05, spread, n)
    a = rng.uniform(-math.pi, math.pi, n)
    pts = np.column_stack((r * np.cos(a), r * np.sin(a)))
    lim = Limits()
    got = dwa(v0, w0, (gx, gy), pts, lim, v_pref=v_pref)
    want = reference_dwa(v0, w0, (gx, gy), pts, lim, v_pref=v_pref)
    assert got.ok == want.ok
    assert math.isclose(got.v, want.v, abs_tol=1e-9) and math.isclose(got.w, want.w, abs_tol=1e-9), (got, want)


@given(lo=st.floats(-2.0, 2.0), hi=st.floats(-2.0, 2.0), n=st.integers(1, 12))
def test_the_window_samples_are_numpys_linspace_bit_for_bit(lo: float, hi: float, n: int) -> None:
    from robot.navigation.local import _linspace

    assert np.array_equal(_linspace(lo, hi, n), np.linspace(lo, hi, n))
