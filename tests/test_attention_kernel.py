"""The leg detector's compiled pass (robot/attention/_legkernel.c) computes what its Python path computes, bit for bit.

The kernel is optional (built by ``pip install -e .`` where a C compiler is found); without it these
tests are skipped (except on CI, where the build must have worked) and the Python path, checked
against the vectorised rules in tests/test_attention_units.py, is what runs.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention import legs as legs_module
from robot.attention.legs import LegDetector, LegSpec
from tests.test_attention_units import BEARINGS, _scan
from tests.stage_helpers import ACTORS

needs_kernel = pytest.mark.skipif(legs_module._KERNEL is None, reason="the compiled leg kernel is not built (pip install -e . with a C compiler)")


def test_ci_built_the_leg_kernel():
    """CI installs with gcc: a kernel that silently failed to build would leave every comparison
    below skipped and the detector on its slow path."""
    if os.environ.get("CI", "").lower() not in ("1", "true", "yes"):
        pytest.skip("only CI requires the compiled kernel")
    assert legs_module._KERNEL is not None
    assert LegDetector(BEARINGS).kernel is legs_module._KERNEL


def _candidates(det: LegDetector, ranges: np.ndarray) -> list[tuple[float, float]]:
    """The leg-like segments' centres before the furniture filter (what the filter is shown)."""
    seen: list[tuple[float, float]] = []
    det(ranges, reject_points=lambda pts: seen.extend(pts) or [False] * len(pts))
    return seen


def _same(ranges: np.ndarray, spec: LegSpec) -> None:
    fast, slow = LegDetector(BEARINGS, spec), LegDetector(BEARINGS, spec, compiled=False)
    assert fast.kernel is not None and slow.kernel is None
    assert _candidates(fast, ranges) == _candidates(slow, ranges)  # floats compared with ==: the same bits
    for reject in (None, lambda pts: [y < -1.0 for _, y in pts]):
        a, b = fast(ranges, reject_points=reject), slow(ranges, reject_points=reject)
        assert a.points == b.points and a.kinds == b.kinds and a.leg_points == b.leg_points


@needs_kernel
@settings(max_examples=150, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    people=st.integers(0, 5),
    posts=st.integers(0, 6),
    together=st.booleans(),
    no_echo=st.floats(0.0, 0.4),
    noise=st.sampled_from([0.0, 0.003, 0.01, 0.05]),
    wall=st.floats(0.4, 9.0),
)
def test_the_compiled_pass_finds_the_python_paths_candidates_bit_for_bit(seed, people, posts, together, no_echo, noise, wall):
    """Random rooms: people (legs apart or together as one blob), table legs, a wall near or beyond the
    range (segments past 8 points; leg-like ones past 128 are in test_the_compiled_sums_are_numpys_on_long_segments),
    range noise, beams without echo."""
    rng = np.random.default_rng(seed)
    circles, squares = [], []
    for _ in range(people):
        cx, cy = rng.uniform(0.3, 7.0), rng.uniform(-3.0, 3.0)
        spread = rng.uniform(0.10, 0.14) if together else rng.uniform(0.15, 0.45)
        a = rng.uniform(0, math.pi)
        for sgn in (-1, 1):
            circles.append((cx + sgn * spread / 2 * math.cos(a), cy + sgn * spread / 2 * math.sin(a), rng.uniform(0.04, 0.08)))
    for _ in range(posts):
        squares.append((rng.uniform(0.3, 7.0), rng.uniform(-3.0, 3.0), rng.uniform(0.03, 0.3)))
    ranges = _scan(circles, squares, wall=wall) + rng.normal(0.0, noise, BEARINGS.shape[0])
    ranges[rng.random(BEARINGS.shape[0]) < no_echo] = 8.19
    _same(ranges, LegSpec(offset=float(rng.uniform(0.0, 0.2))))


