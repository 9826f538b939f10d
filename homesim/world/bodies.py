"""The moving bodies of the world: the PeopleBot and the people.

The robot is a dynamic pymunk body driven like a differential-drive base:
each physics step sets its velocity from the commanded (v, omega), limited
in speed and acceleration, and the contact solver stops it at walls,
furniture and people. People are kinematic bodies (their scripts move
them): a collision circle for the body and two leg circles that swing in an
alternating gait while they walk; only the legs reach the laser's height.
Head direction is separate from body direction. A kinematic body would
shove the robot (it has infinite mass), so the world holds a person back
rather than let a step bump into the robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from . import chipmunk as cp
from ..geometry import wrap_angle

# Shape categories (bit masks) for collision filtering and queries.
CAT_WALL = 1
CAT_FURNITURE = 2
CAT_ROBOT = 4
CAT_HUMAN = 8
CAT_LEGS = 16
CAT_LASER = 32  # added to every shape that reaches the laser's height
CAT_QUERY = 64  # the category of geometry queries (shapes that only queries may find mask this in)
LASER_FILTER = pymunk.ShapeFilter(categories=CAT_QUERY, mask=CAT_LASER)

# PeopleBot: footprint 0.51 m long, 0.43 m wide (radius about 0.30 m).
ROBOT_LENGTH = 0.51
ROBOT_WIDTH = 0.43
ROBOT_RADIUS = 0.30
ROBOT_REACH = math.hypot(0.51 / 2, 0.43 / 2) + 0.01  # the footprint's bounding circle (0.34 m)
LASER_OFFSET = 0.13  # laser at the front, metres ahead of the centre
LASER_HEIGHT = 0.30
CAMERA_HEIGHT = 1.41
MIC_HEIGHT = 1.06
MIC_SPACING = 0.281
MIC_OFFSET = 0.10  # microphones at the front of the upper platform

# People.
HUMAN_RADIUS = 0.25
LEG_RADIUS = 0.06
LEG_SPREAD = 0.10  # lateral offset of each leg from the body centre
STRIDE = 0.6  # metres per full gait cycle
HEAD_LIMIT = math.radians(80)  # how far a head turns from the body's direction


class RobotBody:
    """The PeopleBot base in the world: commanded velocities in, pose out."""

    def __init__(self, space: pymunk.Space, x: float, y: float, heading: float, *, max_speed: float = 0.5, max_turn: float = math.radians(100)) -> None:
        self.max_speed = max_speed
        self.max_turn = max_turn
        self.max_accel = 1.0  # m/s^2
        self.max_turn_accel = math.radians(300)  # rad/s^2
        self.body = pymunk.Body(40.0, math.inf)
        self.body.position = (x, y)
        self.body.angle = heading
        hw, hl = ROBOT_WIDTH / 2, ROBOT_LENGTH / 2
        self.shape = pymunk.Poly(self.body, [(-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw)], radius=0.01)
        self.shape.filter = pymunk.ShapeFilter(categories=CAT_ROBOT)
        self.shape.friction = 0.0
        self.shape.collision_type = CAT_ROBOT
        space.add(self.body, self.shape)
        self.cmd_v = 0.0
        self.cmd_w = 0.0
        self.v = 0.0
        self.w = 0.0
        self.odometer = 0.0  # metres actually travelled
        self.in_contact = False
        self._pose: tuple[float, float, float] | None = None  # kept until the body moves

    @property
    def pose(self) -> tuple[float, float, float]:
        """(x, y, heading): read from Chipmunk once after each move (ground truth, metrics and
        sensors ask several times a step); whatever moves the body calls :meth:`moved`."""
        pose = self._pose
        if pose is None:
            x, y = cp.position(self.body)
            pose = self._pose = (x, y, float(wrap_angle(cp.angle(self.body))))
        return pose

    def moved(self) -> None:
        """The body was moved (a step, a push, a placement): :attr:`pose` reads it afresh."""
        self._pose = None

    def command(self, v: float, w: float) -> None:
        """Set the wanted forward speed (m/s) and turn rate (rad/s); limits apply.

        ``min``/``max`` give what ``np.clip`` gave (NaN stays NaN, -0.0 stays -0.0) without
        its cost on one number.
        """
        a, b = self.max_speed, self.max_turn
        self.cmd_v = float(min(max(v, -a), a))
        self.cmd_w = float(min(max(w, -b), b))

    def before_step(self, dt: float) -> float:
        """Set the body's velocities from the command (acceleration-limited); returns its angle."""
        a, b = self.max_accel * dt, self.max_turn_accel * dt
        self.v += min(max(self.cmd_v - self.v, -a), a)
        self.w += min(max(self.cmd_w - self.w, -b), b)
        body = self.body
        th = cp.angle(body)
        v = self.v
        cp.set_velocity(body, v * math.cos(th), v * math.sin(th))
        cp.set_angular_velocity(body, self.w)
        return th

    def after_step(self, dt: float, before: tuple[float, float], after: tuple[float, float] | None = None) -> None:
        """Odometry and the wheels' real speed from the move ``before`` -> ``after`` (read when None)."""
        px, py = cp.position(self.body) if after is None else after
        moved = math.hypot(px - before[0], py - before[1])
        self.odometer += moved
        # What the base really achieved (a wall stops it): the wheels follow.
        if dt > 0 and moved < abs(self.v) * dt * 0.5:
            self.v = math.copysign(moved / dt, self.v) if self.v else 0.0

    def world_point(self, forward: float, left: float = 0.0) -> tuple[float, float]:
        x, y, th = self.pose
        c, s = math.cos(th), math.sin(th)
        return x + c * forward - s * left, y + s * forward + c * left


