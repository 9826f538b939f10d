"""Localisation: MCL on the map server's plan tracks the robot with drifting odometry; its error
is measured against ground truth by homesim.tour.metrics.localisation."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from homesim.tour.metrics.localisation import LocalisationMetric
from homesim.sim import Simulation
from homesim.tour.stage import Stage
from homesim.world.world import World
from robot.hardware.laser import LaserSpec, simulate_scan
from robot.hardware.map_server import floor_plan, map_element
from robot.localisation import install
from robot.localisation.mcl import MCL, MCLParams, compose, relative
from tests.world_helpers import EXAMPLE, drive_base, scenario
from tests.stage_helpers import ACTORS


class _Run:
    def __init__(self, sim):
        self.sim = sim
        self.config = None


def _tour(*, noise=(0.05, 0.05, 0.05), start_error=None, until=40.0, seed=7):
    """The example flat (people walking about in the laser's view), the robot driving circles
    with odometry noisier than the default; returns (stage, localiser, metric, odometry error)."""
    sc = scenario(EXAMPLE)
    sim = Simulation(seed=seed, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    base = stage.hardware["base"]
    base.spec = replace(base.spec, distance_noise=noise[0], drift=noise[1], turn_noise=noise[2])
    if start_error is not None:  # the operator gives a start pose that is off
        ms = stage.hardware["map_server"]
        x, y, th = ms.plan.start
        ms._reply = map_element(replace(ms.plan, start=(x + start_error[0], y + start_error[1], th + start_error[2])))
    loc = install(_Run(sim))["localiser"]
    metric = LocalisationMetric(None)
    stage.dispatcher.add(metric.channels, metric.on_message)
    stage.world.add_listener(metric.on_step)
    drive_base(stage, 0.3, 0.25)
    odo_err = []

    async def watch_odometry():
        import asyncio

        s = (sc.robot.x, sc.robot.y, sc.robot.heading)
        while True:
            await asyncio.sleep(1.0)
            p = compose(s, base.odometry)
            t = stage.world.robot.pose
            odo_err.append(math.hypot(p[0] - t[0], p[1] - t[1]))

    sim.spawn(watch_odometry(), name="watch")
    stage.run(until=until)
    sim.close()
    return stage, loc, metric, odo_err


@pytest.fixture(scope="module")
def tour():
    return _tour()


def test_localisation_tracks_the_robot_where_odometry_drifts(tour):
    stage, loc, metric, odo_err = tour
    s = metric.summary()
    assert s["samples"] >= 390  # one estimate per odometry message (10 Hz for 40 s)
    assert s["unmatched"] == 0
    assert max(odo_err) > 0.25  # odometry alone wanders off by decimetres...
    assert s["mean_m"] < 0.04 and s["max_m"] < 0.12  # ...the localised pose stays within centimetres
    assert s["heading_max_deg"] < 5.0
    assert loc.mcl.updates > 50  # it corrected while driving (not only the start pose)


def test_published_poses_are_typed_at_the_odometry_rate_with_their_capture_time(tour):
    stage, loc, metric, _ = tour
    poses = [m for m in stage.messages if m.channel == "/robot/localisation/pose"]
    odos = [m for m in stage.messages if m.channel == "/robot/odometry"]
    assert abs(len(poses) - len(odos)) <= 1
    assert all(p.xml.get("frame") == "map" for p in poses)
    times = [float(p.xml.get("time")) for p in poses]
    assert times == sorted(times) and all(abs(t - p.created) < 1e-6 for t, p in zip(times, poses))
    covs = np.array([[float(p.xml.get(k)) for k in ("cxx", "cyy", "ctt")] for p in poses])
    assert (covs >= 0).all() and covs[-1, 0] < 0.01  # spread: under 10 cm std at the end


def test_a_wrong_start_pose_converges():
    """The operator's start pose is 15 cm and 4 degrees off: the first scans (taken at rest)
    pull the estimate in, so no published pose is that far off, and it stays within centimetres."""
    stage, loc, metric, _ = _tour(noise=(0.02, 0.01, 0.03), start_error=(0.12, -0.09, math.radians(4)), until=12.0)
    s = metric.summary()
    assert s["max_m"] < 0.08 and s["final_m"] < 0.05
    assert s["heading_max_deg"] < 3.0


def test_no_map_server_fails_the_run_saying_so():
    sim = Simulation(seed=1, scenario="none")
    loc = install(_Run(sim))["localiser"]
    loc.map_timeout = 2.0
    with pytest.raises(Exception, match="no floor plan from map_server"):
        sim.run(until=5.0)


def test_the_same_seed_gives_the_same_poses():
    a = [m.xml.attrib for m in _tour(until=4.0, seed=3)[0].messages if m.channel == "/robot/localisation/pose"]
    b = [m.xml.attrib for m in _tour(until=4.0, seed=3)[0].messages if m.channel == "/robot/localisation/pose"]
    assert a == b and len(a) >= 39


# ------------------------------------------------------------ the filter alone

poses = st.tuples(st.floats(-20, 20), st.floats(-20, 20), st.floats(-math.pi, math.pi))


@given(poses, poses)
def test_relative_and_compose_are_inverse(a, b):
    c = compose(a, relative(a, b))
    assert c[0] == pytest.approx(b[0], abs=1e-9) and c[1] == pytest.approx(b[1], abs=1e-9)
    assert math.remainder(c[2] - b[2], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


_WORLD = {}


def _world():
    if "w" not in _WORLD:
        _WORLD["w"] = World(scenario(EXAMPLE))
    return _WORLD["w"]


def _settle(pose, start, seed, scans=6):
    world = _world()
    rng = np.random.default_rng(seed)
    mcl = MCL(floor_plan(scenario(EXAMPLE)), rng, MCLParams(particles=300), start=start)
    spec = LaserSpec()
    for _ in range(scans):
        ranges = simulate_scan(world, pose, spec, rng)
        mcl.predict((0.0, 0.0, 0.0))
        mcl.correct(ranges, spec.bearings(), spec.offset, spec.max_range)
        mcl.x += rng.normal(0, 0.01, mcl.x.shape)  # a robot at rest still jitters its cloud (as AMCL)
        mcl.y += rng.normal(0, 0.01, mcl.y.shape)
    return mcl.estimate()[0]


@pytest.mark.parametrize("pose", [(2.0, 2.3, 0.0), (3.0, 2.0, 1.2), (4.0, 2.5, -2.0), (7.5, 2.0, 0.3)])
def test_scans_pull_an_offset_cloud_onto_the_true_pose(pose):
    """A cloud started 8 cm / 3 deg off ends within 3 cm after a few noisy scans from the true pose."""
    x, y, th = pose
    ex, ey, eth = _settle(pose, (x + 0.06, y - 0.05, th + math.radians(3)), seed=1)
    assert math.hypot(ex - x, ey - y) < 0.03
    assert abs(math.remainder(eth - th, 2 * math.pi)) < math.radians(1.5)


@settings(max_examples=10, deadline=None)
@given(st.floats(1.0, 5.0), st.floats(1.5, 4.5), st.floats(-math.pi, math.pi), st.integers(0, 2**16))
@example(4.625, 2.0, -0.5, 63)  # 2 m from the outer wall: the cloud slid into the wall's far face
@example(5.0, 3.75, 0.0, 38982)  # facing the wall between two rooms: both its faces are seen from the rooms
def test_scans_never_push_the_estimate_away(x, y, th, seed):
    """Anywhere in the living room clear of furniture, whatever the view (facing a bare wall
    leaves one direction unobservable), the scans never leave the estimate further off than it
    started (8 cm)."""
    for ob in _world().obstacles:
        if ob.kind != "wall" and _inside(ob.polygon, x, y, margin=0.35):
            return
    ex, ey, eth = _settle((x, y, th), (x + 0.06, y - 0.05, th + math.radians(3)), seed, scans=4)
    assert math.hypot(ex - x, ey - y) < 0.08


def test_the_field_holds_only_the_faces_seen_from_the_rooms():
    """A wall's far face (outside the flat, or inside a closed obstacle) is no surface: a pose
    shifted by the wall's thickness towards it must not explain the scan as well as the truth."""
    mcl = MCL(floor_plan(scenario(EXAMPLE)), np.random.default_rng(0))
    near, far = mcl.field.lookup(np.array([4.6, 4.6]), np.array([0.05, -0.05]))  # wall y in [-0.05, 0.05]
    assert near < 0.02 and far > 0.08
    inner = mcl.field.lookup(np.array([9.1]), np.array([1.5]))[0]  # inside the closed cupboard x 8.8-9.4
    assert inner > 0.2


def _inside(poly, x, y, margin):
    lo, hi = poly.min(axis=0) - margin, poly.max(axis=0) + margin
    return lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1]
