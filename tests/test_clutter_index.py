"""The leg filter's grid index: it tests a point only against the footprints near it, and answers as a scan over all.

``FurnitureLegs.inside_points`` runs for every leg candidate and sonar echo against every wall piece and raised
footprint of the flat; the grid index (``robot/attention/clutter.py``) must change which footprints are tried,
never the answer (the traces stay byte-identical).
"""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from homesim.scenario.loader import load_scenario
from robot.attention.clutter import CELL, FurnitureLegs
from robot.floorplan import FloorPlan, MapObstacle, MapWall
from robot.hardware.map_server import floor_plan
from tests.world_helpers import EXAMPLE

coord = st.floats(-6.0, 6.0, allow_nan=False)


@st.composite
def plans(draw: st.DrawFn) -> FloorPlan:
    """Wall pieces, raised furniture and floor-standing furniture (convex quadrilaterals), anywhere."""
    walls = tuple(MapWall(draw(coord), draw(coord), draw(coord), draw(coord), draw(st.floats(0.05, 0.3)))
                  for _ in range(draw(st.integers(0, 5))))
    walls = tuple(w for w in walls if math.hypot(w.x2 - w.x1, w.y2 - w.y1) > 0.05)
    obstacles = []
    for k in range(draw(st.integers(0, 5))):
        cx, cy, hw, hh = draw(coord), draw(coord), draw(st.floats(0.1, 2.0)), draw(st.floats(0.1, 2.0))
        th = draw(st.floats(0.0, math.pi))
        c, s = math.cos(th), math.sin(th)
        pts = tuple((cx + c * u - s * v, cy + s * u + c * v) for u, v in ((-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)))
        obstacles.append(MapObstacle(f"o{k}", "table", pts, draw(st.sampled_from([0.0, 0.4])), 0.8))
    return FloorPlan(walls, tuple(obstacles), (), (0.0, 0.0, 0.0))


def _scan_all(legs: FurnitureLegs, x: float, y: float) -> bool:
    """The answer without the index: every footprint whose box holds the point, all its edges."""
    return any(x0 <= x <= x1 and y0 <= y <= y1 and all(x * a + y * b <= c for a, b, c in edges)
               for x0, y0, x1, y1, edges in legs._footprints)


def _points(legs: FurnitureLegs, draw: st.DrawFn) -> list[tuple[float, float]]:
    """Points anywhere, on the boxes' edges and corners, and on the cells' borders (where rounding could bite)."""
    pts = draw(st.lists(st.tuples(st.floats(-9.0, 9.0, allow_nan=False), st.floats(-9.0, 9.0, allow_nan=False)), max_size=30))
    for x0, y0, x1, y1, _ in legs._footprints:
        pts += [(x0, y0), (x1, y1), (x0, y1), (x1, y0), ((x0 + x1) / 2, y1)]
    if legs._footprints:
        ox, oy, _, _ = legs._box
        pts += [(ox + i * CELL, oy + j * CELL) for i in range(-1, 4) for j in range(-1, 4)]
    return pts + [(math.nan, 0.0), (math.inf, 0.0), (0.0, -math.inf)]


@settings(max_examples=60, deadline=None)
@given(plans(), st.data(), st.sampled_from([0.02, 0.06, 0.3]))
def test_the_index_answers_as_a_scan_over_every_footprint(plan, data, margin):
    legs = FurnitureLegs(plan, margin=margin, wall_margin=margin)
    pts = _points(legs, data.draw)
    assert legs.inside_points(pts) == [_scan_all(legs, x, y) for x, y in pts]


@settings(max_examples=60, deadline=None)
@given(plans(), st.data())
def test_a_point_is_tried_against_every_box_that_holds_it_and_only_boxes_near_it(plan, data):
    legs = FurnitureLegs(plan)
    for x, y in _points(legs, data.draw):
        near = legs.near(x, y)
        holding = [f for f in legs._footprints if f[0] <= x <= f[2] and f[1] <= y <= f[3]]
        assert all(any(f is g for g in near) for f in holding)
        # only footprints whose box overlaps the point's cell (a cell's side away at most)
        assert all(f[0] - CELL <= x <= f[2] + CELL and f[1] - CELL <= y <= f[3] + CELL for f in near)


def test_on_the_library_flat_a_point_is_tried_against_a_few_footprints_not_all():
    legs = FurnitureLegs(floor_plan(load_scenario(EXAMPLE)))
    xs = [(-1.0 + 0.37 * i, -1.0 + 0.29 * j) for i in range(40) for j in range(40)]
    tried = [len(legs.near(x, y)) for x, y in xs]
    assert legs.count > 10 and max(tried) < legs.count / 2
    assert legs.inside_points(xs) == [_scan_all(legs, x, y) for x, y in xs]