@dataclass
class Pointing:
    """A person's pointing gesture: the arm from the shoulder to ``target`` (x, y, z)."""

    target_name: str
    target: tuple[float, float, float]
    until: float


class HumanBody:
    """A scripted person in the world: position, body and head direction, legs.

    Scripts call :meth:`walk_velocity` (or :meth:`stand`) and set
    :attr:`head`; the world calls :meth:`advance` after each physics step
    to move the gait. ``present`` turns False when the person has left.
    """

    def __init__(self, space: pymunk.Space, name: str, x: float, y: float, heading: float, *, height: float, torso: tuple[float, float, float], speed: float,
                 order: int = 0) -> None:
        self.name = name
        self.order = order  # her place in the scenario's list of people: who goes first in a tie (never her name)
        self.height = height
        self.torso = torso
        self.speed = speed
        self.heading = heading
        self.head = 0.0  # head yaw relative to the body
        self.phase = 0.0
        self.gait_amp = 0.0
        self.present = True
        self.pointing: Pointing | None = None
        self.walk = (0.0, 0.0)  # the velocity the script wants; the world may hold the person back
        self.walk_speed = 0.0  # its size
        self.velocity = (0.0, 0.0)  # the body's velocity as last set (a kinematic body keeps it)
        self.held = False  # the last step was refused (the robot was in the way)
        self.held_time = 0.0  # seconds spent held back, in total
        self.crowded = False  # the last step was refused (another person was in the way)
        self.crowded_time = 0.0  # seconds spent held back by other people, in total
        self.space = space
        self._xy: tuple[float, float] | None = None  # the position, kept until the body moves
        self._placed: tuple[float, float] | None = None  # (heading, swing) last set on the body and legs
        self.body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.body.position = (x, y)
        self.shape = pymunk.Circle(self.body, HUMAN_RADIUS)
        self.shape.filter = pymunk.ShapeFilter(categories=CAT_HUMAN, mask=CAT_ROBOT)
        self.shape.collision_type = CAT_HUMAN
        self.legs = [pymunk.Circle(self.body, LEG_RADIUS, (0.0, s * LEG_SPREAD)) for s in (1.0, -1.0)]
        for leg in self.legs:
            leg.sensor = True
            leg.filter = pymunk.ShapeFilter(categories=CAT_LEGS | CAT_LASER, mask=CAT_QUERY)
        space.add(self.body, self.shape, *self.legs)
        self.leg_offsets = ((0.0, LEG_SPREAD), (0.0, -LEG_SPREAD))  # as last set on the leg shapes
        # What _place_legs calls every step, bound once.
        self._set_angle = cp.angle_setter(self.body)
        self._set_legs = (cp.offset_setter(self.legs[0]), cp.offset_setter(self.legs[1]))
        self._reindex = cp.reindexer(space, self.body)
        self._place_legs()

    # ------------------------------------------------------------ state
    @property
    def position(self) -> tuple[float, float]:
        """(x, y), read from Chipmunk once after each move (the world calls :meth:`moved` after a step)."""
        xy = self._xy
        if xy is None:
            xy = self._xy = cp.position(self.body)
        return xy

    def moved(self) -> None:
        """The body was moved (a physics step, a push): :attr:`position` reads it afresh."""
        self._xy = None

    @property
    def pose(self) -> tuple[float, float, float]:
        x, y = self.position
        return x, y, self.heading

    @property
    def gaze(self) -> float:
        """World direction the face looks towards."""
        return float(wrap_angle(self.heading + self.head))

    @property
    def face_z(self) -> float:
        return self.height - 0.12

    @property
    def shoulder_z(self) -> float:
        return self.height * 0.82

    @property
    def torso_z(self) -> float:
        return self.height * 0.7

    def face_point(self) -> tuple[float, float, float]:
        x, y = self.position
        return x, y, self.face_z

    def hand_point(self) -> tuple[float, float, float] | None:
        """Where the pointing hand is (0.6 m along the arm), or None."""
        if self.pointing is None:
            return None
        x, y = self.position
        sx, sy, sz = x, y, self.shoulder_z
        tx, ty, tz = self.pointing.target
        d = np.array([tx - sx, ty - sy, tz - sz])
        n = float(np.linalg.norm(d))
        if n < 1e-9:
            return sx, sy, sz
        d *= 0.6 / n
        return sx + d[0], sy + d[1], sz + d[2]

    def leg_centres(self) -> np.ndarray:
        """World positions (2, 2) of the two legs."""
        x, y = self.position
        c, s = math.cos(self.heading), math.sin(self.heading)
        (ox0, oy0), (ox1, oy1) = self.leg_offsets
        return np.array(((x + c * ox0 - s * oy0, y + s * ox0 + c * oy0), (x + c * ox1 - s * oy1, y + s * ox1 + c * oy1)))

    # ---------------------------------------------------------- motion
    def walk_velocity(self, vx: float, vy: float) -> None:
        """Walk with this world velocity (from the next step); the body turns to the walking direction.

        The world applies it step by step and holds the person back
        instead when the step would bump into the robot.
        """
        self.walk = (float(vx), float(vy))
        self.walk_speed = math.hypot(*self.walk)
        self.set_velocity(*self.walk)
        if vx * vx + vy * vy > 1e-8:
            self.heading = math.atan2(vy, vx)

    def stand(self) -> None:
        self.walk = (0.0, 0.0)
        self.walk_speed = 0.0
        self.set_velocity(0.0, 0.0)

    def set_velocity(self, vx: float, vy: float) -> None:
        """Set the body's velocity (the only way it changes: nothing pushes a kinematic body)."""
        if (vx, vy) != self.velocity:
            self.velocity = (vx, vy)
            cp.set_velocity(self.body, vx, vy)

    def turn_to(self, heading: float) -> None:
        self.heading = float(wrap_angle(heading))

    def look(self, world_direction: float) -> None:
        """Turn the head towards a world direction (the body follows beyond the head's limit)."""
        rel = float(wrap_angle(world_direction - self.heading))
        if abs(rel) > HEAD_LIMIT:
            self.heading = float(wrap_angle(world_direction - math.copysign(HEAD_LIMIT, rel)))
            rel = math.copysign(HEAD_LIMIT, rel)
        self.head = rel

    def teleport(self, x: float, y: float) -> None:
        self.body.position = (x, y)
        self._xy = None
        self.space.reindex_shapes_for_body(self.body)

    def advance(self, dt: float) -> None:
        """After a physics step: move the gait by the distance walked.

        Standing still (no velocity) the phase stays where it is (``phase + 0.0`` is
        ``phase``), so it is not recomputed; the swing still decays.
        """
        vx, vy = self.velocity
        if vx or vy:
            speed = math.hypot(vx, vy)
            self.phase = (self.phase + 2 * math.pi * speed * dt / STRIDE) % (2 * math.pi)
            target_amp = STRIDE / 4 * min(1.0, speed / 0.4)
        else:
            target_amp = 0.0  # STRIDE / 4 * min(1.0, 0.0 / 0.4)
        self.gait_amp += (target_amp - self.gait_amp) * min(1.0, 8.0 * dt)
        self._place_legs()

    def _place_legs(self) -> None:
        """Turn the body frame to the heading and swing the legs in it (both only when they
        changed: setting the same angle or offset again gives Chipmunk the same state)."""
        heading = self.heading
        swing = self.gait_amp * math.sin(self.phase)
        placed = self._placed
        if placed is None or placed[0] != heading or heading == 0.0:  # 0.0: a -0.0 the step made +0.0 is set again
            self._set_angle(heading)
        if placed is None or placed[1] != swing or swing == 0.0:
            offsets = self.leg_offsets = ((swing, LEG_SPREAD), (-swing, -LEG_SPREAD))
            left, right = self._set_legs
            left(offsets[0])
            right(offsets[1])
        self._placed = (heading, swing)
        if self.present:
            self._reindex()

    def remove(self) -> None:
        """Leave the world (walked out of the flat)."""
        if self.present:
            self.space.remove(self.body, self.shape, *self.legs)
            self.present = False
            self.pointing = None
