"""map_server: the a-priori floor plan, typed, matching the scenario's walls, doors and furniture."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.errors import SchemaValidationError
from homesim.sim import Simulation
from homesim.world.raycast import cast_rays
from homesim.tour.stage import Stage
from homesim.xmlio import load_schema
from robot.floorplan import MapFormatError, parse_map
from robot.hardware.map_server import MAP_SCHEMA, floor_plan, map_element
from tests.world_helpers import EXAMPLE, scenario
from tests.stage_helpers import ACTORS


def _fetch_map(seed: int = 1) -> tuple[Stage, etree._Element]:
    sc = scenario(EXAMPLE)
    sim = Simulation(seed=seed, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    client = sim.bus.participant("client", host="robot")
    got = {}

    async def ask() -> None:
        got["reply"] = await client.call("map_server", "map", etree.Element("map_request"), timeout=1.0)

    sim.spawn(ask(), name="ask")
    sim.run(until=0.5)
    sim.close()
    return stage, got["reply"].xml


def test_the_reply_is_typed_and_carries_walls_doors_furniture_rooms_and_start():
    stage, xml = _fetch_map()
    load_schema(MAP_SCHEMA).check(xml)  # raises on a reply the schema refuses
    plan = parse_map(xml)
    sc = stage.scenario
    # The wall with the front door (0,5)->(0,0), door at 1.2 m, 0.9 m wide: two pieces, the gap between.
    pieces = sorted((w.y1, w.y2) for w in plan.walls if w.x1 == 0.0 and w.x2 == 0.0)
    assert pieces == [(3.35, 0.0), (5.0, 4.25)]
    assert len(plan.walls) == 7  # 5 walls, two of them cut by a door
    assert {o.name for o in plan.obstacles if o.type != "leg"} == {f.name for f in sc.furniture}
    table = next(o for o in plan.obstacles if o.name == "table")
    assert (table.bottom, table.top) == (0.7, 0.75)
    assert sum(o.type == "leg" for o in plan.obstacles) == 8  # two tables, four legs each
    assert [r.name for r in plan.rooms] == ["living room", "kitchen"]
    assert plan.start == pytest.approx((2.0, 2.3, 0.0))


def test_the_laser_cut_of_the_plan_ranges_like_the_world():
    """Rays cast against the plan at the laser's height read what rays against the world's
    static geometry read: walls, sofa and table legs are there, table tops are not."""
    stage, xml = _fetch_map()
    plan = parse_map(xml)
    a, b = plan.segments_at(0.30)
    world = stage.world
    for pose in [(2.0, 2.3, 0.0), (4.0, 2.5, 1.2), (7.5, 2.0, -2.0), (1.0, 3.0, math.pi)]:
        origin = (pose[0] + 0.13 * math.cos(pose[2]), pose[1] + 0.13 * math.sin(pose[2]))
        angles = pose[2] + np.radians(np.arange(-90, 90.5, 0.5))
        wa, wb = world.segments_at(0.30)  # the world's static geometry at the laser's height
        want = cast_rays(origin, angles, wa, wb, max_range=8.19)
        got = cast_rays(origin, angles, a, b, max_range=8.19)
        assert np.abs(got - want).max() < 1e-3, pose  # the reply writes 0.1 mm


def test_a_malformed_reply_is_refused_by_the_schema_and_the_parser():
    plan = floor_plan(scenario(EXAMPLE))
    xml = map_element(plan)
    xml.find("wall").set("x1", "NaN")
    with pytest.raises(SchemaValidationError):
        load_schema(MAP_SCHEMA).check(xml)
    with pytest.raises(MapFormatError, match="not finite"):
        parse_map(xml)
    nostart = map_element(plan)
    nostart.remove(nostart.find("start"))
    with pytest.raises(MapFormatError, match="no <start>"):
        parse_map(nostart)


def test_the_server_refuses_to_send_an_untyped_reply():
    sc = scenario(EXAMPLE)
    sim = Simulation(seed=1, scenario=sc.name)
    stage = Stage(sim, sc, actors=ACTORS, keep_messages=True)
    server = stage.hardware["map_server"]
    bad = map_element(server.plan)
    bad.find("start").set("theta", "7")  # degrees by mistake: outside [-pi, pi]
    server._reply = bad
    client = sim.bus.participant("client", host="robot")
    errors = []

    async def ask() -> None:
        try:
            await client.call("map_server", "map", etree.Element("map_request"))
        except Exception as e:  # the call fails with the server's validation error
            errors.append(e)

    sim.spawn(ask(), name="ask")
    sim.run(until=0.5)
    sim.close()
    assert errors and "theta" in str(errors[0])


@settings(max_examples=30, deadline=None)
@given(st.floats(-3.14159, 3.14159), st.floats(0.05, 0.3))
def test_round_trip_keeps_the_plan(theta, thickness):
    """map_element -> parse_map is the identity up to the 0.1 mm the reply writes."""
    import dataclasses

    plan = floor_plan(scenario(EXAMPLE))
    walls = tuple(dataclasses.replace(w, thickness=thickness) for w in plan.walls)
    plan = dataclasses.replace(plan, walls=walls, start=(plan.start[0], plan.start[1], theta))
    back = parse_map(map_element(plan))
    assert back.start == pytest.approx(plan.start, abs=1e-5)
    assert len(back.walls) == len(plan.walls)
    for w, v in zip(plan.walls, back.walls):
        assert (v.x1, v.y1, v.x2, v.y2, v.thickness) == pytest.approx((w.x1, w.y1, w.x2, w.y2, w.thickness), abs=1e-4)
    for o, q in zip(plan.obstacles, back.obstacles):
        assert (q.name, q.bottom, q.top) == (o.name, o.bottom, o.top)
        assert np.abs(q.polygon() - o.polygon()).max() < 1e-4
