"""The PeopleBot's footprint and the one rule every module that moves the base keeps to people.

Three modules send ``/robot/base/cmd``: the follower, the player (go-to) and person attention
(turning on the spot to the person it attends to, or to a voice). A command is safe for people
only if the footprint it sweeps keeps clear of every body the robot knows of, whichever module
sent it, so the rule lives here, beside the contract, and each of them calls it
(:func:`people_sweep_clear`, :func:`turn_clear`). Bodies are robot-frame centres with a
:data:`BODY` m radius round each (the laser sees legs, the body is wider).

Pure code, no bus, no state.
"""

from __future__ import annotations

import math

import numpy as np

#: The PeopleBot's footprint: half length and half width (m), centred on the base.
HALF_LENGTH = 0.51 / 2
HALF_WIDTH = 0.43 / 2
#: m: the air the robot keeps between its footprint and a tracked person's body when it can help
#: it: an arc that drives and would come closer within its whole horizon is inadmissible, unless it
#: does not bring the robot any closer than it is (so a person who walks up to the robot is never
#: fled into something, and waiting is always allowed). Head-on that is a stop about 0.76 m from
#: the person's centre, 0.25 m of air in front of the bumper; passing beside someone, 0.72 m centre
#: to centre (issue 26: yield, stop at a safe distance, never touch). Turning on the spot is
#: exempt in the dynamic window (it brings nobody nearer the robot's centre); the turns each module
#: sends outside the window are held to :func:`turn_clear`.
SOCIAL_GAP = 0.25
#: m: a person's body radius round their tracked centre (the laser sees their legs).
BODY = 0.25
#: m: a turn on the spot keeps the footprint's corners this far from a person's body.
TURN_GAP = 0.05
#: m and rad: the largest step of a command's sweep between the poses :func:`people_sweep_clear` checks
#: (a corner 0.33 m out moves under 2 cm per 0.05 rad)
SWEEP_STEP = 0.02
SWEEP_TURN_STEP = 0.05


