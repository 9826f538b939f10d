"""The ``dialog`` module: frames and supervisor feedback in, speech and ES events out.

Listens to ``/robot/speech/frames`` (the understanding), ``/robot/es/conditions/dialog``,
``/robot/es/rejected/dialog`` and ``/robot/es/status`` (the supervisor),
``/robot/localisation/pose`` (for place teaching), ``/robot/speaker/status``,
``/robot/audio/sources`` and ``/robot/attention/partner`` (barge-in). Publishes ES events on
``/robot/es/events`` and is the only module that speaks
(``/robot/speaker/say``). A reactive module's question comes through the ES, as the papers
route everything: the condition ``ask`` (``<OPTIONS timeout><option index text/>+</OPTIONS>``)
starts the clarify sub-dialog, and the answer goes back as the ES event ``clarified``
(``<ANSWER index/>`` or ``<ANSWER none="true"/>``, the latter with ``deixis="true"`` for "this one"
and the answer's ``POSITION`` for "the one on the table": :func:`unchosen_answer`). The occlusion
question too: the condition ``step_aside`` (the object attention cannot see what the partner points
at, she stands in front of it) starts the ``step_aside`` sub-dialog, and once it has been said the
dialog sends the ES event ``asked_aside`` (``said="true"``). ``dialog/ask`` (RPC, the same
questions answered directly, ``about="occluded"`` for the second) stays for tools only.

Timing (virtual, docs/semantics.md §7): the dialog is a serial processor; each input
costs ``dialog_cost``; its events leave then, and what the robot says leaves
``generation_time`` later (language generation and synthesis onset), so an
answer starts about 200 ms (the papers' Fig. 6) after understanding ended.
Sentences are queued while the robot is still talking: a new ``<say>`` would
cut the one in progress.

Barge-in: while the robot talks, a sound direction at ``barge_in_level`` dB
or more *from the partner's bearing* means the partner speaks: the robot's
sentence is cut (an empty ``<say/>``), queued sentences are dropped and the
robot listens. The partner's bearing is the person attention's
``/robot/attention/partner`` (robot frame, every scan while there is a
partner; older than ``partner_fresh`` s counts as no partner); a direction
counts when it lies within ``barge_in_width`` degrees of it, both folded to
the front half-plane (the microphone pair cannot tell front from back). The
window is the person attention's own sound-to-track tolerance
(``CueSpec.sound_tolerance``, 9 degrees: the pair resolves a voice in front
to about 1.5 degrees) around where the pair hears her (:func:`heard_bearing`: a
mouth above the pair beside the robot is heard nearer the front), so the dialog
and the attention agree on when the partner speaks; a 20-degree window let a talker behind the robot, heard at
his mirrored direction 20 degrees off the partner's, cut the robot's answers
(distractor seed 2).
Without a partner nothing cuts the robot off: a radio or a visitor talking
elsewhere in the room does not. Only a frame recorded after the robot began
the sentence counts (its ``time`` against the speaker's ``start``): over a
slow link the frames arrive late, and one recorded while the partner was
still finishing her own turn must not cut the robot's answer to it. The microphones' echo cancellation takes the
robot's own voice out of ``/robot/audio/sources``, so no level rule is needed
for it (one dropped a partner standing closer than about 0.7 m).

Leaving the interaction: when the supervisor's status leaves a sub-dialog's states
(back to LookingAround), a sub-dialog that asked the user a question is abandoned
(:meth:`DialogManager.on_state`) and its sentences not yet said are dropped: the
person it asked has gone, and a bystander's next words must not answer it.

Addressee (issue 26, chat near the partner): an utterance is taken as addressed to the robot unless
the robot's own percepts say otherwise. As the papers have it, speech is meant for the robot when the
partner speaks facing it; the person attention's ``/robot/attention/partner`` says whether her frontal
face is seen (``facing="true"``), whether the camera had her face in the image and found no frontal
face there, i.e. she looks away (``"false"``), or cannot tell (``"unknown"``: the camera is on her
hands or an object), and how many other people stand within 1.6 m of her (``company``). A frame is
*not addressed* (dropped, understood or not, counted as ``not_addressed``: no "say that again" to
others' chat) when, of the partner reports during the utterance (its ``start``..``end``), none
says ``facing="true"``, at least half say ``"false"`` (turned away, or walking away from the robot)
and the last one says ``"false"`` with ``company`` >= 1: she was not facing the robot while the
words were spoken and ended up in a group turned to the others, so the words (hers or a
bystander's a few degrees beside her) are their chat. What she does after outweighs an older facing:
when some reports during the words say ``facing="true"``, the reports after the last of them decide by
the same test, provided they are at least half of the utterance's reports and the words do not name the
robot (seen facing it as a bystander began to speak, she turned and walked over to the group for most of
his words:
flow/chat_group_bye seed 2 with the camera raised for her hands, lane addr23); a facing in the last
report keeps it addressed.
Looking away alone is not enough (a user speaks while glancing at a shelf), nor is company alone (a
bystander beside a partner who faces the robot); without reports, or when the camera cannot tell,
the utterance counts as addressed. Alone, she talks to herself (issue 26 item 3: "where did I put
that novel", searching a bookcase 2 m away) when every report during the words says ``away="true"``
(she walked off from the robot, facing where she went, and the camera, on her face since, has not
seen her frontal face, nor has she walked back towards it) and she stands ``ASIDE_DISTANCE`` (1.2 m)
or further away and does not call the robot by its name (the speech module's ``named``: from across
the room the camera cannot see her face turn back, but "BIRON, go to the lounge" is meant for it): a partner
who turns back to it, or comes back, is heard again; so is one who says again, within ``REPEAT_WINDOW`` s,
what got no answer (the same act: one repeats a request that was not answered, not one's muttering). While the supervisor is in ``Following`` she leads with her back
to the robot, so the microphones decide instead (:meth:`Dialog._her_voice`): not addressed only when
several sound frames during the words heard a voice and none from her direction.

Someone behind her (chat18): the pair cannot tell two people a few degrees apart, but it hears how loud a
voice is. Face to face, words whose voice from her direction is ``FARTHER_DB`` dB or more under her own voice
(:meth:`Dialog._farther_than_her`: both taken back to 1 m by her distance; hers is the quietest of her recent
turns understood whole) come from someone further away behind her, and are not addressed unless they name the
robot. Before anyone greeted it, half-heard words that neither greet nor call it are overheard chat
(:meth:`Dialog._chat_before_greeting`).

A greeting with a request ("hello BIRON, follow me"): the understanding sends the greeting
(``opens="true"``) and then the request (``after="greeting"``). Before the interaction (LookingAround,
PotentialPartner, AskingForHelp) the request waits until the supervisor takes the greeting
(``partner_found``), at most ``AFTER_GREETING_WAIT`` s, and goes when the greeting is refused; during the
interaction the greeting is left out and the request handled at once.

Catching up (issue 26 item 10): while the follower's ``/robot/follow/status`` says
``approaching`` (it comes up to the partner after "stop"), a request she makes waits (the
latest one) and is handled when the robot stands near her facing her, so a place is not
taught from the other room.

Metrics: :meth:`summary` (turns, repairs, rejections explained, task success
per sub-dialog, barge-ins) for the run summary.
"""

from __future__ import annotations

import asyncio
import math
import re
import os
from collections import deque
from copy import deepcopy
from dataclasses import replace
from typing import Any, Callable

from lxml import etree

from homesim.errors import BusError
from homesim.message import Message
from homesim.module import Module
from robot.deployment import cost_scale
from homesim.vloop import to_ns

from robot.partner_search import STOOD_FOR
from robot.contract import (ES_CONDITIONS, ES_EVENTS, ES_REJECTED, ES_STATUS, FOLLOW_STATUS, FRAMES, PARTNER, POSE, SAY, SOURCES,
                            SPEAKER_STATUS)

from .loader import BIRON_DIALOGS, load
from .manager import DialogManager, Explain, Instance, Output, Say, Send
from .model import Dialogs

