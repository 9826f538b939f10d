"""The few Chipmunk calls the physics step makes on every body, without pymunk's Python layer.

pymunk is the physics (DESIGN); its attribute properties (``body.position``,
``body.velocity = ...``) each cost a microsecond or two of Python wrapping
(a ``Vec2d``, an assert, a ``__setattr__`` mixin) around one call into
Chipmunk. The world step makes about fifteen such accesses per body at
50 Hz, so the step calls pymunk's own cffi binding of Chipmunk directly for
them: the same C functions, with the same arguments, in the same order, so
the simulation is bit-identical. If pymunk ever stops shipping that binding
(``pymunk._chipmunk_cffi``), the functions fall back to the public
properties: slower, same results.
"""

from __future__ import annotations

import pymunk

try:  # pymunk >= 6: the cffi module every pymunk class calls into
    from pymunk._chipmunk_cffi import lib as _lib
except ImportError:  # a pymunk without it: the public API
    _lib = None

_FUNCTIONS = ("cpBodyGetPosition", "cpBodySetPosition", "cpBodyGetAngle", "cpBodySetAngle", "cpBodySetVelocity",
              "cpBodySetAngularVelocity", "cpCircleShapeSetOffset", "cpSpaceReindexShapesForBody")


def _binding_usable() -> bool:
    """Every function and every handle (``_body``, ``_shape``, ``_space``) the direct calls use is there:
    a pymunk that renamed or dropped any of them gets the public properties, not an AttributeError."""
    if _lib is None or not all(hasattr(_lib, f) for f in _FUNCTIONS):
        return False
    try:
        body = pymunk.Body()
        return all(hasattr(o, a) for o, a in ((body, "_body"), (pymunk.Circle(body, 1.0), "_shape"), (pymunk.Space(), "_space")))
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


__all__ = ["DIRECT", "position", "set_position", "angle", "set_angle", "set_velocity",
           "set_angular_velocity", "set_circle_offset", "reindex"]
