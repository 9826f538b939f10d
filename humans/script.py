"""Script interpretation shared by people and other sound sources.

A script is a tuple of actions from :mod:`homesim.scenario.model`. An
:class:`Actor` runs it as one asyncio coroutine in virtual time: ``say``
puts an utterance into the world's sound field and lasts as long as the
words take, ``wait`` sleeps, ``wait-for`` polls what the robot said and
where it is (so scripts react to the robot, not only to the clock), and
``repeat`` loops (a pass that took no virtual time is followed by one world
step, so a repeat can never hang the simulation). :class:`~humans.person.Person` adds the bodily actions;
:class:`Radio` is an actor with no body (a radio or a TV).

Every action is recorded in ``log`` as (start, end, description), the
actor's own ground truth for transcripts and expectations; only the last
:data:`LOG_LENGTH` actions are kept, so a forever-repeat over a long run
does not grow the actor's memory.
"""

from __future__ import annotations

import asyncio
import math
import re
from collections import deque

from homesim.errors import ScenarioError
from homesim.scenario.model import Action, Repeat, Say, SourceSpec, Wait, WaitFor
from homesim.world.world import World

#: How many of an actor's latest actions its ``log`` keeps.
LOG_LENGTH = 4096

POLL = 0.1  # seconds between checks of a wait-for condition

#: The pause before a person repeats herself (a turn-taking gap, seconds).
TURN_GAP = 0.5

#: What a person takes for the robot asking her to say it again, or asking whether it heard
#: her right ("Did you say hello to me?", "Is this plant?": she does her turn again rather than
#: answer "yes"); ``repair=`` overrides.
DEFAULT_REPAIR = r"(say|point at) (that|it) again|pardon|repeat that|did not understand|didn't understand|did not catch|did you say|shall i\b|^is this\b"


class ScriptError(ScenarioError):
    """A script action cannot be carried out (e.g. no path to a walk's goal): names file and line."""


