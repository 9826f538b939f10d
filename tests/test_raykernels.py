"""The compiled raycast kernels (homesim/world/_raykernels.c) give the Python paths' floats, bit for bit.

Each property runs the same call twice, once with the kernel and once with ``raycast._K`` set to
None (the pure-Python/numpy path every machine has), and compares the bytes. Where the kernel is
not built these tests skip, except on CI, where the build must have worked (gcc is there).
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim import kernels
from homesim.world import raycast
from homesim.world.raycast import FanCaster, Prisms, RayCaster, add_range_noise, sight_lines_clear
from tests.conftest import examples

K = raycast._K
needs_kernel = pytest.mark.skipif(K is None, reason="the compiled raycast kernel is not built here (pip install -e . with a C compiler)")


def test_the_kernel_is_built_on_ci():
    """CI installs with gcc: a kernel that silently failed to build would leave every comparison
    below skipped and the product on its slow path."""
    if os.environ.get("CI", "").lower() not in ("1", "true", "yes"):
        pytest.skip("only CI requires the compiled kernel")
    assert K is not None


def test_a_stale_or_unwanted_kernel_is_not_used(monkeypatch):
    """A build from another version of the C source is ignored (the Python path runs), as is
    any kernel when HOMESIM_PURE_PYTHON is set."""
    assert kernels.load("homesim.world._raykernels", 10**6) is None
    assert kernels.load("homesim.no_such_kernel", 1) is None
    monkeypatch.setenv("HOMESIM_PURE_PYTHON", "1")
    assert kernels.load("homesim.world._raykernels", 2) is None
    monkeypatch.setenv("HOMESIM_PURE_PYTHON", "0")
    assert kernels.load("homesim.world._raykernels", 2) is K


def _both(fn):
    """``fn()`` with the kernel, then with the Python path."""
    with_kernel = fn()
    raycast._K = None
    try:
        return with_kernel, fn()
    finally:
        raycast._K = K


def _same(x: np.ndarray, y: np.ndarray) -> bool:
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


_coord = st.floats(-8.0, 8.0, allow_nan=False)
_odd = st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, 1e-300, 1e300])


@needs_kernel
@settings(max_examples=examples(60, 500), deadline=None)
@given(
    segs=st.lists(st.tuples(_coord, _coord, _coord, _coord) | st.tuples(_coord, _odd, _coord, _coord), max_size=12),
    circles=st.lists(st.tuples(_coord, _coord, st.floats(0.0, 3.0)) | st.tuples(_odd, _coord, _odd), max_size=8),
    origin=st.tuples(st.floats(-4.0, 4.0), st.floats(-4.0, 4.0)) | st.tuples(_odd, st.floats(-1.0, 1.0)),
    start=st.floats(-7.0, 7.0),
    n=st.sampled_from([2, 3, 46, 361]),
    span=st.floats(1e-4, 2 * math.pi),
    max_range=st.sampled_from([8.19, 2.5, 0.0, math.inf]),
    backfaces=st.booleans(),
    snap=st.sampled_from(["none", "end at origin", "origin on line"]),
)
@example(segs=[(1.0, -1.0, 1.0, 1.0)], circles=[(0.0, 0.0, 0.5)], origin=(0.0, 0.0), start=-1.5, n=361, span=math.pi, max_range=8.19,
         backfaces=False, snap="none")
@example(segs=[], circles=[(0.0, 0.0, math.nan)], origin=(0.0, 0.0), start=0.0, n=2, span=0.5, max_range=8.19, backfaces=False,
         snap="none")  # a NaN leg radius at the laser: the Python path divided by zero (it raised)
@example(segs=[(2.0, -3.0, 2.0, 3.0)], circles=[(-1.0, 0.05, 0.1)], origin=(0.0, 0.0), start=-math.pi / 2, n=361, span=math.pi, max_range=2.0,
         backfaces=True, snap="none")
def test_fan_caster_kernel_gives_the_python_paths_floats(segs, circles, origin, start, n, span, max_range, backfaces, snap):
    """Walls (segments) and legs (circles) on any even fan, geometry near, far, at and around the
    laser, NaN and infinite coordinates: the kernel's ranges are the Python path's bytes (and the
    dense kernel's)."""
    angles = start + span / (n - 1) * np.arange(n)
    ox, oy = origin
    rows = []
    for ax, ay, bx, by in segs:
        if snap == "end at origin":
            ax, ay = ox, oy
        elif snap == "origin on line":
            bx, by = 2 * ox - ax, 2 * oy - ay
        rows.append((ax, ay, bx, by))
    a = np.array([s[:2] for s in rows], dtype=float).reshape(-1, 2)
    b = np.array([s[2:] for s in rows], dtype=float).reshape(-1, 2)
    c = np.array([ci[:2] for ci in circles], dtype=float).reshape(-1, 2)
    r = np.array([ci[2] for ci in circles], dtype=float)
    with np.errstate(all="ignore"):
        got, want = _both(lambda: FanCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces))
        assert _same(got, want)
        if not backfaces:
            got, want = _both(lambda: FanCaster().scan(origin, angles, a, b, c, r, max_range))
            assert _same(got, want)
        # And the dense kernel's, on geometry of a home's size (1e300 overflows its range cull's
        # squares, a NaN or infinite circle its cull: the fan casters agree with each other there).
        sane = all(np.all(np.abs(x) < 1e6) for x in (a, b, c, r, np.array(origin)))
        if FanCaster().fan(angles) is not None and sane:
            dense = RayCaster().cast(origin, angles, a, b, c, r, max_range, backfaces=backfaces)
            assert np.array_equal(got, dense, equal_nan=True)


