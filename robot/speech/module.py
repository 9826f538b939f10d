"""The ``understanding`` module: recognised utterances in, typed speech frames out.

Input: ``/robot/audio/speech`` (``<utterance start end bearing level confidence>words</utterance>``;
the older recogniser's ``wer`` stands in for a missing confidence as ``1 - wer``,
and its ``self="true"`` utterances are skipped).

Output: ``/robot/speech/frames`` (``robot/schemas/speech-frames.xsd``):
``<understood start end confidence [unknown ignored corrected partial answer fragment named opens after]><SPEECH><TIMESTAMP val/>..</SPEECH><words>..</words></understood>``
(``TIMESTAMP``: the utterance's start in virtual milliseconds, as the papers' frames carry it)
or ``<not_understood start end confidence [unknown] reason [named] [call] [addressee]>words</not_understood>``
(``call="true"``: the robot's name and at most one word more, :func:`only_calls_robot`).
A greeting that opens a request ("hello BIRON, follow me") is two frames: the greeting
(``opens="true"``), then the request (``after="greeting"``), which the dialog handles once the
greeting has been taken.

Timing (virtual, docs/semantics.md §7 / the papers' Fig. 6): recognition takes most
of the time and grows with the utterance's length, ``recognition_base +
recognition_per_word * words`` after the utterance ends; then understanding
costs ``understanding_cost``. The module is one serial processor: an utterance
that ends while another is still being recognised waits for it.

Own voice: the microphones' echo canceller removes what the speaker announced
(``/robot/speaker/status``), but an echo that leaks through (a speaker status
the canceller missed, a reverberant room) must not be taken for the partner.
The rule uses what the speaker published, never loudness alone (a partner a
hand's breadth away is as loud as the loudspeaker): an utterance is the robot's
own voice when it starts with one of the robot's sentences (within
``own_voice_onset`` s), its words are that sentence's (word-sequence similarity
at least ``own_voice_match``; of a cut sentence, the part said before the cut),
and it is no louder at the microphones than the loudspeaker's announced
``level`` (dB at 1 m) plus ``echo_gain_db`` (the microphones are about 0.3 m
from the loudspeaker) and ``echo_tolerance_db``. Anything else, a partner
talking over the robot included, is understood (:func:`is_own_voice`).
"""

from __future__ import annotations

import asyncio
import re
from copy import copy
from collections import deque
from dataclasses import dataclass
from difflib import SequenceMatcher
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from homesim.message import Message
from homesim.module import Module
from robot.deployment import cost_scale
from homesim.vloop import to_ns

from robot.contract import FRAMES, SPEAKER_STATUS, SPEECH

if TYPE_CHECKING:  # the grammar (lark, the lexicon, the LALR tables) is loaded at the first utterance
    from .grammar import Understander, Understanding
    from .lexicon import Lexicon

FRAMES_XSD = Path(__file__).resolve().parent.parent / "schemas" / "speech-frames.xsd"

_SHARED: list[Understander] = []


def shared_understander() -> Understander:
    """One grammar per process (loading the lexicon and building the LALR tables takes ~0.1 s)."""
    if not _SHARED:
        from .grammar import Understander

        _SHARED.append(Understander())
    return _SHARED[0]