class Actor:
    """Runs a script of say / wait / wait-for / repeat actions."""

    def __init__(self, world: World, name: str, script: tuple[Action, ...], *, loudness: float = 60.0) -> None:
        self.world = world
        self.name = name
        self.script = script
        self.loudness = loudness
        self.log: deque[tuple[float, float, str]] = deque(maxlen=LOG_LENGTH)
        self.done = False
        self.turn: list[Action] = []  # what the actor did since her last wait-for: her turn

    @property
    def now(self) -> float:
        return asyncio.get_running_loop().time()

    async def run(self) -> None:
        """Play the whole script, then stay idle."""
        await self.play(self.script)
        self.done = True

    async def play(self, actions: tuple[Action, ...]) -> None:
        for act in actions:
            start = self.now
            if not isinstance(act, (WaitFor, Repeat)):
                self.turn.append(act)
            await self.perform(act)
            self.log.append((start, self.now, _describe(act)))

    async def perform(self, act: Action) -> None:
        """Carry out one action (subclasses add the bodily ones)."""
        if isinstance(act, Say):
            await self.say(act)
        elif isinstance(act, Wait):
            await asyncio.sleep(act.duration)
        elif isinstance(act, WaitFor):
            await self.wait_for(act)
        elif isinstance(act, Repeat):
            await self.repeat(act)
        else:
            raise TypeError(f"{self.name!r} cannot perform {type(act).__name__}")

    @property
    def active(self) -> bool:
        """Whether the actor can still act (a person who has left cannot)."""
        return True

    async def repeat(self, act: Repeat) -> None:
        """Play the body ``times`` times (for ever when None), always letting time pass.

        A pass can take no virtual time at all (a walk-to where the person
        already stands, a wait-for whose condition already holds): the loop
        would then never yield and the whole simulation would hang at that
        instant. Such a pass is followed by one world step (``world.dt``),
        so the repeat polls at the world's rate instead. It ends when the
        actor is no longer active (the person has left).
        """
        n = 0
        while (act.times is None or n < act.times) and self.active:
            start = self.now
            await self.play(act.body)
            n += 1
            if self.now <= start:
                await asyncio.sleep(self.world.dt)

    async def say(self, act: Say) -> None:
        u = self.world.sound.say(self.name, act.text, self.now, loudness=act.loudness if act.loudness is not None else self.loudness, duration=act.duration)
        self.on_speaking(True)
        try:
            await asyncio.sleep(u.end - u.start)
        finally:
            self.on_speaking(False)

    def on_speaking(self, speaking: bool) -> None:
        """Hook: people open their mouths (nothing to do for a radio)."""

    def robot_within(self) -> float | None:
        """Distance to the robot (None when this actor has no position)."""
        p = self.world.source_point(self.name)
        if p is None:
            return None
        x, y, _ = self.world.robot.pose
        return math.hypot(p[0] - x, p[1] - y)

    async def wait_for(self, act: WaitFor) -> bool:
        """Wait until the robot says a matching phrase or comes close; False on timeout.

        With ``retries``, a miss (the robot asks for a repair, or the timeout
        passes) makes the person do her turn again (every action since her
        previous wait-for: a point and a sentence, say; not the pause that
        came before it) and wait anew.
        """
        repair = re.compile(act.repair or DEFAULT_REPAIR, re.IGNORECASE) if act.retries else None
        turn, self.turn = tuple(self.turn), []
        while turn and isinstance(turn[0], Wait):  # the pause before her turn is not part of it
            turn = turn[1:]
        for attempt in range(act.retries + 1):
            outcome = await self._wait_once(act, repair)
            if outcome == "answered":
                return True
            if attempt == act.retries or not turn or not self.active:
                return False
            self.log.append((self.now, self.now, f"not understood ({outcome}): does her turn again"))
            await asyncio.sleep(TURN_GAP)
            if not self.active:
                return False
            await self.play(turn)
            self.turn = []
        return False

    async def _wait_once(self, act: WaitFor, repair: re.Pattern[str] | None) -> str:
        """One wait: ``answered``, ``repair`` (the robot asked to hear it again) or ``timeout``."""
        since = self.now
        pattern = re.compile(act.robot_says, re.IGNORECASE) if act.robot_says else None
        deadline = math.inf if act.timeout is None else since + act.timeout
        # What was already heard and matched nothing: ended up to ``last`` (the previous poll),
        # ``seen`` those that ended exactly then. Each poll looks only at what ended since (a cut
        # at the very instant of the previous poll ends an utterance exactly then), which finds
        # the same first match as looking at everything since the wait began.
        last = since
        seen: frozenset[int] = frozenset()
        while True:
            if pattern is not None:
                # An utterance counts once it has been heard to its end, after the
                # wait began (it may have started before: the person hears it end).
                now = self.now
                heard = self.world.sound.ended(last, now, closed=last > since)
                last, seen_before = now, seen
                seen = frozenset(u.n for u in heard if u.end == now)
                for u in heard:
                    if u.source != "robot" or u.n in seen_before:
                        continue
                    # A question back ("Did you say hello to me?") is no answer, even with the words in it.
                    if repair is not None and repair.search(u.text):
                        return "repair"
                    if pattern.search(u.text):
                        return "answered"
            if act.robot_within is not None:
                d = self.robot_within()
                if d is not None and d <= act.robot_within:
                    return "answered"
            if self.now >= deadline - 1e-6:  # virtual time is integer ns: never sleep 0
                # Nobody gives up on an answer while it is being spoken: wait for its end.
                talking = self.world.sound.speaking("robot", self.now)
                if talking is None:
                    return "timeout"
                deadline = talking.end + 1e-3
            await asyncio.sleep(min(POLL, max(deadline - self.now, 0.0)) if deadline < math.inf else POLL)


class Radio(Actor):
    """A radio or TV: a sound source with a script and no body."""

    def __init__(self, world: World, spec: SourceSpec) -> None:
        super().__init__(world, spec.name, spec.script, loudness=spec.loudness)
        self.spec = spec


def _describe(act: Action) -> str:
    name = type(act).__name__
    if isinstance(act, Say):
        return f"say {act.text!r}"
    if isinstance(act, Wait):
        return f"wait {act.duration:g} s"
    if hasattr(act, "target"):
        t = act.target  # type: ignore[union-attr]
        what = t.name if t.name else (f"({t.x:g}, {t.y:g})" if t.kind == "point" else t.kind)
        return f"{name.lower()} {t.kind} {what}"
    return name.lower()