@needs_kernel
def test_fan_caster_kernel_on_the_home_tours_scans():
    """Recorded geometry: the home tour's walls and furniture at the laser's height, its people's
    legs, the robot at poses of its tour (every scan of the first 30 s), kernel against Python."""
    from pathlib import Path

    from homesim.tour.runner import Run, RunOptions
    from robot.hardware.laser import LaserSpec, laser_origin

    spec = LaserSpec()
    root = Path(__file__).resolve().parents[1]
    poses, legs = [], []
    with Run.from_file(root / "scenarios" / "home_tour.xml", RunOptions(seed=0, until=30.0)) as run:
        world = run.world
        for t in np.arange(0.5, 30.0, 0.5):
            run.sim.run(until=float(t))
            poses.append(world.robot.pose)
            legs.append(world.leg_circles())
        a, b = world._laser_segments
    for pose, (c, r) in zip(poses, legs):
        angles = spec.bearings() + pose[2]
        origin = laser_origin(pose, spec)
        got, want = _both(lambda: FanCaster().scan(origin, angles, a, b, c, r, spec.max_range))
        assert _same(got, want)


@needs_kernel
@settings(max_examples=examples(40, 300), deadline=None)
@given(ranges=st.lists(st.floats(0.0, 10.0) | st.sampled_from([8.19, 0.0, math.nan, math.inf]), min_size=0, max_size=40),
       noise=st.floats(-0.5, 0.5) | st.sampled_from([math.nan, -0.0]))
def test_range_noise_kernel_gives_the_python_paths_floats(ranges, noise):
    r0 = np.array(ranges, dtype=float)
    z = np.full(r0.shape[0], noise) + np.linspace(-0.1, 0.1, r0.shape[0])
    with np.errstate(all="ignore"):
        got, want = _both(lambda: add_range_noise(r0.copy(), z, 8.19))
    assert _same(got, want)


def _box(x: float, y: float, w: float, h: float) -> np.ndarray:
    return np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]])