CONDITIONS = f"{ES_CONDITIONS}/dialog"
REJECTED = f"{ES_REJECTED}/dialog"
#: s: the follower says "approaching" every control step (0.1 s); older than this, it no longer drives
APPROACH_FRESH = 1.0
#: requests held during one approach: every understood instruction reaches the ES in order (issue 23
#: item 4); beyond this many, the oldest is handled at once rather than dropped (keeps memory bounded)
HELD_MAX = 8
#: s: after a released request, time for the ES's answer to come back before the next (a WLAN round trip
#: with a retransmission is well under this)
RELEASE_SETTLE = 0.5
#: sound frames with a direction, during one utterance, that the rule while she leads needs before it
#: may say the words were not hers (at the microphones' 10 Hz, 0.3 s of speech)
VOICE_FRAMES = 3
#: dB: a direction this loud is a voice for that rule (speech at 1-4 m is 50-65 dB; the hum of the
#: flat is far below)
VOICE_LEVEL = 40.0
#: m: a partner turned away (the person attention's ``away``: she walked off from the robot and was not
#: seen facing it or coming back since) this far from it or further, beyond arm's reach and the near
#: personal zone, talks to herself, not to the robot (the addressee rule; nearer, she may show it something)
ASIDE_DISTANCE = 1.2
#: the partner report's facing as the addressee rule keeps it for a partner turned away that far
ASIDE = "aside"
#: conditions whose news overtakes a dialog's sentence not yet said: that dialog's sentences made before
#: the condition came are dropped (the go-to's "OK, I am going to the study." when its plan fails at once)
WITHDRAWN_BY = {"unknown_place": "goto"}
#: s: words she says turned away from the robot no more than this long after words said to someone else
#: (a call, a name, "the robot" in the third person), with no report of her facing the robot in between,
#: go on that other conversation (on the phone: "oh hi Mum" ... "no, the kitchen is fine, come over at six")
OTHER_TALK_GAP = 10.0
#: s: words turned aside that say again what she said turned aside no more than this long before (the
#: same act, unanswered) are meant for the robot: one repeats a request that got no answer, not one's
#: muttering (issue 26, fresh12 defect 0: "where is my cup" and "good bye" three times each with her
#: back to the robot, every one dropped, and the robot deaf to her for the rest of the tour)
REPEAT_WINDOW = 20.0
#: m: a request to follow her said facing the robot, then turned to someone near her, is for the robot when she walks
#: off at least this much further from it from her last facing in the words to the frame's arrival (she leads:
#: review23 N1), or when its words address the robot (:data:`TO_THE_ROBOT`); "come and meet my sister" said to a
#: friend who stands there, she not walking off, is chat (review24 F8)
LEAD_WALK = 0.3
#: word pairs by which a follow request addresses its hearer as the one to come along ("follow me", "come with us")
TO_THE_ROBOT = frozenset({("follow", "me"), ("follow", "us"), ("with", "me"), ("with", "us")})
#: ES states where an expired greeting met nobody: a "late" one if a potential partner was reported meanwhile
SEEN_STATES = frozenset({"LookingAround", "PotentialPartner", "AskingForHelp"})
#: s: a potential partner reported this long before the greeting's recorded start still counts (the
#: person attention reports her as she begins to speak; the recorder's start may lie a little later)
PERSON_SLACK = 1.0
#: ES states in which a greeting is what starts the interaction: a request said after "hello BIRON" in
#: the same breath waits there until the greeting has been taken (the ES takes requests only from a partner)
GREETABLE = frozenset({"", "LookingAround", "PotentialPartner", "AskingForHelp"})
#: ES states with nobody greeted yet (no interaction, no help asked for): words the robot did not get whole
#: and that neither greet nor call it are taken as other people's chat (:meth:`Dialog._chat_before_greeting`)
UNGREETED = frozenset({"", "LookingAround", "PotentialPartner"})
#: s: how long a request said with a greeting waits for the greeting to be taken (the ES keeps a greeting
#: 3 s; a greeting heard with low confidence is first confirmed: "Did you say hello to me?")
AFTER_GREETING_WAIT = 15.0
#: s: after "I have arrived at the kitchen" (condition ``arrived``), while the robot looks for a partner
#: (LookingAround, PotentialPartner), a whole request or a good-bye said to it this long after the arrival
#: is taken as said with a greeting: the partner who sent it there goes on with the tour (issue 26, tours
#: 1000-011/059: her "bye for now" and requests after the arrival got "Please say hello to me first" or
#: nothing). The greeting is synchronised with a potential partner as any greeting (someone speaking
#: facing the robot), so a radio's words still start nothing; nobody seen, it expires: "I can't see you.
#: Please look at me." (:meth:`Dialog._resume_after_arrival`)
ARRIVAL_RESUME = 60.0
#: s: a call by name alone before an interaction ("biron", "that biron": the speech module's ``call="true"``,
#: the rest of "Hello BIRON" lost as the robot turns toward her voice) waits this long after it was heard for
#: someone speaking facing the robot (the supervisor's ``person_info``) and is then answered as her greeting
#: (:meth:`Dialog._take_call`); nobody seen by then, it is dropped without a word (a radio's "BIRON" starts
#: nothing). About the time the base needs to turn round to a voice behind it and find her face
CALL_WAIT = 8.0
#: A held call is answered only for a potential partner standing where the call came from (review20 F2: a radio's
#: "Byron!" then anyone who spoke facing the robot within CALL_WAIT was greeted). The call's sound frames are kept
#: with the robot's pose at each (the localiser's, map frame, which the dialog hears anyway: the robot turns between
#: the call and her face, so a robot-frame bearing will not do, fixrev21); at ``person_info`` her place (its bearing
#: and distance, put in the same frame) gives where the pair
#: would have heard her from each of those poses (:func:`heard_span`, front and back alike). More than half the
#: call's frames with a direction must lie within :data:`CALL_WIDTH` of that (a robot turning during the call brings
#: a voice from the far side and her mirrored bearing together for a frame or two: review20's radio_then_mutter
#: seed 0, 3 of 6 frames); with fewer than VOICE_FRAMES such
#: frames (or no pose) nothing tells, and the call is hers as before. A call not hers stays held for another
#: potential partner until CALL_WAIT is over
CALL_FRAMES_HERS = 0.5
#: degrees: the error budget of a frame's direction against where she stands: the pair's reading (TDOA noise 20 us,
#: about 1.4 degrees ahead), the frame against the nearest pose (0.05 s of a 0.8 rad/s turn: 2.3) and a
#: margin. The calls of the library (turn/greet_from_behind, flow/sub20_call_from_behind_kitchen) lie within 4; the
#: barge-in width (9) let a radio 14 degrees off her mirrored bearing through (review20's radio_then_mutter)
CALL_WIDTH = 6.0
#: acts that are no request of their own (answers, a greeting) and never resume the tour after an arrival
NOT_RESUMING = frozenset({"GREETING", "YES", "NO", "THAT_ONE"})
#: s: a good-bye said while the robot looks at what she showed waits this long at most for the look to end
#: (the object is stored, "OK, I have learned your kettle", then the good-bye): a look takes a few seconds
GOODBYE_AFTER_LOOK = 8.0
#: ES states in which the partner leads, back turned: the addressee rule decides by where the voice came
#: from (:meth:`Dialog._her_voice`), since her face cannot tell
LEADING_STATES = frozenset({"Following"})
#: ES states in which the robot drives on its own, away from the partner, and its person attention sleeps:
#: words are hers when a voice came from where she was last seen (:meth:`Dialog._from_her_place`)
DRIVING_STATES = frozenset({"Navigating"})
#: Requests a pause ends the walk for (issue 26, session 8 item 5): said while following is paused ("hang on",
#: the follower standing with her), "this is my cup" or "this is the kitchen" is taught; the dialog sends
#: "stop" before it, so the supervisor leaves Following as after her "stop" (never "say stop first").
ENDS_A_PAUSE = frozenset({"object_teaching", "place_teaching"})
#: s: a voice heard from the partner's direction this recently means someone is still talking there: the
#: robot does not begin a sentence over it (turn-taking: it waits for a pause; the barge-in rule would cut
#: the sentence at once anyway). Above the microphones' frame interval (0.1 s) and a breath between words,
#: below the ~1 s from the end of an utterance to the robot's answer to it, so answers are not delayed.
TURN_GAP = 0.5
STEP_ASIDE_TRIES = 2  # the step-aside question dropped unsaid (she was speaking) is put once more,
STEP_ASIDE_PAUSE = 10.0  # s: ... when she pauses, waiting at most this long
#: dB: a voice from the partner's direction this much quieter than her own voice (both taken back to 1 m by
#: her distance, the level of the quietest of her recent turns) comes from someone standing further away behind
#: her (chat18, :meth:`Dialog._farther_than_her`): a voice twice as far is 6 dB quieter, and her own turns
#: vary by a decibel or two about the quietest of them (the median of a turn's frames), so her words are not
#: taken for another's
FARTHER_DB = 4.0
#: s: a report of someone else seen this long before the words began still counts (the laser loses a person
#: for a moment when her legs hide his)
OTHERS_SLACK = 3.0
#: her recent turns whose level the rule keeps (the quietest of them is hers: a repair said louder never
#: makes her normal voice sound like someone else's)
HER_TURNS = 5
#: face to face, words of which fewer than this share of the voiced sound frames came from where she stands
#: are another talker's (the addressee rule; an overlap with her next turn is a few frames)
HER_SHARE = 0.25
#: s: a sentence held for a pause this long is said anyway (someone talking on and on near her)
HOLD_MAX = 8.0
#: s: how often a held sentence looks for the pause
HOLD_STEP = 0.1
#: s: a voice from her direction that has gone on this long with no pause of TURN_GAP is no turn of hers
#: but a source that never pauses (a radio or TV behind her, review12 item 5): the robot neither waits for it
#: nor is cut off by it. The longest turn in the corpus (28 words) lasts 11.5 s at the users' speech rate
#: (homesim.world.acoustics: 0.4 s a word); a radio reading the news goes on for minutes with 0.3 s breaths.
VOICE_RUN_MAX = 15.0
#: s of holding allowed in any HOLD_WINDOW s: beyond it the robot talks (a room where someone talks on and
#: on near her would otherwise silence it for good)
HOLD_BUDGET, HOLD_WINDOW = 15.0, 60.0
#: the requests the robot makes on its own while it follows (asking someone in its way to let it pass, asking
#: her to slow down): they are said only in a pause of *every* voice the microphones hear (any direction, any
#: level they report), ASK_QUIET s long. While it follows, she may speak from where it cannot see her (through a
#: door, 3 m off in the next room, her track coasting) and quieter than the barge-in level: begun over her, its own
#: voice masks hers at the microphones and her words ("stop") are lost with no barge-in to cut it off (cross22,
#: fresh10 hall_crossing_kids: "Excuse me, may I pass" over her "Okay, you can stop" three times). A request
#: already waiting is not queued again (the follower repeats it while it is still held up).
FOLLOW_ASKS = frozenset({"excuse_me", "too_fast", "in_her_way"})
# A held request of its own goes stale with the follower's news (review23 N4): "may I pass" once it drives on
# freely (the follower's held-up crawl, HELD_UP_CRAWL, or faster; modules share no code) or stands by her; "slow
# down" once she stopped or it came up to her (within the follower's band, 1.5 m). The follower asks again
# while it is still held up or she still pulls away (every 5 s), so a request dropped here is never lost
MOVING_FREELY = 0.25
CAUGHT_UP = 1.5
#: s: the pause of every voice before such a request: her words' frame reaches the dialog about 1 s after
#: her last word (recognition, understanding), and its answer comes first
ASK_QUIET = 2.0
#: the microphone pair's geometry (m: ahead of the centre, spacing, height) and a standing adult's
#: mouth height, as the person attention's CueSpec has them (modules share no code: tests/test_layers.py)
MIC_OFFSET, MIC_SPACING, MIC_HEIGHT, MOUTH_HEIGHT = 0.10, 0.281, 1.06, 1.6
#: m: the mouth heights a voice may come from (a child or a seated adult .. a tall adult), as the
#: person attention's CueSpec.mouth_heights: her height is unknown, and half a metre from the robot it
#: moves where the pair hears her by tens of degrees
MOUTH_HEIGHTS = (1.15, 1.85)


def heard_bearing(bearing_deg: float, distance: float, mouth: float = MOUTH_HEIGHT) -> float:
    """Where the microphone pair hears a voice from a person at (bearing, distance) (degrees, front
    half-plane): a mouth above the pair, beside it, shortens the path difference (a person 1.7 m away
    76 degrees to the side is heard at about 69), as the person attention matches voices to tracks."""
    b = math.radians(bearing_deg)
    x, y = distance * math.cos(b) - MIC_OFFSET, distance * math.sin(b)
    h, dz = MIC_SPACING / 2, mouth - MIC_HEIGHT
    dl = math.sqrt(x * x + (y - h) ** 2 + dz * dz)
    dr = math.sqrt(x * x + (y + h) ** 2 + dz * dz)
    return math.degrees(math.asin(max(-1.0, min(1.0, (dr - dl) / MIC_SPACING))))


def _turned_to_others(cues: list[tuple[str, int]]) -> bool:
    """The addressee rule's "turned to others" (module docstring): of partner reports ``(facing, company)``,
    at least half have her turned away (``"false"`` or :data:`ASIDE`) and the last one too, with someone
    else within the group radius of her (``company`` >= 1). False for no reports."""
    if not cues:
        return False
    away = sum(f in ("false", ASIDE) for f, _ in cues)
    last_f, last_c = cues[-1]
    return 2 * away >= len(cues) and last_f in ("false", ASIDE) and last_c >= 1


def heard_span(bearing_deg: float, distance: float) -> tuple[float, float]:
    """(lowest, highest) bearing (degrees, front half-plane) the pair can hear a person at (bearing,
    distance) at, over :data:`MOUTH_HEIGHTS`: a degree wide across the room, tens of degrees at half a
    metre (follow_while_looking seed 1: her "follow me" from 0.55 m was heard 12 degrees off the
    typical-height bearing and dropped as another talker's)."""
    lo, hi = MOUTH_HEIGHTS
    zs = [lo, hi] + ([MIC_HEIGHT] if lo < MIC_HEIGHT < hi else [])
    bs = [heard_bearing(bearing_deg, distance, z) for z in zs]
    return min(bs), max(bs)


def span_off(deg: float, span: tuple[float, float] | float) -> float:
    """How far (degrees) the direction ``deg``, folded to the front, lies outside ``span`` (0 inside;
    a single bearing is a span of one, folded to the front too)."""
    b = front_bearing(deg)
    lo, hi = span if isinstance(span, tuple) else (front_bearing(span),) * 2
    return max(0.0, lo - b, b - hi)


def _known(span: tuple[float, float] | float | None) -> bool:
    """A partner report that says where the pair hears her (a span, or a finite bearing)."""
    return span is not None and (isinstance(span, tuple) or math.isfinite(span))


def front_bearing(deg: float) -> float:
    """A bearing (degrees) folded to the front half-plane [-90, 90], as the microphone pair reports them."""
    return math.degrees(math.asin(max(-1.0, min(1.0, math.sin(math.radians(deg))))))


def _without_article(words: list[str]) -> list[str]:
    """An option's words without a leading article: the document's ``option`` sentence adds its own
    (the object attention sends "the plant on the right"; the robot said "the the plant")."""
    return words[1:] if words and words[0].lower() in ("the", "a", "an") else words


def options_phrase(doc: Dialogs, options: list[str]) -> str:
    """"the red cup or the blue one" from option texts, in the document's words (a repeated last word
    becomes its ``same-noun`` word); empty without options (the clarification then asks "which one")."""
    texts = [" ".join(_without_article(o.split())) for o in options if _without_article(o.split())]
    if not texts:
        return ""
    first_noun = texts[0].split()[-1]
    out = [texts[0]]
    for t in texts[1:]:
        words = t.split()
        if len(words) > 1 and words[-1] == first_noun:
            words[-1] = doc.sentence("same-noun")
        out.append(" ".join(words))
    return doc.listing([doc.sentence("option", option=o) for o in out])


#: A whole stop said to the robot (the stood-stop exception, :meth:`Dialog._stop_after_she_stood`): "stop",
#: "stop now", "stop here", "you can stop", with "please", "ok" or its name about them; not "stop it" or
#: "stop that", said to other people
STOP_REQUEST = re.compile(r"(?:(?:ok|okay|please|biron)\s+)*(?:you\s+can\s+)?stop(?:\s+(?:now|here))?(?:\s+(?:please|biron|now))*")


def _plain_words(frame: etree._Element) -> str:
    """The words of a frame, lower case, without punctuation (for :data:`STOP_REQUEST`)."""
    w = frame.find("words")
    text = (w.text if w is not None else frame.text) or ""
    return " ".join(re.sub(r"[^a-z' ]+", " ", text.lower()).split())


def _to_the_robot(frame: etree._Element) -> bool:
    """Do the frame's words ask the hearer to come along with the speaker ("follow me", "come with us":
    :data:`TO_THE_ROBOT`)? Said facing the robot, that hearer is the robot."""
    words = (frame.findtext("words") or "").lower().replace(",", " ").replace(".", " ").split()
    return any(pair in TO_THE_ROBOT for pair in zip(words, words[1:]))


def _whole(frame: etree._Element) -> bool:
    """Whether a frames-channel element is a whole understood request: understood, not partial, not a
    fragment, no word unknown or left out (a "sorry" before it, the speech module's ``corrected``, turns back to
    the robot: "Sorry. Follow me please"; the addressee rule's :meth:`Dialog._talking_to_another`)."""
    return (frame.tag == "understood" and frame.get("partial") != "true" and frame.get("fragment") != "true"
            and not frame.get("unknown") and not frame.get("ignored"))


def robot_side(side: str, view: str | None, facing: str) -> str:
    """A side said in an answer, in the robot's view (the options' words are the robot's).

    A plain side ("the one on the left", "on your left") is the robot's. "On my left" is the speaker's
    (``view="speaker"``): when the partner faces the robot (its camera sees her frontal face,
    ``facing="true"``), her left is the robot's right; otherwise she stands beside or behind it looking
    the same way as its camera, and her left is its left (docs/semantics.md §4).
    """
    if view == "speaker" and facing == "true":
        return {"left": "right", "right": "left"}.get(side, side)
    return side


#: Sides that say a distance ("the nearer one", "the one in front", "the far one", "the one at the back").
#: How often a which-one question is put in all (the object attention's ``MAX_ASKINGS``): an answer to the
#: first putting that is not understood goes back to the asker, which may have seen her point with it.
MAX_CLARIFY_ASKINGS = 2

DEPTH_SIDES = frozenset({"near", "front", "far", "back"})
#: An option's depth words -> its rank from her and from the robot (0 nearest, -1 farthest), as the object
#: attention words options one behind the other along her arm (robot.objects.resolve.option_texts).
DEPTH_RANKS = {"in front": (0, 0), "in the middle": (1, 1), "behind it": (-1, -1), "at the back": (-1, -1),
               "nearer to you": (0, -1), "nearer to me": (-1, 0)}


