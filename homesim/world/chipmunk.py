"""The few Chipmunk calls the physics step makes on every body, without pymunk's Python layer.

pymunk is the physics (the project's fixed choice); its attribute properties (``body.position``,
``body.velocity = ...``) each cost a microsecond or two of Python wrapping
(a ``Vec2d``, an assert, a ``__setattr__`` mixin) around one call into
Chipmunk. The world step makes about fifteen such accesses per body at
50 Hz (and a point query or two per person near the robot, and ``Space.step``
with its bookkeeping), so the step calls pymunk's own cffi binding of Chipmunk directly for
them: the same C functions, with the same arguments, in the same order, so
the simulation is bit-identical. If pymunk ever stops shipping that binding
(``pymunk._chipmunk_cffi``), the functions fall back to the public
properties: slower, same results.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import pymunk

try:  # pymunk >= 6: the cffi module every pymunk class calls into
    from pymunk._chipmunk_cffi import ffi as _ffi
    from pymunk._chipmunk_cffi import lib as _lib
except ImportError:  # a pymunk without it: the public API
    _ffi = _lib = None

_FUNCTIONS = ("cpBodyGetPosition", "cpBodySetPosition", "cpBodyGetAngle", "cpBodySetAngle", "cpBodySetVelocity",
              "cpBodySetAngularVelocity", "cpCircleShapeSetOffset", "cpSpaceReindexShapesForBody",
              "cpShapePointQuery", "cpSpaceStep")
#: What :func:`step` uses of pymunk's ``Space`` (the bookkeeping its ``step`` does around ``cpSpaceStep``).
_SPACE_FIELDS = ("_space", "_locked", "_removed_shapes", "_add_later", "_remove_later", "_post_step_callbacks",
                 "_bodies_to_check", "threaded", "_remove")


def _binding_usable() -> bool:
    """Every function and every handle (``_body``, ``_shape``, ``_space``) the direct calls use is there:
    a pymunk that renamed or dropped any of them gets the public properties, not an AttributeError."""
    if _lib is None or _ffi is None or not all(hasattr(_lib, f) for f in _FUNCTIONS):
        return False
    try:
        body = pymunk.Body()
        space = pymunk.Space()
        _ffi.new("cpPointQueryInfo *")
        return (all(hasattr(o, a) for o, a in ((body, "_body"), (pymunk.Circle(body, 1.0), "_shape")))
                and all(hasattr(space, a) for a in _SPACE_FIELDS))
    except Exception:  # noqa: BLE001 - any surprise in pymunk's internals: the public API
        return False


#: Whether the direct calls are in use (else the public properties).
DIRECT = _binding_usable()


if DIRECT:
    _get_pos = _lib.cpBodyGetPosition
    _set_pos = _lib.cpBodySetPosition
    _get_angle = _lib.cpBodyGetAngle
    _set_angle = _lib.cpBodySetAngle
    _set_vel = _lib.cpBodySetVelocity
    _set_angvel = _lib.cpBodySetAngularVelocity
    _set_offset = _lib.cpCircleShapeSetOffset
    _reindex = _lib.cpSpaceReindexShapesForBody
    _point_query = _lib.cpShapePointQuery
    _space_step = _lib.cpSpaceStep
    _query_info = _ffi.new("cpPointQueryInfo *")  # reused: the answer is read before the next query

    def position(body: pymunk.Body) -> tuple[float, float]:
        """The body's position (x, y) as plain floats."""
        v = _get_pos(body._body)
        return v.x, v.y

    def set_position(body: pymunk.Body, x: float, y: float) -> None:
        _set_pos(body._body, (x, y))

    def angle(body: pymunk.Body) -> float:
        return _get_angle(body._body)  # type: ignore[no-any-return]

    def set_angle(body: pymunk.Body, a: float) -> None:
        _set_angle(body._body, a)

    def set_velocity(body: pymunk.Body, vx: float, vy: float) -> None:
        _set_vel(body._body, (vx, vy))

    def set_angular_velocity(body: pymunk.Body, w: float) -> None:
        _set_angvel(body._body, w)

    def set_circle_offset(shape: pymunk.Circle, ox: float, oy: float) -> None:
        """What ``Circle.unsafe_set_offset`` does."""
        _set_offset(shape._shape, (ox, oy))

    def reindex(space: pymunk.Space, body: pymunk.Body) -> None:
        """What ``Space.reindex_shapes_for_body`` does."""
        _reindex(space._space, body._body)

    def angle_setter(body: pymunk.Body) -> Callable[[float], None]:
        """``set_angle`` bound to one body (one call, no Python frame: for what runs every step)."""
        return partial(_set_angle, body._body)

    def offset_setter(shape: pymunk.Circle) -> Callable[[tuple[float, float]], None]:
        """``set_circle_offset`` bound to one circle, taking the offset as a pair."""
        return partial(_set_offset, shape._shape)

    def reindexer(space: pymunk.Space, body: pymunk.Body) -> Callable[[], None]:
        """``reindex`` bound to one body of one space."""
        return partial(_reindex, space._space, body._body)

    def point_distance(shape: pymunk.Shape, x: float, y: float) -> float:
        """``shape.point_query((x, y)).distance``: signed distance from the point to the shape."""
        return _point_query(shape._shape, (x, y), _query_info)  # type: ignore[no-any-return]

    def step(space: pymunk.Space, dt: float) -> None:
        """What ``Space.step`` does: the same ``cpSpaceStep`` and the same bookkeeping around it
        (a space with bodies still to check, or threaded, goes through ``Space.step`` itself)."""
        if space._bodies_to_check or space.threaded:
            space.step(dt)
            return
        try:
            space._locked = True
            _space_step(space._space, dt)
            space._removed_shapes.clear()
        finally:
            space._locked = False
        if space._add_later or space._remove_later or space._post_step_callbacks:  # what callbacks asked for
            space.add(*space._add_later)
            space._add_later.clear()
            removed = set()
            while space._remove_later:
                to_remove, _ = space._remove_later.popitem()
                if to_remove not in removed:
                    removed.add(to_remove)
                    space._remove(to_remove)
            for key in space._post_step_callbacks:
                space._post_step_callbacks[key](space)
            space._post_step_callbacks.clear()