@needs_kernel
@settings(max_examples=examples(60, 400), deadline=None)
@given(
    boxes=st.lists(st.tuples(_coord, _coord, st.floats(0.01, 4.0), st.floats(0.01, 4.0), st.floats(0.0, 1.5), st.floats(0.0, 2.0),
                             st.booleans()), max_size=6),
    people=st.lists(st.tuples(_coord, _coord, st.floats(0.0, 0.4), st.floats(0.0, 2.0)), max_size=4),
    targets=st.lists(st.tuples(_coord, _coord, st.floats(-0.5, 2.5)), min_size=1, max_size=6),
    origin=st.tuples(_coord, _coord, st.floats(0.0, 2.0)),
    skip_seed=st.integers(0, 2**16),
    margin=st.sampled_from([1e-6, 0.1, 0.0]),
    odd=st.sampled_from(["none", "target at origin", "nan target", "on an edge"]),
)
def test_sight_lines_kernel_gives_the_python_paths_answers(boxes, people, targets, origin, skip_seed, margin, odd):
    """3D sight lines past furniture boxes (clockwise ones too), under tops, past people with
    their own-body skips, targets at the origin, on an edge, NaN: kernel and Python agree."""
    polys = [(_box(x, y, w, h)[::-1] if cw else _box(x, y, w, h)) for x, y, w, h, _, _, cw in boxes]
    prisms = Prisms(polys, [bot for *_, bot, _, _ in boxes], [bot + top for *_, bot, top, _ in boxes])
    tg = np.array(targets, dtype=float)
    if odd == "target at origin":
        tg[0] = origin
    elif odd == "nan target":
        tg[0, 1] = math.nan
    elif odd == "on an edge" and polys:
        tg[0, :2] = polys[0][0]
    c = np.array([p[:2] for p in people], dtype=float).reshape(-1, 2)
    r = np.array([p[2] for p in people], dtype=float)
    top = np.array([p[3] for p in people], dtype=float)
    skip = np.random.default_rng(skip_seed).random((tg.shape[0], c.shape[0])) < 0.3
    with np.errstate(all="ignore"):
        for sk in (skip, None):
            got, want = _both(lambda: sight_lines_clear(origin, tg, prisms, c, r, top, skip=sk, margin=margin))
            assert _same(got, want)


@needs_kernel
def test_the_kernels_hypot_is_numpys():
    """The kernel's one libm call whose result decides what the Python path decides with numpy
    (sight-line lengths, the legs' far cull) must give numpy's floats: both are the C library's hypot.
    Random, tiny, huge and special values, and the home tour's recorded leg offsets."""
    rng = np.random.default_rng(7)
    x = np.concatenate((rng.normal(0.0, 5.0, 100000), rng.uniform(-1e-3, 1e-3, 5000), [0.0, -0.0, 3.0, 1e-300, 1e300, math.inf, math.nan]))
    y = np.concatenate((rng.normal(0.0, 5.0, 100000), rng.uniform(-1e-3, 1e-3, 5000), [0.0, 4.0, 4.0, 1e-300, 1e300, 1.0, 1.0]))
    out = np.empty_like(x)
    K.hypots(x, y, out)
    assert _same(out, np.hypot(x, y))