def footprint_distance(px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Distance from points (in a pose's frame) to the footprint rectangle (0 inside)."""
    dx = np.maximum(np.abs(px) - HALF_LENGTH, 0.0)
    dy = np.maximum(np.abs(py) - HALF_WIDTH, 0.0)
    return np.hypot(dx, dy)


def arcs(v: np.ndarray, w: np.ndarray, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Poses (x, y, theta), each (len(v), len(times)), along constant-(v, w) arcs from the origin."""
    vv, ww, tt = v[:, None], w[:, None], times[None, :]
    th = ww * tt
    small = np.abs(ww) < 1e-6
    safe_w = np.where(small, 1.0, ww)
    x = np.where(small, vv * tt, vv / safe_w * np.sin(th))
    y = np.where(small, 0.0, vv / safe_w * (1.0 - np.cos(th)))
    return x, y, th


def people_sweep_clear(v: float, w: float, people: np.ndarray, *, duration: float, gap: float = SOCIAL_GAP) -> bool:
    """Whether the footprint swept by (``v``, ``w``) held ``duration`` s keeps ``gap`` m from every body
    (``people``: (P, 2) robot-frame centres), or, from a body closer than that already, no nearer than now.

    Per body, and with poses as dense as the sweep needs at any turn rate (:data:`SWEEP_STEP`,
    :data:`SWEEP_TURN_STEP`): the dynamic window's six poses over 1.6 s are 0.45 rad apart at
    1.4 rad/s, and it exempts turns on the spot, so its give-way command swung a corner into the
    partner 0.6-0.9 m away (u_catch_up_slow seed 5). Standing still is always clear."""
    if not len(people) or (v == 0.0 and w == 0.0):
        return True
    n = max(5, math.ceil(abs(w) * duration / SWEEP_TURN_STEP), math.ceil(abs(v) * duration / SWEEP_STEP))
    x, y, th = arcs(np.array([v]), np.array([w]), np.linspace(0.0, duration, n + 1))
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = people[None, :, 0] - x[0][:, None], people[None, :, 1] - y[0][:, None]
    gaps = footprint_distance(c * dx + s * dy, -s * dx + c * dy) - BODY  # (n + 1, P); row 0 is now
    return bool(np.all(gaps.min(axis=0) >= np.minimum(gaps[0], gap) - 1e-3))


def turn_clear(w: float, people: np.ndarray, *, duration: float) -> bool:
    """Whether turning on the spot at ``w`` rad/s for ``duration`` s keeps the footprint's corners
    :data:`TURN_GAP` from every body (``people``: (P, 2) robot-frame centres), or no nearer than now."""
    # per body: someone already pressed against it (or a track misplaced onto it) must not make a
    # turn into anyone else clear (a global minimum did: cross_studio_four seed 0, a corner swung
    # into a man held up beside it while a ghost track lay on the robot); at poses dense enough for
    # the turn rate (six over 0.5 s let a corner move 6 cm between them at 1.75 rad/s)
    return people_sweep_clear(0.0, w, people, duration=duration, gap=TURN_GAP)


def sweep_poses(v: float, w: float, duration: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The poses (x, y, theta), each (n + 1,), at which a sweep of (``v``, ``w``) held ``duration`` s is checked:
    as dense as :data:`SWEEP_STEP` and :data:`SWEEP_TURN_STEP` ask, the start (now) first."""
    n = max(5, math.ceil(abs(w) * duration / SWEEP_TURN_STEP), math.ceil(abs(v) * duration / SWEEP_STEP))
    x, y, th = arcs(np.array([v]), np.array([w]), np.linspace(0.0, duration, n + 1))
    return x[0], y[0], th[0]


def points_sweep_clear(v: float, w: float, points: np.ndarray, *, duration: float, gap: float) -> bool:
    """Whether the footprint swept by (``v``, ``w``) held ``duration`` s keeps ``gap`` m from every one of
    ``points`` (robot frame: the laser's echoes), or comes no nearer to them than it is now."""
    if not len(points) or (v == 0.0 and w == 0.0):
        return True
    x, y, th = sweep_poses(v, w, duration)
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    dx, dy = points[None, :, 0] - x[:, None], points[None, :, 1] - y[:, None]
    d = footprint_distance(c * dx + s * dy, -s * dx + c * dy).min(axis=1)  # (n + 1,): the nearest echo per pose
    return bool(d.min() >= min(float(d[0]), gap) - 1e-3)


#: m: the footprint's outline is checked against the floor plan at points this far apart
OUTLINE_STEP = 0.05


def outline() -> np.ndarray:
    """(K, 2) points round the footprint's edge (robot frame), :data:`OUTLINE_STEP` m apart or closer, corners included."""
    nx, ny = math.ceil(2 * HALF_LENGTH / OUTLINE_STEP), math.ceil(2 * HALF_WIDTH / OUTLINE_STEP)
    xs, ys = np.linspace(-HALF_LENGTH, HALF_LENGTH, nx + 1), np.linspace(-HALF_WIDTH, HALF_WIDTH, ny + 1)
    return np.concatenate((np.column_stack((xs, np.full_like(xs, HALF_WIDTH))), np.column_stack((xs, np.full_like(xs, -HALF_WIDTH))),
                           np.column_stack((np.full_like(ys[1:-1], HALF_LENGTH), ys[1:-1])),
                           np.column_stack((np.full_like(ys[1:-1], -HALF_LENGTH), ys[1:-1]))))


#: s: from the scan that shows someone walking into the robot's way until it brakes (a track's
#: velocity lags a scan or two; the command loop runs at 10 Hz)
CONTACT_REACT = 0.2
#: m: the air left between the footprint and the predicted body of someone walking into its way once
#: the robot stands: their personal space (:data:`SOCIAL_GAP`), not only their body
CONTACT_GAP = SOCIAL_GAP
#: m: ... and of someone standing (the dynamic window keeps its gap to them where it can, and passes
#: someone standing beside its way slowly at less: only never driven at)
CONTACT_GAP_STANDING = 0.10
#: s: people are predicted this long beyond the robot's own stop (they walk on while it brakes, and a
#: little after: stopping in front of someone who then walks into it is no yield)
CONTACT_AFTER = 0.3
#: m/s: someone slower than this stands (is only not driven nearer when already close)
CONTACT_STILL = 0.2
#: m/s: the speeds tried, this far apart (the limit is one of them, or ``max_speed``)
CONTACT_STEP = 0.025


def contact_speed_limit(people: np.ndarray, max_speed: float, *, decel: float, w: float = 0.0, dw: float = 0.0,
                        react: float = CONTACT_REACT, gap: float = CONTACT_GAP, still_gap: float = CONTACT_GAP_STANDING,
                        after: float = CONTACT_AFTER) -> float:
    """:func:`contact_speed_limit_on_arc` for every turn rate the robot can reach in one step: the least of the
    limits at ``w - dw``, ``w`` and ``w + dw`` (review18 F4: the dynamic window picks any turn rate within
    ``dw`` of the present one, and one of them may turn toward someone). ``dw`` = 0: the present arc only."""
    lim = contact_speed_limit_on_arc(people, max_speed, decel=decel, w=w, react=react, gap=gap, still_gap=still_gap, after=after)
    if dw > 0.0 and lim > 0.0:
        for wr in (w - dw, w + dw):
            lim = min(lim, contact_speed_limit_on_arc(people, lim, decel=decel, w=wr, react=react, gap=gap,
                                                      still_gap=still_gap, after=after))
    return lim


def contact_speed_limit_on_arc(people: np.ndarray, max_speed: float, *, decel: float, w: float = 0.0,
                               react: float = CONTACT_REACT, gap: float = CONTACT_GAP, still_gap: float = CONTACT_GAP_STANDING,
                               after: float = CONTACT_AFTER) -> float:
    """The highest forward speed (m/s, at most ``max_speed``) from which the robot, driving on ``react`` s
    along the arc of turn rate ``w`` and then braking straight at ``decel`` m/s^2, keeps ``gap`` m of air
    (``still_gap`` to someone standing, slower than :data:`CONTACT_STILL`) between its footprint and every
    body at every instant until it stands (and ``after`` s more), each person walking on at their measured velocity (``people``: (K, 4) robot-frame centres and velocities;
    bodies :data:`BODY` round them) -- or, from someone standing that close already, no less air than
    standing leaves; someone walking ahead of its centre who comes within ``gap`` even of the standing robot,
    it stands for (0).

    Every speed from 0 up to the limit is safe, not only the limit (no racing ahead of a child darting
    across: the robot stops before his predicted path instead). Time to contact, not distance: someone
    walking away ahead, or past well clear, does not slow it; someone walking at its path does, early
    (corr_hallway_crossing: a boy running out of a side door 1 m ahead across a 1.1 m hallway was met
    at 0.45 m/s, the follower slowing only 0.25 s before it touched him). Pure, deterministic."""
    if not len(people) or max_speed <= 0.0:
        return max(max_speed, 0.0)
    speeds = np.arange(0.0, max_speed + 1e-9, CONTACT_STEP)
    if speeds[-1] < max_speed - 1e-9:
        speeds = np.append(speeds, max_speed)
    horizon = react + max_speed / decel + after
    times = np.linspace(0.0, horizon, max(8, math.ceil(horizon / 0.05)) + 1)
    # the robot's travel and heading at each time, per speed: on at v for react s (turning at w), then braking
    v, t = speeds[:, None], times[None, :]
    t_on = np.minimum(t, react)
    t_brake = np.clip(t - react, 0.0, v / decel)
    th_end = w * t_on
    small = abs(w) < 1e-6
    x_on = v * t_on if small else v / w * np.sin(th_end)
    y_on = np.zeros_like(x_on) if small else v / w * (1.0 - np.cos(th_end))
    s_brake = v * t_brake - 0.5 * decel * t_brake ** 2
    x = x_on + s_brake * np.cos(th_end)
    y = y_on + s_brake * np.sin(th_end)
    c, s = np.cos(th_end), np.sin(th_end)
    # (S, T, K): each person's predicted centre in the robot's pose at that time
    px = people[None, None, :, 0] + people[None, None, :, 2] * t[..., None] - x[..., None]
    py = people[None, None, :, 1] + people[None, None, :, 3] * t[..., None] - y[..., None]
    air = footprint_distance(c[..., None] * px + s[..., None] * py, -s[..., None] * px + c[..., None] * py) - BODY
    least = air.min(axis=1)  # (S, K): the least air to each person over the horizon
    walking = np.hypot(people[:, 2], people[:, 3]) > CONTACT_STILL
    gaps = np.where(walking, gap, still_gap)
    need = np.minimum(least[0], gaps) - 1e-3  # standing's own air, or the gap
    # someone walking, ahead of its centre, who comes within the gap even of the standing robot: it stands
    # for them (a yield), not edging on; someone behind it walking up is not helped by its standing, and a
    # person standing close beside it is only not driven nearer
    need = np.where(walking & (people[:, 0] > 0.0) & (least[0] < gaps), np.inf, need)
    ok = np.all(least >= need[None, :], axis=1)
    ok[0] = True
    bad = np.nonzero(~ok)[0]
    if not len(bad):
        return float(max_speed)
    return float(speeds[bad[0] - 1]) if bad[0] > 0 else 0.0
