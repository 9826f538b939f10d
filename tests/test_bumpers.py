"""The PeopleBot's bumper rings (robot.hardware.bumpers) and the reflex every base command keeps to them (robot.bumpers).

A bumper is the one sensor that says the base touches something now. The switches are computed from the
world's geometry at the rings' height (walls, low furniture, table legs, a person's body), so a table top
the robot runs its upper body into is felt by the world's contact solver but by no bumper, as on the real
robot. The reflex: never drive into a pressed ring, no turn on the spot with one ring pressed, back away
after a new press while driving into it, and with both pressed only turning.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from homesim.world.world import World
from robot.bumpers import BACKOFF_SPEED, BACKOFF_TIME, BumperReflex
from robot.hardware.bumpers import TRAVEL, BumperSensor, BumperSpec, bumper_element
from robot.hardware.channels import SCHEMAS
from robot.contract import BUMPERS
from tests.world_helpers import put_person, room
from tests.stage_helpers import HARDWARE

HL, HW = 0.51 / 2 + 0.01, 0.43 / 2 + 0.01  # the shell: the footprint and the body's rounding


class _Flat:
    """What the rings can meet: wall segments and people (their 0.25 m body discs), the robot at ``pose``."""

    def __init__(self, segments: list[tuple[tuple[float, float], tuple[float, float]]] = (), people: list[tuple[float, float]] = (),
                 pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self._a = np.array([s[0] for s in segments], dtype=float).reshape(-1, 2)
        self._b = np.array([s[1] for s in segments], dtype=float).reshape(-1, 2)
        self.humans = {f"p{k}": SimpleNamespace(present=True, position=p) for k, p in enumerate(people)}
        self.robot = SimpleNamespace(pose=pose)

    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        return self._a, self._b


def pressed(flat: _Flat) -> set[tuple[str, int]]:
    return set(BumperSensor(flat).read())  # type: ignore[arg-type]


FRONT = {("front", k) for k in range(5)}
REAR = {("rear", k) for k in range(5)}


def test_a_wall_touching_the_front_presses_the_front_ring_and_one_a_few_centimetres_off_nothing():
    assert pressed(_Flat([((HL + 0.003, -2.0), (HL + 0.003, 2.0))])) == FRONT
    assert pressed(_Flat([((HL + 0.03, -2.0), (HL + 0.03, 2.0))])) == set()
    assert pressed(_Flat([((-HL - 0.002, -2.0), (-HL - 0.002, 2.0))])) == REAR


def test_a_corner_touched_from_the_flank_presses_only_that_corner_segment():
    # a door jamb's end against the left flank, 5 cm behind the front face
    assert pressed(_Flat([((HL - 0.05, HW + 0.002), (HL - 0.05, HW + 0.5))])) == {("front", 4)}
    # the middle of the flank has no bumper: the sonar and the floor plan keep it off things
    assert pressed(_Flat([((0.0, -HW - 0.002), (0.0, -HW - 0.5))])) == set()


def test_a_person_the_robot_drives_into_presses_it_and_one_the_world_holds_off_does_not():
    assert pressed(_Flat(people=[(HL + 0.25 + 0.002, 0.0)])) >= {("front", 2)}
    assert pressed(_Flat(people=[(HL + 0.25 + 0.02, 0.0)])) == set()  # the world holds a walker 2 cm off
    assert pressed(_Flat(people=[(-HL - 0.175, -HW - 0.175)])) == {("rear", 4)}  # at the rear right corner


def test_the_rings_turn_with_the_robot():
    wall = [((2.0 + HL + 0.002, -2.0), (2.0 + HL + 0.002, 2.0))]
    assert pressed(_Flat(wall, pose=(2.0, 0.0, 0.0))) == FRONT
    assert pressed(_Flat(wall, pose=(2.0, 0.0, math.pi))) == REAR


@settings(max_examples=150, deadline=None)
@given(d=st.floats(-0.005, 0.2), at=st.floats(-math.pi, math.pi), tilt=st.floats(-0.6, 0.6))
def test_a_switch_closes_exactly_when_the_ring_comes_within_its_travel_of_a_wall(d, at, tilt):
    """A straight wall anywhere round the robot: some segment is pressed if and only if a point of a ring lies
    within the travel of it (the flanks' middles carry no bumper), and only segments of that ring."""
    nx, ny = math.cos(at), math.sin(at)
    # the wall's line: normal (nx, ny), at the distance the footprint's shell reaches that way plus d
    reach = max(abs(sx * HL * nx + sy * HW * ny) for sx in (-1, 1) for sy in (-1, 1))
    px, py = (reach + d) * nx, (reach + d) * ny
    tx, ty = -ny * math.cos(tilt) + nx * 0.0, nx * math.cos(tilt)
    wall = [((px - 3 * tx, py - 3 * ty), (px + 3 * tx, py + 3 * ty))]
    got = pressed(_Flat(wall))
    spec = BumperSpec()
    # the truth at the tested points: their distance to the wall line
    a, b = np.array(wall[0][0]), np.array(wall[0][1])
    u = (b - a) / np.linalg.norm(b - a)
    rel = spec.points[:, 1:] - a
    dist = np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0])
    want = {spec.which[int(k)] for k in spec.points[dist <= TRAVEL, 0]}
    assert got == want
    if d > TRAVEL + 0.003:
        assert got == set()