def test_a_kernel_built_from_other_source_than_the_checkout_is_not_used(tmp_path, monkeypatch):
    """An editable install builds the .so once; a later checkout that changes the C source (a
    pull, an edit) leaves the old build next to the new source. Unless someone remembered to bump
    VERSION, the stale build would run, and every kernel-vs-Python test would check the old code.
    The build records the hash of the source it was compiled from and load refuses a mismatch."""
    if K is None:
        pytest.skip("the compiled raycast kernel is not built here")
    import shutil
    import sys
    from pathlib import Path

    src = os.path.join(os.path.dirname(raycast.__file__), "_raykernels.c")
    for name, edit in (("rv3same", False), ("rv3edited", True)):
        pkg = tmp_path / name
        pkg.mkdir()
        (pkg / "__init__.py").write_text("")
        shutil.copy(K.__file__, pkg / os.path.basename(K.__file__))
        text = Path(src).read_text(encoding="utf-8")
        if edit:
            text = text.replace("r[i] = max_range;", "r[i] = -1.0;", 1)
        (pkg / "_raykernels.c").write_text(text, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        assert kernels.load("rv3same._raykernels", K.VERSION) is not None
        assert kernels.load("rv3edited._raykernels", K.VERSION) is None
    finally:
        for name in ("rv3same", "rv3same._raykernels", "rv3edited", "rv3edited._raykernels"):
            sys.modules.pop(name, None)


@needs_kernel
@pytest.mark.parametrize("first, count", [(2**63 - 1, 1), (2**62, 2**62), (1, 2**63 - 1)])
def test_sight_lines_refuses_edge_ranges_past_the_edges_even_when_the_sum_overflows(first, count):
    """A prism's edge range [first, first + count) is checked against the edges before any is
    read; first + count computed in Py_ssize_t wrapped negative and passed that check (only
    -fwrapv kept the loop from reading out of bounds)."""
    prisms = Prisms([np.array([[1.0, -1.0], [2.0, -1.0], [2.0, 1.0], [1.0, 1.0]])], [0.0], [2.0])
    packed = list(prisms.packed)
    packed[2] = np.array([first], dtype=np.intp)
    packed[3] = np.array([count], dtype=np.intp)
    with pytest.raises(ValueError, match="prism"):
        K.sight_lines(0.0, 0.0, 1.0, np.array([[3.0, 0.0, 1.0]]), 1e-6, 1e-6, *packed, np.zeros((0, 2)), np.zeros(0), np.zeros(0),
                      None, np.zeros(1, dtype=bool))


@needs_kernel
@settings(max_examples=examples(60, 400), deadline=None)
@given(
    segs=st.lists(st.tuples(_coord, _coord, _coord, _coord) | st.tuples(_coord, _odd, _coord, _coord), max_size=30),
    legs=st.lists(st.tuples(_coord, _coord, st.floats(0.0, 0.3)) | st.tuples(_odd, _coord, _odd), max_size=8),
    pose=st.tuples(st.floats(-4.0, 4.0), st.floats(-4.0, 4.0), st.floats(-7.0, 7.0)),
    which=st.lists(st.integers(0, 15), max_size=8),
    snap=st.sampled_from(["none", "wall through a transducer", "leg on a transducer"]),
)
@example(segs=[(-1.0, -3.0, -1.0, 3.0)], legs=[(-0.1, -0.3, 0.06)], pose=(0.0, 0.0, 0.0), which=list(range(16)), snap="none")
def test_sonar_kernel_gives_the_python_paths_readings(segs, legs, pose, which, snap):
    """A sonar packet cast in one kernel call (robot.hardware.sonar, ``sonar_ranges``) reads the numpy
    path's floats, bit for bit: walls and legs anywhere round the rings, through and on a transducer,
    NaN and infinite coordinates (a NaN reading may differ in its sign bit: both print ``nan``), repeated
    transducers, an empty packet."""
    from robot.hardware import sonar
    from robot.hardware.sonar import SegmentRanges, SonarSpec, sonar_readings

    assert sonar._K is K
    spec = SonarSpec()
    x, y, th = pose
    rows = [list(s) for s in segs]
    circles = [list(c) for c in legs]
    tx, ty, _ = spec.transducers[which[0] if which else 0]
    at = (x + math.cos(th) * tx - math.sin(th) * ty, y + math.sin(th) * tx + math.cos(th) * ty)
    if snap == "wall through a transducer" and rows:
        rows[0][2:] = [2 * at[0] - rows[0][0], 2 * at[1] - rows[0][1]]
    elif snap == "leg on a transducer" and circles:
        circles[0][:2] = at

    class Geometry:
        def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
            a = np.array([s[:2] for s in rows], dtype=float).reshape(-1, 2)
            return a, np.array([s[2:] for s in rows], dtype=float).reshape(-1, 2)

        def leg_circles(self) -> tuple[np.ndarray, np.ndarray]:
            return np.array([c[:2] for c in circles], dtype=float).reshape(-1, 2), np.array([c[2] for c in circles], dtype=float)

    packet = tuple(which)
    with np.errstate(all="ignore"):
        want = sonar_readings(Geometry(), pose, spec, packet, None, compiled=False)
        for got in (sonar_readings(Geometry(), pose, spec, packet, None), sonar_readings(Geometry(), pose, spec, packet, None, kept=SegmentRanges())):
            nan = np.isnan(want)
            assert np.array_equal(np.isnan(got), nan) and _same(got[~nan], want[~nan])
