"""The dialog manager: slot filling, policies, and a stack of sub-dialogs (no bus, no time).

Inputs are the XML the dialog module receives (frames, conditions,
rejections); outputs are :class:`Say`, :class:`Send` and :class:`Explain`
requests that the module turns into bus messages at the right virtual time.
Everything here is deterministic and synchronous, so it is tested directly.

Routing (docs/semantics.md §4, the papers' sub-dialog strategy):

* an answer goes to the topmost dialog waiting for it: "yes"/"no" to a
  pending confirmation, a frame that fills the slot a pending question asked
  for;
* any other frame starts the dialog its act triggers, on top of the stack
  (the dialog below is *interrupted*; it *resumes* when the new one ends,
  saying its resume sentence and repeating its open question, unless the
  user passed over that question in ``drop_after`` turns or the supervisor's
  state changed meanwhile: then it is dropped as abandoned, the user having
  moved on);
* a condition goes to the topmost dialog with a fill for it, else starts the
  dialog it triggers (``clears`` empties the stack first: the interaction
  ended, a technical failure);
* a rejection goes to the dialog that sent the event and becomes the
  document's most specific sentence for (event, reason, state); a rejection
  nobody waits for is still said.

Repairs: nothing understood -> the open question is asked again (up to
``max_reasks``, then the dialog gives up), or, with no open question, the
user is asked to say it again; a frame below ``confirm_below`` fills its
slot with status ``filled`` so the policy confirms it.
"""

from __future__ import annotations

from collections.abc import Callable
from copy import deepcopy
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from .model import Action, DialogDef, Dialogs, Fill, render

#: The robot never asks the same question more than twice (issue 26: confirmations that loop).
MAX_SAME_QUESTION = 2
#: talk24: an act's own words; said again (in a turn not understood) to that act's own question, a yes
_OWN_WORDS = {"GREETING": frozenset({"hello", "hi", "hey", "hallo", "hiya"}),
              "GOODBYE": frozenset({"bye", "goodbye", "bye-bye", "farewell", "goodnight"})}
#: ... nor says the same refusal outside a sub-dialog ("Please look at me and say hello first.") more
#: than twice in a row, with nothing else said and the supervisor's state unchanged in between
MAX_SAME_REFUSAL = 2
#: The sub-dialog that offers to follow her to a place it was never shown ("Sorry, I do not know where the
#: sitting room is. Shall I follow you there?", biron-dialogs.xml) and the slot that holds the offer:
#: while that question is open, her "follow me" and her go-to to the same place said again answer yes
#: (:meth:`DialogManager._offer_taken`)
OFFER_DIALOG, OFFER_SLOT = "unknown_place", "offer"


@dataclass(frozen=True, slots=True)
class Say:
    """Speech output (the module joins the sentences of one step into one utterance)."""

    text: str
    dialog: str


@dataclass(frozen=True, slots=True)
class Send:
    """An event for the supervisor; ``pose``: add the latest localisation pose."""

    event: str
    children: tuple[etree._Element, ...]
    lifetime: float | None
    pose: bool
    dialog: str


@dataclass(frozen=True, slots=True)
class Explain:
    """Self-explanation: the module asks the supervisor for its state and says what the robot can do."""

    dialog: str


Output = Say | Send | Explain


@dataclass(slots=True)
class Slot:
    status: str = "empty"
    value: Any = None
    stamp: etree._Element | None = None  # the TIMESTAMP of the utterance that filled it


#: acts that ask the robot to do nothing it could have just done (a greeting, an answer, the good-bye that ends
#: the talk): never taken as a request repeated over the robot's word that it was done
#: (:meth:`DialogManager.repeats_last_success`)
NOT_A_REQUEST = frozenset({"GREETING", "GOODBYE", "YES", "NO", "THAT_ONE"})


def _is_object(value: Any) -> bool:
    """Whether a slot holds a thing shown (an ``OBJECT`` frame), which "the one on the table" can pick out."""
    return isinstance(value, etree._Element) and value.tag == "OBJECT"


def _same(old: Any, new: Any) -> bool:
    """Whether two fills say the same thing: the same act, type and name (a paraphrase may add to it)."""
    if not (isinstance(old, etree._Element) and isinstance(new, etree._Element)):
        return old == new
    if old.tag != new.tag:
        return False
    if (old.get("type") or new.get("type")) and old.get("type") != new.get("type") and old.get("type") and new.get("type"):
        return False
    a, b = old.find(".//TITLE"), new.find(".//TITLE")
    if a is not None and b is not None and not _same_name((a.get("name") or "").lower(), (b.get("name") or "").lower()):
        return False
    return all(_same(x, y) for x, y in zip(old.findall("PLACE"), new.findall("PLACE")))


#: words in a yes that take back whose it is ("yes, but it is not mine")
_NOT_MINE = frozenset({"not", "isn't", "isnt", "n't", "never"})


def _owner_in_the_yes(value: Any, msg: etree._Element) -> None:
    """"Is this the blue mug?" - "yes, that one is mine": the yes says whose it is too (the understanding keeps
    it the yes: "that one is mine" names nothing new to show). The confirmed object without an owner gets the
    speaker as its owner; before, the owner was lost and the mug stored as nobody's (fresh12 studio_three_mugs
    seed 0). An object that has an owner keeps it; a yes without "mine", or one that denies it, adds none."""
    if not isinstance(value, etree._Element) or value.tag != "OBJECT" or value.find("OWNER") is not None:
        return
    words = (msg.findtext("words") or "").lower().replace(",", " ").replace(".", " ").split()
    if "mine" in words and not any(w in _NOT_MINE for w in words):
        owner = etree.Element("OWNER", name="speaker")
        before = [k for k, c in enumerate(value) if c.tag in ("GESTURE", "TITLE")]  # the frames' order (speech-frames.xsd)
        value.insert(before[-1] + 1 if before else 0, owner)


def _owner_left_out(old: Any, new: Any, act_el: etree._Element) -> bool:
    """Whether a repetition of a thing whose owner a confirmation named says it whole (not partial) without an
    owner: "Is this your kettle?" - "this is the kettle" (her words heard whole, no "my")."""
    return (_is_object(old) and _is_object(new) and old.find("OWNER") is not None and new.find("OWNER") is None
            and act_el.get("partial") != "true")


def _same_name(a: str, b: str) -> bool:
    """Whether two names say the same thing: equal, or one the other's last words ("alarm clock" and, said
    again shorter, "clock": "Is this your alarm clock?" - "yes, my clock" is a yes, not a correction)."""
    x, y = a.split(), b.split()
    short, long_ = (x, y) if len(x) <= len(y) else (y, x)
    return x == y or (bool(short) and long_[-len(short):] == short)


@dataclass(slots=True)
class Instance:
    """A running sub-dialog."""

    d: DialogDef
    serial: int
    slots: dict[str, Slot]
    last_sig: tuple[str, ...] | None = None
    pending: tuple[str, str, str] | None = None  # (ask|confirm, slot, question)
    reasks: int = 0
    ask_once: bool = False  # the open question is an ask put at most once (``<ask once="true">``)
    asked: dict[str, int] = field(default_factory=dict)  # how often each question was said
    passed_over: int = 0  # user turns that went to other dialogs while its question was open
    sent: list[str] = field(default_factory=list)
    rejection: tuple[str, str, str] | None = None  # (event, reason, state) of the last one
    interrupted: bool = False
    interrupted_in: str = ""  # the supervisor's state when it was interrupted
    done: bool = False
    success: bool = False
    on_end: Callable[[Instance], None] | None = None

    def values(self) -> dict[str, Any]:
        return {k: s.value for k, s in self.slots.items()}

    def sig(self) -> tuple[str, ...]:
        return tuple(s.status for s in self.slots.values())

    def holds(self, whens: tuple[tuple[str, str], ...]) -> bool:
        return all(self.slots[s].status == st for s, st in whens)


