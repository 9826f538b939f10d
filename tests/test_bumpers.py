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
    assert r.command(0.3, 0.0, 0.4) == (-BACKOFF_SPEED, 0.0)  # the back-off runs its course
    assert r.command(0.0, 0.0, 0.5) == (0.0, 0.0)  # asked to stand, it stands: the reflex adds no motion
    assert r.command(0.2, 0.0, 0.1 + BACKOFF_TIME + 0.05) == (0.2, 0.0)


def test_a_back_off_the_module_s_own_rules_refuse_is_not_made():
    r = BumperReflex()
    r.command(0.3, 0.0, 0.0)
    _told(("front", 2), at=0.1, reflex=r)
    asked = []
    assert r.command(0.3, 0.0, 0.2, lambda s: asked.append(s) or False) == (0.0, 0.0)  # held to the ring instead
    assert asked == [-BACKOFF_SPEED]
    assert not r.backing_off(0.3)  # refused once, given up: no back-off later behind the module's back
    assert r.command(-0.05, 0.0, 0.3, lambda s: True) == (-0.05, 0.0)  # the module's own backing is its own


def test_a_press_made_by_the_back_off_starts_no_back_off_the_other_way_and_stops_it():
    r = BumperReflex()
    r.command(0.3, 0.0, 0.0)
    _told(("front", 2), at=0.1, reflex=r)
    assert r.command(0.3, 0.0, 0.2) == (-BACKOFF_SPEED, 0.0)
    _told(at=0.3, reflex=r)
    _told(("rear", 2), at=0.5, reflex=r)  # backed into the box behind
    assert not r.backing_off(0.6)
    assert r.command(0.0, 0.0, 0.6) == (0.0, 0.0)
    assert r.command(-0.2, 0.0, 0.7) == (0.0, 0.0)  # the rear ring holds


def test_a_turn_on_the_spot_that_pressed_a_ring_may_be_undone_but_not_pushed_on():
    """review13 item 4: attention turning right swung the front's right corner into a wall; the turn back
    frees it and was refused, so attention could never turn again."""
    r = BumperReflex()
    r.command(0.0, -0.6, 0.0)
    _told(("front", 0), at=0.1, reflex=r)
    assert r.command(0.0, -0.6, 0.2) == (0.0, 0.0)  # on into the wall: no
    assert r.command(0.0, 0.6, 0.3) == (0.0, 0.6)  # back the way it came: yes
    assert r.command(0.3, 0.0, 0.4) == (0.0, 0.0)  # no forward speed while the front is pressed
    s = _told(("front", 2))  # walked into (no turn under way): no turn frees it for sure
    assert s.command(0.0, 0.6, 0.1) == (0.0, 0.0) and s.command(0.0, -0.6, 0.1) == (0.0, 0.0)


def test_each_module_built_without_init_has_its_own_reflex():
    """review13 item 13: one class-level reflex was shared by every module the unit tests build without a bus."""
    from robot.attention.module import PersonAttention
    from robot.navigation.follow import Follower
    from robot.navigation.player import Player

    for cls in (Follower, Player, PersonAttention):
        a, b = object.__new__(cls), object.__new__(cls)
        a.bumpers.command(0.3, 0.0, 0.0)
        _told(("front", 1), at=0.1, reflex=a.bumpers)
        assert a.bumpers.backing_off(0.2) and a.bumpers is a.bumpers
        assert b.bumpers is not a.bumpers and not b.bumpers.pressed and b.bumpers.command(0.3, 0.0, 0.2) == (0.3, 0.0)


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


# ------------------------------------------------------------------ between two obstacles (review13 item 3)
def _between(gap_front: float, gap_rear: float) -> str:
    """A 3 x 2 m room, a box (0.5 m high, the rings meet it) behind the robot: the east wall's face ``gap_front``
    m ahead of the front ring, the box's face ``gap_rear`` m behind the rear ring."""
    face = 2.95 - 2 * HL - gap_front - gap_rear
    return f"""<scenario name="between" seed="3" duration="10"><flat>
      <room name="room" points="0,0 3,0 3,2 0,2"/>
      <walls thickness="0.1"><wall from="0 0" to="3 0"/><wall from="3 0" to="3 2"/><wall from="3 2" to="0 2"/><wall from="0 2" to="0 0"/></walls>
      <furniture name="box" type="shelf" points="{face - 0.45:.4f},0.6 {face:.4f},0.6 {face:.4f},1.4 {face - 0.45:.4f},1.4" height="0.5"/>
    </flat><robot x="1.0" y="1.0" heading="0"/><humans/></scenario>"""


def _outline(face: float) -> np.ndarray:
    """The floor plan's edges near the robot as points every 1 cm (world frame): what a module knows of the flat."""
    edges = [((2.95, 0.05), (2.95, 1.95)), ((face, 0.6), (face, 1.4)), ((face - 0.45, 0.6), (face, 0.6)), ((face - 0.45, 1.4), (face, 1.4))]
    pts = []
    for (ax, ay), (bx, by) in edges:
        n = int(math.hypot(bx - ax, by - ay) / 0.01) + 1
        pts.append(np.column_stack((np.linspace(ax, bx, n), np.linspace(ay, by, n))))
    return np.concatenate(pts)