def test_the_message_satisfies_its_schema():
    schema = etree.XMLSchema(etree.parse(str(SCHEMAS[BUMPERS])))
    assert schema.validate(bumper_element(1.5, (("front", 0), ("front", 4), ("rear", 2))))
    assert schema.validate(bumper_element(2.0, ()))
    assert not schema.validate(etree.fromstring('<bumpers time="1"><pressed ring="side" id="0"/></bumpers>'))


# ------------------------------------------------------------------ the real world
def _drive(world: World, v: float, w: float, steps: int) -> list[tuple[int, set[tuple[str, int]]]]:
    """Drive the world's robot; per step the world's contact count and what the rings feel."""
    sensor, out = BumperSensor(world), []
    for _ in range(steps):
        world.robot.command(v, w)
        world.step()
        out.append((world.contact_count, set(sensor.read())))
    return out


def test_driving_into_a_wall_presses_the_front_ring_when_the_world_feels_the_contact():
    world = room()
    world.place_robot(7.5, 3.0, 0.0)  # 0.19 m of air to the east wall's face
    put_person(world, "ann", 1.0, 1.0)
    steps = _drive(world, 0.3, 0.0, 60)
    first = next(k for k, (c, _) in enumerate(steps) if c)
    assert steps[first][1] & FRONT and not steps[first][1] & REAR
    assert all(not p for c, p in steps[:first - 2])  # nothing pressed on the way there
    back = _drive(world, -0.3, 0.0, 10)
    assert back[-1][1] == set()  # released once it backs away


def test_a_table_top_the_robot_runs_into_is_felt_by_the_world_but_by_no_bumper():
    world = room()
    world.place_robot(3.6, 2.0, -math.pi / 2)  # facing the table's long side, between its legs
    put_person(world, "ann", 7.0, 5.0)
    steps = _drive(world, 0.3, 0.0, 200)
    assert steps[-1][0] > 0  # the world's solver stopped it at the top
    assert all(not p for _, p in steps)


def test_driving_into_someone_standing_presses_the_ring_that_meets_her():
    world = room()
    world.place_robot(3.0, 3.0, 0.0)
    put_person(world, "ann", 3.0 + HL + 0.25 + 0.15, 3.0)
    steps = _drive(world, 0.3, 0.0, 40)
    assert any(p & FRONT for _, p in steps)


# ------------------------------------------------------------------ the reflex
def _told(*segments: tuple[str, int], at: float = 0.0, reflex: BumperReflex | None = None) -> BumperReflex:
    r = reflex or BumperReflex()
    r.update(bumper_element(at, segments), at)
    return r


def test_a_pressed_front_allows_backing_away_but_no_forward_speed_and_no_turn_on_the_spot():
    r = _told(("front", 2))
    assert r.command(0.3, 0.0, 0.1) == (0.0, 0.0)
    assert r.command(0.0, 0.8, 0.2) == (0.0, 0.0)
    assert r.command(-0.1, 0.3, 0.3) == (-0.1, 0.3)
    assert _told(reflex=r, at=0.4).command(0.3, 0.5, 0.5) == (0.3, 0.5)  # released: anything again


def test_a_new_press_while_driving_into_it_backs_away_for_a_while_then_gives_the_module_its_commands_back():
    r = BumperReflex()
    assert r.command(0.3, 0.1, 0.0) == (0.3, 0.1)  # driving forward
    _told(("front", 1), at=0.1, reflex=r)
    assert r.command(0.3, 0.1, 0.2) == (-BACKOFF_SPEED, 0.0)
    assert r.backing_off(0.2 + BACKOFF_TIME / 2)
    _told(at=0.3, reflex=r)  # released as it backs
    assert r.command(0.0, 0.0, 0.4) == (-BACKOFF_SPEED, 0.0)  # the back-off runs its course
    assert r.command(0.2, 0.0, 0.1 + BACKOFF_TIME + 0.05) == (0.2, 0.0)