else:  # tests/test_world_fast_paths.py runs the world on these too

    def position(body: pymunk.Body) -> tuple[float, float]:
        p = body.position
        return float(p.x), float(p.y)

    def set_position(body: pymunk.Body, x: float, y: float) -> None:
        body.position = (x, y)

    def angle(body: pymunk.Body) -> float:
        return float(body.angle)

    def set_angle(body: pymunk.Body, a: float) -> None:
        body.angle = a

    def set_velocity(body: pymunk.Body, vx: float, vy: float) -> None:
        body.velocity = (vx, vy)

    def set_angular_velocity(body: pymunk.Body, w: float) -> None:
        body.angular_velocity = w

    def set_circle_offset(shape: pymunk.Circle, ox: float, oy: float) -> None:
        shape.unsafe_set_offset((ox, oy))

    def reindex(space: pymunk.Space, body: pymunk.Body) -> None:
        space.reindex_shapes_for_body(body)

    def angle_setter(body: pymunk.Body) -> Callable[[float], None]:
        return partial(set_angle, body)

    def offset_setter(shape: pymunk.Circle) -> Callable[[tuple[float, float]], None]:
        return shape.unsafe_set_offset

    def reindexer(space: pymunk.Space, body: pymunk.Body) -> Callable[[], None]:
        return partial(space.reindex_shapes_for_body, body)

    def point_distance(shape: pymunk.Shape, x: float, y: float) -> float:
        return float(shape.point_query((x, y)).distance)

    def step(space: pymunk.Space, dt: float) -> None:
        space.step(dt)


__all__ = ["DIRECT", "position", "set_position", "angle", "set_angle", "set_velocity",
           "set_angular_velocity", "set_circle_offset", "reindex", "point_distance", "step",
           "angle_setter", "offset_setter", "reindexer"]