#: possessive pronouns of the third person: as an owner they refer back to the owner already named
#: ("Is this your husband's green cup?" - "Yes, his cup"), they name nobody of their own
OWNER_PRONOUNS = frozenset({"his", "her", "their"})


def _merge(old: Any, new: Any) -> Any:
    """A refilled element keeps what the new one does not say ("this is my ..." + "a cup"); an owner said as
    "his", "her" or "their" keeps the owner it refers to, or none when none was named (long22: hall_hub_long_tour seed 0 stored the cup as
    "his" and said "OK, I have learned His's green cup.")."""
    if not (isinstance(old, etree._Element) and isinstance(new, etree._Element)) or old.tag != new.tag:
        return new
    pronoun = [o for o in new.findall("OWNER") if (o.get("name") or "").lower() in OWNER_PRONOUNS]
    if pronoun:  # the owner named before stays; with none named, no owner is better than "his" (review22 R6)
        new = deepcopy(new)
        for o in new.findall("OWNER"):
            new.remove(o)
    out = deepcopy(old)
    for k, v in new.attrib.items():
        out.set(k, v)
    new_tags = {c.tag for c in new}
    for c in list(out):
        if c.tag in new_tags:
            out.remove(c)
    order = ["GESTURE", "TITLE", "OWNER", "COLOUR", "ATTRIBUTE", "USE", "POSITION"]
    kids = list(out) + [deepcopy(c) for c in new]
    for c in list(out):
        out.remove(c)
    for c in sorted(kids, key=lambda e: order.index(e.tag) if e.tag in order else len(order)):
        out.append(c)
    return out


def _owner_pronoun_resolved(old: Any, new: Any) -> Any:
    """``new`` with an owner said as "his", "her" or "their" taken as the owner ``old`` named, or as no owner when
    it named none: a pronoun names nobody of its own (review22 R6). "Is this your husband's green cup?" - "no, his
    mug" is the husband's mug; "Is this the green cup?" - "no, his mug", or "this is his cup" said unprompted, is a
    mug or cup with no owner, never "His's" (the understanding keeps the word; the dialog, which knows what was
    asked, decides)."""
    if not _is_object(new):
        return new
    pronouns = [o for o in new.findall("OWNER") if (o.get("name") or "").lower() in OWNER_PRONOUNS]
    if not pronouns:
        return new
    new = deepcopy(new)
    for o in new.findall("OWNER"):
        if (o.get("name") or "").lower() in OWNER_PRONOUNS:
            new.remove(o)
    named = [o for o in old.findall("OWNER") if (o.get("name") or "").lower() not in OWNER_PRONOUNS] \
        if _is_object(old) else []
    if named and new.find("OWNER") is None:
        at = next((i for i, c in enumerate(new) if c.tag not in ("GESTURE", "TITLE")), len(new))
        for k, o in enumerate(named):
            new.insert(at + k, deepcopy(o))
    return new


def _select(fill: Fill, el: etree._Element) -> Any:
    """The value a fill takes from ``el``: the selected node/text, or ``el`` itself; None if the select is empty."""
    if fill.select is None:
        return deepcopy(el)
    res = fill.select(el)
    if isinstance(res, list):
        if not res:
            return None
        res = res[0]
    if isinstance(res, etree._Element):
        return deepcopy(res)
    if isinstance(res, bool):
        return None if not res else "true"
    text = " ".join(str(res).split())
    return text or None