def test_a_press_it_did_not_drive_into_starts_no_back_off():
    r = BumperReflex()
    r.command(-0.1, 0.0, 0.0)  # backing
    _told(("front", 0), at=0.1, reflex=r)  # something pressed the front meanwhile
    assert r.command(-0.1, 0.0, 0.2) == (-0.1, 0.0)


def test_wedged_front_and_back_only_turning_is_left():
    r = _told(("front", 2), ("rear", 2))
    assert r.command(0.2, 0.0, 0.1) == (0.0, 0.0)
    assert r.command(-0.2, 0.0, 0.1) == (0.0, 0.0)
    assert r.command(0.0, 0.5, 0.1) == (0.0, 0.5)


_SEGMENTS = st.sets(st.tuples(st.sampled_from(["front", "rear"]), st.integers(0, 4)))


@settings(max_examples=200, deadline=None)
@given(before=_SEGMENTS, now=_SEGMENTS, last_v=st.floats(-0.3, 0.5), v=st.floats(-0.3, 0.5), w=st.floats(-1.0, 1.0),
       later=st.floats(0.0, 3.0))
def test_no_command_ever_drives_into_a_pressed_ring(before, now, last_v, v, w, later):
    r = _told(*sorted(before))
    r.command(last_v, 0.0, 0.0)
    _told(*sorted(now), at=0.05, reflex=r)
    cv, cw = r.command(v, w, 0.05 + later)
    rings = {ring for ring, _ in now}
    if "front" in rings:
        assert cv <= 0.0
    if "rear" in rings:
        assert cv >= 0.0
    if rings and cv == 0.0 and rings != {"front", "rear"}:
        assert cw == 0.0  # no turn on the spot against one pressed ring
    if not rings and later > BACKOFF_TIME:
        assert (cv, cw) == (v, w)  # nothing pressed, no back-off left: the module's own command


# ------------------------------------------------------------------ closed loop on the bus
def test_driving_into_a_wall_on_the_bus_the_base_reports_the_press_and_the_reflex_backs_away():
    """The real base, world and (strict) bus: a driver that wants to go on into the east wall at 0.3 m/s,
    its commands held to the reflex as the modules hold theirs. The base reports the front ring once it
    touches and the reflex backs it away at once: each touch lasts no more than a few packets, never a robot
    pushing on at the wall (this driver, unlike the modules, knows no floor plan and tries again)."""
    import asyncio

    from homesim.scenario.loader import load_scenario
    from homesim.sim import Simulation
    from homesim.tour.stage import Stage
    from tests.world_helpers import ROOM

    sc = load_scenario(ROOM)
    sim = Simulation(seed=3, scenario=sc.name)
    stage = Stage(sim, sc, actors=HARDWARE)
    try:
        stage.world.place_robot(7.4, 3.0, 0.0)  # 0.29 m of air to the east wall's face
        driver = sim.bus.participant("follower", host="robot")
        reflex, heard = BumperReflex(), []

        def on_bumpers(m) -> None:
            heard.append((sim.now, sorted((p.get("ring"), int(p.get("id"))) for p in m.xml.iter("pressed"))))
            reflex.update(m.xml, sim.now)

        driver.subscribe(BUMPERS, on_bumpers)

        async def drive() -> None:
            while True:
                v, w = reflex.command(0.3, 0.0, sim.now)
                driver.publish("/robot/base/cmd", etree.Element("velocity", v=f"{v:.4f}", w=f"{w:.4f}"))
                await asyncio.sleep(0.1)

        sim.spawn(drive(), name="driver")
        stage.run(6.0)
        assert heard and heard[0][1] and all(ring == "front" for ring, _ in heard[0][1])
        presses = [t for k, (t, p) in enumerate(heard) if p and (k == 0 or not heard[k - 1][1])]
        releases = [t for t, p in heard if not p]
        assert presses and len(releases) >= len(presses) - 1
        for t, r in zip(presses, releases):
            assert r - t <= 0.35  # released within a few packets: it backed away at once
        assert len(presses) == stage.world.contact_count  # the base felt every contact the world counted
    finally:
        sim.close()
