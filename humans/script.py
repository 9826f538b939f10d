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

People are agenda-based users (Schatzmann et al. 2007): the script is the
agenda, and a reaction (``<on hears=...>``, a :class:`Handler`) pushes acts
on top of it when the robot's words match, after which she carries on where
she was. A reaction fires at the next point where she can take a turn:
between two actions, during a pause (``wait``), a walk (she stops, reacts,
walks on) or a ``wait-for`` (whose timeout starts again afterwards), or when
her own sentence ends. What the robot says while she reacts belongs to that
exchange and triggers nothing more. A reaction that fires
:data:`MAX_STREAK` times in a row without her script moving on fails the
run naming its line (``homesim check`` refuses the loops it can see).

Speech need not freeze her: ``<say wait="false">`` starts the words and
goes on to the next action (walk, turn, point) while she talks; a new
``say`` or a ``wait-for`` first lets her finish, ``wait-speech`` waits for
the end. Repairs the way people make them (``repairs=``, or her profile's):
when the robot asks her to repeat or does not answer she does her turn
again (what she said and pointed at), rephrasing it from the paraphrase
bank, louder, after stepping closer or turning to face the robot, each a
choice; after ``patience`` repairs she gives up (carries on, stops, or
leaves). ``retries=`` keeps its meaning: the turn again, word for word.
"""

from __future__ import annotations

import asyncio
import dataclasses
import math
import re
from collections import deque
from collections.abc import Callable

import numpy as np

from homesim.errors import ScenarioError
from homesim.scenario.model import Action, Face, Handler, Leave, PointAt, Repeat, Say, SourceSpec, StepCloser, Wait, WaitFor, WaitSpeech, WalkTo
from homesim.scenario.wordpattern import WordPattern, compile_words
from homesim.world.acoustics import Utterance
from homesim.world.world import World

from .phrasings import default_bank, side_request
from .profiles import Traits

#: How many of an actor's latest actions its ``log`` keeps.
LOG_LENGTH = 4096

POLL = 0.1  # seconds between checks of a wait-for condition

#: The pause before a person repeats herself (a turn-taking gap, seconds).
TURN_GAP = 0.5

#: What a person takes for the robot asking her to say it again, or asking whether it heard
#: her right ("Did you say hello to me?", "Is this plant?": she does her turn again rather than
#: answer "yes"); ``repair=`` overrides.
DEFAULT_REPAIR = r"(say|point at) (that|it) again|pardon|repeat that|did not understand|didn't understand|did not catch|did you say|shall i\b|^is this\b"

#: How much louder each "louder" repair makes her (dB), up to MAX_BOOST: one step of vocal
#: effort (ANSI S3.5-1997: normal 62.4, raised 68.3, loud 74.9 dB, about 6 dB apart).
LOUDER_DB = 6.0
MAX_BOOST = 18.0

#: Requests a reaction re-says to answer "which room / what is it / where shall I go / what are you looking
#: for?": said then, they name what was asked (:meth:`Actor.phrase`).
NAMING = ("teach-place", "teach-object", "go-to", "where-is")
#: What a person takes for the robot telling her it acts on her request by moving or searching ("I will move over
#: to see it", "I will look around you for it", "I am coming", "let me turn round"): a person who repairs the way people do (a profile, or ``repairs``/
#: ``patience``/``give-up``) waits for her answer anew from then (:meth:`Actor._wait_once`).
ACTING_SAYS = re.compile(r"\bI will (move|go|come|drive|turn|look around)\b|\bI am (moving|going over|coming|driving|turning)\b"
                         r"|\blet me (move|go|come|drive|turn)\b", re.IGNORECASE)
#: Such a person, seeing the robot drive or turn (base speed above these, m/s and rad/s), waits while it does and
#: then her wait's timeout anew; but she gives up after at most this many seconds beyond her timeout (a long
#: silence stays a long silence, whatever the robot does meanwhile).
ACTING_SPEED = 0.05
ACTING_TURN = 0.2
ACTING_WAIT_MAX = 30.0
#: A reaction that fires this many times in a row without the script moving on is a loop.
MAX_STREAK = 50


#: Objects of one type within this many metres of each other are "the one on the left / right".
SIDE_GROUP = 1.0


def side_seen_by_robot(world: World, name: str) -> str:
    """Where object ``name`` stands among the similar objects next to it, as the robot sees them
    now: "left", "right" or "middle". A person answering the robot's "which one?" takes the
    robot's view, the frame BIRON itself words its options in ("the cup on the left or the one
    on the right?"); users instructing a robot often do (Moratz, Tenbrink, Bateman and Fischer
    2003, "Spatial knowledge representation for human-robot interaction"). The similar objects
    are those of its type within :data:`SIDE_GROUP` m; alone, its side of the robot's line of sight."""
    o = world.objects[name]
    rx, ry, th = world.robot.pose
    group = [p for p in world.objects.values() if p.type == o.type and math.hypot(p.x - o.x, p.y - o.y) <= SIDE_GROUP]
    if len(group) < 2:
        return "left" if math.remainder(math.atan2(o.y - ry, o.x - rx) - th, math.tau) > 0 else "right"
    cx, cy = sum(p.x for p in group) / len(group), sum(p.y for p in group) / len(group)
    ref = math.atan2(cy - ry, cx - rx)
    order = sorted(group, key=lambda p: (-math.remainder(math.atan2(p.y - ry, p.x - rx) - ref, math.tau), p.name))
    rank = order.index(o)
    return "left" if rank == 0 else "right" if rank == len(order) - 1 else "middle"