def _by_depth(options: list[tuple[int, str]], near: bool, view: str | None) -> int | None:
    """The option a distance answer picks: the nearest (``near``) or the farthest, from her (``view``
    "speaker", or none when the options stand in the same order from her and from the robot: "in front",
    "behind it") or from the robot ("addressee": "the one closer to you"). None when the options were not
    worded by depth, when two fit, or when the options are nearer to one of them each ("nearer to you",
    "nearer to me") and the answer does not say to whom (the robot does not guess)."""
    worded = [ranks for _, text in options for words, ranks in DEPTH_RANKS.items() if words in text]
    if view is None and any(r[0] != r[1] for r in worded):
        return None  # "the nearer one" to "the bottle nearer to you or the one nearer to me?": nearer to whom?
    who = 1 if view == "addressee" else 0
    want = 0 if near else -1
    hits = [idx for idx, text in options
            for words, ranks in DEPTH_RANKS.items() if words in text and ranks[who] == want]
    return hits[0] if len(hits) == 1 else None


def choose(options: list[tuple[int, str]], answer: Any, facing: str = "unknown") -> int | None:
    """The option an answer picks (THAT_ONE with index/colour, an OBJECT, YES to a single option); None if unclear.

    ``facing``: whether the partner faced the robot when she answered (for a side said from her view)."""
    if not isinstance(answer, etree._Element) or not options:
        return None
    if answer.tag == "NO":
        return None
    if answer.tag == "YES":
        return options[0][0] if len(options) == 1 else None
    if answer.tag == "OBJECT" and answer.find("GESTURE") is not None:
        # her teaching said again with pointing ("This red book is mine" while "Do you mean the book on the
        # left or the one on the right?" is asked, fresh7 corr_nonnative_books): the pointing answers, not
        # the noun, which the option worded first shares (the left book was stored when she pointed right)
        return None
    side = answer.get("side")
    # "the blue cup behind it" to "the blue cup on the left or the one on the right?": a side no option was
    # worded by picks nothing; the colour or attribute said with it still may (review-lang7 item 7)
    described = {str(c.get("name")) for c in answer if c.tag in ("COLOUR", "ATTRIBUTE") and c.get("name")}
    if side in DEPTH_SIDES:  # "the nearer one", "the one at the back": the option worded by its depth
        if described and not any(words in text for _, text in options for words in DEPTH_RANKS):
            return _by_words(options, described)
        return _by_depth(options, side in ("near", "front"), answer.get("view"))
    if side in ("left", "right") and (answer.get("index") or "").isdigit():
        # "the second from the left" (talk23): counted along the options' sides, left to right (three like books:
        # "on the left", "in the middle", "on the right"); before, taken as "the one on the left"
        return _by_side_rank(options, robot_side(side, answer.get("view"), facing), int(str(answer.get("index"))))
    if side is not None:  # "the left one": the option the object attention worded by its side
        side = robot_side(side, answer.get("view"), facing)
        words = "in the middle" if side == "middle" else f"on the {side}"
        hits = [idx for idx, text in options if words in text]
        if not hits and described:
            return _by_words(options, described)
        return hits[0] if len(hits) == 1 else None
    index = answer.get("index")
    if index is not None:
        if index == "last":
            return options[-1][0]
        if index.isdigit() and 1 <= int(index) <= len(options):
            return options[int(index) - 1][0]
        if index == "other" and len(options) == 2:
            return options[1][0]
        return None
    words = {c.get("name", "") for c in answer.iter() if c.get("name")}
    if answer.get("side"):  # "the left one": the options say where each is ("the cup on the left")
        words.add(answer.get("side", ""))
    if answer.get("type"):
        words.add(answer.get("type", "").replace("_", " "))
    return _by_words(options, words)


#: The side words of options from left to right (robot.objects.resolve.option_texts).
SIDE_RANKS = ("on the left", "in the middle", "on the right")


def _by_side_rank(options: list[tuple[int, str]], side: str, n: int) -> int | None:
    """The ``n``-th option counted from ``side`` ("left"/"right") when each option is worded by one side word
    (:data:`SIDE_RANKS`) and no two alike; None otherwise or when there is no ``n``-th."""
    ranks = []
    for idx, text in options:
        hit = [r for r, words in enumerate(SIDE_RANKS) if words in text]
        if len(hit) != 1:
            return None
        ranks.append((hit[0], idx))
    if len({r for r, _ in ranks}) != len(ranks):
        return None
    order = [idx for _, idx in sorted(ranks, reverse=side == "right")]
    return order[n - 1] if 1 <= n <= len(order) else None


def _by_words(options: list[tuple[int, str]], words: set[str]) -> int | None:
    """The one option that shares the most of ``words`` (at least one), or None when none or a tie."""
    scores = [(sum(w in text.split() or w == text for w in words), idx) for idx, text in options]
    best = max(s for s, _ in scores)
    winners = [idx for s, idx in scores if s == best]
    return winners[0] if best > 0 and len(winners) == 1 else None


def unchosen_answer(value: Any) -> etree._Element:
    """The reply to ``dialog/ask`` when the words alone pick no option: ``none="true"``, with what the
    asker can still use: ``deixis="true"`` ("this one": look where the partner points now) and the
    answer's ``POSITION`` ("the one on the table": which is on the table)."""
    out = etree.Element("answer", none="true")
    if isinstance(value, etree._Element) and value.tag == "OBJECT" and value.find("GESTURE") is not None:
        out.set("deixis", "true")  # a teaching with pointing said again: where she points now
        owner = value.find("OWNER")
        if owner is not None:
            # "this red book is mine" said again: whose it is goes with it (corr_nonnative_books seed 4: "mine"
            # lost from the request, heard in the answer, and the book stored without owner)
            out.append(etree.fromstring(etree.tostring(owner)))
    if isinstance(value, etree._Element) and value.tag == "THAT_ONE":
        if value.get("deixis") == "true" or value.find("GESTURE") is not None:
            out.set("deixis", "true")
        pos = value.find("POSITION")
        if pos is not None:
            out.append(etree.fromstring(etree.tostring(pos)))
    return out


def landmark_answer(options: list[tuple[int, str]] | None, x: etree._Element) -> etree._Element | None:
    """Frame ``x`` as the which-one answer "the one at <landmark>" when a clarification with ``options`` is
    open and ``x`` is a partial object teaching (words lost) of a thing no option names, said without an
    owner or a colour (the options are "the cup on the left", ...; what she names is what it stands on or
    by); None otherwise. A teaching heard whole, or of the thing asked about, stays what it is."""
    obj = x.find("SPEECH/OBJECT") if x.tag == "understood" and options else None
    if obj is None or options is None or x.get("partial") != "true":
        return None
    title = obj.find("TITLE")
    name = (title.get("name") or "").strip() if title is not None else ""
    if not name or any(obj.find(tag) is not None for tag in ("OWNER", "COLOUR", "ATTRIBUTE", "POSITION")):
        return None
    words = {w for _, text in options for w in text.split()}
    if any(w in words for w in name.split()) or (obj.get("type") or "").replace("_", " ") in words:
        return None
    out = deepcopy(x)
    speech = out.find("SPEECH")
    assert speech is not None
    for c in list(speech):
        if c.tag != "TIMESTAMP":
            speech.remove(c)
    that = etree.SubElement(speech, "THAT_ONE")
    pos = etree.SubElement(that, "POSITION")
    etree.SubElement(pos, "RELATION", name="at")
    etree.SubElement(pos, "TITLE", name=name)
    return out