_PLAN = st.lists(st.tuples(st.sampled_from([0.15, 0.08, 0.0, -0.08, -0.15]), st.sampled_from([0.0, 0.0, 0.4, -0.4]),
                           st.integers(1, 6)), min_size=1, max_size=4)


@settings(max_examples=10, deadline=None)
@given(gap_front=st.floats(0.01, 0.12), gap_rear=st.floats(0.01, 0.15), plan=_PLAN)
def test_between_two_obstacles_the_reflex_causes_no_contact_the_module_s_own_commands_would_not(gap_front, gap_rear, plan):
    """The real base, world and bus; a module that sends ``plan`` ((v, w, tenths of a second) each, then stands)
    through the reflex, holding its back-off to the floor plan as the follower and the player do
    (:func:`robot.navigation.follow.sweep_allowed`). Every new press comes while the base was moving as the
    module itself asked (held, never reversed): none while the reflex was driving on its own, and nothing
    at all moves once the module asks to stand (on b1219b1's merge the back-off bounced the robot between
    the wall and the box, 5 contacts in 4 s with the module asking to stand)."""
    import asyncio

    from homesim.scenario.loader import load_scenario_text
    from homesim.sim import Simulation
    from homesim.tour.stage import Stage
    from robot.navigation.follow import sweep_allowed

    sc = load_scenario_text(_between(gap_front, gap_rear))
    face = 2.95 - 2 * HL - gap_front - gap_rear
    outline = _outline(face)
    sim = Simulation(seed=3, scenario=sc.name)
    stage = Stage(sim, sc, actors=HARDWARE)
    try:
        stage.world.place_robot(2.95 - HL - gap_front, 1.0, 0.0)
        module = sim.bus.participant("follower", host="robot")
        reflex = BumperReflex()
        sent: list[tuple[float, float, float, float]] = [(0.0, 0.0, 0.0, 0.0)]  # (asked v, asked w, sent v, sent w)
        onsets: list[tuple[set[tuple[str, int]], tuple[float, float, float, float]]] = []
        seen: set[tuple[str, int]] = set()

        def on_bumpers(m) -> None:
            now = {(p.get("ring"), int(p.get("id"))) for p in m.xml.iter("pressed")}
            if now - seen:
                onsets.append((now - seen, sent[-4:]))
            seen.clear()
            seen.update(now)
            reflex.update(m.xml, sim.now)

        module.subscribe(BUMPERS, on_bumpers)

        def may_back(speed: float) -> bool:
            x, y, th = stage.world.robot.pose
            c, s = math.cos(th), math.sin(th)
            dx, dy = outline[:, 0] - x, outline[:, 1] - y
            return sweep_allowed(speed, 0.0, np.column_stack((c * dx + s * dy, -s * dx + c * dy)))

        steps = [(v, w) for v, w, n in plan for _ in range(n)]

        async def drive() -> None:
            k = 0
            while True:
                asked = steps[k] if k < len(steps) else (0.0, 0.0)
                v, w = reflex.command(*asked, sim.now, may_back)
                sent.append((*asked, v, w))
                module.publish("/robot/base/cmd", etree.Element("velocity", v=f"{v:.4f}", w=f"{w:.4f}"))
                k += 1
                await asyncio.sleep(0.1)

        sim.spawn(drive(), name="module")
        stage.run(0.1 * len(steps) + 2.0)
        for segments, recent in onsets:
            # the base answers within a few tenths (its acceleration): the commands of the last 0.3 s moved it
            own = [(v, w) for av, aw, v, w in recent if (v, w) != (0.0, 0.0) and v * av >= 0.0 and w * aw >= 0.0]
            assert own, (segments, recent)  # pressed while moving as the module asked (or less), never by the reflex alone
        after = [(av, aw, v, w) for av, aw, v, w in sent[len(steps) + 1:]]
        assert all((v, w) == (0.0, 0.0) for _, _, v, w in after)  # asked to stand: stands
    finally:
        sim.close()


def test_a_module_that_starts_listening_while_a_ring_stays_pressed_hears_it_within_a_packet():
    """review13 item 6: the base sent /robot/bumpers only on a change, so a module restarted by the watchdog
    (a fresh reflex, nothing pressed) or subscribed late drove on into a ring that stayed pressed."""
    from homesim.scenario.loader import load_scenario
    from homesim.sim import Simulation
    from homesim.tour.stage import Stage
    from tests.world_helpers import ROOM

    sc = load_scenario(ROOM)
    sim = Simulation(seed=3, scenario=sc.name)
    stage = Stage(sim, sc, actors=HARDWARE)
    try:
        stage.world.place_robot(7.688, 3.0, 0.0)  # the front ring within its travel of the east wall: pressed
        stage.run(0.5)
        late = BumperReflex()
        sim.bus.participant("follower", host="robot").subscribe(BUMPERS, lambda m: late.update(m.xml, sim.now))
        stage.run(0.8)  # until 0.8 s of sim time: three packets later
        assert late.rings() == (True, False)
        assert late.command(0.3, 0.0, sim.now) == (0.0, 0.0)
    finally:
        sim.close()