def _said_part(turn: tuple[Action, ...]) -> tuple[Action, ...]:
    """What she does again when the robot missed her turn: her words and what goes with them.

    That is the turn from its first sentence or pointing on, with the facing just before it (she turns to
    the robot to speak). What she did before she spoke (a pause, a walk, facing someone else: in
    perceive/step_aside_chat she stands 8 s with two people, walks back and asks "What can you do") is not
    part of it: replaying it made her wait 8 s with her back to the robot before each repeat. A turn with no
    words and no pointing is done again whole but for the pause it opens with.
    """
    first = next((i for i, a in enumerate(turn) if isinstance(a, (Say, PointAt))), None)
    if first is None:
        i = 0
        while i < len(turn) and isinstance(turn[i], Wait):  # the pause before her turn is not part of it
            i += 1
        return turn[i:]
    while first and isinstance(turn[first - 1], Face):
        first -= 1
    return turn[first:]

class GaveUp(Exception):
    """She gave up on the whole tour (give-up stop or leave): her script ends."""


class ScriptError(ScenarioError):
    """A script action cannot be carried out (e.g. no path to a walk's goal): names file and line."""


class Actor:
    """Runs a script of say / wait / wait-for / repeat actions."""

    def __init__(self, world: World, name: str, script: tuple[Action, ...], *, loudness: float = 60.0,
                 handlers: tuple[Handler, ...] = (), traits: Traits | None = None, rng: np.random.Generator | None = None,
                 streams: Callable[[str], np.random.Generator] | None = None) -> None:
        self.world = world
        self.name = name
        self.script = script
        self.loudness = loudness
        self.log: deque[tuple[float, float, str]] = deque(maxlen=LOG_LENGTH)
        self.done = False
        self.turn: list[Action] = []  # what the actor did since her last wait-for: her turn
        self.handlers = handlers
        self.traits = traits if traits is not None else Traits()
        self.rng = rng  # her choices as she goes (phrasings, looking away, pointing): from the run's seed
        # one generator per act of hers (``say:<line>``, ...) when given: a reaction that fires, or
        # a say added to her script, does not shift the draws of her other acts
        self.streams = streams
        self.fired = [0] * len(handlers)  # how often each reaction fired
        self.speech_end = 0.0  # when what she is saying ends
        self.boost = 0.0  # dB louder while she repairs
        self.repairs = 0  # repairs made over the run
        self.gave_up = 0  # times her patience ran out
        self._ear_last = 0.0
        self._ear_seen: frozenset[int] = frozenset()
        self._reacting = False
        self._streak = 0
        self._absorbed: frozenset[int] = frozenset()  # robot utterances heard during her last reaction
        self._last_phrase: dict[tuple[str, str | None], str] = {}
        self._slip: str | None = None  # what she meant when she just misnamed it (to correct herself)
        self.confirmed_wrongly = 0  # wrong guesses of the robot's she said yes to
        self.misnamed = 0  # rooms or things she named wrongly when she taught them
        self.self_corrected = 0  # of those, the slips she corrected at once
        self.scoped_fired_total = 0  # how often a wait's own reactions fired over the run
        self.stopped_early = False  # she gave up by stopping or leaving: her script ended there
        self.scoped: tuple[Handler, ...] = ()  # the reactions of the wait-for she is in (``<on>`` inside it)
        self._scoped_fired: list[int] = []

    @property
    def now(self) -> float:
        return asyncio.get_running_loop().time()

    async def run(self) -> None:
        """Play the whole script, then stay idle."""
        try:
            await self.play(self.script)
        except GaveUp:
            self.stopped_early = True
            self.stand_still()
        self.done = True

    def stand_still(self) -> None:
        """Hook: a person who gave up in the middle of a walk stops where she is."""

    async def play(self, actions: tuple[Action, ...]) -> None:
        for act in actions:
            if not self._reacting:
                self._streak = 0
            if self.handlers:
                await self.react()
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
            if self.handlers:
                await self.pause(act.duration)
            else:
                await asyncio.sleep(act.duration)
        elif isinstance(act, WaitFor):
            await self.wait_for(act)
        elif isinstance(act, Repeat):
            await self.repeat(act)
        elif isinstance(act, WaitSpeech):
            await self.finish_speaking()
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

    async def say(self, act: Say, *, rephrase: bool = False) -> None:
        """Say the action's text (or a phrasing of its request); ``wait=False``: go on while talking."""
        await self.finish_speaking()  # one mouth: she finishes her sentence first
        text = self.phrase(act, rephrase=rephrase)
        loudness = act.loudness if act.loudness is not None else self.loudness
        if self.boost:
            loudness += self.boost
        self.before_speaking(act)
        u = self.world.sound.say(self.name, text, self.now, loudness=loudness, duration=act.duration)
        self.speech_end = u.end
        meant, self._slip = self._slip, None
        if not act.wait:
            return
        self.on_speaking(True)
        try:
            await asyncio.sleep(u.end - u.start)
        finally:
            self.on_speaking(False)
        if meant is not None and self.chance(f"self-correct:{act.line}", self.traits.self_correct):
            self.self_corrected += 1  # "Sorry, I mean the kitchen", right after her slip
            await self.say(Say(None, line=act.line, request="self-correct", about=meant))
            return
        if self.handlers:
            await self.react()

    def phrase(self, act: Say, *, rephrase: bool = False) -> str:
        """What she says: the text; or a phrasing of the request (another one when she rephrases).

        Her profile's mistakes happen here: a correction she was to make becomes a "yes" (she
        confirms the robot's wrong guess), and the first telling of a room or a thing she
        teaches may name it wrongly (:meth:`misnaming`; she may correct herself, :meth:`say`).
        """
        if act.request is None:
            return act.text or ""
        about = act.about if act.side_of is None else side_seen_by_robot(self.world, act.side_of)
        if act.request == "which-side" and about is not None:
            request, about = side_request(about)
            act = dataclasses.replace(act, request=request)
        if act.request in ("correct", "no") and self._reacting and self.chance(f"confirm:{act.line}", self.traits.confirm_wrongly):
            # she says yes to the robot's wrong guess (did not listen closely, or thinks it close enough)
            self.confirmed_wrongly += 1
            act, about = Say(None, line=act.line, request="yes"), None
        elif act.request in ("teach-place", "teach-object") and not rephrase and about and self.traits.misname > 0:
            wrong = self.misnaming(about, f"misname:{act.line}")
            if wrong is not None and (act.text is None or about in act.text):
                self.misnamed += 1
                self._slip = about  # she meant this (she may correct herself once she has said it)
                if act.text is not None:
                    return act.text.replace(about, wrong)
                about = wrong
        if act.text is not None and not rephrase:
            return act.text
        key = (act.request, about)
        avoid = self._last_phrase.get(key, act.text) if rephrase else None
        rng = self.draws(f"say:{act.line}" if act.line is not None else f"say:{act.request}")
        if rng is None:
            raise ScriptError(f"{self.name!r} has no paraphrase bank", source=self.world.scenario.source, line=act.line, element="say")
        bank = default_bank()
        drawn = bank.draw(rng, act.request, self.traits.phrasing, avoid=avoid, about=about)
        if self._reacting and about and act.request in NAMING and not drawn.has_slot:
            # her answer to the robot's question names what it asked about ("Where shall I go?" -
            # "Now go to the kitchen", never "Go over there" again; "Which room is this?" - never
            # "This is where we live"): a second draw, only then, so every other draw stays as it was.
            # A correction may name nothing ("No, the other one": the robot asked "Is this your cup?")
            drawn = bank.draw(rng, act.request, self.traits.phrasing, avoid=avoid, slotted=True, about=about)
        text = bank.render(drawn, about)
        self._last_phrase[key] = text
        return text

    def chance(self, key: str, p: float) -> bool:
        """True with probability ``p`` (from the act's own generator ``key``; no draw when p is 0)."""
        if p <= 0:
            return False
        rng = self.draws(key)
        return rng is not None and float(rng.random()) < p

    def misnaming(self, about: str, key: str) -> str | None:
        """``about`` with its room or thing named wrongly ("the bedroom" for "the kitchen", "my
        red book" for "my red cup"), with her ``misname`` probability; None: she names it right.

        A room becomes another room of her home; a thing, a word of another type."""
        if not self.chance(key, self.traits.misname):
            return None
        rng = self.draws(key)
        assert rng is not None
        low = about.lower()
        rooms = sorted((r.name for r in self.world.scenario.rooms), key=len, reverse=True)
        hit = next((r for r in rooms if re.search(rf"\b{re.escape(r)}\b", low)), None)
        if hit is not None:
            others = sorted(r for r in rooms if r != hit)
        else:
            words = default_bank().object_words
            type_of = {w: t for t, ws in words.items() for w in ws}
            hit = next((w for w in sorted(type_of, key=len, reverse=True) if re.search(rf"\b{re.escape(w)}\b", low)), None)
            if hit is None:
                return None
            others = sorted(ws[0] for t, ws in words.items() if t != type_of[hit] and ws[0] not in default_bank().plurals)
        if not others:
            return None
        return re.sub(rf"\b{re.escape(hit)}\b", others[int(rng.integers(len(others)))], low, count=1)

    def draws(self, key: str) -> np.random.Generator | None:
        """The generator of one of her acts (``key``: ``say:<line>``, ``look:<line>``, ``point:<line>``).

        Per act, so one act's draws (a phrasing, a look away, a pointing error) do not depend on
        how many draws her other acts made before it: adding a reaction that fires leaves the
        rest of her tour as it was. Without ``streams``, her one generator ``rng``.
        """
        return self.streams(key) if self.streams is not None else self.rng

    async def finish_speaking(self) -> None:
        """Wait until what she is saying has ended (nothing when she is silent)."""
        if self.speech_end > self.now + 1e-6:
            await asyncio.sleep(self.speech_end - self.now)

    def on_speaking(self, speaking: bool) -> None:
        """Hook: people open their mouths (nothing to do for a radio)."""

    def before_speaking(self, act: Say) -> None:
        """Hook: a person may look away as she starts to speak (her profile's off-axis)."""

    # ------------------------------------------------------------ reactions
    async def pause(self, duration: float) -> None:
        """A ``wait`` during which reactions can fire (the pause ends when it would have)."""
        end = self.now + duration
        while self.now < end - 1e-6:
            await asyncio.sleep(min(POLL, end - self.now))
            await self.react()

    def hear(self) -> list[Utterance]:
        """What the robot finished saying since her last look (each utterance once)."""
        now = self.now
        last = max(self._ear_last, now - 0.5 * self.world.sound.horizon)
        heard = self.world.sound.ended(last, now, closed=True)
        new = [u for u in heard if u.source == "robot" and u.n not in self._ear_seen]
        self._ear_seen = frozenset(u.n for u in heard if u.end == now)
        self._ear_last = now
        return new

    def reaction_to(self, text: str, *, waiting: bool) -> Handler | None:
        """The first reaction that may fire now and hears ``text``: those of the wait-for she is
        in first (its ``<on>``s, in file order), then her own (in file order)."""
        if waiting:
            for k, h in enumerate(self.scoped):
                if (h.max is None or self._scoped_fired[k] < h.max) and compile_words(h.hears).search(text):
                    return h
        for k, h in enumerate(self.handlers):
            if h.when == "waiting" and not waiting:
                continue
            if h.max is not None and self.fired[k] >= h.max:
                continue
            if compile_words(h.hears).search(text):
                return h
        return None

    async def react(self, *, waiting: bool = False) -> bool:
        """Fire the reaction to what the robot just said, if any; True when one fired."""
        if self._reacting or not self.active:
            return False
        for u in self.hear():
            h = self.reaction_to(u.text, waiting=waiting)
            if h is not None:
                await self.fire(h, u)
                return True
        return False

    async def fire(self, h: Handler, u: Utterance) -> None:
        """Do a reaction's acts, then carry on (the agenda's pushed acts popped)."""
        if any(h is x for x in self.scoped):
            self._scoped_fired[next(i for i, x in enumerate(self.scoped) if x is h)] += 1
            self.scoped_fired_total += 1
        else:
            self.fired[next(i for i, x in enumerate(self.handlers) if x is h)] += 1
        self._streak += 1
        if self._streak > MAX_STREAK:
            raise ScriptError(f"{self.name!r}: the reaction fired {MAX_STREAK} times in a row without her script moving on "
                              f"(the robot's {u.text!r}); give it max=", source=self.world.scenario.source, line=h.line, element="on")
        self.log.append((self.now, self.now, f"hears {u.text!r}: reacts (line {h.line})"))
        self._reacting = True
        turn, self.turn = self.turn, []
        try:
            await self.play(h.body)
        finally:
            self._reacting = False
            self.turn = turn
        # what the robot said meanwhile belongs to this exchange: it triggers no reaction (a
        # wait-for she is in may still take it as its answer)
        self._absorbed = frozenset(u.n for u in self.hear())

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
        came before it) and wait anew. With ``repairs``/``patience``/``give-up``
        (or a profile) she repairs the way people do: :meth:`repair_loop`.
        """
        await self.finish_speaking()  # nobody expects an answer before she has finished
        outer = self.scoped, self._scoped_fired
        self.scoped, self._scoped_fired = act.handlers, [0] * len(act.handlers)
        try:
            return await self._wait_for(act)
        finally:
            self.scoped, self._scoped_fired = outer

    async def _wait_for(self, act: WaitFor) -> bool:
        if act.retries == 0 and (act.repairs is not None or act.patience is not None or act.give_up is not None
                                 or self.traits.repairing):
            ok = await self.repair_loop(act)
        else:
            ok = await self._retry_loop(act)
        # (not in a ``finally``: a run that ends during the wait closes this coroutine after its loop)
        if self.handlers or self.scoped:
            self.hear()  # what she heard while waiting was for the wait
        return ok

    async def repair_loop(self, act: WaitFor) -> bool:
        """Wait; on a miss repair by her strategies at most ``patience`` times, then give up."""
        strategies = act.repairs if act.repairs is not None else self.traits.repairs
        patience = act.patience if act.patience is not None else self.traits.patience
        give_up = act.give_up or self.traits.give_up
        repair = re.compile(act.repair or DEFAULT_REPAIR, re.IGNORECASE)
        turn = tuple(a for a in self.turn if isinstance(a, (Say, PointAt)))  # what she said and showed
        self.turn = []
        outcome = "timeout"
        for attempt in range(patience + 1):
            outcome = await self._wait_once(act, repair, acting=True)
            if outcome == "answered":
                self.boost = 0.0
                return True
            if attempt == patience or not turn or not self.active:
                break
            self.repairs += 1
            how = ", ".join(strategies) or "repeat"
            self.log.append((self.now, self.now, f"not understood ({outcome}): repair {attempt + 1} of {patience} ({how})"))
            await asyncio.sleep(TURN_GAP)
            if not self.active:
                return False
            if "face" in strategies:
                self.face_robot()
            if "closer" in strategies:
                await self.step_closer(StepCloser())
            if "louder" in strategies:
                self.boost = min(self.boost + LOUDER_DB, MAX_BOOST)
            for a in turn:
                if isinstance(a, Say):
                    await self.say(a, rephrase="rephrase" in strategies)
                else:
                    await self.perform(a)
            await self.finish_speaking()
            self.turn = []
        self.boost = 0.0
        if turn and self.active:
            await self.give_up(give_up, outcome)
        return False

    async def give_up(self, how: str, outcome: str) -> None:
        """Her patience is used up: carry on (skip), or say so and stop her script or leave.

        A flat without an exit door cannot be left: she stops there instead (a profile may
        draw ``leave`` for any flat; ``give-up="leave"`` in a scenario needs an exit).
        """
        self.gave_up += 1
        self.log.append((self.now, self.now, f"gives up ({outcome}): {how}"))
        if how == "skip":
            return
        if self.draws("say:give-up") is not None:
            await self.say(Say(None, request="give-up"))
            await self.finish_speaking()
        if how == "leave" and self.world.scenario.exits():
            await self.perform(Leave())
        raise GaveUp(how)

    def face_robot(self) -> None:
        """Hook: turn to face the robot (a person)."""

    async def step_closer(self, act: StepCloser) -> None:
        """Hook: step towards the robot (a person)."""

    async def _retry_loop(self, act: WaitFor) -> bool:
        repair = re.compile(act.repair or DEFAULT_REPAIR, re.IGNORECASE) if act.retries else None
        turn, self.turn = _said_part(tuple(self.turn)), []
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
            # asked to say it again ("Could you say that again?"), she says it again where she stands: the
            # walk that led up to her words is not part of what she repeats (walking her route back and
            # again, with the robot following her, was hall_names_study seed 2's lost tour)
            await self.play(turn if outcome != "repair" else tuple(a for a in turn if not isinstance(a, WalkTo)))
            self.turn = []
        return False

    def sees_robot_act(self) -> bool:
        """Whether the robot's base drives or turns (:data:`ACTING_SPEED`, :data:`ACTING_TURN`) where she can see it
        (a body: nothing tall on the line from her to it)."""
        r = self.world.robot
        if abs(r.v) < ACTING_SPEED and abs(r.w) < ACTING_TURN:
            return False
        sees = getattr(self, "sees", None)
        return sees is not None and self.world.source_point(self.name) is not None and bool(sees((r.pose[0], r.pose[1])))

    async def _wait_once(self, act: WaitFor, repair: re.Pattern[str] | None, acting: bool = False) -> str:
        """One wait: ``answered``, ``repair`` (the robot asked to hear it again) or ``timeout``.

        ``acting`` (a person who repairs the way people do): the robot telling her it moves (:data:`ACTING_SAYS`),
        or seen driving or turning (:meth:`sees_robot_act`), acts on her request: she waits for her answer anew
        from then, at most :data:`ACTING_WAIT_MAX` s beyond her timeout (gen24: tour 9700-10 gave the tour up
        during the robot's 9 s drive to see her vase, 4 s before "I have learned the blue vase")."""
        since = self.now
        pattern: re.Pattern[str] | WordPattern | None = re.compile(act.robot_says, re.IGNORECASE) if act.robot_says else None
        if act.hears:
            pattern = compile_words(act.hears)
        deadline = math.inf if act.timeout is None else since + act.timeout
        longest = deadline + ACTING_WAIT_MAX
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
                    if (self.handlers or self.scoped) and not self._reacting and u.n not in self._absorbed:
                        h = self.reaction_to(u.text, waiting=True)
                        if h is not None:
                            await self.fire(h, u)
                            if act.timeout is not None:  # she waits for the robot's answer anew
                                deadline = self.now + act.timeout
                            continue
                    # A question back ("Did you say hello to me?") is no answer, even with the words in it.
                    if repair is not None and repair.search(u.text):
                        return "repair"
                    if pattern.search(u.text):
                        return "answered"
                    if acting and act.timeout is not None and ACTING_SAYS.search(u.text):
                        deadline = min(max(deadline, self.now + act.timeout), longest)
            elif self.handlers or self.scoped:
                await self.react(waiting=True)
            if act.robot_within is not None:
                d = self.robot_within()
                if d is not None and d <= act.robot_within:
                    return "answered"
            if (acting and act.timeout is not None and self.now + act.timeout > deadline and deadline < longest
                    and self.sees_robot_act()):
                deadline = min(self.now + act.timeout, longest)  # it acts: she waits until it has, and then
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
        return f"say {act.text!r}" if act.request is None else f"say ({act.request}) {act.text or ''}".rstrip()
    if isinstance(act, Wait):
        return f"wait {act.duration:g} s"
    if hasattr(act, "target"):
        t = act.target  # type: ignore[union-attr]
        what = t.name if t.name else (f"({t.x:g}, {t.y:g})" if t.kind == "point" else t.kind)
        return f"{name.lower()} {t.kind} {what}"
    return name.lower()