class DialogManager:
    """The sub-dialog stack over a loaded :class:`Dialogs` document."""

    def __init__(self, doc: Dialogs) -> None:
        self.doc = doc
        self.stack: list[Instance] = []
        self.es_state = ""  # the supervisor's current state, from its status channel
        self._serial = 0
        self._last_done: tuple[str, dict[str, Any], int] | None = None  # (dialog, values, user turn) of the last success
        self._unheard = 0  # user turns in a row not understood (each answered with "say that again")
        # the "Could you say that again?" waiting on her (no sub-dialog question open): its number (the
        # silence watch's key, negative beside the sub-dialogs' serials) and how often it was put in a row
        self._repair: int | None = None
        self._repairs_put = 0
        self._repair_count = 0
        self._hold_resume = False  # a turn that closes one dialog goes on to the next: no resumption speech
        self.metrics: dict[str, Any] = {
            "user_turns": 0, "robot_turns": 0, "told_again": 0, "not_understood": 0, "reasks": 0, "confirmations": 0,
            "give_ups": 0, "rejections": 0, "rejections_explained": 0, "interruptions": 0, "resumptions": 0,
            "barge_ins": 0, "dropped": 0, "events_sent": 0, "ignored_frames": 0, "unhandled_conditions": 0,
            "confirmed_by_repetition": 0, "corrections": 0, "asked_twice_gave_up": 0, "max_same_question": 0, "taken_after_repairs": 0,
            "refusals_unsaid": 0, "taken_up_in_passing": 0, "dialogs": {},
        }
        # (sentence, times in a row) of the last refusal said outside any sub-dialog (:meth:`on_rejected`)
        self._refusal: tuple[str, int] | None = None
        # what the sub-dialogs given up since the last thing done had asked: question -> times said, and
        # the values they were confirming (dialog, slot, value); a request said again takes them up
        # (:meth:`_take_up_given_up`), so a given-up question is never put a third time
        self._given_up_asked: dict[str, int] = {}
        self._given_up_values: list[tuple[str, str, Any]] = []
        # an object she showed while the robot followed her ("oh and that is my kettle", said walking on):
        # the supervisor refuses a teaching while following, so the robot asks her about it once she has
        # stopped (:meth:`take_up_in_passing`) instead of forgetting it (fresh12 item 5)
        self._in_passing: etree._Element | None = None
        self._in_passing_due = False
        self._in_passing_asked = 0  # times asked: at most twice (she may talk over the first)
        self._in_passing_next = False  # asked once: again after her next turn

    # ------------------------------------------------------------------ queries
    @property
    def top(self) -> Instance | None:
        return self.stack[-1] if self.stack else None

    def attending(self) -> bool:
        """Someone is there to talk to (the supervisor is not just looking around)."""
        s = self.doc.states.get("attending")
        return self.es_state in s if s is not None else bool(self.es_state)

    def on_state(self, state: str) -> list[str]:
        """The supervisor's new state (its status channel). A sub-dialog that lives only in some
        states (``in=``, e.g. "attending") and asked the user a question is abandoned when the
        supervisor leaves them: the person
        it asked has gone (the robot looks around again), and the next words heard, someone else's,
        must not answer its question. Returns the ids of the dialogs abandoned."""
        if state != self.es_state:
            self._refusal = None  # a new state: its refusal is news again
            if self._in_passing is not None:
                if self.es_state == "Following" and state == "Interacting":
                    self._in_passing_due = True  # she stopped: now the robot can look at what she showed
                elif state not in ("Following", "Interacting"):
                    self._in_passing, self._in_passing_due = None, False  # shown again, or the tour went on
        self.es_state = state
        gone: list[str] = []
        for inst in list(reversed(self.stack)):
            if (inst.pending is not None and inst.d.in_states is not None and state not in inst.d.in_states
                    and not inst.done):  # a dialog awaiting the supervisor's answer (good-bye) ends by it
                self._finish(inst, [], abandoned=True, resume=False)
                gone.append(inst.d.id)
        return gone

    def take_up_in_passing(self) -> list[Output]:
        """Once she has stopped after showing something while the robot followed her: ask her to show
        it again ("You showed me your kettle on the way. Could you show me again?"); her answer is an
        ordinary teaching. Asked at most twice, the second time after her next exchange (she may talk
        over the first: fresh4 loft_teach_walking_past, "And this is the kitchen" 2 s after "OK, I
        stopped."); forgotten once she shows something or the tour goes elsewhere. Nothing when nothing
        was shown in passing or a sub-dialog is open."""
        if not self._in_passing_due or self._in_passing is None or self.es_state != "Interacting":
            return []
        if any(not i.done for i in self.stack):
            return []  # a sub-dialog is still open ("OK, I stopped." not yet said, a question): after it
        obj = self._in_passing
        self._in_passing_asked += 1
        if self._in_passing_asked >= MAX_SAME_QUESTION:
            self._in_passing, self._in_passing_due = None, False
        else:
            self._in_passing_due = False  # again only after her next exchange (the next status or condition)
            self._in_passing_next = True
        out: list[Output] = []
        named = obj.find("TITLE") is not None or obj.get("type")
        self._say(out, self.doc.sentence("shown-in-passing", object=obj if named else None), "")
        self.metrics["taken_up_in_passing"] += 1
        return out

    def summary(self) -> dict[str, Any]:
        """Dialog metrics (turns, repairs, rejections explained, task success per sub-dialog)."""
        out = {k: v for k, v in self.metrics.items() if k != "dialogs"}
        out["repairs"] = self.metrics["reasks"] + self.metrics["confirmations"] + self.metrics["not_understood"]
        out["dialogs"] = {k: dict(v) for k, v in sorted(self.metrics["dialogs"].items())}
        return out

    def _count(self, did: str, key: str) -> None:
        per = self.metrics["dialogs"].setdefault(did, {"started": 0, "succeeded": 0, "failed": 0, "abandoned": 0})
        per[key] += 1

    # ------------------------------------------------------------------- inputs
    def on_frame(self, msg: etree._Element) -> list[Output]:
        """An ``<understood>`` or ``<not_understood>`` from the understanding."""
        self.metrics["user_turns"] += 1
        if self._in_passing is not None and self._in_passing_next:
            self._in_passing_due, self._in_passing_next = True, False  # asked once, she said something else
        speech = msg.find("SPEECH")
        acts = [c for c in speech if c.tag != "TIMESTAMP"] if speech is not None else []
        if msg.tag != "understood" or not acts:
            again = self._own_word_again(msg)
            if again is not None:
                return again
            return self._not_understood()
        act_el = acts[0]
        act = str(act_el.tag)
        if act == "THAT_ONE" and len(act_el) == 0 and not act_el.attrib:
            # "the one [to the table]" (the recogniser's "to" for "on"): a "which one" answer that
            # picks nothing out (no side, index, colour, place, gesture) answers no question; taken
            # as the choice it was thanked for and the object "not found" (cups_on_table seed 0)
            return self._not_understood()
        if act == "OBJECT" and self.es_state != "Following":
            self._in_passing, self._in_passing_due = None, False  # she shows something now: no need to ask
        conf = float(msg.get("confidence", "1"))
        repaired = self._unheard >= MAX_SAME_QUESTION
        if repaired and conf >= self.doc.confirm_below / 2 and self.doc.confirm_below <= 1.0:
            # she was asked to say it again twice already: what is heard now is taken, not confirmed
            # (a third question for one request; a more cautious document, confirm-below above 1, still asks)
            conf = self.doc.confirm_below
            self.metrics["taken_after_repairs"] += 1
        self._unheard = 0
        self._repair, self._repairs_put = None, 0  # understood: the request to repeat is answered
        if msg.get("partial") == "true" and act_el.get("partial") is None:
            # the understanding lost or skipped words: the policy may ask rather than act on what is
            # left ("this is the <lost word>" is no "look at this")
            act_el = deepcopy(act_el)
            act_el.set("partial", "true")
        stamp = speech.find("TIMESTAMP") if speech is not None else None
        said = msg.get("answer", "")  # "yes"/"no" before the request: "no, the kitchen"
        out: list[Output] = []
        if act == "PLACE" and msg.get("fragment") == "true":
            # a room named alone ("no, the kitchen") answers a question whether to act in its own way
            # (:meth:`_place_answer`): to the offer it is where to go, never the name of this spot
            turned = self._place_answer(msg, act_el, said)
            if turned is not None:
                act, act_el, said, msg = turned
            elif said == "no" and (asked := self._confirming()) is not None and asked.d.another_request_no \
                    and self._answered_by(act) is None:
                # "Shall I follow you?" - "no, the kitchen": the no answers it; the room alone may be a
                # teaching whose "this is" was lost or a go-to whose verb was: asked before it is stored
                conf = min(conf, self.doc.confirm_below / 2)
        offer = self._offer_taken(act, act_el, said)
        if offer is not None:
            return self._take_offer(offer)
        answered = self._answered_by(act)
        if answered is not None and said != "yes" and self._another_request(answered, act, msg):
            # "Shall I go to the kitchen?" - "this is the kitchen" (she was teaching the room; the
            # recogniser heard "to the kitchen"): a whole statement of another dialog's act is no
            # repetition of the request even where its value is the same. It says no to the
            # question and is a request of its own (below); "the kitchen" alone still confirms.
            assert answered.pending is not None
            answered.slots[answered.pending[1]].status = "false"
            answered.pending, answered.reasks, answered.passed_over = None, 0, 0
            self.metrics["corrections"] += 1
            # the dialog below does not resume with its question now: this turn goes on to it (it may
            # answer that question, "Is this the study?" - "this is my study") or starts its own
            self._hold_resume = True
            try:
                self._step(answered, out)
            finally:
                self._hold_resume = False
            answered = self._answered_by(act)
            if answered is not None:
                answered.interrupted = False  # taken up again by this very turn
            said = ""  # the implied no answered the question; a "no" said aloud answered it too
        if answered is None and said and self._confirming() is not None:
            # "no, go to the kitchen" to "Shall I follow you?": the no answers it, the rest is new
            top = self._confirming()
            assert top is not None and top.pending is not None
            top.passed_over = 0
            top.slots[top.pending[1]].status = "true" if said == "yes" else "false"
            top.pending = None
            self._something_done()
            if said == "yes" and act in ("GOODBYE", "FOLLOW") and act not in top.d.trigger:
                # "yes, off you go" / "okay, bye then" to "Shall I go to the lounge?" (or to "Is this your cup?"):
                # the send-off or closing word is how she says yes, never a good-bye of its own (fresh11: the go-to
                # was begun and the tour ended at once). To "Do you want to end the tour?" the yes ends it anyway.
                # So is a follow carried by a yes ("yes, come on": go on, do it) to another dialog's question: one
                # answer, one action (review25 F-I: the go-to and a follow were both sent); to "Shall I follow
                # you?" the follow's own dialog takes it above.
                self._step(top, out)
                return out
            # as above: the rest of this turn goes on to the dialog below (it may answer its open
            # question: "Is this the kitchen?" - "follow me" - "no, the kitchen"), so that dialog does
            # not resume with its question first (it was asked, then asked again by the rest)
            self._hold_resume = True
            try:
                self._step(top, out)
            finally:
                self._hold_resume = False
            answered = self._answered_by(act)
            if answered is not None:
                answered.interrupted = False
                said = ""
        if answered is None and not said and msg.get("fragment") != "true":
            self._superseded(act, out)
        for inst in self.stack:
            if inst.pending is not None:
                inst.passed_over = 0 if inst is answered else inst.passed_over + 1
        # 1. an answer to the topmost open question
        if answered is not None and answered.pending is not None:
            kind, slot, _ = answered.pending
            answered.pending = None
            answered.reasks = 0
            if kind == "confirm" and act in ("YES", "NO"):
                answered.slots[slot].status = "true" if act == "YES" else "false"
                if act == "YES":
                    _owner_in_the_yes(answered.slots[slot].value, msg)
                self._something_done()
            elif kind == "confirm" and act == "THAT_ONE":
                self._confirm_by_choice(answered, slot, act_el, said)
            elif kind == "confirm":
                self._confirm_by_frame(answered, slot, act, act_el, conf, said, stamp)
            else:
                # "This is my <lost word>" - "What is it?" - "It is a teapot": the answer completes the request,
                # and the pointing went with the request. The slots it had filled keep when it was said, so the
                # object attention looks back to that gesture, as after a yes to "Is this ...?" (below,
                # _confirm_by_frame). With the answer's time the gesture was lost: the robot searched round her
                # and covered the room for 40 s before asking her to step aside (flow/follow_while_looking 2, 4).
                # A gesture she makes with the answer ("this is a teapot", pointing again) is later than the
                # request, so the look back from the request's start sees it too (the largest group of rays).
                kept = {n: s.stamp for n, s in answered.slots.items() if s.stamp is not None and s.status != "empty"}
                self._fill_frame(answered, [f for f in answered.d.fills if f.frame and act in f.frame], act_el, conf,
                                 stamp)
                for n, old in kept.items():
                    answered.slots[n].stamp = old
                if answered.ask_once and answered.slots[slot].status == "empty":
                    # "What is it?" - "this is my <lost word>" again: the same word lost twice; asking a
                    # third time does not converge, so the policy goes on without it (the camera says what)
                    answered.slots[slot].status = "false"
            self._step(answered, out)
            return out
        # 2. a new sub-dialog
        d = self.doc.by_trigger(act)
        if d is None:
            if not out and act == "THAT_ONE" and msg.get("fragment") == "true":
                # "closer please", "turn left", "further": a side alone answers only a which-one question
                # (none is open); said now she asks for something the robot did not understand
                return self._not_understood()
            if not out and (msg.get("partial") == "true" or msg.get("unknown")):
                # words the understanding could not use around an answer nobody asked for ("alright
                # you can stop there we have arrived" heard as a bare "alright"): she asked for
                # something; silence would leave her waiting, so the robot asks to hear it again
                return self._not_understood()
            self.metrics["ignored_frames"] += 1
            return out
        if d.in_states is not None and self.es_state not in d.in_states:
            # Nobody to talk to (as far as the dialog knows): the instruction still goes to the
            # supervisor, which decides (the papers: the ES rejects what does not apply in its
            # state, and the rejection comes back so the dialog can say why). A question with
            # nothing to send (self-explanation) is ignored.
            return self._send_unattended(d, act_el, out, stamp)
        if said == "no":
            act_el = self._correcting(d.id, act_el)
        if msg.get("fragment") == "true" and (msg.get("partial") == "true" or msg.get("unknown")) and not said \
                and not repaired:
            # a noun phrase said unprompted with words the grammar could not use ("the study, go",
            # "the garden looks great") names a thing without saying what to do with it (the vague
            # user's "the study, go" taught the study where the robot stood): the robot asks first.
            # A clean "the kitchen" (the recogniser often drops "this is") is taken as before.
            conf = min(conf, self.doc.confirm_below / 2)
        busy = self._carrying_out(d, act, act_el)
        if busy is not None and said != "no":
            # the same request again while the robot carries it out (she repeats her teaching when "I have
            # learned" has not come yet, generated tour 8900-1): not a new request; replacing it restarted
            # the look and its "OK, I have learned" was never said. The robot says it is still at it.
            if any(r.state == self.es_state and r.score(busy.sent[-1], "", self.es_state) >= 0 for r in self.doc.rejections):
                # the words of the state it is busy in ("I am still looking at the object you showed me")
                self._say(out, self.doc.rejection_text(busy.sent[-1], "", self.es_state), busy.d.id)
            return out
        # the same request again while its own confirmation waits below another question ("Is this
        # the kitchen?" - "follow me" - "this is the kitchen"): two hearings agree, as when it answers
        # the question directly; the new instance keeps the old one's count of questions asked
        prior = next((i for i in reversed(self.stack) if i.d is d and i.pending is not None), None)
        inst = self._push(d, out)
        self._fill_frame(inst, [f for f in d.fills if f.frame and act in f.frame], act_el, conf, stamp)
        if prior is not None:
            for q, n in prior.asked.items():
                inst.asked[q] = max(inst.asked.get(q, 0), n)
            kind, slot = prior.pending[0], prior.pending[1]  # type: ignore[index]
            if (kind == "confirm" and said != "no" and inst.slots[slot].status == "filled"
                    and _same(prior.slots[slot].value, inst.slots[slot].value)):
                inst.slots[slot].status = "true"
                self.metrics["confirmed_by_repetition"] += 1
        self._take_up_given_up(inst, said)
        self._step(inst, out)
        return out

    def _offer_open(self) -> Instance | None:
        """The offer to follow her to a place it was never shown, when its question is the topmost open one."""
        top = next((i for i in reversed(self.stack) if i.pending is not None), None)
        if top is None or top.d.id != OFFER_DIALOG or top.pending != ("confirm", OFFER_SLOT, top.pending[2]):
            return None
        return top

    def _place_answer(self, msg: etree._Element, place: etree._Element, said: str) \
            -> tuple[str, etree._Element, str, etree._Element] | None:
        """A room named alone (a noun phrase, ``fragment``: "no, the kitchen", "the kitchen") while the offer
        ("Sorry, I do not know where the sitting room is. Shall I follow you there?") is open: the question was
        where to go, so the room is where she wants the robot, as "Shall I go to the kitchen?" - "no, the
        bathroom" is a go-to to the bathroom. Another room: a go-to to it (the offer ends unsaid; a room it was
        never shown is offered again); the offered room again: a yes, or with "no" a no. Never the name of the
        spot the robot stands in (review22 R3: "no, the kitchen" stored this spot as the kitchen). Returns the
        (act, element, answer, message) the turn is taken as, or None when no offer is open."""
        inst = self._offer_open()
        if inst is None:
            return None
        if _same(inst.slots[OFFER_SLOT].value, place) and said == "no":
            act_el = etree.Element("NO")
        else:
            act_el = etree.Element("GOTO")
            if place.get("partial") is not None:
                act_el.set("partial", str(place.get("partial")))
            kept = deepcopy(place)
            kept.attrib.pop("partial", None)
            act_el.append(kept)
        msg = deepcopy(msg)
        for k in ("fragment", "answer"):
            msg.attrib.pop(k, None)
        return str(act_el.tag), act_el, "", msg

    def _offer_taken(self, act: str, act_el: etree._Element, said: str) -> Instance | None:
        """The open offer to follow her to a place it was never shown that this frame answers yes, or None.

        "Shall I follow you there?" - "follow me" is yes (without this the follow dialog started on top and
        the offer waited below it). "Now come into the sitting room" said again is yes too: she still wants
        the robot in a room only she knows the way to (fresh9/bay_long_tour: her repetition was a new go-to,
        the same "Sorry", and she walked on alone). A go-to to another place, or a "no" first, is not."""
        if said == "no" or act not in ("FOLLOW", "GOTO"):
            return None
        top = self._offer_open()
        if top is None:
            return None
        if act == "GOTO":
            place = act_el.find(".//PLACE") if act_el.tag != "PLACE" else act_el
            if place is None or not _same(top.slots[OFFER_SLOT].value, place):
                return None
        return top

    def _take_offer(self, inst: Instance) -> list[Output]:
        """Her answer taken as yes to the offer: the offer dialog follows her (``_offer_taken``)."""
        out: list[Output] = []
        for other in self.stack:
            if other.pending is not None and other is not inst:
                other.passed_over += 1
        inst.pending, inst.reasks, inst.passed_over = None, 0, 0
        inst.slots[OFFER_SLOT].status = "true"
        self.metrics["confirmed_by_repetition"] += 1
        self._something_done()
        self._step(inst, out)
        return out

    def _take_up_given_up(self, inst: Instance, said: str) -> None:
        """A request said again after its sub-dialog gave up ("Is this the kitchen?" asked twice, nothing
        understood, "Sorry, let us leave that for now.", then "this is the kitchen" again): the given-up
        dialog is gone from the stack, but what it asked is not. The same question is the same words
        whichever sub-dialog says them, so the new instance starts with the given-up counts (the policy
        never puts a question a third time), and the same value it was confirming, heard again, is two
        hearings that agree: confirmed, as when the request is repeated while its question is open."""
        for q, n in self._given_up_asked.items():
            inst.asked[q] = max(inst.asked.get(q, 0), n)
        if said == "no":
            return
        for did, slot, value in self._given_up_values:
            mine = inst.slots.get(slot)
            if did == inst.d.id and mine is not None and mine.status == "filled" and _same(value, mine.value):
                mine.status = "true"
                self.metrics["confirmed_by_repetition"] += 1
                return

    def _give_up(self, inst: Instance, out: list[Output]) -> None:
        """End ``inst`` unfinished ("Sorry, let us leave that for now."), remembering what it asked and
        the values it was confirming until something is done (:meth:`_take_up_given_up`)."""
        self.metrics["give_ups"] += 1
        for q, n in inst.asked.items():
            self._given_up_asked[q] = max(self._given_up_asked.get(q, 0), n)
        if inst.pending is not None and inst.pending[0] == "confirm":
            slot = inst.slots.get(inst.pending[1])
            if slot is not None and slot.status == "filled":
                # bounded: the last few given-up confirmations are all a repetition can take up
                self._given_up_values = [*self._given_up_values[-3:], (inst.d.id, inst.pending[1], slot.value)]
        inst.pending = None
        self._say(out, self.doc.sentence("give-up"), inst.d.id)
        self._finish(inst, out, abandoned=False)

    def _something_done(self) -> None:
        """An event sent or a question answered yes or no: a given-up question may be asked afresh."""
        self._given_up_asked.clear()
        self._given_up_values.clear()

    @property
    def last_success(self) -> tuple[str, dict[str, Any], int] | None:
        """(sub-dialog id, slot values, user turns then) of the last sub-dialog that reached its goal."""
        return self._last_done

    def repeats_last_success(self, msg: etree._Element) -> bool:
        """Whether frame ``msg`` asks again for what the last successful sub-dialog has just done: her next
        turn since (no other turn between), a request of that sub-dialog (not a greeting or an answer) that
        says the same (:func:`_same` on a slot its whole frame fills). The module decides whether she can
        have heard the robot say it was done (:meth:`Dialog._told_again`)."""
        last = self._last_done
        if last is None or msg.tag != "understood" or self.metrics["user_turns"] != last[2]:
            return False
        speech = msg.find("SPEECH")
        acts = [c for c in speech if c.tag != "TIMESTAMP"] if speech is not None else []
        if not acts or str(acts[0].tag) in NOT_A_REQUEST:
            return False
        act = str(acts[0].tag)
        d = self.doc.by_trigger(act)
        if d is None or d.id != last[0]:
            return False
        whole = [f for f in d.fills if f.frame and act in f.frame and f.select is None]
        return any(_same(last[1].get(f.slot), acts[0]) for f in whole if last[1].get(f.slot) is not None)

    def told_again(self) -> None:
        """Her request repeated over the robot's word that it was done: counted as her turn (metrics)."""
        self.metrics["user_turns"] += 1
        self.metrics["told_again"] += 1
        if self._last_done is not None:
            self._last_done = (self._last_done[0], self._last_done[1], self.metrics["user_turns"])

    def _correcting(self, did: str, act_el: etree._Element) -> etree._Element:
        """"No, this is the bedroom" right after "OK, this is the kitchen. I will remember it.": the
        new teaching says which name it replaces (``replaces=``), so the knowledge base renames the
        place instead of keeping both."""
        last = self._last_done
        if last is None or last[0] != did or self.metrics["user_turns"] - last[2] > 1:
            return act_el
        old = next((v for v in last[1].values() if isinstance(v, etree._Element) and v.tag == act_el.tag), None)
        old_title = old.find("TITLE") if old is not None else None
        new_title = act_el.find("TITLE")
        if old_title is None or new_title is None or old_title.get("name") == new_title.get("name"):
            return act_el
        act_el = deepcopy(act_el)
        act_el.set("replaces", old_title.get("name", ""))
        self.metrics["corrections"] += 1
        return act_el

    def _another_request(self, inst: Instance, act: str, msg: etree._Element) -> bool:
        """Whether a frame that fits ``inst``'s open confirmation is a request of another dialog instead.

        A noun phrase alone (``fragment``) answers whatever asked for it; a whole statement
        ("this is the kitchen", "we are in the kitchen") is the request of the dialog its act
        triggers, and confirms only that dialog's question.
        """
        if inst.pending is None or inst.pending[0] != "confirm" or act in ("YES", "NO") or act in inst.d.trigger:
            return False
        if msg.get("fragment") == "true":
            return False
        own = self.doc.by_trigger(act)
        return own is not None and own is not inst.d

    def _superseded(self, act: str, out: list[Output]) -> None:
        """Another request said while a confirmation of a request to act is open answers it no.

        "Do you want to end the tour?" - "follow me": she wants the tour to go on; before, the question
        waited below the follow and her next "yes" or "okay" (to anything) ended the tour (fresh10
        open_fast_crossing). Only a yes-word, the asked request again or its paraphrase confirm
        (:meth:`_answered_by`); a request of another dialog that sends an event (follow, go to, stop, a
        teaching, a where-question) is hers instead. The question ends silently (no "OK, I will stay
        here." to a go-to): the new request's own answer follows. Dialogs without ``another-request="no"``
        (a teaching's "Is this the kitchen?") keep their question open below, to be answered later."""
        top = self._confirming()
        new = self.doc.by_trigger(act)
        if top is None or not top.d.another_request_no or new is None or new is top.d \
                or not any(a.kind == "send" for r in new.rules for a in r.actions):
            return
        assert top.pending is not None
        top.slots[top.pending[1]].status = "false"
        top.pending, top.reasks, top.passed_over = None, 0, 0
        self.metrics["superseded"] = self.metrics.get("superseded", 0) + 1
        self._something_done()
        # what it asked is still asked: the same request said again after the new one must not put its question a
        # third time (the CI profile's example: "follow me", "what can you do", "this is the kitchen", "follow me",
        # each heard poorly, said "Shall I follow you?" three times; :meth:`_take_up_given_up` starts from these)
        for q, n in top.asked.items():
            self._given_up_asked[q] = max(self._given_up_asked.get(q, 0), n)
        self._finish(top, out, abandoned=True, resume=False)

    def _own_word_again(self, msg: etree._Element) -> list[Output] | None:
        """A turn not understood, said while the greeting's or the good-bye's own question is open ("Did you
        say hello to me?", "Do you want to end the tour?"), that holds that act's own word ("hello", "hi";
        "bye", "goodbye"): she said it again, as people do, with more words the understanding lost; a yes
        (talk24: "Sorry, I did not understand you. Do you want to end the tour?" to a repeated good-bye).
        None when no such question is open, the turn was said to someone else, or the word is not there."""
        top = self._confirming()
        if top is None or top.pending is None or msg.get("addressee") == "other":
            return None
        heard = set("".join(c if c.isalpha() or c == "'" else " " for c in (msg.text or "").lower()).split())
        if not any(act in top.d.trigger and heard & words for act, words in _OWN_WORDS.items()):
            return None
        top.passed_over, top.reasks = 0, 0
        top.slots[top.pending[1]].status = "true"
        top.pending = None
        self._unheard = 0
        self._repair, self._repairs_put = None, 0
        self._something_done()
        self.metrics["confirmed_by_repetition"] += 1
        out: list[Output] = []
        self._step(top, out)
        return out

    def _confirming(self) -> Instance | None:
        """The dialog whose confirmation question is the topmost open question, if any."""
        for inst in reversed(self.stack):
            if inst.pending is not None:
                return inst if inst.pending[0] == "confirm" else None
        return None

    def _confirm_by_frame(self, inst: Instance, slot: str, act: str, act_el: etree._Element, conf: float,
                          said: str, stamp: etree._Element | None) -> None:
        """A request said again while its confirmation is open ("Shall I follow you?" - "could you
        follow me please"; "Is this the kitchen?" - "no, the living room").

        The same request again, in any words, confirms it: two hearings agree. Other content
        corrects it: the new value fills the slot as any frame does (confirmed again when heard
        with low confidence). A "no" before the same content is a no.
        """
        fills = [f for f in inst.d.fills if f.frame and act in f.frame]
        old = inst.slots[slot].value
        new = next((v for v in (_select(f, act_el) for f in fills if f.slot == slot) if v is not None), None)
        same = new is not None and _same(old, new)
        unowned = same and _owner_left_out(old, new, act_el)
        if unowned and said == "no":
            # "Is this your kettle?" - "no, the kettle": the thing is right, whose it is was not (a guess
            # from a lost word, robot/speech/grammar.py _determiner_lost): the same thing, no owner. A
            # correction with a deictic word of its own ("no, that cup") points anew: it keeps its own time,
            # so the object attention looks at that gesture, not the first one (review23 N2; issue 26 item 5)
            kept = inst.slots[slot].stamp if act_el.find("GESTURE") is None else None
            self._fill_frame(inst, fills, act_el, conf, stamp, replace=True)
            if kept is not None:
                inst.slots[slot].stamp = kept
            inst.slots[slot].status = "true"
            self.metrics["corrections"] += 1
        elif same and said != "no":
            kept = inst.slots[slot].stamp
            self._fill_frame(inst, fills, act_el, conf, stamp)
            if unowned:
                # "Is this your kettle?" - "this is the kettle", said again whole without "my": she says
                # what it is and not that it is hers; the owner the question named is dropped
                value = inst.slots[slot].value
                for o in value.findall("OWNER"):
                    value.remove(o)
            if kept is not None:
                # "Is this your clock?" - "yes, my clock": the pointing went with the request, not with the
                # yes; the event keeps when the request was said, so the object attention looks back to
                # that gesture (fresh7 split_talkative_hidden: the yes's time lost it, "could not find").
                # Also when the yes has a deictic word ("yes, that's my bag"): the word is no gesture, and
                # one she makes with the yes is later than the request, so the look back from the request's
                # start sees it too (fresh10 hall_wardrobe_bags: the yes's time lost the gesture behind her,
                # the robot searched round her for 12 s and asked her to step aside too late, 9 of 10 runs)
                inst.slots[slot].stamp = kept
            inst.slots[slot].status = "true"
            self.metrics["confirmed_by_repetition"] += 1
        elif same:
            inst.slots[slot].status = "false"
        else:
            self._fill_frame(inst, fills, act_el, conf, stamp, replace=True)
            self.metrics["corrections"] += 1
            inst.last_sig = None  # the same slot statuses with a new value: the policy acts again (confirms it)

    def _confirm_by_choice(self, inst: Instance, slot: str, choice: etree._Element, said: str) -> None:
        """"Is this your cup?" - "the one on the table" (or "the left one", "the red one"): an answer
        that says which one takes the thing asked about as meant (a yes) and adds how she picked it
        out, so the object attention looks for that one. "No, the one on the table" is a no."""
        if said == "no":
            inst.slots[slot].status = "false"
            return
        obj = deepcopy(inst.slots[slot].value)
        for child in choice:
            if obj.find(str(child.tag)) is None or child.tag in ("ATTRIBUTE", "POSITION"):
                obj.append(deepcopy(child))
        if choice.get("side") and obj.get("side") is None:
            obj.set("side", str(choice.get("side")))
        inst.slots[slot].value, inst.slots[slot].status = obj, "true"
        self.metrics["confirmed_by_choice"] = self.metrics.get("confirmed_by_choice", 0) + 1
        self._something_done()

    def _send_unattended(self, d: Any, act_el: etree._Element, out: list[Output],
                         stamp: etree._Element | None = None) -> list[Output]:
        """Send the sub-dialog's event for an instruction heard outside its states, without starting it
        (with the utterance's TIMESTAMP, as every SPEECH the dialog sends: the papers' frames carry it)."""
        send = next((a for r in d.rules for a in r.actions if a.kind == "send" and a.event), None)
        if send is None:
            self.metrics["ignored_frames"] += 1
            return out
        speech = etree.Element("SPEECH")
        if stamp is not None:
            speech.append(deepcopy(stamp))
        speech.append(deepcopy(act_el))
        self.metrics["events_sent"] += 1
        self.metrics["sent_unattended"] = self.metrics.get("sent_unattended", 0) + 1
        out.append(Send(send.event or "", (speech,), send.lifetime, send.pose, d.id))
        return out

    def on_condition(self, cond: etree._Element) -> list[Output]:
        """A condition from the supervisor (``<condition name ...><param>...``)."""
        name = cond.get("name", "")
        out: list[Output] = []
        d = self.doc.by_condition(name)
        for inst in reversed(self.stack):
            fills = [f for f in inst.d.fills if f.condition == name]
            if fills:
                self._fill_other(inst, fills, cond)
                if d is not None and d.clears:
                    # the interaction is over (good-bye agreed): the dialog that waited for it says its
                    # last words and the rest ends with it, unresumed (an object teaching waiting for a
                    # search the ES cancelled said "Now, back to your kettle." after every later sentence)
                    held, self._hold_resume = self._hold_resume, True
                    try:
                        self._step(inst, out)
                    finally:
                        self._hold_resume = held
                    while self.stack:
                        self._finish(self.stack[-1], out, abandoned=True, resume=False)
                else:
                    self._step(inst, out)
                return out
        if d is None:
            self.metrics["unhandled_conditions"] += 1
            return out
        if d.clears:
            while self.stack:
                self._finish(self.stack[-1], out, abandoned=True, resume=False)
        inst = self._push(d, out)
        self._fill_other(inst, [f for f in d.fills if f.condition == name], cond)
        self._step(inst, out)
        return out

    def on_rejected(self, rej: etree._Element) -> list[Output]:
        """A rejected event returned by the supervisor (``<rejected name reason state>``)."""
        name, reason, state = rej.get("name", ""), rej.get("reason", ""), rej.get("state", "")
        self.metrics["rejections"] += 1
        out: list[Output] = []
        for inst in reversed(self.stack):
            fills = [f for f in inst.d.fills if f.rejected == name]
            if fills and name in inst.sent:
                shown = inst.slots.get("object")
                if name == "object_teaching" and state == "Following" and shown is not None \
                        and isinstance(shown.value, etree._Element):
                    self._in_passing, self._in_passing_due = deepcopy(shown.value), False
                    self._in_passing_asked, self._in_passing_next = 0, False
                inst.rejection = (name, reason, state)
                self._fill_other(inst, fills, rej)
                self._step(inst, out)
                if not any(isinstance(o, Say) for o in out):
                    self._say(out, self.doc.rejection_text(name, reason, state), inst.d.id)
                self.metrics["rejections_explained"] += 1
                return out
        # No refusal a third time in a row (the same sentence, nothing else said, the state unchanged):
        # words nobody can take back (a TV's "stay with us ..." heard while it looks around) would
        # otherwise get "Please look at me and say hello first." every few seconds; she heard it twice.
        text = self.doc.rejection_text(name, reason, state)
        times = self._refusal[1] if self._refusal is not None and self._refusal[0] == text else 0
        self.metrics["rejections_explained"] += 1
        if times >= MAX_SAME_REFUSAL:
            self.metrics["refusals_unsaid"] += 1
            return out
        self._say(out, text, "")
        self._refusal = (text, times + 1)
        return out

    def start(self, did: str, values: dict[str, Any] | None = None,
              on_end: Callable[[Instance], None] | None = None,
              asked: dict[str, int] | None = None) -> tuple[Instance | None, list[Output]]:
        """Start dialog ``did`` directly (e.g. a clarification), its slots preset to ``values`` (status true).

        ``asked``: how often each question was said already by the sub-dialog this one asks again for
        (the object attention's second putting of a which-one question): the same question is the
        same words whichever instance says them, so the policy never puts it a third time in all.

        Raises ValueError for a value of a slot the dialog does not have (nothing is started)."""
        out: list[Output] = []
        d = self.doc.dialogs.get(did)
        if d is None:
            return None, out
        unknown = sorted(set(values or {}) - set(d.slots))
        if unknown:
            raise ValueError(f"dialog {did!r} has no slot {', '.join(unknown)} (slots: {', '.join(d.slots)})")
        inst = self._push(d, out)
        inst.on_end = on_end
        for k, v in (values or {}).items():
            inst.slots[k] = Slot("true", v)
        for q, n in (asked or {}).items():
            inst.asked[q] = max(inst.asked.get(q, 0), n)
        self._step(inst, out)
        return inst, out

    def mark(self, inst: Instance, slot: str, on: bool) -> None:
        """Set (``on``: status true) or clear the slot ``slot`` of the running ``inst`` that the module
        decides, not the words: the clarify dialog's ``unchosen`` (the answer about to come picks none
        of the options: no "Thank you." for it, the asker asks again). No slot of that name: nothing."""
        if slot in inst.slots:
            inst.slots[slot] = Slot("true", True) if on else Slot()

    def cancel(self, inst: Instance, *, quiet: bool = False) -> list[Output]:
        """Abandon a running dialog (e.g. a clarification that timed out). ``quiet``: the dialog below goes on
        without its resume phrase or question said again (its asker puts the next question itself)."""
        out: list[Output] = []
        if inst in self.stack:
            was_top = self.stack[-1] is inst
            self._finish(inst, out, abandoned=True, resume=not quiet)
            if quiet and was_top and self.stack:
                self.stack[-1].interrupted = False
        return out

    def barge_in(self) -> None:
        """The partner spoke while the robot talked (the module cut the robot's sentence)."""
        self.metrics["barge_ins"] += 1

    def explanation(self, state: str, applies: list[str], waits: tuple[str, ...] | list[str] = ()) -> str:
        """What the robot is doing and can do now, from the supervisor's state and the events it takes.

        ``applies``: events the current state applies at once; ``waits``: events
        it keeps until another state of its category (a greeting waits for a
        potential partner). Waiting events are offered only when none of the
        dialog's events applies now (while following, a waiting "this is my
        cup" is no capability to advertise).
        """
        parts = []
        phrase = self.doc.state_phrases.get(state)
        if phrase:
            parts.append(phrase)
        caps = [text for e, text in self.doc.capabilities.items() if e in applies]
        if not caps:
            caps = [text for e, text in self.doc.capabilities.items() if e in waits]
        if caps:
            parts.append(self.doc.sentence("can-now", capabilities=self.doc.listing(caps)))
        return " ".join(parts) if parts else self.doc.rejection_text("", "", state)

    # ---------------------------------------------------------------- internals
    def _answered_by(self, act: str) -> Instance | None:
        """The dialog whose open question a frame of ``act`` answers, or None (only the topmost open question takes answers)."""
        for inst in reversed(self.stack):
            if inst.pending is None:
                continue
            kind, slot, _ = inst.pending
            if kind == "confirm" and act in ("YES", "NO"):
                return inst
            if kind == "confirm" and act == "THAT_ONE" and _is_object(inst.slots[slot].value):
                return inst  # "Is this your cup?" - "the one on the table": yes, and which one
            fills = [f for f in inst.d.fills if f.frame and act in f.frame]
            if fills and (kind == "ask" or any(f.slot == slot for f in fills)):
                return inst
            return None
        return None

    def open_question(self) -> tuple[int, str] | None:
        """(serial, question) of the question the top sub-dialog waits on (None: none, or one the
        sub-dialog times itself: ``clarify``'s answer has the asker's own timeout)."""
        inst = self.top
        if inst is None or inst.pending is None:
            if self._repair is not None and not any(i.pending is not None for i in self.stack):
                return -self._repair, self.doc.not_understood  # "Could you say that again?" waits too
            return None
        if inst.d.id == "clarify":
            return None
        return inst.serial, inst.pending[2]

    def on_silence(self, serial: int, question: str) -> list[Output]:
        """Nothing was heard for a while after ``question`` (issue 26 item 7): put it once more, and when
        it was put twice already, go on without it ("Sorry, let us leave that for now."): never the same
        question a third time, never waiting on it for ever."""
        out: list[Output] = []
        if serial < 0:
            return self._repair_met_by_silence(-serial)
        inst = self.top
        if inst is None or inst.serial != serial or inst.pending is None or inst.pending[2] != question:
            return out  # answered, or another question by now
        self.metrics["silence_reasks"] = self.metrics.get("silence_reasks", 0) + 1
        if self._may_ask(inst, question, out):
            self._say(out, question, inst.d.id)
        return out

    def _repair_met_by_silence(self, repair: int) -> list[Output]:
        """"Could you say that again?" and nothing heard (the reviewer's F4: the robot's most frequent
        question): the same rule as for a sub-dialog's question, put once more, and when it was put twice
        in a row already, go on politely ("Sorry, let us leave that for now."), never a third time."""
        out: list[Output] = []
        if repair != self._repair or self.open_question() != (-repair, self.doc.not_understood):
            return out  # answered, or another question by now
        if not self.attending():
            self._repair = None  # nobody to ask any more
            return out
        self.metrics["silence_reasks"] = self.metrics.get("silence_reasks", 0) + 1
        if self._repairs_put < MAX_SAME_QUESTION:
            self._repairs_put += 1
            self.metrics["max_same_question"] = max(self.metrics["max_same_question"], self._repairs_put)
            self._say(out, self.doc.not_understood, "")
        else:
            self.metrics["asked_twice_gave_up"] += 1
            self._repair, self._repairs_put = None, 0
            self._say(out, self.doc.sentence("give-up"), "")
        return out

    def _may_ask(self, inst: Instance, question: str, out: list[Output]) -> bool:
        """Count a question about to be asked; the third time the same question would be asked,
        the dialog gives up instead ("Sorry, let us leave that for now."): no question loops."""
        n = inst.asked.get(question, 0)
        if n >= MAX_SAME_QUESTION:
            self.metrics["asked_twice_gave_up"] += 1
            self._give_up(inst, out)
            return False
        inst.asked[question] = n + 1
        self.metrics["max_same_question"] = max(self.metrics["max_same_question"], n + 1)
        return True

    def _say(self, out: list[Output], text: str, did: str) -> None:
        if text:
            out.append(Say(text, did))
            self._refusal = None  # something else was said (on_rejected sets it again after its own)

    def _not_understood(self) -> list[Output]:
        out: list[Output] = []
        self.metrics["not_understood"] += 1
        self._unheard += 1
        for inst in reversed(self.stack):
            if inst.pending is None:
                continue
            inst.reasks += 1
            if inst.reasks > self.doc.max_reasks:
                self._give_up(inst, out)
            elif self._may_ask(inst, inst.pending[2], out):
                self.metrics["reasks"] += 1
                # the question said again is the request to repeat: the apology alone before it (with
                # "Could you say that again?" each re-ask was one more question in the dialog, and three
                # questions re-asked once each put it to the user a third time)
                self._say(out, self.doc.sentence("not-understood-reask") or self.doc.not_understood, inst.d.id)
                self._say(out, inst.pending[2], inst.d.id)
            return out
        if self.attending():
            help_ = self.doc.sentence("not-understood-help")
            if help_ and self._unheard > MAX_SAME_QUESTION and self._unheard % (MAX_SAME_QUESTION + 1) == 0:
                # "Could you say that again?" twice in a row already: not a third time, but what she can say
                self.metrics["help_given"] = self.metrics.get("help_given", 0) + 1
                self._repair, self._repairs_put = None, 0  # what she can say: no question to put again
                self._say(out, help_, "")
                return out
            self.metrics["reasks"] += 1
            if self.doc.not_understood:
                # a request to repeat waits on her like a question (the silence watch, on_silence)
                self._repair_count += 1
                self._repair = self._repair_count
                self._repairs_put += 1
            self._say(out, self.doc.not_understood, "")
        return out

    def _carrying_out(self, d: DialogDef, act: str, act_el: etree._Element) -> Instance | None:
        """The running instance of ``d`` whose request the robot is carrying out (its event sent, its goal
        not reached, no question of its own open) when ``act_el`` asks for the same again (:func:`_same`
        on the slot the whole frame fills); None otherwise."""
        whole = [f for f in d.fills if f.frame and act in f.frame and f.select is None]
        for inst in reversed(self.stack):
            if inst.d is not d or inst.done or not inst.sent or inst.pending is not None or inst.holds(d.goal):
                continue
            for f in whole:
                slot = inst.slots.get(f.slot)
                if slot is not None and slot.status in ("true", "filled") and _same(slot.value, act_el):
                    return inst
        return None

    def _push(self, d: DialogDef, out: list[Output]) -> Instance:
        for old in [i for i in self.stack if i.d.id == d.id]:  # said again: the new request replaces the old
            self._finish(old, out, abandoned=True, resume=False)
        while len(self.stack) >= self.doc.max_depth:
            self._finish(self.stack[0], out, abandoned=True, resume=False)
        if self.stack:
            self.stack[-1].interrupted = True
            self.stack[-1].interrupted_in = self.es_state
            self.metrics["interruptions"] += 1
        self._serial += 1
        inst = Instance(d, self._serial, {s: Slot() for s in d.slots})
        self.stack.append(inst)
        self._count(d.id, "started")
        return inst

    def _fill_frame(self, inst: Instance, fills: list[Fill], act_el: etree._Element, conf: float,
                    stamp: etree._Element | None = None, *, replace: bool = False) -> None:
        for f in fills:
            value = _select(f, act_el)
            if value is None:
                continue
            slot = inst.slots[f.slot]
            status = f.status or ("true" if conf >= self.doc.confirm_below else "filled")
            value = _owner_pronoun_resolved(slot.value if slot.status != "false" else None, value)
            slot.value = _merge(slot.value, value) if slot.status != "false" and not replace else value
            slot.status = status
            slot.stamp = stamp

    def _fill_other(self, inst: Instance, fills: list[Fill], el: etree._Element) -> None:
        for f in fills:
            value = _select(f, el)
            if value is None and f.select is not None:
                continue
            slot = inst.slots[f.slot]
            if f.status is not None:
                slot.status = f.status
            elif f.test is not None:
                slot.status = "true" if bool(f.test(el)) else "false"
            else:
                slot.status = "true"
            slot.value = value

    def _step(self, inst: Instance, out: list[Output]) -> None:
        """Fire the policy while the state changes (each state fires at most once)."""
        for _ in range(16):
            if inst.done:
                return
            sig = inst.sig()
            if sig == inst.last_sig:
                return
            inst.last_sig = sig
            rule = next((r for r in inst.d.rules if inst.holds(r.whens)
                         and (r.in_states is None or self.es_state in r.in_states)), None)
            if rule is None:
                return
            for a in rule.actions:
                self._act(inst, a, out)
                if inst.done:
                    return

    def _act(self, inst: Instance, a: Action, out: list[Output]) -> None:
        did = inst.d.id
        values = inst.values()
        if a.kind == "say":
            self._say(out, render(a.text, values), did)
        elif a.kind in ("ask", "confirm"):
            q = render(a.text, values)
            if not self._may_ask(inst, q, out):
                return
            inst.pending = (a.kind, a.slot or "", q)
            inst.ask_once = a.once
            if a.kind == "confirm":
                self.metrics["confirmations"] += 1
            self._say(out, q, did)
        elif a.kind == "send":
            children = []
            for slot, wrapper in a.copies:
                v = inst.slots[slot].value
                if isinstance(v, etree._Element):
                    if v.tag == wrapper:
                        children.append(deepcopy(v))
                    else:
                        w = etree.Element(wrapper)
                        stamp = inst.slots[slot].stamp
                        if wrapper == "SPEECH" and stamp is not None:  # as the papers' frames: when it was said
                            w.append(deepcopy(stamp))
                        w.append(deepcopy(v))
                        children.append(w)
            inst.sent.append(a.event or "")
            self.metrics["events_sent"] += 1
            self._something_done()
            out.append(Send(a.event or "", tuple(children), a.lifetime, a.pose, did))
        elif a.kind == "explain":
            out.append(Explain(did))
        elif a.kind == "explain-rejection":
            ev, reason, state = inst.rejection or ("", "", self.es_state)
            self._say(out, self.doc.rejection_text(ev, reason, state), did)
        elif a.kind == "clear":
            inst.slots[a.slot or ""] = Slot()
        elif a.kind == "end":
            self._finish(inst, out, abandoned=False)

    def _finish(self, inst: Instance, out: list[Output], *, abandoned: bool, resume: bool = True) -> None:
        if inst.done:
            return
        inst.done = True
        inst.success = not abandoned and inst.holds(inst.d.goal)
        if inst.success:
            self._last_done = (inst.d.id, inst.values(), self.metrics["user_turns"])
        self._count(inst.d.id, "abandoned" if abandoned else ("succeeded" if inst.success else "failed"))
        was_top = self.stack and self.stack[-1] is inst
        self.stack.remove(inst)
        if inst.on_end is not None:
            inst.on_end(inst)
        if resume and was_top and self.stack and not self._hold_resume:
            below = self.stack[-1]
            if below.interrupted and below.pending is not None and (
                    below.passed_over >= self.doc.drop_after or below.interrupted_in != self.es_state):
                # the user went on to other things instead of answering, or the robot does something
                # else now (following since): drop it, do not ask again
                self.metrics["dropped"] += 1
                self._finish(below, out, abandoned=True)
                return
            if below.interrupted:
                below.interrupted = False
                self.metrics["resumptions"] += 1
                if below.d.resume:
                    self._say(out, render(below.d.resume, below.values()), below.d.id)
                if below.pending is not None and self._may_ask(below, below.pending[2], out):
                    self._say(out, below.pending[2], below.d.id)