@needs_kernel
@pytest.mark.filterwarnings("ignore:invalid value encountered")  # the Python path's inf * 0 for an infinite range
@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), pieces=st.integers(1, 60), jump=st.floats(0.02, 0.3))
def test_the_compiled_pass_equals_the_python_path_on_arbitrary_ranges(seed, pieces, jump):
    """Piecewise ranges of any shape (negative and zero ranges, NaN, exactly max_range, infinities):
    the same candidates and detections, and the same spec checks."""
    rng = np.random.default_rng(seed)
    ranges = np.repeat(rng.uniform(-0.5, 9.0, pieces), -(-BEARINGS.shape[0] // pieces))[: BEARINGS.shape[0]]
    ranges = ranges + rng.normal(0.0, 0.02, ranges.shape[0])
    specials = rng.integers(0, ranges.shape[0], 5)
    ranges[specials] = rng.choice([np.nan, np.inf, 0.0, 6.5, -0.0], 5)
    _same(ranges, LegSpec(jump=jump, offset=0.13))


@needs_kernel
def test_the_kernel_reads_strided_scans_and_refuses_a_foreign_array():
    det = LegDetector(BEARINGS, LegSpec(offset=0.13))
    scan = _scan(circles=[(2.5, 0.1, 0.06), (2.5, -0.1, 0.06)])
    strided = np.repeat(scan, 2)[::2]  # not contiguous: the detector copies it for the kernel
    assert det(strided).points == det(scan).points == LegDetector(BEARINGS, LegSpec(offset=0.13), compiled=False)(scan).points
    with pytest.raises(TypeError, match="float64"):
        legs_module._KERNEL.candidates(scan.astype(np.float32), det._cos, det._sin, det._params)


@needs_kernel
@settings(max_examples=200, deadline=None)
@given(
    legs=st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), max_size=14),
    grid=st.booleans(),
    blobs=st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), max_size=3),
)
def test_the_compiled_pairing_pairs_as_the_python_one(legs, grid, blobs):
    """Nearest legs first, each in one pair, ties in the row-major order (legs on a grid make equal
    distances), then blobs, then singles: the same points and kinds as legs.py's _pair."""
    if grid:  # many exactly equal distances
        legs = [(round(x * 4) / 4, round(y * 4) / 4) for x, y in legs]
    want = legs_module._pair(list(legs), list(blobs), 0.55)
    points, kinds = legs_module._KERNEL.pair(list(legs), list(blobs), 0.55, (0.55 * 1.01) ** 2)
    assert points == want.points and kinds == want.kinds


@needs_kernel
def test_the_compiled_pass_on_recorded_scans_of_three_crossing_people():
    """Scans the simulated laser made (three people crossing past a table and chairs, 6 s): the
    same detections both ways, with a furniture filter (the footprints tested on the points as given)."""
    from homesim.scenario.loader import load_scenario
    from homesim.sim import Simulation
    from homesim.tour.stage import Stage
    from robot.attention.clutter import FurnitureLegs
    from robot.hardware.map_server import floor_plan

    root = Path(__file__).resolve().parents[1]
    sc = load_scenario(root / "scenarios" / "attention" / "three_crossing.xml")
    sim = Simulation(seed=sc.seed, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS)
    scans: list[np.ndarray] = []
    stage.dispatcher.add("/robot/laser/scan", lambda m: scans.append(np.array(m.attachments["ranges"], dtype=float)))
    stage.run(6.0)
    sim.close()
    inside = FurnitureLegs(floor_plan(sc)).inside_points
    spec = LegSpec(offset=0.13)
    fast, slow = LegDetector(BEARINGS, spec), LegDetector(BEARINGS, spec, compiled=False)
    assert len(scans) >= 50
    found = 0
    for ranges in scans:
        a, b = fast(ranges, reject_points=inside), slow(ranges, reject_points=inside)
        assert a.points == b.points and a.kinds == b.kinds and a.leg_points == b.leg_points
        found += len(a)
    assert found > 0


@needs_kernel
@pytest.mark.parametrize("length", [5, 7, 8, 9, 16, 17, 100, 128, 129, 130, 137, 140, 150, 200, 257, 300, 361])
def test_the_compiled_sums_are_numpys_on_long_segments(length):
    """One leg-like segment of ``length`` beams (an arc close around the laser: its chord stays a
    leg's width however many beams it covers), so its centre, which is compared bit for bit, comes
    from sums over every point: numpy's pairwise sums below 8 points, in 8 accumulators up to 128,
    split in halves beyond (the random rooms above rarely make a leg-like segment that long)."""
    n = BEARINGS.shape[0]
    rng = np.random.default_rng(length)
    half_angle = min(length * 0.5, 180.0) / 2
    radius = min(2.0, 0.18 / (2 * math.sin(math.radians(max(half_angle, 0.25)))))
    start = max(0, min(n - length, n // 2 - length // 2))
    for _ in range(5):
        ranges = np.full(n, 8.19)  # no echo around it: in front of its background
        ranges[start : start + length] = radius + rng.normal(0.0, 1e-4, length) * np.geomspace(1.0, 1e-3, length)
        slow = LegDetector(BEARINGS, LegSpec(offset=0.13), compiled=False)
        assert _candidates(slow, ranges), "the segment must be a leg candidate, else its sums are not compared"
        _same(ranges, LegSpec(offset=0.13))
