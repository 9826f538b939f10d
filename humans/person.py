"""A scripted person: walks (around obstacles), faces, points, talks, waits, leaves.

:class:`Person` drives one :class:`~homesim.world.bodies.HumanBody` through
its script. Walking plans a path on the world's occupancy grid and moves
the kinematic body along it in short legs (re-planned every half second
when the goal moves, e.g. walking up to the robot). Paths keep clear of the
robot where it stands; a person the robot gets in the way of is held back
by the world (never pushes it) and re-plans around it, or waits when the
robot blocks the only way. While walking the head looks ahead. ``face``
turns the head (the body follows beyond the head's reach) or, with
``body="true"``, the whole body. ``point`` raises an arm
towards the target for its duration. ``leave`` walks out through an exit
door and removes the person from the world. A walk whose goal walls or
furniture close off fails the run with a :class:`~humans.script.ScriptError`
naming the action's file and line; nobody walks through a wall.

Her :class:`~humans.profiles.Traits` set her voice level, the distance at
which she stops in front of the robot, her walking speed, how often she
speaks looking away from the robot (``off_axis``: she turns her head 60 to
150 degrees off it as she starts to speak) and how far her pointing misses
(the pointed-at point turned about her by a normal error of
``pointing_error`` degrees). Without a profile they are the scripted
person's: 60 dB, 0.9 m, the scenario's speed, always facing, exact.
"""

from __future__ import annotations

import asyncio
import math
import re

import numpy as np

from collections.abc import Callable

from homesim.scenario.model import Action, Face, Handler, HumanSpec, Leave, PointAt, Say, StepCloser, Target, WalkTo
from homesim.world.acoustics import Utterance
from homesim.world.bodies import HUMAN_RADIUS, ROBOT_REACH, HumanBody, Pointing
from homesim.world.raycast import line_of_sight
from homesim.scenario.pathplan import NoPathError
from homesim.world.world import World

from .profiles import Traits
from .script import Actor, ScriptError

ARRIVED = 0.05  # metres: close enough to a waypoint
LEG_TIME = 0.5  # seconds between re-planning checks while walking
ROBOT_STOP = 0.9  # default distance to keep from the robot when walking to it
HUMAN_STOP = 0.8  # default distance to keep from a person when walking to them (not on top of them)
#: A user (a person with a profile) held back by the robot this long (s) without a free step asks it
#: to make way ("Excuse me, could you let me pass?"), then to come along ("Follow me"), and at
#: BLOCKED_GIVE_UP gives the walk up her profile's way (skip: on with her script from where she
#: is; stop, leave), counted as giving up (``blocked_walks``). A scripted person without a
#: profile waits for the robot to move, as before (library scenarios time that themselves).
BLOCKED_ASKS = ((4.0, "make-way"), (12.0, "follow"))
BLOCKED_GIVE_UP = 25.0
#: Making way (the other direction): the nearest person standing in the robot's way (ahead of it within
#: PASS_NEAR m and PASS_LANE m of its axis, or beside it within PASS_BESIDE m, not behind) who hears it
#: ask to pass ("excuse me") or to step back ("Could you step back a little, please?", door25; not its "Am I in your way?") steps about PASS_STEP m aside, out of its lane, faces as before and carries
#: on with what she was doing (someone further on, the partner it follows, stays).
#: She listens every PASS_POLL s (a task of her own: her script's timing is untouched).
PASS_WORDS = re.compile(r"\bexcuse me\b|\bcould you step back\b", re.IGNORECASE)
PASS_NEAR = 1.6
PASS_LANE = 0.9
PASS_BESIDE = 1.2
PASS_STEP = 0.9
PASS_POLL = 0.5
#: m: a walk up to the robot or to a person ends only where nothing this high (a wall, a tall shelf) stands on the
#: straight line between them: who walks up to someone to talk stops where they see each other, never on the
#: other side of a wall at her distance (fresh10/hall_goto_music_room: he stopped in the hall 1.2 m from the robot
#: standing in the music room behind the wall, and greeted it through the wall, unseen, for the rest of the run)
SIGHT_HEIGHT = 1.0
#: Other people (the user simulation's walking among people; docs/users.md "Walking among people"). Her
#: paths keep PASS_GAP m between her body and anyone standing (centres 2 * HUMAN_RADIUS + PASS_GAP apart)
#: and the world never lets two bodies overlap (homesim.world.world.PEOPLE_APART). Someone walking towards
#: her within ONCOMING m is passed on her right, CLEAR / 2 right of where they meet (two discs to her left of that
#: point, KEEP_RIGHT apart): both go to their own right, side by side, never the mirror dance. A person within AHEAD m of her next leg's
#: line (closer than CLEAR of it) makes her plan again before she walks into her.
PASS_GAP = 0.1
ONCOMING = 2.5
KEEP_RIGHT = 0.6
AHEAD = 2.0
CLEAR = 2 * HUMAN_RADIUS + PASS_GAP
#: s held back by someone before she steps back out of the way of someone held back by her (the one of the
#: two listed later in the scenario, so exactly one does), YIELD_STEP m mostly aside (to her right) and a little back; she then waits at most YIELD_WAIT s for
#: them to pass before walking on. Held back by people CROWD_GIVE_UP s in all on one walk, she ends it where
#: she stands (as near as the people there allow), saying so in her log; but for leaving the flat, which she
#: never ends short (she would vanish mid-room): she waits at the door for the way to clear.
#: Someone whose way crosses hers (their closest approach within GIVE_WAY_HORIZON s, nearer than CLEAR; not
#: head-on, which KEEP_RIGHT settles) and who reaches the crossing first is let pass: she stands GIVE_WAY_STEP s
#: at a time (GIVE_WAY_MAX s at most in a row) and looks again. Who is first: the earlier arrival where the two
#: lines cross (within GIVE_WAY_TIE s: the one listed first in the scenario, never by name); walking the same way, the one ahead.
GIVE_WAY_HORIZON = 3.0
GIVE_WAY_STEP = 0.25
GIVE_WAY_MAX = 4.0
GIVE_WAY_TIE = 0.2
YIELD_AFTER = 1.5
YIELD_STEP = 0.7
YIELD_WAIT = 4.0
CROWD_GIVE_UP = 20.0