class Dialog(Module):
    """BIRON's dialog control as a bus module (participant ``dialog``)."""

    #: when words said to someone else (or going on that talk) last ended; when a partner report last had
    #: her facing the robot (the addressee rule's :meth:`_talking_to_another`; set per instance as they come)
    _other_talk_end = -math.inf
    _heard_at = -math.inf  # when a frame meant for the robot (understood or not) last came: no silence
    _silence_due = -math.inf  # when the newest silence watch was set: an older one gives way to it
    _faced_at = -math.inf
    #: (act, start) of the last words dropped as not addressed (the repeat rule, :data:`REPEAT_WINDOW`)
    _unanswered: tuple[str, float] | None = None
    #: the id of the frame whose stop was taken through the stood-stop exception (:meth:`_stop_after_she_stood`)
    _stood_stop_cause: str | None = None
    #: (time, bearing, level) of the voiced sound frames (bounded), her distance (m, when reported) and the level
    #: of her recent turns taken back to 1 m: the voice-level rule (:meth:`_farther_than_her`)
    _levels: deque[tuple[float, float, float]] | None = None
    _partner_dist: tuple[float, float] | None = None
    _partner_dists: deque[tuple[float, float]] | None = None  # (time, her distance) of recent reports
    _her_levels: deque[float] | None = None
    _her_turns: deque[tuple[float, float]] | None = None  # (start, end) of her recent turns: overlaps left out
    #: (time, how many other people the attention tracks besides her: the partner report's ``others``)
    _others_cues: deque[tuple[float, int]] | None = None

    def __init__(
        self,
        sim: Any,
        dialogs: Dialogs | str | os.PathLike[str] = BIRON_DIALOGS,
        *,
        name: str = "dialog",
        host: str = "robot",
        dialog_cost: float = 0.03,
        generation_time: float = 0.17,
        barge_in_level: float = 45.0,
        barge_in_width: float = 9.0,
        partner_fresh: float = 1.0,
        ask_timeout: float = 10.0,
        confirm_below: float | None = None,
    ) -> None:
        super().__init__(sim, name, host=host)
        self.doc = dialogs if isinstance(dialogs, Dialogs) else load(dialogs)
        if confirm_below is not None:  # a more (or less) cautious robot than the document's: option dialog.confirm_below
            if not 0.0 <= confirm_below <= 2.0:
                raise ValueError(f"dialog.confirm_below must lie in [0, 2] (above 1: confirm every request), got {confirm_below}")
            self.doc = replace(self.doc, confirm_below=confirm_below)
        self.manager = DialogManager(self.doc)
        scale = cost_scale(sim, self.name, self.bus.host)  # the papers' laptop: 1 (docs/deployment.md)
        self.dialog_cost = dialog_cost * scale
        self.generation_time = generation_time * scale
        self.barge_in_level = barge_in_level
        self.barge_in_width = barge_in_width
        self.partner_fresh = partner_fresh
        self._partner: tuple[float, float] | None = None  # (bearing in degrees, robot frame; when heard)
        # (time, facing, company, heard bearing) of the latest partner reports, for the addressee rule (bounded: ~30 s at 10 Hz)
        # (time, facing, company, where the pair can hear her: a span of bearings, heard_span, or None)
        self._partner_cues: deque[tuple[float, str, int, tuple[float, float] | float | None]] = deque(maxlen=300)
        self._partner_place: tuple[float, float] | None = None  # where she was last reported (map frame, via the pose)
        # (time, directions heard) of the latest sound frames with a voice, for the rule while she leads (bounded)
        self._sources: deque[tuple[float, tuple[float, ...]]] = deque(maxlen=300)
        self._levels = deque(maxlen=600)
        self._her_levels = deque(maxlen=HER_TURNS)
        self._her_turns = deque(maxlen=HER_TURNS)
        self._partner_dists = deque(maxlen=300)
        self._others_cues = deque(maxlen=300)
        self.not_addressed = 0
        self._addressed_at = -math.inf  # when an understood frame was last taken as meant for the robot
        self._aside_since = math.inf  # when she was last reported turning aside (the addressee rule)
        self._withdrawn: dict[str, float] = {}  # dialog id -> when its sentences not yet said were withdrawn
        self._unanswered = None
        self._person_at: float | None = None  # when the supervisor last reported a potential partner (person_info)
        self.ask_timeout = ask_timeout
        self._busy_until = 0.0
        self._pose: etree._Element | None = None  # the latest pose message's payload (read only for place teaching)
        self._talking = False  # a <say> is out and not yet done/interrupted
        self._cut = False  # this utterance was already cut by a barge-in
        self._talk_start = 0.0  # when the current sentence began (sent, then the speaker's start)
        # text, causes, dialogs, when it was ready to be said, whether it is a repair ("say that again")
        self._queue: deque[tuple[str, tuple[str, ...], frozenset[str], float, bool]] = deque()
        self._voice_at = -math.inf  # when a voice from the partner's direction was last heard (turn-taking)
        self._dropped_at: dict[str, float] = {}  # sub-dialog id -> when a sentence of it was last dropped unsaid (turn-taking)
        self._talk_dialogs: tuple[str, ...] = ()  # the sub-dialogs of the sentence being said (a barge-in drops them unsaid)
        self._voice_since = -math.inf  # when that voice began with no pause of TURN_GAP since (VOICE_RUN_MAX)
        self._any_voice_at = -math.inf  # when any voice, from anywhere, was last heard (FOLLOW_ASKS)
        self._any_voice_since = -math.inf  # when that sound began with no pause of TURN_GAP since (VOICE_RUN_MAX)
        self._spoke_at = -math.inf  # when its own last sentence ended (said or cut): FOLLOW_ASKS leave her the turn
        self.asks_held = 0  # follower requests that waited for a pause of every voice (metrics)
        self._hold_steps: deque[float] = deque(maxlen=int(HOLD_WINDOW / HOLD_STEP) + 1)  # when each hold step began
        self._repair_dropped = False  # the last repair due was dropped (the next is said: never twice in a row)
        self._holding = False  # a held sentence waits for a pause (one timer)
        self._held_head: tuple[Any, ...] | None = None  # the sentence held (counted once)
        self.held_sentences = 0  # sentences that waited for a pause (metrics)
        self.stale_repairs = 0  # "say that again" not said: the talk went on meanwhile (metrics)
        self.pauses_ended = 0  # a teaching said while following was paused: "stop" sent before it (metrics)
        # the robot's word that the last successful sub-dialog was done ("OK, I have learned your radio."): [the
        # success it tells of (the manager's last_success), its text, when it ended (said or cut; inf before)]
        self._told: list[Any] | None = None
        self._repairs = frozenset(t for t in (self.doc.not_understood, self.doc.sentence("not-understood-reask"),
                                              self.doc.sentence("not-understood-help")) if t)
        self._said = 0  # serial of the last <say> sent
        # the follower comes up to the partner after "stop" (issue 26 item 10): a request she makes
        # meanwhile waits until it stands facing her (a place taught from the other room would be
        # stored where the robot lags); they are kept in order and released when the approach ends
        self._approach_seen = -math.inf  # when the follower last said "approaching"
        self._follow_state = ""  # the follower's last status state ("paused": a wait said while she leads)
        self._waiting_since = math.inf  # since when the follower has said "waiting" (it stands by her) without a break
        self._searching_since = math.inf  # since when the follower has said "searching" (she is out of sight) without a break
        self._began: tuple[str, float] | None = None  # the frame last handled: (its id, when its words began)
        self._held: deque[Message] = deque()
        # a request said with a greeting ("hello BIRON, follow me") and until when it may wait for the
        # greeting to be taken (:meth:`_greeting_taken`)
        self._after_greeting: tuple[Message, float] | None = None
        # until when a request after an arrival resumes the tour with an implicit greeting (ARRIVAL_RESUME)
        self._resume_until = -math.inf
        self._goodbye_held: Message | None = None  # a good-bye said during ObjectTeaching (see GOODBYE_AFTER_LOOK)
        # a call by name alone before an interaction and until when it waits for a potential partner (CALL_WAIT)
        # with the sound frames heard during it: (the robot's map x, y, theta then, directions heard in degrees) each
        self._call: tuple[Message, float, list[tuple[float, float, float, tuple[float, ...]]]] | None = None
        # the latest poses (time, map x, y, theta: the localiser's), to place the call's frames (bounded: 10 s at 10 Hz)
        self._poses: deque[tuple[float, float, float, float]] = deque(maxlen=100)
        # where the supervisor's latest potential partner stands (map x, y), None when unknown (person_info)
        self._person_place: tuple[float, float] | None = None
        self._asking: list[tuple[int, str]] | None = None  # the open clarification's options (see _unanswerable)
        self._asking_inst: Instance | None = None  # ... and its clarify sub-dialog (see _mark_unchosen)
        self._clarify_asked: dict[str, int] | None = None  # the last clarify sub-dialog's askings (see _clarify)
        self._hand_back = False  # the open clarification's asker puts the question again itself (see _clarify)
        self._releasing = False  # held requests are being handled one turn at a time
        bus = self.bus
        bus.subscribe(FRAMES, self._on_frame)
        bus.subscribe(CONDITIONS, self._on_condition)
        bus.subscribe(REJECTED, self._on_rejected)
        bus.subscribe(ES_STATUS, self._on_status)
        bus.subscribe(POSE, self._on_pose)
        bus.subscribe(SPEAKER_STATUS, self._on_speaker)
        bus.subscribe(SOURCES, self._on_sources)
        bus.subscribe(PARTNER, self._on_partner)
        bus.subscribe(FOLLOW_STATUS, self._on_follow)
        bus.serve("ask", self._rpc_ask)

    async def run(self) -> None:
        """Beat; everything else happens as messages are delivered."""
        while True:
            self.beat()
            await asyncio.sleep(self.heartbeat.interval if self.heartbeat else 1.0)

    def summary(self) -> dict[str, Any]:
        """Dialog metrics for the run summary (plain data)."""
        out = self.manager.summary()
        out["not_addressed"] = self.not_addressed
        out["held_for_a_pause"] = self.held_sentences
        out["stale_repairs_dropped"] = self.stale_repairs
        out["asks_held_for_a_pause"] = self.asks_held
        out["pauses_ended_by_teaching"] = self.pauses_ended
        return out

    def addressed(self, start: float, end: float, named: bool = False, shows: bool = False,
                  repeated: bool = False, whole: bool = True, leads: bool = False, to_robot: bool = False) -> bool:
        """The addressee rule (module docstring): is speech heard from ``start`` to ``end`` meant for
        the robot? No when no partner report in that span has her facing it, at least half have her
        turned away (``facing="false"``) and the last one too, with someone else near her (and when she
        faced it, the same of the reports after her last facing, if they are at least half of the span's
        and the words do not name the robot: what she does after outweighs the older facing; a deictic
        ``shows`` does not keep them, as in the group test without a facing; a request to follow her,
        ``leads``, does when its words address the robot, ``to_robot``, "follow me", "come with me", or she walks off
        (:meth:`_walks_off`): it is said turning to lead the way, past whoever stands there, review23 N1; "come and
        meet my sister" said to a friend, then turned to her, is not, review24 F8); and no when
        every report has her turned aside (the attention's ``away``: she walked off and has not faced
        the robot or come back since, at least ``ASIDE_DISTANCE`` from it) and she does not call it by
        its name (``named``, the speech module's ``named="true"``) nor says again what got no answer
        (``repeated``, see :data:`REPEAT_WINDOW`): she talks to herself."""
        if self.manager.es_state in LEADING_STATES:
            return self._her_voice(start, end)
        if self.manager.es_state in DRIVING_STATES:
            return self._from_her_place(start, end)
        if not (named or repeated) and self._farther_than_her(start, end):
            # a voice from her direction, much quieter than hers, with someone else in the room: his (a guest
            # chatting by the bookcase behind her, tests/scenarios/flow/chat18_remarks_behind_partner.xml).
            # With nobody else seen, it is her own softer voice (across a counter, a quieter line: review18 F1,
            # tests/scenarios/flow/fixrev19_alone_softer.xml); words said again after no answer are hers too
            return False
        during = [(f, c) for t, f, c, _ in self._partner_cues if start <= t <= end]
        times = [t for t, _, _, _ in self._partner_cues if start <= t <= end]
        faced = [i for i, (f, _) in enumerate(during) if f == "true"]
        if faced:
            # she faced the robot during the words: meant for it, unless what she did after her last facing
            # outweighs it: for at least half the words she was then seen turned away, and at the end turned
            # to someone near her (chat_group_bye seed 2 with the camera raised for her hands: Olga seen facing
            # the robot for 0.4 s as Rosa began "how was your holiday", then 1.4 s walking over to the group)
            # A request to follow her is said as she turns to lead the way, past whoever stands by her: the
            # turn is the request's own (review23 N1: "please follow me into the kitchen" said facing the
            # robot, then walking to the door past her friend, was dropped as chat)
            after = during[faced[-1] + 1:]
            if leads and not (named or to_robot) and not self._walks_off(times[faced[-1]]):
                leads = False  # neither "follow me" nor walking off: the turn to her friend is what it looks like
            return named or leads or 2 * len(after) < len(during) or not _turned_to_others(after)
        if self._voice_elsewhere(start, end):
            # the microphones heard the words, and hardly any of it from where she stands (distractor
            # seed 0 on obj12: Tom's "I need to find my keys" 13 degrees off Anna, her face not seen,
            # overlapping her next words by 0.3 s, was taught as her keys): another talker's
            return False
        if not during:
            return True
        if self._talking_to_another(start, during, whole) and not (named or shows or repeated):
            # she talks with someone else (on the phone nobody stands near her: fresh5 row_phone_between,
            # "oh hi Mum ..." then, still turned away, "no, the kitchen is fine, come over at six"):
            # what she says turned away goes on that talk until she faces the robot again
            self._other_talk_end = max(self._other_talk_end, end) if math.isfinite(end) else self._other_talk_end
            return False
        if all(f == ASIDE for f, _ in during):
            # she walked off, her back to the robot, the whole time: talking to herself, unless she
            # calls it by its name ("BIRON, go to the lounge" from across the room, where the camera
            # cannot see her face turn back), shows something ("and this one is my husband's cup" at
            # the desk she walked up to: showing needs someone to show it to), or has talked with the
            # robot since she turned away (its answer heard, she goes on with her back to it:
            # fresh3 open_two_cups_rooms seeds 0-2 lost every later request), or says again words
            # that got no answer (a request repeated is waiting for one; without this rule nothing she
            # said turned aside could ever start that exchange: deaf to her for the rest of the run)
            return named or shows or repeated or self._addressed_at > self._aside_since
        return not _turned_to_others(during)

    def _walks_off(self, since: float) -> bool:
        """Has the partner walked at least :data:`LEAD_WALK` further from the robot since ``since`` (her
        distance reports up to now)? A request to follow her is said as she turns to lead the way."""
        dists = [d for t, d in (self._partner_dists or ()) if t >= since]
        return len(dists) >= 2 and max(dists) - dists[0] >= LEAD_WALK

    def _chat_before_greeting(self, x: etree._Element) -> bool:
        """Whether frame ``x`` is chat the robot overheard before anyone greeted it: the supervisor has
        nobody to talk with (:data:`UNGREETED`: looking around, or a potential partner who has not greeted),
        the robot waits on no answer of its own (no sub-dialog's question, no "say that again" open), and
        the words are no whole request (not understood, or understood only in part: a word unknown, lost
        or left out) and neither greet nor take leave nor call the robot by its name. An interaction
        begins with a greeting; a request said whole before one still gets "Please say hello to me first.",
        and "BIRON, ..." misheard still gets "say that again"."""
        if self.manager.es_state not in UNGREETED or x.tag not in ("understood", "not_understood"):
            return False
        if _whole(x) or x.get("named") == "true" or x.get("opens") == "true" or x.get("after") == "greeting":
            return False
        if x.find("SPEECH/GREETING") is not None or x.find("SPEECH/GOODBYE") is not None:
            return False
        if self.manager.open_question() is not None or any(not i.done for i in self.manager.stack):
            return False
        return True

    def _talking_to_another(self, start: float, during: list[tuple[str, int]], whole: bool) -> bool:
        """Whether words beginning at ``start`` go on a talk with someone else: words said to another
        (the speech module's ``addressee="other"``) ended at most :data:`OTHER_TALK_GAP` s before, no
        partner report has had her facing the robot since nor has one during these words, and either
        she is seen turned away during them (at least half the reports say she looks away, the last one
        too) or the camera cannot tell (it looks at her hands while she talks) and the words are no
        whole request (``whole``: understood, nothing left out, misheard or partial): "no, the kitchen
        is fine, come over at six" goes on her call; "follow me", said whole, is for the robot."""
        if not math.isfinite(start) or not 0.0 <= start - self._other_talk_end <= OTHER_TALK_GAP:
            return False
        if self._faced_at >= self._other_talk_end or any(f == "true" for f, _ in during):
            return False
        away = sum(f in ("false", ASIDE) for f, _ in during)
        if during and 2 * away >= len(during) and during[-1][0] in ("false", ASIDE):
            return True
        return not whole

    def _her_voice(self, start: float, end: float) -> bool:
        """The addressee rule while she leads (``Following``): her back is turned, so her face tells
        nothing, but the microphones tell where the words came from. Speech is *not* hers (a bystander's
        remark as she walks past him) only when at least ``VOICE_FRAMES`` sound frames during the
        utterance heard a direction and none of them lay within ``barge_in_width`` of where the pair
        hears her (:func:`heard_bearing`, both folded to the front: the pair cannot tell front from
        back). Without such frames, or without her bearing, it is hers: her "stop" must never be lost."""
        cues = [(t, b) for t, _, _, b in self._partner_cues if _known(b) and start - 0.5 <= t <= end + 0.5]
        if not cues:
            return True
        frames = [(t, bs) for t, bs in self._sources if start <= t <= end and bs]
        if len(frames) < VOICE_FRAMES:
            return True
        for t, bs in frames:
            her = min(cues, key=lambda c: abs(c[0] - t))[1]
            if any(span_off(b, her) <= self.barge_in_width for b in bs):
                return True
        return False

    def _stop_after_she_stood(self, x: Any, start: float) -> bool:
        """A stop heard in Following from off the followed track's bearing (:meth:`_her_voice` said not
        hers) is taken all the same when the follower had said ``waiting`` (it stands by that track) for
        at least :data:`~robot.partner_search.STOOD_FOR` s when the words began, and still says so: her
        walk is over, and the track may be someone she walked past who stands silent there (the person
        attention listens to the other voice then, and makes the stop's speaker the partner:
        :meth:`PersonAttention._stop_speaker`). Only a stop: other words from off her bearing stay a
        bystander's, and so does a stop said while she walks. And only a whole stop said to the robot
        (:data:`STOP_REQUEST`: "stop", "stop now", "you can stop"): "stop it" or "stop that" is said to
        another person (review18 F2)."""
        return (self.manager.es_state in LEADING_STATES and x.tag == "understood" and x.find("SPEECH/STOP") is not None
                and math.isfinite(start)
                and ((self._follow_state == "waiting" and start - self._waiting_since >= STOOD_FOR
                      and _whole(x) and STOP_REQUEST.fullmatch(_plain_words(x)) is not None)
                     or self._stop_while_searching(start)))

    def _walk_over(self, cause: str) -> bool:
        """Whether her walk is over for a teaching said while the robot follows (:data:`ENDS_A_PAUSE`): a pause
        (she said "hang on": the follower's status ``paused``), or the follower has said ``waiting`` (it stands by
        her: she stands; not ``held``, held up on its way to her beyond its band, review22 R4) for at least :data:`~robot.partner_search.STOOD_FOR` s when the words began and still
        says so, as for a stop from off her bearing (:meth:`_stop_after_she_stood`). fresh7 corr_fast_walker_goto:
        a fast leader's "here, stop" was not heard from 6 m behind a wall, the robot came up to him and stood by
        him, and "this is the guest room", the sunglasses and the go-to all got "say stop first" to the end. A
        teaching said while she walks on (status ``following``) is refused as before."""
        if self._follow_state == "paused":
            return True
        start = self._began[1] if self._began is not None and self._began[0] == cause else self.now
        return (self._follow_state == "waiting" and math.isfinite(start)
                and start - self._waiting_since >= STOOD_FOR)

    def _stop_while_searching(self, start: float) -> bool:
        """The follower said ``searching`` (she is out of its sight) from before the words began and still
        says so: a stop heard then from off the bearing of the track it follows is hers (a fast leader who
        went on through a door or a passage and stopped there; the track is a guess, or went over to someone
        else); the person attention listens to the voice nobody seen explains then. Only a stop (the caller
        checks that)."""
        return self._follow_state == "searching" and start >= self._searching_since

    def _her_turn_level(self, start: float, end: float, others: bool = False) -> float | None:
        """The level of the voice heard from her direction during ``start``..``end`` (the median of the
        voiced sound frames within ``barge_in_width`` of where the pair hears her), taken back to 1 m by her
        distance; None without her bearing or distance or with fewer than ``VOICE_FRAMES`` such frames.
        ``others``: leave out the frames during her own recent turns (words overlapping hers: her voice and
        the other one merge there)."""
        if self._levels is None or self._partner_dist is None:
            return None
        cues = [(t, b) for t, _, _, b in self._partner_cues if _known(b) and start - 0.5 <= t <= end + 0.5]
        if not cues:
            return None
        dists = [(t, d) for t, d in (self._partner_dists or ()) if start - 0.5 <= t <= end + 0.5]
        mine = []
        for t, b, level in self._levels:
            if start <= t <= end:
                if others and self._her_turns and any(a <= t <= b for a, b in self._her_turns):
                    continue
                her = min(cues, key=lambda c: abs(c[0] - t))[1]
                if span_off(b, her) <= self.barge_in_width:
                    # her distance when the frame was heard (she may walk up while she talks)
                    d = min(dists, key=lambda c: abs(c[0] - t))[1] if dists else self._partner_dist[0]
                    mine.append(level + 20.0 * math.log10(max(d, 0.3)))
        if len(mine) < VOICE_FRAMES:
            return None
        mine.sort()
        return mine[len(mine) // 2]

    def _her_reference(self) -> float | None:
        """Her own voice's level at 1 m: the quietest of her recent turns (None before one was heard)."""
        return min(self._her_levels) if self._her_levels else None

    def _farther_than_her(self, start: float, end: float) -> bool:
        """Whether the words heard from her direction came from someone further away behind her: their
        level, taken back to 1 m by *her* distance, lies ``FARTHER_DB`` or more under her own voice's (the
        pair cannot tell two people a few degrees apart, but a voice from twice as far is 6 dB quieter)."""
        ref = self._her_reference()
        if ref is None or not self._someone_else(start, end):
            return False
        level = self._her_turn_level(start, end, others=True)
        return level is not None and level <= ref - FARTHER_DB

    def _someone_else(self, start: float, end: float) -> bool:
        """Whether a partner report from :data:`OTHERS_SLACK` s before ``start`` to the end of the words saw
        someone else besides her (the attention's ``others``): only then can a quieter voice from her direction
        be another person's (review18 F1). Not only someone seen in line behind her: her own legs hide a person
        standing right behind her from the laser."""
        return any(n >= 1 for t, n in (self._others_cues or ()) if start - OTHERS_SLACK <= t <= end + 0.5)

    def _learn_her_level(self, start: float, end: float) -> None:
        """Remember the level of a turn understood and taken as hers (the voice-level rule's reference)."""
        if self._her_levels is None or self.manager.es_state in LEADING_STATES or self.manager.es_state in DRIVING_STATES:
            return
        level = self._her_turn_level(start, end)
        if level is not None:
            self._her_levels.append(level)
        if self._her_turns is not None and math.isfinite(start) and math.isfinite(end):
            self._her_turns.append((start, end))

    def _voice_elsewhere(self, start: float, end: float) -> bool:
        """Face to face (not while she leads), the words are another talker's when at least
        ``VOICE_FRAMES`` sound frames during them heard a voice and fewer than ``HER_SHARE`` of those
        frames heard one within ``barge_in_width`` of where the pair hears her: the tail of her own next
        turn, overlapping his words, does not make them hers. Without such frames, or without her
        bearing, nothing is decided here (False)."""
        cues = [(t, b) for t, _, _, b in self._partner_cues if _known(b) and start - 0.5 <= t <= end + 0.5]
        frames = [(t, bs) for t, bs in self._sources if start <= t <= end and bs]
        if not cues or len(frames) < VOICE_FRAMES:
            return False
        hers = 0
        for t, bs in frames:
            her = min(cues, key=lambda c: abs(c[0] - t))[1]
            hers += any(span_off(b, her) <= self.barge_in_width for b in bs)
        return hers < HER_SHARE * len(frames)

    def _from_her_place(self, start: float, end: float) -> bool:
        """The addressee rule while the robot drives on its own (``Navigating``): its person attention
        sleeps, so no face or track says who speaks, but the partner stays where she sent it (or
        follows slowly), and the pair hears where a voice comes from. Words are *not* hers (a bystander
        on the phone in the corridor, facing the robot as it passes: "see you later then") only when at
        least ``VOICE_FRAMES`` sound frames during them heard a voice and none lay within
        ``barge_in_width`` of the direction of the place she was last reported at (from the robot's
        pose at each frame, folded to the front). Without that evidence they are hers."""
        place, pose = self._partner_place, self._pose
        if place is None or pose is None:
            return True
        frames = [(t, bs) for t, bs in self._sources if start <= t <= end and bs]
        if len(frames) < VOICE_FRAMES:
            return True
        try:
            px, py, th = float(pose.get("x", "nan")), float(pose.get("y", "nan")), float(pose.get("theta", "nan"))
        except ValueError:
            return True
        dx, dy = place[0] - px, place[1] - py
        if not all(math.isfinite(v) for v in (dx, dy, th)):
            return True
        d = math.hypot(dx, dy)
        her = heard_span(math.degrees(math.remainder(math.atan2(dy, dx) - th, 2 * math.pi)), max(d, 0.3))
        return any(span_off(b, her) <= self.barge_in_width for _, bs in frames for b in bs)

    # ------------------------------------------------------------------ inputs
    def _on_frame(self, msg: Message) -> None:
        x = msg.xml
        if self.manager.es_state in DRIVING_STATES and (x.find("SPEECH/STOP") is not None or x.find("SPEECH/WAIT") is not None):
            self._on_addressed(msg)  # anyone may stop a robot that drives on its own (safety): never dropped
            return
        if x.tag == "not_understood" and x.get("addressee") == "other":
            # words that call someone else ("Tom, can you put the kettle on"): not for the robot, and no
            # "say that again" to them (counted with the other chat it did not answer)
            self.not_addressed += 1
            end = float(x.get("end", "nan"))
            if math.isfinite(end):
                self._other_talk_end = max(self._other_talk_end, end)  # a talk with someone else goes on
            return
        if self._chat_before_greeting(x):
            # nobody has greeted the robot: half-heard words that neither greet nor call it are people
            # talking among themselves (tour-1000-014: after the good-bye, two visitors chatting face to
            # face with the robot behind one of them got "Is this the watch?" and "Sorry, I did not
            # understand you" six times). No answer, no question of its own
            self.not_addressed += 1
            return
        if x.tag in ("understood", "not_understood"):
            began, act = float(x.get("start", "nan")), said_act(x)
            last = self._unanswered
            repeated = last is not None and act == last[0] and 0.0 <= began - last[1] <= REPEAT_WINDOW
            if not self.addressed(began, float(x.get("end", "nan")), named=x.get("named") == "true",
                                  shows=x.tag == "understood" and x.find("SPEECH//GESTURE") is not None,
                                  repeated=repeated, whole=_whole(x),
                                  leads=x.tag == "understood" and x.find("SPEECH/FOLLOW") is not None,
                                  to_robot=_to_the_robot(x)):
                if not self._stop_after_she_stood(x, began):
                    self.not_addressed += 1  # chat among the partner's group: not a request to the robot
                    self._unanswered = (act, began) if math.isfinite(began) else None
                    return
                # taken through the stood-stop exception: its stop event says so (stood="true"), and only then
                # does the person attention make the stop's speaker the partner (review18 F2)
                self._stood_stop_cause = msg.id
            self._unanswered = None
            if repeated and math.isfinite(began):
                self._addressed_at = began  # said again for the robot, even not understood: their exchange
        if _whole(x) or (x.tag == "understood" and x.get("named") == "true"):
            self._learn_her_level(float(x.get("start", "nan")), float(x.get("end", "nan")))
        if x.tag == "understood":
            # a turn taken as meant for the robot (the rule's exchange): when its words began, so that
            # words said before she turned aside ("wait, I want to show you my book", then she walks off
            # to the shelf) do not make her muttering there ("now where did I put it") meant for it
            began = float(x.get("start", "nan"))
            self._addressed_at = began if math.isfinite(began) else self.now
        self._on_addressed(msg)

    def _on_addressed(self, msg: Message) -> None:
        # words taken as meant for the robot: no silence after a question (_on_silence). Not words to
        # someone else or a television's (the reviewer's F5: they kept a question ignored by the partner
        # from ever being put again or left)
        self._heard_at = self.now
        if self.now - self._approach_seen < APPROACH_FRESH or self._releasing:
            if len(self._held) >= HELD_MAX:  # bounded: the oldest goes now, none is lost
                self._handle_frame(self._held.popleft())
            self._held.append(msg)  # handled once the robot stands near her (see _on_follow)
            if not self.now - self._approach_seen < APPROACH_FRESH:
                self._release_held()  # the follower fell silent without "stopped"
            return
        self._handle_frame(msg)

    def _handle_frame(self, msg: Message) -> None:
        x = msg.xml
        self._began = (msg.id, float(x.get("start", "nan")))
        greetable = self.manager.es_state in GREETABLE
        if x.get("opens") == "true" and not greetable:
            # "hello BIRON, follow me" while they are already talking: the greeting is a greeting only,
            # nothing to start ("We are already talking"); the request in its next frame is what she wants
            return
        if not greetable and x.get("partial") == "true" and x.find("SPEECH/GREETING") is not None:
            # "hello again, [this is→is the] kitchen" during the tour: a greeting with words the robot
            # could not use is a turn it did not understand ("Did you say hello to me?" or "We are
            # already talking" would answer the greeting she did not mean as the request)
            heard = etree.Element("not_understood", start=x.get("start", "0"), end=x.get("end", "0"),
                                  confidence=x.get("confidence", "0"), reason="a greeting with words not understood")
            heard.text = x.findtext("words") or ""
            self._emit(self.manager.on_frame(heard), msg.id)
            return
        if self._take_call(msg):
            return
        if self.manager.es_state == "ObjectTeaching" and x.find("SPEECH/GOODBYE") is not None:
            # "thanks, bye" while the robot still looks at what she showed (fresh4 loft_teach_walking_past: the
            # good-bye ended the look and the kettle was never stored): the look ends first, then the good-bye
            self._goodbye_held = msg
            self.sim.loop.call_at_ns(to_ns(self.now + GOODBYE_AFTER_LOOK), self._release_goodbye, msg)
            return
        landmark = landmark_answer(self._asking, x)
        if landmark is not None:
            # "the [one on→that] the table" to "Do you mean the cup on the left or the one on the right?": words
            # lost, what is left names another thing than the one asked about, no owner: the landmark of a
            # which-one answer ("the one at the table"), not a new teaching of the table (perceive/cups_on_table
            # seed 5: "Now, back to your cup." and the question again, unanswered)
            x = landmark
        if self._unanswerable(x):
            # "the [one→is] closer [to→is] you" to "the bottle nearer to you or the one nearer to me?": "closer"
            # alone says not to whom, and picks neither; taken as the choice, the robot thanked her and gave
            # up on the bottle (bottles_across_island seeds 2, 7). Not understood: the question is asked again
            heard = etree.Element("not_understood", start=x.get("start", "0"), end=x.get("end", "0"),
                                  confidence=x.get("confidence", "0"), reason="an answer that picks no option")
            heard.text = x.findtext("words") or ""
            self._emit(self.manager.on_frame(heard), msg.id)
            return
        if x.get("after") == "greeting" and greetable:
            # the request said with the greeting waits until the greeting is taken (partner_found);
            # a greeting refused or not taken in time takes the request with it
            self._after_greeting = (msg, self.now + AFTER_GREETING_WAIT)
            return
        if self._resume_after_arrival(msg):
            return
        inst = self._asking_inst
        if (x.tag == "not_understood" and inst is not None and self._hand_back and not inst.done and self.manager.stack
                and self.manager.stack[-1] is inst and sum(inst.asked.values()) < MAX_CLARIFY_ASKINGS):
            # her answer to "Do you mean ...?" not understood, the question put once: the asker may have seen
            # her point with it ("this one" heard "is one", perceive/cups_this_one): it decides first, and puts
            # the question again itself if the pointing does not single one out (no "say that again" here)
            self._emit(self.manager.cancel(inst, quiet=True), msg.id)
            return
        if self._told_again(x, msg.id):
            return
        self._mark_unchosen(x)
        self._emit(self.manager.on_frame(x), msg.id)

    def _told_again(self, x: etree._Element, cause: str) -> bool:
        """Her request again, begun before the robot had said to its end that it was done (a retry over "OK, I have
        learned your radio.", cutting it: perceive/study_far_behind_user seed 5 began the look a second time, and
        her good-bye came in ObjectTeaching): it is not asked anew, the robot says it again, once. Words begun
        after the robot's word was heard to its end are a new request (a second radio shown), as before."""
        told = self._told
        if told is None or x.tag != "understood" or not float(x.get("start", "inf")) < told[2]:
            return False
        if not self.manager.repeats_last_success(x):
            return False
        self._told = None  # once: a third time is a new request
        self.manager.told_again()
        self._enqueue(told[1], cause)
        return True

    def _mark_unchosen(self, x: etree._Element) -> None:
        """While a clarification is open, tell its sub-dialog whether frame ``x``, taken as the answer,
        picks none of the options (:func:`choose`): then no "Thank you." (the asker may put the same
        question again right after; thanked, then asked again, the user was told her answer was taken)."""
        inst, options = self._asking_inst, self._asking
        if inst is None or options is None:
            return
        speech = x.find("SPEECH") if x.tag == "understood" else None
        act = None if speech is None else next(
            (c for c in speech if isinstance(c.tag, str) and c.tag in ("THAT_ONE", "OBJECT", "YES", "NO")), None)
        self.manager.mark(inst, "unchosen", act is not None and choose(options, act, self._facing_now()) is None)

    def _unanswerable(self, x: etree._Element) -> bool:
        """Whether frame ``x`` is a which-one answer (``THAT_ONE``) to the open clarification that picks none
        of its options (:func:`choose`) and holds nothing else the asker can use (no pointing, no place:
        :func:`unchosen_answer`): an answer the robot did not get, not the choice of neither."""
        options = self._asking
        act = x.find("SPEECH/THAT_ONE") if x.tag == "understood" and options else None
        if act is None or options is None:
            return False
        if choose(options, act, self._facing_now()) is not None:
            return False
        left = unchosen_answer(act)
        return left.get("deixis") is None and len(left) == 0

    def _release_goodbye(self, msg: Message | None = None) -> None:
        """The good-bye held during a look goes now (the look ended, or it took ``GOODBYE_AFTER_LOOK`` s)."""
        held = self._goodbye_held
        if held is None or (msg is not None and held is not msg):
            return
        self._goodbye_held = None
        self._emit(self.manager.on_frame(held.xml), held.id)

    def _resume_after_arrival(self, msg: Message) -> bool:
        """A whole request or good-bye said within ``ARRIVAL_RESUME`` s of an arrival while the robot looks
        for a partner (no question of its own open): greet for her (a greeting of hers with the request's
        time, ``<GREETING resumed="true"/>``: the greeting dialog then says nothing) and hold the request
        until the supervisor takes the greeting (``partner_found``), as "hello BIRON, follow me". Once per
        arrival. Returns whether it did."""
        x = msg.xml
        if not (self.now <= self._resume_until and self.manager.es_state in ("LookingAround", "PotentialPartner")
                and _whole(x) and x.get("opens") != "true" and self._after_greeting is None
                and self.manager.open_question() is None and not any(not i.done for i in self.manager.stack)):
            return False
        speech = x.find("SPEECH")
        acts = [c for c in speech if c.tag != "TIMESTAMP"] if speech is not None else []
        if not acts or str(acts[0].tag) in NOT_RESUMING:
            return False
        self._resume_until = -math.inf
        greet = etree.Element("understood", start=x.get("start", "0"), end=x.get("end", "0"), confidence="1")
        gs = etree.SubElement(greet, "SPEECH")
        etree.SubElement(gs, "GREETING", resumed="true")
        stamp = speech.find("TIMESTAMP") if speech is not None else None
        if stamp is not None:
            gs.append(deepcopy(stamp))
        self._after_greeting = (msg, self.now + AFTER_GREETING_WAIT)
        self._emit(self.manager.on_frame(greet), msg.id)
        return True

    def _take_call(self, msg: Message) -> bool:
        """A call by name alone (``call="true"``: "biron", "that biron") before anyone greeted the robot, no
        question of its own open: someone wants its attention and the rest of her greeting was lost (turn/
        greet_from_behind seeds 1, 8: "Hello BIRON" from behind heard as "biron" while the base turned to
        her voice; no answer, and her greeting said again came 7 s later). It is her greeting: answered at
        once when a potential partner is reported, else held until one is (``person_info``) within
        :data:`CALL_WAIT` s, then dropped unanswered. Said to "Did you say hello to me?" (the greeting's own
        confirmation, "hello a" heard before), it is her greeting said again: the yes (sub20_radio_says_the_name
        seed 4: "Hello BIRON" heard "is biron" got "Sorry, I did not understand you. Did you say hello to me?").
        Not while another sub-dialog waits on her. Returns whether the frame was such a call."""
        x = msg.xml
        if not (x.tag == "not_understood" and x.get("call") == "true" and self.manager.es_state in UNGREETED
                and not any(not i.done and i.d.id != "greeting" for i in self.manager.stack)):
            return False  # (open: nothing, or the greeting's own "Did you say hello to me?", which the call answers)
        start, end = float(x.get("start", "nan")), float(x.get("end", "nan"))
        frames = []
        last: tuple[float, ...] = ()
        for t, bs in self._sources:
            if start <= t <= end and bs and self._poses and bs != last:
                # (a frame that repeats the one before word for word is the detector's hangover after the voice
                # ended: its last reading again, no new evidence of where it came from, whatever the robot's turn)
                _, ox, oy, oth = min(self._poses, key=lambda o: abs(o[0] - t))
                frames.append((ox, oy, oth, bs))
            if start <= t <= end:
                last = bs
        self._call = (msg, self.now + CALL_WAIT, frames)
        if self.manager.es_state == "PotentialPartner":
            self._answer_call()
        return True

    def _call_hers(self, frames: list[tuple[float, float, float, tuple[float, ...]]]) -> bool:
        """Whether the call heard in ``frames`` came from where the potential partner stands (:data:`CALL_FRAMES_HERS`):
        from each frame's pose, where the pair would hear her (:func:`heard_span`) against what it heard."""
        her = self._person_place
        if her is None or len(frames) < VOICE_FRAMES:
            return True  # nothing tells where the call came from, or where she stands: hers, as before
        hers = 0
        for ox, oy, oth, bs in frames:
            dx, dy = her[0] - ox, her[1] - oy
            span = heard_span(math.degrees(math.atan2(dy, dx) - oth), math.hypot(dx, dy))
            hers += any(span_off(b, span) <= CALL_WIDTH for b in bs)
        return hers > CALL_FRAMES_HERS * len(frames)

    def _answer_call(self) -> None:
        """Send the held call by name as her greeting (``<GREETING name="biron"/>`` with the call's time), if it
        is still waiting, nobody has greeted meanwhile and the potential partner stands where the call came from
        (:data:`CALL_FRAMES_HERS`; else it waits on for another)."""
        held = self._call
        if held is None or self.now > held[1] or self.manager.es_state not in UNGREETED:
            self._call = None
            return
        if not self._call_hers(held[2]):
            return  # someone else faces the robot: the call was not hers (a radio's "Byron!", then her mutter)
        self._call = None
        x = held[0].xml
        greet = etree.Element("understood", start=x.get("start", "0"), end=x.get("end", "0"), confidence="1",
                              named="true")
        gs = etree.SubElement(greet, "SPEECH")
        began = float(x.get("start", "nan"))
        if math.isfinite(began):
            etree.SubElement(gs, "TIMESTAMP", val=str(round(began * 1000.0)))
        etree.SubElement(gs, "GREETING", name="biron")
        self._emit(self.manager.on_frame(greet), held[0].id)

    def _greeting_taken(self) -> None:
        """The supervisor took the greeting (partner found): the request said with it is handled now."""
        held, self._after_greeting = self._after_greeting, None
        if held is not None and self.now <= held[1]:
            self._emit(self.manager.on_frame(held[0].xml), held[0].id)

    def _release_held(self) -> None:
        """Handle the requests held during an approach, oldest first, one turn each (as if she had
        waited for each answer: two released at once would interleave their sub-dialogs)."""
        if self._held and not self._releasing:
            self._releasing = True
            self.sim.spawn(self._release_in_turn(), name=f"{self.name}-held")

    async def _release_in_turn(self) -> None:
        try:
            while self._held and not (self.bus.closed or self.bus.hung):
                self._handle_frame(self._held.popleft())
                if self._held:
                    await asyncio.sleep(RELEASE_SETTLE)  # the ES's answer to it comes back first
                    await self._until_said()
        finally:
            self._releasing = False

    def _on_follow(self, msg: Message) -> None:
        state = msg.xml.get("state", "")
        if state != "waiting":
            self._waiting_since = math.inf
        elif self._follow_state != "waiting":
            self._waiting_since = self.now
        if state != "searching":
            self._searching_since = math.inf
        elif self._follow_state != "searching":
            self._searching_since = self.now
        self._follow_state = state
        self._withdraw_stale_asks(msg)
        if msg.xml.get("state") == "approaching":
            self._approach_seen = self.now
            return
        self._approach_seen = -math.inf
        self._release_held()

    def _withdraw_stale_asks(self, msg: Message) -> None:
        """A request of its own still waiting in the queue (:meth:`_hold_ask` holds it up to ``HOLD_MAX``)
        that the follower's status has overtaken is not said (:data:`MOVING_FREELY`, :data:`CAUGHT_UP`)."""
        if not self._queue:
            return
        state = msg.xml.get("state", "")
        try:
            speed, distance = float(msg.xml.get("speed", "0")), float(msg.xml.get("distance", "nan"))
        except ValueError:
            return
        stood = state in ("waiting", "stopped", "paused")
        stale = set()
        if stood or (state == "following" and speed >= MOVING_FREELY):
            stale.add("excuse_me")
        if state == "following" and speed >= MOVING_FREELY:  # (standing by her in her way is when it asks)
            stale.add("in_her_way")
        if stood or state == "approaching" or distance <= CAUGHT_UP:
            stale.add("too_fast")
        if not stale:
            return
        self._drop_queued(lambda q: bool(q[2]) and q[2] <= stale and q[3] < msg.created)

    def _drop_queued(self, drop: Callable[[tuple[Any, ...]], bool]) -> int:
        """Take the queued sentences ``drop`` picks (asked in queue order) out of the queue, each of their
        dialog acts marked dropped now (never said: the speaker did not begin them); the count dropped."""
        kept: deque[tuple[Any, ...]] = deque()
        for q in self._queue:
            if drop(q):
                for d in q[2]:
                    self._dropped_at[d] = self.now
            else:
                kept.append(q)
        dropped = len(self._queue) - len(kept)
        self._queue = kept
        return dropped

    def _on_condition(self, msg: Message) -> None:
        if msg.xml.get("name") == "ask":  # a reactive module's question, routed through the ES
            self.sim.spawn(self._ask_for_es(msg), name=f"{self.name}-ask")
            return
        if msg.xml.get("name") == "person_info":  # someone speaks facing the robot (potential partner)
            self._person_at = msg.created
            self._person_place = self._place_of(msg.xml.find(".//PERSON"), msg.created)
            if self._call is not None:
                self._answer_call()  # her call by name, heard before the robot had turned to her
        if msg.xml.get("name") == "arrived":  # a go-to ended: her next request resumes the tour
            self._resume_until = self.now + ARRIVAL_RESUME
        if msg.xml.get("name") == "step_aside":  # the object attention cannot see past the partner
            self.sim.spawn(self._step_aside_for_es(msg), name=f"{self.name}-step-aside")
            return
        withdrawn = WITHDRAWN_BY.get(msg.xml.get("name", ""))
        if withdrawn is not None:
            # "OK, I am going to the study." made on entering Navigating, overtaken 0.1 s later by the plan's
            # failure (a place it was never shown): only "Sorry, I do not know where the study is" is said
            self._withdrawn[withdrawn] = self.now
            self._queue = deque(q for q in self._queue if not q[2] or not q[2] <= {withdrawn})
        self._emit(self.manager.on_condition(msg.xml), msg.id)
        if msg.xml.get("name") == "partner_found":
            self._greeting_taken()
        # "OK, I stopped." said (the stop dialog done): now ask about what she showed while it followed
        self._emit(self.manager.take_up_in_passing(), msg.id)
        if self._goodbye_held is not None and msg.xml.get("name") in ("object_learned", "object_not_found"):
            self._release_goodbye()  # the look ended and its result was said: now her good-bye

    async def _ask_for_es(self, msg: Message) -> None:
        """Condition ``ask`` (param ``options``: ``<OPTIONS timeout><option index text/>+</OPTIONS>``):
        ask the partner, then answer with the ES event ``clarified`` (``<ANSWER index/>`` or
        ``<ANSWER none="true"/>``, with ``deixis`` / ``POSITION`` as :func:`unchosen_answer` says),
        which the ES routes back to the module that asked."""
        opts = next((p.find("OPTIONS") for p in msg.xml.iterfind("param") if p.find("OPTIONS") is not None), None)
        options = [] if opts is None else [(int(o.get("index", str(i))), o.get("text", ""))
                                           for i, o in enumerate(opts.iterfind("option"))]
        timeout = float(opts.get("timeout", str(self.ask_timeout))) if opts is not None else self.ask_timeout
        # again="true": the asker puts the question it put just before once more (its answer picked none
        # of the options): the sub-dialog goes on with the last one's count of askings (review14 F1)
        again = opts is not None and opts.get("again") == "true"
        answer = await self._clarify(options, timeout, msg.id, again=again, hand_back=True)
        if self.bus.closed or self.bus.hung:
            return
        ev = etree.Element("event", name="clarified")
        out = etree.SubElement(ev, "ANSWER", dict(answer.attrib))
        for child in answer:  # "the one on the table": its POSITION
            out.append(child)
        self.bus.publish(ES_EVENTS, ev, causes=(msg.id,), transfer=True)

    async def _step_aside_for_es(self, msg: Message) -> None:
        """Condition ``step_aside``: ask the partner to step aside (the ``step_aside`` sub-dialog),
        then tell the ES it has been said: event ``asked_aside`` with ``said="true"`` (``"false"``
        when the sub-dialog could not start), which the ES routes back to the object attention."""
        said = False
        for _ in range(STEP_ASIDE_TRIES):
            made = self.now
            inst, outs = self.manager.start("step_aside", {"asked": "true"})
            if inst is None:
                break
            self._emit(outs, msg.id)
            await self._until_said()
            # dropped unsaid by the turn-taking (she was speaking when it was ready, fresh9 bay_three_books):
            # she was not asked; ask again now that she has paused, never report it said
            said = self._dropped_at.get("step_aside", -math.inf) < made
            if said or self.bus.closed or self.bus.hung:
                break
            paused = self.now + STEP_ASIDE_PAUSE
            while self.now - self._voice_at < TURN_GAP and self.now < paused:  # until she pauses
                await asyncio.sleep(0.1)
        if self.bus.closed or self.bus.hung:
            return
        ev = etree.Element("event", name="asked_aside", said="true" if said else "false")
        self.bus.publish(ES_EVENTS, ev, causes=(msg.id,), transfer=True)

    def _on_rejected(self, msg: Message) -> None:
        rej = msg.xml
        if rej.get("name") == "greeting":
            self._after_greeting = None  # nobody took the greeting: the request said with it goes too
        if rej.get("name") == "greeting" and rej.get("reason") == "expired" and rej.get("state") in SEEN_STATES:
            # The supervisor had seen her speak facing the robot since she began the greeting (its
            # person_info), so the greeting expired because it came too late (a slow dialog host, a
            # slow link), not because nobody was there: "I can't see you" would be untrue.
            stamp = rej.find(".//SPEECH/TIMESTAMP")
            said = float(stamp.get("val", "nan")) / 1000.0 if stamp is not None else math.nan
            if self._person_at is not None and math.isfinite(said) and self._person_at >= said - PERSON_SLACK:
                rej = deepcopy(rej)
                rej.set("reason", "late")
        self._emit(self.manager.on_rejected(rej), msg.id)

    def _on_status(self, msg: Message) -> None:
        state = msg.xml.get("state", "")
        if state in UNGREETED and self.manager.es_state not in UNGREETED:
            # the interaction is over: the voice-level rule's references were that partner's voice; the next
            # partner's own turns make hers (a quiet earlier partner would switch the rule off: review18 F6)
            for d in (self._her_levels, self._her_turns):
                if d is not None:
                    d.clear()
        if state not in UNGREETED:
            self._call = None  # greeted (or anything else began): a call held for a potential partner is past
        gone = self.manager.on_state(state)
        if self.manager.es_state not in ("LookingAround", "PotentialPartner"):
            self._resume_until = -math.inf  # an interaction began (or anything else): the arrival is past
        if gone and self._queue:
            # their sentences not yet said (a question waiting behind the good-bye) are dropped too
            self._queue = deque(q for q in self._queue if not q[2] or not q[2] <= set(gone))
        if self._goodbye_held is not None and self.manager.es_state not in ("ObjectTeaching", "Interacting"):
            self._release_goodbye()  # the look ended elsewhere (a failure, the partner gone): no reason to wait
        # she stopped after showing something while it followed her: ask her to show it again (when no
        # sub-dialog is still open, e.g. the stop's "OK, I stopped." waits for its condition: then after it)
        self._emit(self.manager.take_up_in_passing(), msg.id)

    def _place_of(self, person: etree._Element | None, at: float) -> tuple[float, float] | None:
        """Where a reported PERSON (bearing in degrees and distance, robot frame when the report was made, ``at``)
        stands in the map frame: placed with the localiser's pose nearest ``at``, not the latest one (review22 R8:
        the report of someone found while the base still turns to her voice comes over the WLAN after poses the
        turn has moved on by degrees, a good part of :data:`CALL_WIDTH`). None without a pose or a place."""
        if person is None or not self._poses:
            return None
        b, d = float(person.get("bearing", "nan")), float(person.get("distance", "nan"))
        if not (math.isfinite(b) and math.isfinite(d)):
            return None
        _, ox, oy, oth = min(self._poses, key=lambda o: abs(o[0] - at))  # ties: the earlier pose (deque order)
        return ox + d * math.cos(oth + math.radians(b)), oy + d * math.sin(oth + math.radians(b))

    def _on_pose(self, msg: Message) -> None:
        self._pose = el = msg.xml  # this receiver's own copy; its POSE is built only when an event needs it
        self._poses.append((float(el.get("time", repr(msg.created))), float(el.get("x")), float(el.get("y")), float(el.get("theta"))))

    def _on_speaker(self, msg: Message) -> None:
        tag = msg.xml.tag
        if tag == "speaking":
            self._talking = True
            self._cut = False
            start = float(msg.xml.get("start", "nan"))
            if math.isfinite(start):
                self._talk_start = start
        elif tag in ("done", "interrupted"):
            self._spoke_at = self.now  # the turn is hers now (FOLLOW_ASKS leave it to her)
            if self._told is not None and self._told[2] == math.inf and self._told[1] in msg.xml.get("text", ""):
                self._told[2] = self.now
            if tag == "done" or not self._queue:
                self._talking = False
            if tag == "done":
                self._watch_silence(msg.id)
            self._say_next()

    def _watch_silence(self, cause: str) -> None:
        """A sentence with the open question was said: if nothing is heard for ``ask_timeout`` s after it
        (no frame, no voice from her direction), the manager puts it once more or goes on without it
        (:meth:`DialogManager.on_silence`; issue 26 item 7: a question met by silence)."""
        q = self.manager.open_question()
        if q is None:
            return
        said_at = self._silence_due = self.now
        self.sim.loop.call_at_ns(to_ns(said_at + self.ask_timeout), self._on_silence, q, said_at, cause)

    def _on_silence(self, q: tuple[int, str], said_at: float, cause: str) -> None:
        if self.bus.closed or self.bus.hung or self._talking or self._queue:
            return
        if said_at < self._silence_due:
            return  # the robot said more since (the question again): 10 s count from its newest sentence
        if self._heard_at >= said_at or self._voice_at >= said_at or self.manager.open_question() != q:
            return  # she answered, spoke, or the talk went on
        self._emit(self.manager.on_silence(*q), cause)

    def _on_partner(self, msg: Message) -> None:
        b = float(msg.xml.get("bearing", "nan"))
        d = float(msg.xml.get("distance", "nan"))
        span = None
        if math.isfinite(b) and math.isfinite(d) and d > 0:
            # where the microphone pair hears her voice (a mouth above the pair, beside it, is
            # heard nearer the front: the person attention matches voices to tracks the same way)
            span = heard_span(b, d)
            b = heard_bearing(b, d)
        self._partner = (b, self.now) if math.isfinite(b) else None
        self._partner_dist = (d, self.now) if math.isfinite(d) and d > 0 else None
        if self._partner_dist is not None and self._partner_dists is not None:
            self._partner_dists.append((msg.created, d))
        pose = self._pose
        raw = float(msg.xml.get("bearing", "nan"))
        if pose is not None and math.isfinite(raw) and math.isfinite(d):
            th = float(pose.get("theta", "nan")) + math.radians(raw)
            self._partner_place = (float(pose.get("x", "nan")) + d * math.cos(th), float(pose.get("y", "nan")) + d * math.sin(th))
        facing = msg.xml.get("facing", "unknown")
        if facing != "true" and msg.xml.get("away") == "true" and math.isfinite(d) and d >= ASIDE_DISTANCE:
            facing = ASIDE  # she walked off and turned her back on the robot (the addressee rule)
            if not self._partner_cues or self._partner_cues[-1][1] != ASIDE:
                self._aside_since = msg.created
        if facing == "true":
            self._faced_at = msg.created
        self._partner_cues.append((msg.created, facing, int(msg.xml.get("company", "0")), span))
        if self._others_cues is not None:
            self._others_cues.append((msg.created, int(msg.xml.get("others", "0"))))

    def _facing_now(self) -> str:
        """The latest partner report's ``facing`` ("true", "false", "unknown"), if recent."""
        if self._partner_cues and self.now - self._partner_cues[-1][0] <= self.partner_fresh:
            f = self._partner_cues[-1][1]
            return "false" if f == ASIDE else f  # her back turned: she does not face it
        return "unknown"

    def partner_bearing(self) -> float | None:
        """The partner's bearing (degrees, robot frame) if the person attention reported it recently."""
        if self._partner is None or self.now - self._partner[1] > self.partner_fresh:
            return None
        return self._partner[0]

    def _on_sources(self, msg: Message) -> None:
        self._note_voice(msg)
        if msg.xml.find("source") is not None:  # any voice, from anywhere (FOLLOW_ASKS wait for a pause of them all)
            t = float(msg.xml.get("time", repr(msg.created)))
            if t - self._any_voice_at >= TURN_GAP:
                self._any_voice_since = t
            self._any_voice_at = max(self._any_voice_at, t)
        # every state: the addressee rule asks where the words came from (bounded deque)
        heard = tuple(float(src.get("bearing", "nan")) for src in msg.xml.iterfind("source")
                      if float(src.get("level", "0")) >= VOICE_LEVEL and math.isfinite(float(src.get("bearing", "nan"))))
        if heard:
            self._sources.append((float(msg.xml.get("time", repr(msg.created))), heard))
            if self._levels is not None:
                t = float(msg.xml.get("time", repr(msg.created)))
                for src in msg.xml.iterfind("source"):
                    level, bearing = float(src.get("level", "0")), float(src.get("bearing", "nan"))
                    if level >= VOICE_LEVEL and math.isfinite(bearing):
                        self._levels.append((t, bearing, level))
        if not self._talking or self._cut:
            return
        if float(msg.xml.get("time", "inf")) < self._talk_start:
            return  # recorded before the robot began this sentence (a late frame): not an interruption
        partner = self.partner_bearing()
        if partner is None or self._endless_voice():
            return  # a radio or TV where she stands talks on: it does not cut the robot off
        want = front_bearing(partner)
        for src in msg.xml.iterfind("source"):
            level, bearing = float(src.get("level", "0")), float(src.get("bearing", "nan"))
            if level >= self.barge_in_level and math.isfinite(bearing) and abs(front_bearing(bearing) - want) <= self.barge_in_width:
                self._cut = True
                # cut by her voice: this sentence and those queued were not heard (review22 R2: a step-aside
                # question cut after three words was reported said, and the robot waited for a step she never heard of)
                for d in (*self._talk_dialogs, *(d for q in self._queue for d in q[2])):
                    self._dropped_at[d] = self.now
                self._queue.clear()
                self.manager.barge_in()
                self.bus.publish(SAY, etree.Element("say", text=""), causes=(msg.id,))
                return

    def _note_voice(self, msg: Message) -> None:
        """Remember when a voice came from the partner's direction (as the barge-in rule hears her:
        ``barge_in_level`` dB or more within ``barge_in_width`` of her, folded to the front). The
        microphones' echo cancellation takes the robot's own voice out; without a partner nothing counts."""
        partner = self.partner_bearing()
        if partner is None:
            return
        want = front_bearing(partner)
        for src in msg.xml.iterfind("source"):
            level, bearing = float(src.get("level", "0")), float(src.get("bearing", "nan"))
            if level >= self.barge_in_level and math.isfinite(bearing) and abs(front_bearing(bearing) - want) <= self.barge_in_width:
                t = float(msg.xml.get("time", repr(msg.created)))
                if t - self._voice_at >= TURN_GAP:
                    self._voice_since = t  # a pause before it: a new turn begins
                self._voice_at = max(self._voice_at, t)
                return

    def _endless_voice(self) -> bool:
        """Whether the voice from her direction has gone on for ``VOICE_RUN_MAX`` s without a pause: a source
        that never pauses (a radio, a TV), not her turn; the robot neither waits for it nor yields to it."""
        return self._voice_at - self._voice_since >= VOICE_RUN_MAX

    # ----------------------------------------------------------------- outputs
    def _slot(self) -> float:
        """When the next input's processing ends (serial processor)."""
        t = max(self.now, self._busy_until) + self.dialog_cost
        self._busy_until = t
        return t

    def _emit(self, outs: list[Output], cause: str) -> None:
        if not outs:
            return
        t = self._slot()
        if any(isinstance(o, Explain) for o in outs):
            self.sim.spawn(self._emit_with_explanation(outs, t, cause), name=f"{self.name}-explain")
            return
        self.sim.loop.call_at_ns(to_ns(t), self._send_events, outs, cause)
        done = self.manager.last_success
        if done is not None and (self._told is None or self._told[0] is not done):
            told = " ".join(o.text for o in outs if isinstance(o, Say) and o.dialog == done[0] and o.text)
            if told:
                self._told = [done, told, math.inf]
        texts = [o.text for o in outs if isinstance(o, Say)]
        if texts:
            dialogs = frozenset(o.dialog for o in outs if isinstance(o, Say))
            self.sim.loop.call_at_ns(to_ns(t + self.generation_time), self._enqueue, " ".join(texts), cause, dialogs, t)

    async def _emit_with_explanation(self, outs: list[Output], t: float, cause: str) -> None:
        await asyncio.sleep(max(0.0, t - self.now))
        self._send_events(outs, cause)
        texts: list[str] = []
        for o in outs:
            if isinstance(o, Say):
                texts.append(o.text)
            elif isinstance(o, Explain):
                texts.append(await self._explanation())
        await asyncio.sleep(max(0.0, t + self.generation_time - self.now))
        self._enqueue(" ".join(x for x in texts if x), cause)

    async def _explanation(self) -> str:
        """Ask the supervisor what it is doing and what it accepts now."""
        try:
            reply = await self.bus.call("supervisor", "introspect", etree.Element("introspect"), timeout=1.0)
        except BusError:
            return self.manager.explanation(self.manager.es_state, [])
        st = reply.xml
        applies = [e.get("name", "") for e in st.iterfind("accepts/event") if e.get("status") == "applies"]
        waits = [e.get("name", "") for e in st.iterfind("accepts/event") if e.get("status") == "waits"]
        return self.manager.explanation(st.get("state", ""), applies, waits)

    def _send_events(self, outs: list[Output], cause: str) -> None:
        if self.bus.closed or self.bus.hung:
            return
        for o in outs:
            if isinstance(o, Send):
                if o.event in ENDS_A_PAUSE and self.manager.es_state in LEADING_STATES and self._walk_over(cause):
                    # she said "hang on" and the robot waits by her: the walk is over, what she shows now is
                    # taught (fresh5 stair_wait_walks_on: "I am still following you; say stop first.")
                    stop = etree.Element("event", name="stop")
                    etree.SubElement(etree.SubElement(stop, "SPEECH"), "STOP")
                    self.bus.publish(ES_EVENTS, stop, causes=(cause,), transfer=True)
                    self._follow_state = ""
                    self.pauses_ended += 1
                el = etree.Element("event", name=o.event)
                if o.event == "stop" and cause == self._stood_stop_cause:
                    el.set("stood", "true")  # taken through the stood-stop exception (the person attention reads it)
                    self._stood_stop_cause = None
                if o.lifetime is not None:
                    el.set("lifetime", repr(float(o.lifetime)))
                for c in o.children:
                    el.append(c)
                if o.pose and self._pose is not None:
                    x = self._pose
                    el.append(etree.Element("POSE", x=x.get("x", "0"), y=x.get("y", "0"), theta=x.get("theta", "0"),
                                            frame=x.get("frame", "map")))
                self.bus.publish(ES_EVENTS, el, causes=(cause,), transfer=True)

    def _enqueue(self, text: str, cause: str, dialogs: frozenset[str] = frozenset(), made: float | None = None) -> None:
        if not text:
            return
        if made is not None and dialogs and all(self._withdrawn.get(d, -math.inf) >= made for d in dialogs):
            return  # made before its dialog's news was overtaken (see WITHDRAWN_BY): never said
        if dialogs and dialogs <= FOLLOW_ASKS and any(q[0] == text for q in self._queue):
            return  # the same request of its own already waits for a pause: asked once
        self._queue.append((text, (cause,), dialogs, self.now, text in self._repairs))
        if not self._talking:
            self._say_next()

    def _say_next(self) -> None:
        if not self._queue or self.bus.closed or self.bus.hung or self._hold_ask() or self._hold():
            return
        text, causes, dialogs, *_ = self._queue.popleft()
        self._talk_dialogs = tuple(sorted(dialogs))
        self._repair_dropped = False  # something said: the next repair due may be dropped again
        self._talking = True
        self._cut = False
        self._talk_start = self.now
        self._said += 1
        self.manager.metrics["robot_turns"] += 1
        self.bus.publish(SAY, etree.Element("say", text=text), causes=causes)
        # Without a word from the speaker (none installed, or its status lost) the
        # queue must not stall: give up waiting well after the sentence would end.
        patience = 0.5 + 0.45 * max(1, len(text.split()))
        self.sim.loop.call_at_ns(to_ns(self.now + patience), self._speaker_silent, self._said)

    def _hold(self) -> bool:
        """Turn-taking (issue 26, fresh3 passage_talk_aside: the robot began and cut off "Sorry, I did not
        understand you" eight times over a couple talking to each other): while a voice from the partner's
        direction was heard within ``TURN_GAP`` s, the next sentence waits for a pause. A sentence ready
        before a voice was heard there is not said at all: begun, the barge-in rule would have cut it at
        that voice's first frame (the same outcome, without talking over her; her words are her next
        turn, answered in their own right; a "say that again" among them is counted as
        ``stale_repairs``), except a repair when the last repair due was dropped too (never two in a row,
        review12 item 5). A sentence held ``HOLD_MAX`` s is said anyway. It never waits for a voice that
        does not pause (:meth:`_endless_voice`: a radio or TV behind her), nor holds more than
        ``HOLD_BUDGET`` s in ``HOLD_WINDOW`` s. True while a sentence is held (a timer looks again)."""
        if self.now - self._voice_at >= TURN_GAP or self._endless_voice():
            return False
        if sum(1 for t in self._hold_steps if self.now - t < HOLD_WINDOW) * HOLD_STEP >= HOLD_BUDGET:
            return False
        def overtaken(q: tuple[Any, ...]) -> bool:
            if self._voice_at <= q[3]:
                return False
            if q[4]:  # a repair: never two dropped in a row
                if self._repair_dropped:
                    return False
                self._repair_dropped = True
                self.stale_repairs += 1
            return True

        if self._drop_queued(overtaken):
            self.manager.barge_in()  # as if begun and cut: the dialog's barge-in count
        if not self._queue or self.now - self._queue[0][3] >= HOLD_MAX:
            return not self._queue
        if self._queue[0] is not self._held_head:
            self._held_head = self._queue[0]
            self.held_sentences += 1
        if not self._holding:
            self._holding = True
            self._hold_steps.append(self.now)
            self.sim.loop.call_at_ns(to_ns(self.now + HOLD_STEP), self._hold_over)
        return True

    def _hold_ask(self) -> bool:
        """A request of its own while it follows (:data:`FOLLOW_ASKS`) waits for a pause of every voice heard,
        ``ASK_QUIET`` s (she may be speaking where it cannot see her, under the barge-in level: its voice would
        mask hers), and as long after its own last sentence (the turn is hers: split_children_cross seed 0 began
        "Excuse me" the moment its "Could you say that again?" ended, and his "Stop" 0.5 s later was lost under
        it). Something else to say behind it (an answer to her words) goes first, and the request is
        dropped (the follower asks again while still held up). Like :meth:`_hold`: at most ``HOLD_MAX`` s,
        never for a sound that does not pause (``VOICE_RUN_MAX``), within ``HOLD_BUDGET``. True while held."""
        head = self._queue[0]
        if not head[2] or not head[2] <= FOLLOW_ASKS:
            return False
        if any(not (q[2] and q[2] <= FOLLOW_ASKS) for q in self._queue):
            while self._queue and self._queue[0][2] and self._queue[0][2] <= FOLLOW_ASKS:
                for d in self._queue.popleft()[2]:
                    self._dropped_at[d] = self.now
            return False
        endless = self._any_voice_at - self._any_voice_since >= VOICE_RUN_MAX
        if (self.now - max(self._spoke_at, -math.inf if endless else self._any_voice_at) >= ASK_QUIET
                or self.now - head[3] >= HOLD_MAX
                or sum(1 for t in self._hold_steps if self.now - t < HOLD_WINDOW) * HOLD_STEP >= HOLD_BUDGET):
            return False
        if head is not self._held_head:
            self._held_head = head
            self.asks_held += 1
        if not self._holding:
            self._holding = True
            self._hold_steps.append(self.now)
            self.sim.loop.call_at_ns(to_ns(self.now + HOLD_STEP), self._hold_over)
        return True

    def _hold_over(self) -> None:
        self._holding = False
        if not self._talking:
            self._say_next()

    def _speaker_silent(self, serial: int) -> None:
        if serial == self._said and self._talking:
            self._talking = False
            self._say_next()

    # ---------------------------------------------------------------------- RPC
    async def _until_said(self, fut: asyncio.Future[Any] | None = None) -> None:
        """Wait until what was just emitted has been said (or ``fut`` is done: answered meanwhile)."""
        said = self._busy_until + self.generation_time  # when it is handed to the speaker
        await asyncio.sleep(max(0.0, said - self.now) + 0.01)
        while (self._talking or self._queue) and not (fut is not None and fut.done()):
            await asyncio.sleep(0.1)

    async def _rpc_ask(self, msg: Message) -> etree._Element:
        """Clarification by RPC (kept for tools; BIRON's modules ask through the ES): index or none."""
        req = msg.xml
        if req.get("about") == "occluded":  # no choice to make: ask her to step aside, answer when said
            inst, outs = self.manager.start("step_aside", {"asked": "true"})
            if inst is None:
                return etree.Element("answer", none="true")
            self._emit(outs, msg.id)
            await self._until_said()
            return etree.Element("answer", said="true")
        options = [(int(o.get("index", str(i))), o.get("text", "")) for i, o in enumerate(req.iterfind("option"))]
        return await self._clarify(options, float(req.get("timeout", str(self.ask_timeout))), msg.id)

    def _said_which(self) -> etree._Element | None:
        """The side she named in answer to the object teaching's confirmation ("Is this your cup?" -
        "the left one", kept on the object by the manager), as a ``THAT_ONE`` :func:`choose` reads; None
        when she named none."""
        for inst in reversed(self.manager.stack):
            obj = inst.slots["object"].value if "object" in inst.slots else None
            if isinstance(obj, etree._Element) and obj.tag == "OBJECT" and obj.get("side"):
                return etree.Element("THAT_ONE", side=str(obj.get("side")))
        return None

    async def _clarify(self, options: list[tuple[int, str]], timeout: float, cause: str, *,
                       again: bool = False, hand_back: bool = False) -> etree._Element:
        """Ask the partner which option they mean (the clarify sub-dialog): ``<answer index/>``, or
        ``<answer none="true"/>`` with what the asker can still use (:func:`unchosen_answer`).
        ``again``: the same question put once more by its asker; the new sub-dialog starts with the
        last one's count of askings, so a which-one question is put at most twice in all, whichever
        path (the asker's second putting, the dialog's "say that again") asks again. ``hand_back``: the
        asker (the object attention, through the ES) puts it again itself: an answer to its first putting
        that is not understood ends the sub-dialog unanswered (``asked="1"``) instead of "Sorry, ... Do you
        mean ...?", so the asker first uses the pointing it saw with the answer (:meth:`_handle_frame`)."""
        said = self._said_which()
        if said is not None:
            picked = choose(options, said, self._facing_now())
            if picked is not None:  # "Is this your cup?" - "the left one": she said which one already
                return etree.Element("answer", index=str(picked))
        fut: asyncio.Future[Instance] = self.sim.loop.create_future()

        def ended(inst: Instance) -> None:
            if not fut.done():
                fut.set_result(inst)

        phrase = options_phrase(self.doc, [t for _, t in options])
        prior, self._clarify_asked = self._clarify_asked if again else None, None
        inst, outs = self.manager.start("clarify", {"options": phrase} if phrase else {}, on_end=ended, asked=prior)
        if inst is None:
            return etree.Element("answer", none="true")
        self._asking, self._asking_inst = options, inst
        self._hand_back = hand_back
        try:
            return await self._clarified(inst, fut, options, timeout, cause, outs)
        finally:
            self._asking = self._asking_inst = None
            self._hand_back = False
            self._clarify_asked = dict(inst.asked)  # (a few questions: what the next putting "again" goes on from)

    async def _clarified(self, inst: Instance, fut: asyncio.Future[Instance], options: list[tuple[int, str]],
                         timeout: float, cause: str, outs: list[Any]) -> etree._Element:
        """The clarify sub-dialog ``inst`` started (its first outputs ``outs``): wait for its answer."""
        self._emit(outs, cause)
        # The partner has ``timeout`` s to answer once the question has been said (a long
        # question with its options takes several seconds to say), and again once the sub-dialog
        # asked it again (an answer it did not understand): her time runs from the latest asking.
        await self._until_said(fut)
        asked = sum(inst.asked.values())
        while True:
            try:
                async with asyncio.timeout(timeout):
                    done = await asyncio.shield(fut)  # a timeout leaves the sub-dialog's end to come
                break
            except TimeoutError:
                if sum(inst.asked.values()) > asked and not fut.done():
                    asked = sum(inst.asked.values())
                    continue
                self._emit(self.manager.cancel(inst), cause)
                return etree.Element("answer", none="true")
        value = done.slots["choice"].value if done.success else None
        picked = choose(options, value, self._facing_now())
        if picked is None:
            out = unchosen_answer(value)
            # how often the question was put: an asker that finds the answer picks none of its options asks
            # again only while the same question has been put once (never more than twice in all)
            out.set("asked", str(max(1, sum(inst.asked.values()))))
            return out
        return etree.Element("answer", index=str(picked))


def said_act(frame: etree._Element) -> str:
    """What a speech frame asks or tells, for telling a repeat: its ``SPEECH`` without the time stamp
    (so "where is my cup" and a misheard "where uh my cup" are one act), or its words when not understood."""
    speech = frame.find("SPEECH")
    if speech is None:
        return "words:" + " ".join((frame.findtext("words") or frame.text or "").lower().split())
    speech = deepcopy(speech)
    for stamp in speech.findall("TIMESTAMP"):
        speech.remove(stamp)
    return etree.tostring(speech, encoding="unicode")
