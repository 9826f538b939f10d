"""The simulated flat: pymunk physics plus the geometry the sensors query.

:class:`World` is built from a :class:`~homesim.scenario.model.Scenario`:
walls (with door gaps) and furniture become static pymunk polygons, the
robot a dynamic differential-drive body, people kinematic bodies with
legs. ``step(dt)`` advances physics by an integer step count (time is
``steps * dt``, no float drift). The world keeps numpy arrays of the static
geometry for the raycast kernel, split by height so that the laser at
0.30 m sees walls, table legs and furniture reaching down to the floor but
not table tops; the camera's sloping sight lines are checked in 3D against
every obstacle's vertical extent (:attr:`World.prisms`) and people's
heights.

The world is ground truth. Robot modules never hold a reference to it:
hardware models read it and publish noisy measurements on the bus.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable

import numpy as np
import pymunk

from ..scenario.model import Furniture, Scenario, Target
from . import chipmunk as cp
from .acoustics import SoundField
from .bodies import (
    CAT_FURNITURE,
    CAT_HUMAN,
    CAT_LASER,
    CAT_ROBOT,
    CAT_WALL,
    HUMAN_RADIUS,
    LASER_HEIGHT,
    LEG_RADIUS,
    ROBOT_REACH,
    HumanBody,
    RobotBody,
)
from ..geometry import is_convex, point_in_polygon, polygon_area, polygon_centroid, polygon_edges, split_wall, wall_rectangle
from ..scenario.pathplan import WALKER_RADIUS, Grid, door_sides, scenario_bounds
from .raycast import FanCaster, Prisms

StepListener = Callable[["World"], None]
ContactListener = Callable[[float, str], None]
Overlap = tuple[float, pymunk.Vec2d, pymunk.Shape]

#: How close (metres) a person's body may walk up to the robot's footprint.
PERSON_GAP = 0.02
#: How close (metres, centre to centre) two people may come: their bodies (HUMAN_RADIUS circles) PERSON_GAP apart.
PEOPLE_APART = 2 * HUMAN_RADIUS + PERSON_GAP
#: The farthest (metres) anything moves in one physics sub-step (no tunnelling through walls).
MAX_SUBSTEP_MOVE = 0.05
#: Overlap with a wall (metres) beyond which the robot's last move is undone.
STUCK_DEPTH = 0.003
#: Cells (metres) of the robot's no-contact look-up, and the safety margin of that test.
CLEAR_CELL = 0.05
CONTACT_MARGIN = 0.02
#: Cells (metres) of the room look-up (:meth:`World.room_of`).
ROOM_CELL = 0.1
#: How many of the robot's latest contacts :attr:`World.contacts` keeps (the count goes on).
CONTACT_LOG = 1000
_UNKNOWN, _MIXED = object(), object()
#: A query for walls and furniture only (people and the robot do not match it).
STATIC_QUERY = pymunk.ShapeFilter(mask=CAT_WALL | CAT_FURNITURE)


class Obstacle:
    """A static convex polygon with the vertical span it occupies."""

    __slots__ = ("name", "kind", "polygon", "bottom", "top")

    def __init__(self, name: str, kind: str, polygon: np.ndarray, bottom: float, top: float) -> None:
        self.name = name
        self.kind = kind  # "wall", "furniture", "leg"
        self.polygon = polygon
        self.bottom = bottom
        self.top = top


class World:
    """Physics and geometry of one scenario's flat (see the module docstring)."""

    def __init__(self, scenario: Scenario, *, dt: float | None = None) -> None:
        self.scenario = scenario
        self.dt = 1.0 / scenario.world_rate if dt is None else dt
        self.steps = 0
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        self.space.iterations = 20
        self.sound = SoundField()
        self.avatar: dict[str, object] = {"pan": 0.0, "tilt": 0.0, "expression": "neutral"}  # the robot display's face
        self.ptu = (0.0, 0.0)  # the camera's pan and tilt (radians), set by the camera model
        self.obstacles: list[Obstacle] = []
        self._listeners: list[StepListener] = []
        self._contacts: deque[tuple[float, str]] = deque(maxlen=CONTACT_LOG)
        self._contact_listeners: list[ContactListener] = []
        self.contact_count = 0  # every contact the robot began, all run long
        self._build_static(scenario)
        r = scenario.robot
        self.robot = RobotBody(self.space, r.x, r.y, r.heading, max_speed=r.max_speed, max_turn=r.max_turn)
        self.humans: dict[str, HumanBody] = {}
        for k, h in enumerate(scenario.humans):
            self.humans[h.name] = HumanBody(self.space, h.name, h.x, h.y, h.heading, height=h.height, torso=h.torso, speed=h.speed,
                                            order=k)
        self._people = list(self.humans.values())
        # Robot positions (5 cm cells) with no wall or furniture within reach: no contact to resolve there.
        self._clear_cells: dict[tuple[int, int], bool] = {}
        self.sources = {s.name: (s.x, s.y, s.height) for s in scenario.sources}
        self.objects = {o.name: o for o in scenario.objects}
        self._seg_cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self.space.on_collision(CAT_ROBOT, None, begin=self._on_robot_contact)
        self._laser_segments = self.segments_at(LASER_HEIGHT)
        self.caster = FanCaster()
        self._leg_radii: dict[int, np.ndarray] = {}  # leg_circles' radii per leg count (read-only)
        self._grids: dict[float, Grid] = {}
        self._room_polys = [(r.name, [(float(x), float(y)) for x, y in r.polygon]) for r in scenario.rooms]
        self._room_cells: dict[tuple[int, int], object] = {}
        self._prisms: Prisms | None = None

    # ------------------------------------------------------------ building
    def _build_static(self, sc: Scenario) -> None:
        sb = self.space.static_body
        for wall in sc.walls:
            for a, b in split_wall(wall.start, wall.end, [(d.at, d.width) for d in wall.doors]):
                rect = wall_rectangle(a, b, wall.thickness)
                self._add_static(Obstacle(f"wall@{wall.line}", "wall", rect, 0.0, 3.0), CAT_WALL | CAT_LASER, sb)
        for f in sc.furniture:
            poly = np.array(f.polygon, dtype=float)
            if not is_convex(poly):
                raise ValueError(f"furniture {f.name!r} is not convex")
            laser = CAT_LASER if f.clearance <= LASER_HEIGHT <= f.height else 0
            self._add_static(Obstacle(f.name, "furniture", poly, f.clearance, f.height), CAT_FURNITURE | laser, sb)
            if f.clearance > 0:
                for leg in table_legs(f):
                    # Legs carry the top: the robot meets the top first, so legs are sensors.
                    self._add_static(Obstacle(f"{f.name}/leg", "leg", leg, 0.0, f.clearance), CAT_FURNITURE | CAT_LASER, sb, sensor=True)

    def _add_static(self, ob: Obstacle, categories: int, body: pymunk.Body, *, sensor: bool = False) -> None:
        if polygon_area(ob.polygon) < 0:  # keep every polygon counter-clockwise (backface culling)
            ob.polygon = ob.polygon[::-1].copy()
        self.obstacles.append(ob)
        shape = pymunk.Poly(body, [tuple(p) for p in ob.polygon])
        shape.filter = pymunk.ShapeFilter(categories=categories)
        shape.friction = 0.0
        shape.sensor = sensor
        shape.collision_type = CAT_WALL if ob.kind == "wall" else CAT_FURNITURE
        self.space.add(shape)

    def _on_robot_contact(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        a, b = arbiter.shapes
        other = b if a.body is self.robot.body else a
        if other.sensor:
            return
        if other.collision_type == CAT_HUMAN:
            what = next((n for n, h in self.humans.items() if h.shape is other), "human")
        elif other.collision_type == CAT_WALL:
            what = "wall"
        else:
            what = "furniture"
        t = self.time
        self._contacts.append((t, what))
        self.contact_count += 1
        for fn in self._contact_listeners:
            fn(t, what)

    # --------------------------------------------------------------- time
    @property
    def time(self) -> float:
        """World time in seconds: the step count times dt."""
        return self.steps * self.dt

    def add_listener(self, fn: StepListener) -> None:
        """Call ``fn(world)`` after every step (ground truth, plots); it must not change the world."""
        self._listeners.append(fn)

    def remove_listener(self, fn: StepListener) -> None:
        """Stop calling ``fn`` (a recorder that has closed its file); nothing if it is not listening."""
        if fn in self._listeners:
            self._listeners.remove(fn)

    def add_contact_listener(self, fn: ContactListener) -> None:
        """Call ``fn(time, what)`` whenever the robot begins touching something (``what``: "wall",
        "furniture" or a person's name); during the physics step, so it must not change the world."""
        self._contact_listeners.append(fn)

    def step(self, dt: float | None = None) -> None:
        """Advance physics by one step of ``dt`` (the world's own dt by default).

        A step is split into equal sub-steps so that nothing moves more than
        MAX_SUBSTEP_MOVE in one (a fast robot or a low world rate would
        otherwise carry the robot through a wall between two contact checks).
        At the default rate and speeds a step is a single sub-step.
        """
        dt = self.dt if dt is None else dt
        n = self.substeps(dt)
        if n == 1:
            self._substep(dt)
        else:
            h = dt / n
            for _ in range(n):
                self._substep(h)
        self.steps += 1
        for fn in self._listeners:
            fn(self)

    def substeps(self, dt: float) -> int:
        """How many sub-steps a step of ``dt`` needs (the fastest point moves at most MAX_SUBSTEP_MOVE in each)."""
        rb = self.robot
        v, w = rb.v, rb.w
        v, w = (-v if v < 0 else v), (-w if w < 0 else w)  # abs()
        fastest = (v if v > rb.max_speed else rb.max_speed) + (w if w > rb.max_turn else rb.max_turn) * ROBOT_REACH
        for hb in self._people:
            if hb.present and hb.walk_speed > fastest:
                fastest = hb.walk_speed
        x = fastest * dt / MAX_SUBSTEP_MOVE - 1e-9
        return 1 if x <= 1.0 else math.ceil(x)  # max(1, ceil(x))

    def _substep(self, dt: float) -> None:
        rb = self.robot
        body = rb.body
        people = self._people
        angle = rb.before_step(dt)
        before = cp.position(body)
        self._hold_people_back(dt, before)
        cp.step(self.space, dt)
        rb.moved()
        for h in people:
            h.moved()
        after: tuple[float, float] | None = cp.position(body)
        if not self._no_contact(after):
            if self._resolve_robot_contacts():
                # Turning in a tight spot (between a wall and a table): the solver cannot
                # stop a turn (the base's turn rate is imposed), so the turn is blocked.
                body.angle = angle
                body.angular_velocity = rb.w = 0.0
                self.space.reindex_shapes_for_body(body)
                if self._resolve_robot_contacts():
                    body.position = before
                    self.space.reindex_shapes_for_body(body)
            rb.moved()
            after = None  # the contacts may have moved it: after_step reads it
        rb.after_step(dt, before, after)
        for h in people:
            if h.present:
                h.advance(dt)

    def _no_contact(self, at: tuple[float, float] | None = None) -> bool:
        """Whether the robot provably touches nothing (so :meth:`_resolve_robot_contacts` would do nothing).

        Nothing static lies within its reach of the robot's 5 cm cell (asked of pymunk once
        per cell and kept) and every person's body is farther than both radii. Exact: a
        shape query there would find no overlap at all. ``at``: the robot's position if the
        caller has it.
        """
        x, y = cp.position(self.robot.body) if at is None else at
        reach = ROBOT_REACH + HUMAN_RADIUS + 2 * CONTACT_MARGIN
        for h in self._people:
            if h.present:
                hx, hy = h.position
                if (hx - x) ** 2 + (hy - y) ** 2 <= reach * reach:
                    return False
        cell = (math.floor(x / CLEAR_CELL), math.floor(y / CLEAR_CELL))
        clear = self._clear_cells.get(cell)
        if clear is None:
            centre = ((cell[0] + 0.5) * CLEAR_CELL, (cell[1] + 0.5) * CLEAR_CELL)
            near = self.space.point_query(centre, ROBOT_REACH + CLEAR_CELL + CONTACT_MARGIN, STATIC_QUERY)
            clear = self._clear_cells[cell] = not any(not q.shape.sensor for q in near if q.shape is not None)
        return clear

    def _hold_people_back(self, dt: float, robot_at: tuple[float, float] | None = None) -> None:
        """People never push the robot: a step that would bring someone within
        PERSON_GAP of the robot's footprint (and closer than now) is not taken.
        Nor does anyone walk into someone else: a step that would bring two people's bodies
        within PERSON_GAP of each other (centres closer than :data:`PEOPLE_APART`, and closer
        than now) is not taken either (:meth:`_crowded`).

        Scripts set the velocity they want (``HumanBody.walk``); the person
        stands still for this step instead, and walks on when the way is free.
        ``robot_at``: the robot's position if the caller has it.
        """
        shape = self.robot.shape
        rx, ry = cp.position(self.robot.body) if robot_at is None else robot_at
        people = self._people
        several = len(people) > 1
        for k, h in enumerate(people):
            if not h.present:
                continue
            vx, vy = h.walk
            held = crowded = False
            if vx or vy:
                x, y = h.position
                far = ROBOT_REACH + HUMAN_RADIUS + PERSON_GAP + math.hypot(vx, vy) * dt
                if (x - rx) ** 2 + (y - ry) ** 2 < far * far:  # near enough to matter
                    now = cp.point_distance(shape, x, y)
                    nxt = cp.point_distance(shape, x + vx * dt, y + vy * dt)
                    held = nxt < HUMAN_RADIUS + PERSON_GAP and nxt < now
                if not held and several:
                    crowded = self._crowded(k, x + vx * dt, y + vy * dt, x, y, dt)
            if held or crowded:
                h.set_velocity(0.0, 0.0)
            else:
                h.set_velocity(vx, vy)
            h.held = held
            h.crowded = crowded
            if held:
                h.held_time += dt
            if crowded:
                h.crowded_time += dt

    def _crowded(self, k: int, nx: float, ny: float, x: float, y: float, dt: float) -> bool:
        """Whether person ``k`` stepping from (x, y) to (nx, ny) would come within :data:`PEOPLE_APART`
        of someone (centre to centre) and nearer than now.

        People are decided in the world's order within a step: someone decided before her is where
        her velocity for this step takes her; someone after her may still stand or walk, so both
        where she stands and where she wants to be must be clear. Whatever each is then decided to
        do, no two bodies end the step overlapping (that one steps away from an overlap is allowed)."""
        apart2 = PEOPLE_APART * PEOPLE_APART
        for j, o in enumerate(self._people):
            if j == k or not o.present:
                continue
            ox, oy = o.position
            reach = PEOPLE_APART + (abs(o.walk[0]) + abs(o.walk[1]) + abs(nx - x) / dt + abs(ny - y) / dt) * dt
            if (ox - x) ** 2 + (oy - y) ** 2 >= reach * reach:
                continue  # too far to matter this step
            now2 = (ox - x) ** 2 + (oy - y) ** 2
            if j < k:
                vx, vy = o.velocity  # decided this step
                spots = ((ox + vx * dt, oy + vy * dt),)
            else:
                wx, wy = o.walk
                spots = ((ox, oy), (ox + wx * dt, oy + wy * dt)) if (wx or wy) else ((ox, oy),)
            for px, py in spots:
                d2 = (px - nx) ** 2 + (py - ny) ** 2
                if d2 < apart2 and d2 < now2:
                    return True
        return False

    def _resolve_robot_contacts(self) -> bool:
        """Hard contacts: push the robot out of whatever it overlaps after a step; walls win.

        The robot's velocity is commanded every step, so the solver's soft
        correction alone would let it lean several centimetres into a wall;
        a bumper-like projection keeps it within the solver's slop. Walls
        and furniture are resolved first. A person the robot overlaps
        pushes it back only if that does not put it into a wall or furniture;
        otherwise the person is moved back instead (the robot squeezed
        between a person and a wall never goes through the wall).
        Returns whether the robot is still stuck in a wall or furniture.
        """
        body = self.robot.body
        for _ in range(4):
            static, person = self._overlaps()
            if static is not None:
                self._push_robot(static[0], static[1])
                continue
            if person is None:
                return False
            depth, n, shape = person
            old = body.position
            self._push_robot(depth, n)
            if self._overlaps()[0] is not None:
                body.position = old
                self.space.reindex_shapes_for_body(body)
                hb = shape.body
                hb.position = (hb.position.x + n.x * depth, hb.position.y + n.y * depth)
                who = next((h for h in self._people if h.body is hb), None)
                if who is not None:
                    who.moved()
                    who.set_velocity(0.0, 0.0)
                else:
                    hb.velocity = (0.0, 0.0)
                self.space.reindex_shapes_for_body(hb)
        static = self._overlaps()[0]
        return static is not None and static[0] > STUCK_DEPTH

    def _overlaps(self) -> tuple[Overlap | None, Overlap | None]:
        """The deepest overlaps of the robot with a wall or furniture, and with a person:
        (depth, the normal pointing from the robot into the other shape, the shape)."""
        static = person = None
        for info in self.space.shape_query(self.robot.shape):
            shape = info.shape
            if shape is None or shape.sensor:
                continue
            cps = info.contact_point_set
            # shape_query reports only overlapping shapes; the sign of the
            # distance depends on the pair's order in Chipmunk, so use its size.
            depth = max((abs(p.distance) for p in cps.points), default=0.0)
            if depth <= 1e-4:
                continue
            if shape.body.body_type == pymunk.Body.STATIC:
                if static is None or depth > static[0]:
                    static = (depth, cps.normal, shape)
            elif person is None or depth > person[0]:
                person = (depth, cps.normal, shape)
        return static, person

    def _push_robot(self, depth: float, n: pymunk.Vec2d, _shape: object = None) -> None:
        body = self.robot.body
        body.position = (body.position.x - n.x * depth, body.position.y - n.y * depth)
        vn = body.velocity.x * n.x + body.velocity.y * n.y
        if vn > 0:
            body.velocity = (body.velocity.x - vn * n.x, body.velocity.y - vn * n.y)
        self.space.reindex_shapes_for_body(body)
        self.robot.moved()

    def place_robot(self, x: float, y: float, heading: float) -> None:
        """Put the robot somewhere at rest (tests, notebooks); no collision check."""
        b = self.robot.body
        b.position = (x, y)
        b.angle = heading
        b.velocity = (0.0, 0.0)
        b.angular_velocity = 0.0
        self.robot.v = self.robot.w = 0.0
        self.space.reindex_shapes_for_body(b)
        self.robot.moved()

    @property
    def contacts(self) -> list[tuple[float, str]]:
        """(time, what) of the contacts the robot began (walls, furniture, people): every one, up to
        the latest :data:`CONTACT_LOG` (a run's memory does not grow with its length; the count of
        all of them is :attr:`contact_count`, and :meth:`add_contact_listener` sees each)."""
        return list(self._contacts)

    # ------------------------------------------------------------ geometry
    def segments_at(self, z: float) -> tuple[np.ndarray, np.ndarray]:
        """Edges (a, b) of every static obstacle whose vertical extent contains height ``z``
        (what a horizontal beam at z hits). Sloping sight lines use :attr:`prisms`."""
        key = round(z, 3)
        got = self._seg_cache.get(key)
        if got is not None:
            return got
        chosen = [o for o in self.obstacles if o.bottom <= z <= o.top]
        if chosen:
            pairs = [polygon_edges(o.polygon) for o in chosen]
            a = np.concatenate([p[0] for p in pairs])
            b = np.concatenate([p[1] for p in pairs])
        else:
            a = b = np.zeros((0, 2))
        a.flags.writeable = b.flags.writeable = False  # shared from the cache (and so the laser knows them)
        self._seg_cache[key] = (a, b)
        return a, b

    def leg_circles(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres (K, 2) and radii (K,) of every present person's legs.

        The centres are :meth:`~homesim.world.bodies.Human.leg_centres`' floats (the same
        expressions), gathered in plain floats into one array; the radii array is shared per
        count and read-only."""
        rows = []
        for h in self.humans.values():
            if h.present:
                x, y = h.position
                heading = h.heading
                c, s = math.cos(heading), math.sin(heading)
                (ox0, oy0), (ox1, oy1) = h.leg_offsets
                rows.append((x + c * ox0 - s * oy0, y + s * ox0 + c * oy0))
                rows.append((x + c * ox1 - s * oy1, y + s * ox1 + c * oy1))
        k = len(rows)
        radii = self._leg_radii.get(k)
        if radii is None:
            radii = self._leg_radii[k] = np.full(k, LEG_RADIUS)
            radii.flags.writeable = False
        return (np.array(rows) if k else np.zeros((0, 2))), radii

    def person_cylinders(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
        """Present people as upright cylinders for occlusion: centres (K, 2), radii, heights, names."""
        people = [h for h in self.humans.values() if h.present]
        if not people:
            return np.zeros((0, 2)), np.zeros(0), np.zeros(0), []
        k = len(people)
        return np.array([h.position for h in people]), np.full(k, HUMAN_RADIUS * 0.8), np.array([h.height for h in people]), [h.name for h in people]

    @property
    def prisms(self) -> Prisms:
        """Every static obstacle as a vertical prism (footprint, bottom, top) for 3D sight lines."""
        if self._prisms is None:
            obs = self.obstacles
            self._prisms = Prisms([o.polygon for o in obs], [o.bottom for o in obs], [o.top for o in obs])
        return self._prisms

    def laser_ranges(self, origin: tuple[float, float], angles: np.ndarray, max_range: float, out: np.ndarray | None = None) -> np.ndarray:
        """Exact ranges at laser height along world angles (no noise): walls, furniture, legs.

        The static part (walls and furniture) is cast once per laser pose and kept: while the
        robot stands still (a dialog, a wait) only the people's legs are recast
        (:meth:`~homesim.world.raycast.FanCaster.scan`, bit-identical to casting everything
        together).
        """
        a, b = self._laser_segments
        c, r = self.leg_circles()
        return self.caster.scan(origin, angles, a, b, c, r, max_range, out=out)

    def target_point(self, t: Target, *, who: str | None = None) -> tuple[float, float, float]:
        """World point (x, y, z) of a script or expectation target."""
        sc = self.scenario
        if t.kind == "point":
            return t.x, t.y, 0.0
        if t.kind == "robot":
            x, y, _ = self.robot.pose
            return x, y, 1.0
        if t.kind == "place":
            p = sc.place(t.name or "")
            return p.x, p.y, 0.0
        if t.kind == "room":
            cx, cy = polygon_centroid(np.array(sc.room(t.name or "").polygon))
            return cx, cy, 0.0
        if t.kind == "object":
            return self.object_point(t.name or "")
        if t.kind == "furniture":
            f = sc.piece(t.name or "")
            cx, cy = polygon_centroid(np.array(f.polygon))
            return cx, cy, f.height
        if t.kind == "human":
            h = self.humans[t.name or ""]
            x, y = h.position
            return x, y, h.face_z
        raise ValueError(f"{t.kind!r} is not a point target")

    def object_point(self, name: str) -> tuple[float, float, float]:
        """Centre of an object: on its furniture's top, or on the floor."""
        o = self.objects[name]
        base = self.scenario.piece(o.on).height if o.on else 0.0
        return o.x, o.y, base + o.height / 2

    def source_point(self, name: str) -> tuple[float, float, float] | None:
        """Where a sound source is: a present person's mouth, a radio, the robot's speaker."""
        if name == "robot":
            x, y = self.robot.world_point(0.1)
            return x, y, 1.2
        h = self.humans.get(name)
        if h is not None:
            return h.face_point() if h.present else None
        return self.sources.get(name)

    def room_of(self, x: float, y: float) -> str | None:
        """Name of the room containing (x, y), or None outside the flat.

        Looked up in a grid of :data:`ROOM_CELL` cells, filled as they are asked for: a cell
        that no room edge comes near has one answer everywhere in it (the even-odd test
        changes only across an edge), the one at its centre; a cell an edge crosses or
        touches asks the polygons every time. So the answer is the polygons' own.
        """
        try:
            key = (math.floor(x / ROOM_CELL), math.floor(y / ROOM_CELL))
        except (ValueError, OverflowError):  # NaN or beyond any cell: the polygons answer (no room)
            return self._room_exact(x, y)
        got = self._room_cells.get(key, _UNKNOWN)
        if got is _UNKNOWN:
            got = self._room_cells[key] = self._cell_room(key)
        return self._room_exact(x, y) if got is _MIXED else got  # type: ignore[return-value]

    def _room_exact(self, x: float, y: float) -> str | None:
        for name, poly in self._room_polys:
            if point_in_polygon((x, y), poly):
                return name
        return None

    def _cell_room(self, key: tuple[int, int]) -> object:
        """The room of every point of a grid cell, or _MIXED when a room edge comes near it."""
        cx, cy = (key[0] + 0.5) * ROOM_CELL, (key[1] + 0.5) * ROOM_CELL
        clear = ROOM_CELL * 0.7072 + 1e-6  # beyond the cell's half diagonal
        for _, poly in self._room_polys:
            n = len(poly)
            for i in range(n):
                (ax, ay), (bx, by) = poly[i], poly[(i + 1) % n]
                dx, dy = bx - ax, by - ay
                dd = dx * dx + dy * dy
                t = 0.0 if dd < 1e-18 else min(1.0, max(0.0, ((cx - ax) * dx + (cy - ay) * dy) / dd))
                if math.hypot(cx - (ax + t * dx), cy - (ay + t * dy)) <= clear:
                    return _MIXED
        return self._room_exact(cx, cy)

    def walk_grid(self, clearance: float = WALKER_RADIUS) -> Grid:
        """The occupancy grid people plan their walks on (built once per clearance)."""
        grid = self._grids.get(clearance)
        if grid is None:
            grid = self._grids[clearance] = Grid.for_scenario(self.scenario, clearance=clearance)
        return grid

    def exit_points(self, door: str | None = None) -> tuple[tuple[float, float], tuple[float, float]]:
        """(inside, outside) points straight through an exit door, clear of the wall (the first exit when None)."""
        for wall, d in self.scenario.exits():
            if door is not None and d.name != door:
                continue
            p1, p2 = door_sides(wall, d)
            return (p1, p2) if self.room_of(*p1) is not None else (p2, p1)
        raise KeyError(f"no exit door named {door!r}" if door else "the flat has no exit door")

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the rooms and walls."""
        return scenario_bounds(self.scenario)


def table_legs(f: Furniture) -> list[np.ndarray]:
    """Square legs (side ``f.leg``) just inside each corner of a raised piece."""
    poly = np.array(f.polygon, dtype=float)
    cx, cy = polygon_centroid(poly)
    legs = []
    h = f.leg / 2
    for vx, vy in poly:
        d = np.array([cx - vx, cy - vy])
        n = float(np.hypot(*d))
        ux, uy = (d / n) if n > 1e-9 else (0.0, 0.0)
        # Inset so the square lies inside the top (diagonal of the square is leg*sqrt2).
        px, py = vx + ux * f.leg * 1.5, vy + uy * f.leg * 1.5
        legs.append(np.array([[px - h, py - h], [px + h, py - h], [px + h, py + h], [px - h, py + h]]))
    return legs