_NOT_XML = re.compile("[^\u0009\u000a\u000d\u0020-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _xml_safe(text: str) -> str:
    """``text`` without the characters XML cannot carry (control characters, lone surrogates)."""
    return _NOT_XML.sub("", text)


def calls_robot(words: str, lexicon: Lexicon) -> bool:
    """Whether ``words`` call the robot by its name ("BIRON, go to the lounge"): a word the lexicon
    lists as the robot's name (ROBOTNAME). The dialog's addressee rule takes such words as meant for
    the robot whichever way the speaker faces (docs/semantics.md, the addressee rule)."""
    return any(lexicon.entries.get((w,), ("", ""))[0] == "ROBOTNAME" for w in lexicon.words(words))


def only_calls_robot(words: str, lexicon: Lexicon) -> bool:
    """Whether ``words`` are the robot's name and at most one word more ("biron", "that biron", "hey
    byron"): a call for its attention, the rest of what was said lost ("Hello BIRON" heard while the robot
    turns toward her voice). The dialog answers such a call before an interaction as a greeting, once
    someone speaking is seen facing it (docs/semantics.md, the call by name)."""
    said = lexicon.words(words)
    names = sum(lexicon.entries.get((w,), ("", ""))[0] == "ROBOTNAME" for w in said)
    return names > 0 and len(said) - names <= 1


def frame_message(u: Understanding, start: float, end: float, confidence: float, named: bool = False,
                  call: bool = False) -> etree._Element:
    """The frames-channel element for one understanding; ``named``: the words call the robot by its
    name (:func:`calls_robot`), said as ``named="true"``; ``call``: they say nothing else the robot
    could use (:func:`only_calls_robot`), said on a ``not_understood`` as ``call="true"``."""
    if u.frame is None:
        el = etree.Element("not_understood", start=f"{start:.6f}", end=f"{end:.6f}", confidence=f"{confidence:.3f}",
                           reason=u.reason)
        if u.unknown:
            el.set("unknown", _xml_safe(" ".join(u.unknown)))
        if named:
            el.set("named", "true")
        if named and call and not u.aside:
            el.set("call", "true")
        if u.aside:
            el.set("addressee", "other")  # said to someone else: no request, and no "say that again"
        el.text = _xml_safe(u.words)
        return el
    conf = confidence * u.coverage
    el = etree.Element("understood", start=f"{start:.6f}", end=f"{end:.6f}", confidence=f"{conf:.3f}")
    if named:
        el.set("named", "true")
    for attr, words in (("unknown", u.unknown), ("ignored", u.ignored), ("corrected", u.corrected)):
        if words:
            el.set(attr, _xml_safe(" ".join(words)))
    if u.partial:
        el.set("partial", "true")
    if u.answer:
        el.set("answer", u.answer)
    if u.fragment:
        el.set("fragment", "true")
    # the frame carries when the utterance began, as the papers' frames do (<TIMESTAMP val/>, ms)
    speech = etree.SubElement(el, "SPEECH")
    etree.SubElement(speech, "TIMESTAMP", val=str(max(0, round(start * 1000.0))))
    for act in u.frame:
        speech.append(copy(act))  # the understanding's own frame stays as it was
        if u.stay and act.tag == "WAIT":
            speech[-1].set("stay", "true")  # "wait here": the robot is to stay, not to pause (biron.scxml)
    etree.SubElement(el, "words").text = _xml_safe(u.words)
    return el


@dataclass(slots=True)
class RobotSentence:
    """What the speaker announced it plays: words, start, end (earlier when cut), level (dB at 1 m; None: not said)."""

    words: tuple[str, ...]
    start: float
    end: float
    level: float | None
    cut: bool = False


def _words(text: str) -> tuple[str, ...]:
    return tuple(w for w in re.sub(r"[^\w' ]+", " ", text.lower()).split() if w)


def is_own_voice(words: str, start: float, level: float | None, said: list[RobotSentence] | deque[RobotSentence], *,
                 onset: float = 0.5, match: float = 0.6, echo_gain_db: float = 10.5, tolerance_db: float = 6.0) -> bool:
    """Whether a recognised utterance is the robot's own sentence heard back (see the module docstring).

    ``words``/``start``/``level``: the recogniser's utterance (``level`` None when it gave none);
    ``said``: the speaker's announced sentences. Only an utterance that starts with a robot sentence,
    says its words and is not louder than the loudspeaker can make it at the microphones is the robot's.
    """
    heard = _words(words)
    if not heard:
        return False
    for r in said:
        if abs(start - r.start) > onset or start > r.end:
            continue
        if level is not None and r.level is not None and level > r.level + echo_gain_db + tolerance_db:
            continue
        ref = r.words[: len(heard) + 1] if r.cut else r.words
        if ref and SequenceMatcher(None, heard, ref, autojunk=False).ratio() >= match:
            return True
    return False


class SpeechUnderstanding(Module):
    """Bus module running the semantic grammar on each recognised utterance."""

    def __init__(
        self,
        sim: Any,
        *,
        name: str = "understanding",
        host: str = "robot",
        recognition_base: float = 0.25,
        recognition_per_word: float = 0.12,
        understanding_cost: float = 0.01,
        own_voice_onset: float = 0.5,
        own_voice_match: float = 0.6,
        echo_gain_db: float = 10.5,
        echo_tolerance_db: float = 6.0,
        understander: Understander | None = None,
        typed: bool = True,
    ) -> None:
        super().__init__(sim, name, host=host)
        self._understander = understander  # None: the shared grammar, loaded when the first utterance arrives (start-up)
        # Calibrated to the papers' laptop (Fig. 6); on another host the CPU speed scales them (docs/deployment.md).
        scale = cost_scale(sim, self.name, self.bus.host)
        self.recognition_base = recognition_base * scale
        self.recognition_per_word = recognition_per_word * scale
        self.understanding_cost = understanding_cost * scale
        self.own_voice = {"onset": own_voice_onset, "match": own_voice_match, "echo_gain_db": echo_gain_db,
                          "tolerance_db": echo_tolerance_db}
        self._busy_until = 0.0
        self._robot_speech: deque[RobotSentence] = deque(maxlen=8)
        self.counts = {"utterances": 0, "understood": 0, "not_understood": 0, "own_voice": 0}
        if typed and sim.bus.channel_schema(FRAMES) is None:
            sim.bus.declare_channel(FRAMES, FRAMES_XSD)
        self.bus.subscribe(SPEECH, self._on_utterance)
        self.bus.subscribe(SPEAKER_STATUS, self._on_speaker)

    @property
    def understander(self) -> Understander:
        """The grammar this module runs (the process's shared one unless one was given)."""
        if self._understander is None:
            self._understander = shared_understander()
        return self._understander

    async def run(self) -> None:
        """Beat; utterances are handled as they are delivered."""
        while True:
            self.beat()
            await asyncio.sleep(self.heartbeat.interval if self.heartbeat else 1.0)

    def recognition_time(self, words: int) -> float:
        """Virtual seconds the recogniser needs after an utterance of ``words`` words ends."""
        return self.recognition_base + self.recognition_per_word * max(1, words)

    def _on_speaker(self, msg: Message) -> None:
        el = msg.xml
        if el.tag == "speaking":
            level = el.get("level")
            self._robot_speech.append(RobotSentence(_words(el.get("text", "")), float(el.get("start", "0")),
                                                    float(el.get("end", "0")), None if level is None else float(level)))
        elif el.tag == "interrupted":
            said = _words(el.get("text", ""))
            for r in reversed(self._robot_speech):
                if r.words == said and not r.cut:
                    r.end, r.cut = min(r.end, self.now), True
                    break

    def _on_utterance(self, msg: Message) -> None:
        xml = msg.xml
        if xml.get("self") == "true":
            return
        start, end = float(xml.get("start", "0")), float(xml.get("end", "0"))
        words = xml.text or ""
        level = xml.get("level")
        if is_own_voice(words, start, None if level is None else float(level), self._robot_speech, **self.own_voice):
            self.counts["own_voice"] += 1
            return
        conf_text = xml.get("confidence")
        if conf_text is not None:
            confidence = float(conf_text)
        else:
            confidence = 1.0 - float(xml.get("wer", "0"))
        confidence = min(1.0, max(0.0, confidence))
        n_words = len(words.split())
        now = self.now
        ready = max(now, end + self.recognition_time(n_words), self._busy_until) + self.understanding_cost
        self._busy_until = ready
        self.sim.loop.call_at_ns(to_ns(ready), self._publish, msg.id, words, start, end, confidence)

    def _publish(self, cause: str, words: str, start: float, end: float, confidence: float) -> None:
        if self.bus.closed or self.bus.hung:
            return
        u = self.understander.understand(words)
        self.counts["utterances"] += 1
        self.counts["understood" if u.frame is not None else "not_understood"] += 1
        named = calls_robot(words, self.understander.lexicon)
        rest = self.understander.understand(" ".join(u.rest)) if u.rest else None
        if rest is not None and rest.frame is None:
            rest = None
        call = named and u.frame is None and only_calls_robot(words, self.understander.lexicon)
        greeting = frame_message(u, start, end, confidence, named, call)
        if rest is not None:
            greeting.set("opens", "true")
        self.bus.publish(FRAMES, greeting, causes=(cause,), transfer=True)
        if rest is not None:
            # "hello BIRON, follow me": the request said after the greeting is a frame of its own, for
            # the dialog to handle once the greeting is taken (the ES takes a follow only from a partner)
            req = frame_message(rest, start, end, confidence, named)
            req.set("after", "greeting")
            self.bus.publish(FRAMES, req, causes=(cause,), transfer=True)