class Person(Actor):
    """Runs a :class:`~homesim.scenario.model.HumanSpec`'s script on its body."""

    def __init__(self, world: World, spec: HumanSpec, traits: Traits | None = None, rng: np.random.Generator | None = None,
                 streams: Callable[[str], np.random.Generator] | None = None) -> None:
        traits = traits if traits is not None else Traits()
        super().__init__(world, spec.name, spec.script, loudness=traits.voice, handlers=spec.handlers, traits=traits, rng=rng, streams=streams)
        self.spec = spec
        self.body: HumanBody = world.humans[spec.name]
        if traits.speed is not None:
            self.body.speed = traits.speed
        self._looked_away = False  # her head is turned away because she looked away as she spoke
        self.blocked_walks = 0  # walks she gave up because the robot stood in her way
        self.made_way = 0  # times she stepped out of the robot's way when it asked to pass
        self._stepping = False  # stepping aside for the robot: her script's next walk waits for it
        self._leaving = False  # walking out through an exit: the one walk that may end outside the flat
        self.yielded = 0  # times she stepped back out of someone's way
        self.crowd_stops = 0  # walks she ended short because people stood in her way
        self._walking_up = False  # this walk goes up to the robot or a person (a goal she does not choose)

    @property
    def active(self) -> bool:
        return self.body.present

    async def perform(self, act: Action) -> None:
        if not self.body.present:
            return
        try:
            if isinstance(act, WalkTo):
                await self.walk_to(act.target, stop_at=act.stop_at, speed=act.speed)
            elif isinstance(act, Face):
                self.face(act.target, body=act.body)
            elif isinstance(act, PointAt):
                await self.point(act)
            elif isinstance(act, Leave):
                await self.leave(act)
            elif isinstance(act, StepCloser):
                await self.step_closer(act)
            else:
                await super().perform(act)
        except NoPathError as exc:
            # Never a straight line through walls: the run fails, naming the action.
            self.body.stand()
            tag = {WalkTo: "walk-to", StepCloser: "step-closer"}.get(type(act), "leave")
            raise ScriptError(f"{self.name!r} at ({self.body.position[0]:.2f}, {self.body.position[1]:.2f}) cannot get there: {exc}", source=self.world.scenario.source,
                line=act.line, element=tag) from exc

    # ------------------------------------------------------------ making way
    async def courtesy(self) -> None:
        """Step out of the robot's way when it asks to pass (:data:`PASS_WORDS`), as people do:
        only she who stands (not walking) ahead of it in its lane (:meth:`in_the_way`)."""
        last = self.now
        while True:
            await asyncio.sleep(PASS_POLL)
            now = self.now
            asked = [u for u in self.world.sound.ended(last, now) if u.source == "robot" and PASS_WORDS.search(u.text)]
            last = now
            if asked and self.body.present and self.body.walk_speed < 1e-3 and not self._stepping:
                spot = self.in_the_way()
                if spot is not None:
                    await self.step_aside(spot)

    def in_the_way(self) -> tuple[float, float] | None:
        """Where she steps to if she stands in the robot's way (ahead of it, near its axis) and is the
        nearest there (the one it speaks to: someone further on, the partner it follows, stays):
        PASS_STEP m further out from its axis on her side, else None."""
        rx, ry, th = self.world.robot.pose
        x, y = self.body.position
        c, s = math.cos(th), math.sin(th)

        def lane(px: float, py: float) -> tuple[float, float] | None:
            a, lat = c * (px - rx) + s * (py - ry), -s * (px - rx) + c * (py - ry)
            ahead = 0.0 < a < PASS_NEAR and abs(lat) < PASS_LANE
            beside = a > -0.3 and math.hypot(a, lat) < PASS_BESIDE  # her space may wedge it against a jamb
            return (a, lat) if ahead or beside else None

        mine = lane(x, y)
        if mine is None:
            return None
        d = math.hypot(x - rx, y - ry)
        humans = getattr(self.world, "humans", {})
        for other in humans.values():
            if other is self.body or not other.present:
                continue
            ox, oy = other.position
            if lane(ox, oy) is not None and math.hypot(ox - rx, oy - ry) < d:
                return None  # someone nearer stands in its way: it asks them
        along, lateral = mine
        side = 1.0 if lateral >= 0 else -1.0
        return x - s * side * PASS_STEP, y + c * side * PASS_STEP

    async def step_aside(self, spot: tuple[float, float]) -> None:
        """Walk to ``spot`` (the free spot nearest it), turn back as she faced, carry on."""
        self._stepping = True
        heading, head = self.body.heading, self.body.head
        start = self.now
        try:
            self.log.append((start, start, f"steps aside for the robot to ({spot[0]:.2f}, {spot[1]:.2f})"))
            await self.walk_to(Target("point", x=spot[0], y=spot[1]), speed=min(self.body.speed, 0.6), aside=True)
            self.body.stand()
            self.body.turn_to(heading)
            self.body.head = head
            self.made_way += 1
        except NoPathError:
            self.body.stand()  # nowhere to go: she stays where she is
        finally:
            self._stepping = False

    # ------------------------------------------------------------ walking
    def goal_of(self, target: Target) -> tuple[float, float]:
        x, y, _ = self.world.target_point(target, who=self.name)
        return x, y

    async def walk_to(self, target: Target, *, stop_at: float = 0.0, speed: float | None = None, aside: bool = False) -> None:
        """:meth:`_walk_to`, knowing meanwhile whether she walks up to the robot or a person (a step aside
        inside such a walk is not one; the walk goes on as one after it)."""
        before, self._walking_up = self._walking_up, target.kind in ("robot", "human")
        try:
            await self._walk_to(target, stop_at=stop_at, speed=speed, aside=aside)
        finally:
            self._walking_up = before

    async def _walk_to(self, target: Target, *, stop_at: float = 0.0, speed: float | None = None, aside: bool = False) -> None:
        """Walk until within ``stop_at`` of the target (or at the nearest free spot).

        Raises NoPathError when walls or furniture close the goal off (the
        person never walks through them). A walk of her script waits while she steps out of the
        robot's way (``aside``: that step itself).
        """
        while self._stepping and not aside:
            await asyncio.sleep(PASS_POLL)
        speed = speed or self.body.speed
        if stop_at <= 0 and target.kind in ("robot", "human"):
            stop_at = self.traits.distance if target.kind == "robot" else HUMAN_STOP
        moving = target.kind in ("robot", "human")
        where = lambda: self.goal_of(target)  # noqa: E731
        if target.kind == "robot" and self.traits.approach:
            # she walks up to stand in front of it at her distance, on the line between them
            # (face to face, an F-formation), not to the free spot nearest its centre
            keep = stop_at
            where = lambda: self.approach_point(keep)  # noqa: E731
            stop_at = 0.0
        goal = where()
        path = self.plan(goal)
        blocked, asked = 0.0, 0  # seconds held back by the robot without a free leg; requests made
        crowded, crowd_total = 0.0, 0.0  # seconds held back by people: in a row, on this walk
        looked = False  # this leg's way was checked for people (walk_to plans round them once per leg)
        gave = 0.0  # seconds she has stood letting someone cross first
        while True:
            here = self.body.position
            sees = not moving or self.sees(self.goal_of(target))  # (a walk up to someone ends in sight of them)
            if math.hypot(goal[0] - here[0], goal[1] - here[1]) <= max(stop_at, ARRIVED) and sees:
                break
            if not path:
                if not moving and self._kept_short(goal, max(stop_at, ARRIVED)):
                    # short of her place only because people walk there (or will meet her there): she lets
                    # them pass and goes on (someone standing on it she ends beside, as near as they allow)
                    if crowd_total >= CROWD_GIVE_UP:
                        self._end_walk_short(here)
                        break
                    self.body.stand()
                    await asyncio.sleep(LEG_TIME)
                    crowd_total += LEG_TIME
                    path = self.plan(goal)
                    continue
                break
            wx, wy = path[0]
            dx, dy = wx - here[0], wy - here[1]
            dist = math.hypot(dx, dy)
            travel = dist
            if len(path) == 1 and stop_at > 0 and sees:
                # Stop short of the goal along the last leg (the last waypoint may
                # already be short of it: the free spot nearest to a goal inside
                # furniture or next to the robot).
                travel = dist - max(0.0, stop_at - math.hypot(goal[0] - wx, goal[1] - wy))
                if travel <= ARRIVED:
                    break
            if dist <= ARRIVED:
                path.pop(0)
                continue
            if not looked and self._someone_ahead(here, (wx, wy)):
                # someone stands or walks on her next leg: round them (a new plan keeps clear of people;
                # once per leg: when they close the only way she walks up to them and waits)
                looked = True
                path = self.plan(goal)
                continue
            looked = False
            if gave < GIVE_WAY_MAX and self._give_way(here, (dx / dist * speed, dy / dist * speed)):
                # someone crosses her way and gets there first: she lets them pass, then walks on
                self.body.stand()
                await asyncio.sleep(GIVE_WAY_STEP)
                gave += GIVE_WAY_STEP
                continue
            gave = 0.0
            t = min(LEG_TIME, travel / speed)
            t = max(t, self.world.dt)
            v = min(speed, travel / t)
            self.body.head = 0.0
            self.body.walk_velocity(v * dx / dist, v * dy / dist)
            held, crowd = self.body.held_time, self.body.crowded_time
            await asyncio.sleep(t)
            if self.handlers and not aside and await self.react():
                # she stopped to react (answer, point, step aside): on from where she is now
                goal = where()
                path = self.plan(goal)
                continue
            if moving:
                new_goal = where()
                if math.hypot(new_goal[0] - goal[0], new_goal[1] - goal[1]) > 0.2:
                    goal = new_goal
                    path = self.plan(goal)
                    continue
            if self.body.held_time > held:
                blocked += t
                if self.traits.profile and not aside and await self._blocked(blocked, asked):
                    return
                if self.traits.profile and asked < len(BLOCKED_ASKS) and blocked >= BLOCKED_ASKS[asked][0]:
                    asked += 1
                path = self.plan(goal)  # the robot got in the way: around it, or wait for it
            else:
                blocked = 0.0
            if self.body.crowded_time > crowd:
                # someone is in her way: round them, or wait; step back for someone who waits for her
                crowded += self.body.crowded_time - crowd
                crowd_total += self.body.crowded_time - crowd
                if crowd_total >= CROWD_GIVE_UP and not self._leaving:  # (leaving, she waits to get out: never gone mid-room)
                    self._end_walk_short(here)
                    break
                if crowded >= YIELD_AFTER and not aside:
                    t0 = self.now
                    if await self._make_room():
                        crowded = 0.0
                        crowd_total += self.now - t0  # stepping back and waiting count as held back
                        goal = where()
                path = self.plan(goal)
            else:
                crowded = 0.0
        self.body.stand()

    def _end_walk_short(self, here: tuple[float, float]) -> None:
        """Count and log a walk given up because people stand in her way (the study counts these)."""
        self.crowd_stops += 1
        self.log.append((self.now, self.now, f"ends her walk at ({here[0]:.2f}, {here[1]:.2f}): people stand in her way"))

    async def _blocked(self, blocked: float, asked: int) -> bool:
        """Held back ``blocked`` s: ask the robot to make way / come along, or give the walk up (True)."""
        if blocked >= BLOCKED_GIVE_UP:
            self.body.stand()
            self.blocked_walks += 1
            await self.give_up(self.traits.give_up, "the robot blocks her way")
            return True
        if asked < len(BLOCKED_ASKS) and blocked >= BLOCKED_ASKS[asked][0]:
            self.body.stand()
            self.face_robot()
            await self.say(Say(None, request=BLOCKED_ASKS[asked][1]))
            await self.finish_speaking()
        return False

    def approach_point(self, distance: float) -> tuple[float, float]:
        """The point ``distance`` from the robot on the line from it to her (where she is when nearer; the robot's
        own place while that point lies behind a wall from it: :meth:`sees`).

        In an L-shaped flat that line can cut the inner corner, and the point fall outside the flat:
        then the robot's own place, whose nearest free spot inside the flat her walk ends at
        (:meth:`homesim.scenario.pathplan.Grid.plan`), never one beyond the outer wall."""
        rx, ry, _ = self.world.robot.pose
        hx, hy = self.body.position
        d = math.hypot(hx - rx, hy - ry)
        if d <= distance:
            x, y = hx, hy
        else:
            x, y = rx + (hx - rx) * distance / d, ry + (hy - ry) * distance / d
        if self.world.room_of(x, y) is None and self.world.room_of(rx, ry) is not None:
            return rx, ry
        if not self.sees((rx, ry), (x, y)):
            # that point lies behind a wall from the robot (it stands in a room, she comes along the hall
            # outside): towards the robot itself, round through the door, until the point is in its sight
            return rx, ry
        return x, y

    def sees(self, point: tuple[float, float], here: tuple[float, float] | None = None) -> bool:
        """Whether nothing :data:`SIGHT_HEIGHT` high (walls, tall furniture) stands on the straight line from
        ``here`` (where she stands) to ``point``: whom she walks up to she stops in sight of."""
        a, b = self.world.segments_at(SIGHT_HEIGHT)
        if not len(a):
            return True
        origin = self.body.position if here is None else here
        return bool(line_of_sight(origin, np.array([point], dtype=float), a, b)[0])

    def _kept_short(self, goal: tuple[float, float], near: float) -> bool:
        """Whether her walk ended short of ``goal`` only because of people walking: nearer than ``near`` to it
        she is not, nobody stands within CLEAR of it, and without the people's discs her path would take her
        nearer to it."""
        x, y = self.body.position
        d = math.hypot(goal[0] - x, goal[1] - y)
        if d <= near + 0.05:
            return False
        for o in self.others():
            if o.walk_speed < 1e-3 and math.hypot(o.position[0] - goal[0], o.position[1] - goal[1]) < CLEAR + 0.05:
                return False
        try:
            end = self.plan(goal, people=False)[-1]
        except NoPathError:
            return False
        return math.hypot(goal[0] - end[0], goal[1] - end[1]) < d - 0.05

    def plan(self, goal: tuple[float, float], *, people: bool = True) -> list[tuple[float, float]]:
        """A path to ``goal`` around walls, furniture and the robot where it stands now.

        When the robot blocks the only way (it stands in a doorway) the path
        goes through it: the world holds the person back at the robot until
        it moves. NoPathError when walls and furniture alone close the goal off.

        Every walk but leaving ends inside the flat: where the goal is not free (the robot's disc over
        it, a wall), at the free spot nearest it among the flat's rooms, never one beyond an outer wall
        (gen12: a walk up to the robot by an outer wall went out through the front door).
        """
        grid = self.world.walk_grid()
        x, y, _ = self.world.robot.pose
        inside = not self._leaving  # every walk but leaving ends inside the flat
        robot = [(x, y, ROBOT_REACH)]
        people = self.people_discs() if people else []
        if people:
            # round the people too; when they close the only way, through them: the world holds her
            # back where they stand and she waits (or steps back for them: walk_to)
            try:
                return grid.plan(self.body.position, goal, avoid=robot + people, inside=inside)
            except NoPathError:
                pass
        try:
            return grid.plan(self.body.position, goal, avoid=robot, inside=inside)
        except NoPathError:
            # walking up to the robot or a person, the place she aims at may lie in a pocket closed off from
            # her (gen24, tour-9700-07: 1.2 m from the robot, between a bookshelf and a table): as near as she gets
            return grid.plan(self.body.position, goal, inside=inside, reachable=self._walking_up and inside)

    def others(self) -> list[HumanBody]:
        """The other people in the flat, in the world's order."""
        humans = getattr(self.world, "humans", {})
        return [h for h in humans.values() if h is not self.body and h.present]

    def people_discs(self) -> list[tuple[float, float, float]]:
        """Discs her path keeps clear of (the grid grows each by her own radius): everyone standing, at
        PASS_GAP from her body; anyone walking towards her within ONCOMING m, with a second disc KEEP_RIGHT m
        to her left of them, so that she passes them on her right (and they, doing the same, her on theirs)."""
        x, y = self.body.position
        mvx, mvy = self.body.walk
        r = HUMAN_RADIUS + PASS_GAP
        discs: list[tuple[float, float, float]] = []
        for o in self.others():
            ox, oy = o.position
            if o.walk_speed < 1e-3:
                discs.append((ox, oy, r))
                continue
            dx, dy = ox - x, oy - y
            d = math.hypot(dx, dy)
            if d > ONCOMING or d < 1e-6:
                continue
            closing = (o.walk[0] - mvx) * dx + (o.walk[1] - mvy) * dy < 0.0
            if not closing:
                continue
            lx, ly = -dy / d, dx / d  # her left, looking at them
            # where they meet (their speeds share the way between them: both reckon the same point), she keeps
            # CLEAR / 2 to her right of it, they (doing the same) CLEAR / 2 to theirs: side by side, CLEAR apart,
            # never the mirror dance (the world keeps the bodies apart meanwhile)
            mine = max(math.hypot(mvx, mvy), self.body.speed, 0.1)
            f = mine / (mine + max(o.walk_speed, 0.1))
            mx, my = x + f * dx, y + f * dy
            shift = r + self.world.walk_grid().clearance - CLEAR / 2
            for k in (shift, shift + KEEP_RIGHT):
                discs.append((round(mx + k * lx, 3), round(my + k * ly, 3), r))
        return discs

    def _someone_ahead(self, here: tuple[float, float], to: tuple[float, float]) -> bool:
        """Whether someone (standing, or walking towards her) is within AHEAD m along her leg ``here`` -> ``to``
        and nearer than CLEAR to its line: she plans round them before walking on."""
        ax, ay = here
        dx, dy = to[0] - ax, to[1] - ay
        n = math.hypot(dx, dy)
        if n < 1e-9:
            return False
        ux, uy = dx / n, dy / n
        reach = min(n, AHEAD)
        for o in self.others():
            ox, oy = o.position
            along = (ox - ax) * ux + (oy - ay) * uy
            if along <= 0.0 or along >= reach + CLEAR - 0.05:
                continue  # behind her, or beyond where this leg ends
            if abs(-(ox - ax) * uy + (oy - ay) * ux) >= CLEAR - 0.02:
                continue
            if o.walk_speed >= 1e-3 and (o.walk[0] * ux + o.walk[1] * uy) > 0.0:
                continue  # walking on ahead of her, the same way
            return True
        return False

    def _give_way(self, here: tuple[float, float], v: tuple[float, float]) -> bool:
        """Whether she should let someone walking across her way pass first (see GIVE_WAY_HORIZON): walking
        at ``v`` from ``here``, she would come nearer than CLEAR to them within the horizon, their ways are not
        head-on, and they reach the crossing first."""
        x, y = here
        vx, vy = v
        sp = math.hypot(vx, vy)
        if sp < 1e-6:
            return False
        for o in self.others():
            if o.walk_speed < 1e-3:
                continue
            ox, oy = o.position
            wx, wy = o.walk
            px, py = ox - x, oy - y
            rvx, rvy = wx - vx, wy - vy
            rv2 = rvx * rvx + rvy * rvy
            if rv2 < 1e-9:
                continue  # the same velocity: the distance stays as it is
            tca = -(px * rvx + py * rvy) / rv2
            if tca <= 0.0 or tca > GIVE_WAY_HORIZON:
                continue
            if math.hypot(px + rvx * tca, py + rvy * tca) >= CLEAR:
                continue
            ws = o.walk_speed
            cos = (vx * wx + vy * wy) / (sp * ws)
            if cos < -0.7:
                continue  # head-on: both keep right (people_discs)
            if cos > 0.7:
                if px * vx + py * vy > 0.0:
                    return True  # the same way, she is ahead: behind her
                continue
            # where the two ways cross: here + s * v / sp = o + r * w / ws
            ux, uy, qx, qy = vx / sp, vy / sp, wx / ws, wy / ws
            den = ux * (-qy) - uy * (-qx)
            if abs(den) < 1e-9:
                continue
            s_ = (px * (-qy) - py * (-qx)) / den
            r_ = (ux * py - uy * px) / den
            mine, theirs = s_ / sp, r_ / ws
            if theirs < mine - GIVE_WAY_TIE or (abs(theirs - mine) <= GIVE_WAY_TIE and o.order < self.body.order):
                return True
        return False

    async def _make_room(self) -> bool:
        """Held back by someone who is held back by her (two people face to face in a narrow place): the
        one listed later in the scenario steps YIELD_STEP m to her right and a little back (away from the other), and
        waits (at most YIELD_WAIT s) for them to pass. True when she stepped back."""
        x, y = self.body.position
        near = [(math.hypot(o.position[0] - x, o.position[1] - y), o) for o in self.others()]
        near = [(d, o) for d, o in near if d < CLEAR + 0.1]
        if not near:
            return False
        d, other = min(near, key=lambda p: p[0])
        if not (other.walk_speed >= 1e-3 and other.crowded and other.order < self.body.order):
            return False
        ox, oy = other.position
        ux, uy = (x - ox) / max(d, 1e-6), (y - oy) / max(d, 1e-6)  # away from them
        rx, ry = uy, -ux  # her right, facing them
        # mostly aside (to her right), a little back: out of their way, not on along it ahead of them
        k = 1.0 / math.hypot(1.0, 0.5)
        spot = (x + YIELD_STEP * k * (0.5 * ux + rx), y + YIELD_STEP * k * (0.5 * uy + ry))
        self.yielded += 1
        self.log.append((self.now, self.now, f"steps back for {other.name} to ({spot[0]:.2f}, {spot[1]:.2f})"))
        try:
            await self.walk_to(Target("point", x=spot[0], y=spot[1]), aside=True)
        except NoPathError:
            pass
        self.body.stand()
        waited = 0.0
        while waited < YIELD_WAIT and other.present and other.walk_speed >= 1e-3:
            bx, by = self.body.position
            if math.hypot(other.position[0] - bx, other.position[1] - by) > 1.5:
                break
            await asyncio.sleep(LEG_TIME)
            waited += LEG_TIME
        return True

    # ------------------------------------------------------- facing, pointing
    def direction_to(self, target: Target) -> float:
        if target.kind == "angle":
            return target.angle
        gx, gy = self.goal_of(target)
        x, y = self.body.position
        return math.atan2(gy - y, gx - x)

    async def fire(self, h: Handler, u: Utterance) -> None:
        """She stops to react: a walk's velocity held through the reaction walked her on blind
        (through a wall 0.5 m past her goal, seven seconds of answer at 1 m/s); the walk goes on
        afterwards from where she stopped."""
        if self.body.present:
            self.body.stand()
        await super().fire(h, u)

    def stand_still(self) -> None:
        if self.body.present:
            self.body.stand()

    def face_robot(self) -> None:
        """Turn the head to the robot (a repair: she faces it to be heard)."""
        if self.body.present:
            self.face(Target("robot"))

    async def step_closer(self, act: StepCloser) -> None:
        """Walk ``act.by`` metres nearer to the robot, no nearer than ``act.nearest``."""
        d = self.robot_within()
        if d is None or not self.body.present:
            return
        goal = max(act.nearest, d - act.by)
        if d - goal > 0.05:
            # straight towards the robot (a step, not a walk around it): she stays where it can see her
            self.log.append((self.now, self.now, f"steps closer: {d:.2f} -> {goal:.2f} m"))
            x, y = self.body.position
            rx, ry, _ = self.world.robot.pose
            k = (d - goal) / d
            await self.walk_to(Target("point", x=x + k * (rx - x), y=y + k * (ry - y)))
            self.face(Target("robot"))

    def before_speaking(self, act: Say) -> None:
        """As she starts to speak she may look away from the robot (her profile's off-axis)."""
        p = self.traits.off_axis
        rng = self.draws(f"look:{act.line}" if act.line is not None else f"look:{act.request}")
        if p <= 0 or rng is None or not self.body.present:
            return
        away, side, size = rng.random(), rng.random(), rng.random()
        robot = self.direction_to(Target("robot"))
        if away < p:
            off = math.radians(60.0 + 90.0 * size) * (1 if side < 0.5 else -1)
            self.body.look(robot + off)
            self._looked_away = True
            self.log.append((self.now, self.now, f"speaks looking {math.degrees(off):+.0f} deg off the robot"))
        elif self._looked_away:
            # the last time she looked away as she spoke; this time she speaks to the robot
            self.body.look(robot)
            self._looked_away = False

    def face(self, target: Target, *, body: bool = False) -> None:
        """Turn the head (or the whole body) towards a target or a world angle."""
        self._looked_away = False
        d = self.direction_to(target)
        if body:
            self.body.turn_to(d)
            self.body.head = 0.0
        else:
            self.body.look(d)

    async def point(self, act: PointAt) -> None:
        """Raise an arm at the target for the gesture's duration."""
        point = self.world.target_point(act.target, who=self.name)
        sd = self.traits.pointing_error
        rng = self.draws(f"point:{act.line}")
        if sd > 0 and rng is not None:
            # her arm misses by a normal angular error about where she stands
            err = math.radians(sd) * float(rng.standard_normal())
            hx, hy = self.body.position
            dx, dy = point[0] - hx, point[1] - hy
            c, s_ = math.cos(err), math.sin(err)
            point = (hx + c * dx - s_ * dy, hy + s_ * dx + c * dy, *point[2:])
        name = act.target.name or act.target.kind
        self.body.pointing = Pointing(name, point, self.now + act.duration)
        try:
            await asyncio.sleep(act.duration)
        finally:
            self.body.pointing = None

    # ---------------------------------------------------------------- leave
    async def leave(self, act: Leave) -> None:
        """Walk out through an exit door (a planned path, like any walk) and disappear from the world.

        Still talking (``<say wait="false"/>`` then ``<leave/>``), she finishes her sentence
        at the door before she is gone: a sound source that vanished would leave words in the
        air that no microphone can place, and the robot would hear none of them.
        """
        _, outside = self.world.exit_points(act.door)
        self._leaving = True  # the one walk that ends outside the flat (Person.plan)
        await self.walk_to(Target("point", x=outside[0], y=outside[1]))
        self.body.stand()
        await self.finish_speaking()
        self.body.remove()
