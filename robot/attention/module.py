"""The person attention system as a bus module: participant ``person_attention``.

Per laser scan (``/robot/laser/scan``): detect legs (:mod:`.legs`), move the
candidates into the odom frame with the odometry pose extrapolated to the
scan's time, anchor them to tracks (:mod:`.tracker`), read the categories
from the speaking/facing attributes (:mod:`.cues`, fed by
``/robot/audio/sources`` and ``/robot/camera/faces`` as they arrive), select
the person of interest (:mod:`.selection`), advance the attention FSM
(:mod:`.fsm`) and act:

- ``/robot/attention/tracks`` every scan, ``/robot/attention/state`` on each
  change and once a second, ``/robot/attention/partner`` every scan while a
  partner exists (docs/robot-contract.md);
- ES events on ``/robot/es/events`` (each names the laser scan it was decided
  on as its cause, so the trace links a scan to the event): ``potential_partner`` (``<PERSON id
  bearing distance speaking facing/>``) when the selected person speaks
  while facing the robot, repeated every ``pp_repeat`` s while it lasts;
  ``potential_partner_lost`` when they stop and the last ``potential_partner``
  has run out of its validity (``pp_valid``, its AFSM lifetime); ``partner_lost`` in a
  top-down state by the leaving rule (:meth:`PersonAttention.partner_left`; once per loss) on the
  partner's anchored evidence: a leg update, a frontal
  face, a torso blob at the partner's bearing (``/robot/camera/torsos``)
  or their voice from there: a partner the camera still sees is not lost
  because their legs did not associate for a moment. Lifetimes are the AFSM's;
- ``/robot/ptu/cmd``: the camera on the person (face, hands, torso) or the
  object focus (``/robot/objects/focus``), ahead while sleeping;
- ``/robot/base/cmd``: turning on the spot towards the person in Listen,
  Interaction and Object (a zero command when it faces them or leaves
  those states); never in Follow, where the follower drives, nor while the
  follower's status says ``approaching`` (it comes up to the partner after
  "stop" and faces her itself);
- ``/robot/audio/steer``: the recogniser's beam (:meth:`PersonAttention.beam`):
  on the partner in the top-down states; bottom-up on the potential
  partner (selected, speaking while facing the robot); otherwise on the
  dominant unexplained sound direction (the loudest direction of the last
  ``/robot/audio/sources`` frame that no confirmed track accounts for, at
  most ``dominant_max_age`` old), so a greeting from where no person is seen
  (a radio) is still recognised and reaches the supervisor, which rejects it
  as expired because no potential partner backs it (docs/semantics.md §2), while a
  seen person talking without facing the robot stays unheard (gated, docs/semantics.md §3);
  off when all is quiet.

Orders arrive on ``/robot/es/orders/person_attention``; an unknown order
changes nothing and is kept, with the reason, in
:attr:`PersonAttention.refused` (bounded).
"""

from __future__ import annotations

import asyncio
import math
from collections import deque
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module

from robot.blindside import SonarEchoes, blind_clear, blind_points, explained_by_points, seen_legs
from robot.bumpers import BumperReflex, own_reflex
from robot.contract import (ATTENTION_STATE, BASE_CMD, BUMPERS, ES_EVENTS, ES_ORDERS, FACES, FOCUS, FOLLOW_STATUS, FRAMES, ODOMETRY, PARTNER, PLAN,
                            PLAYER_STATUS, POSE, PTU_CMD, SCAN, SONAR, SOURCES, STEER, TORSOS, TRACKS)

from .appearance import Colours, anchor_torsos, same_clothes
from .clutter import FurnitureLegs
from .cues import CueSpec, Hysteresis, bearings_from, match_faces, match_sounds, sound_bearing_span, sound_bearings_from, span_offset, voice_reach
from .fsm import CAMERA, TURNS, AttentionFSM, OrderRefused
from .legs import SINGLE, LegDetector, LegSpec
from .looking import HeardFrom, LookedAt, angle_between
from .records import TrackRow, TracksRecord, own_document as _own_document
from robot.footprint import outline, people_sweep_clear, points_sweep_clear, sweep_poses, turn_clear
from robot.partner_search import STOOD_FOR, Closing, follow_search_time, way_distance, yielding
from .selection import SelectionParams, Selector
from .tracker import FACE, Tracks, TrackerSpec
from .visibility import hidden_points

SCHEMAS = Path(__file__).resolve().parent.parent / "schemas"
ORDERS = f"{ES_ORDERS}/person_attention"

#: The attention system's own typed channels (declared by :func:`declare_channels`).
CHANNEL_SCHEMAS = {
    TRACKS: SCHEMAS / "attention-tracks.xsd",
    ATTENTION_STATE: SCHEMAS / "attention-state.xsd",
    PARTNER: SCHEMAS / "attention-partner.xsd",
}


def declare_channels(bus: Any) -> None:
    """Type the attention system's channels on ``bus``."""
    for ch, path in CHANNEL_SCHEMAS.items():
        bus.declare_channel(ch, path)


@dataclass(frozen=True)
class AttentionParams:
    """Every time limit and gain of the attention behaviour, with its default."""

    pp_repeat: float = 1.0  # s: potential_partner repeated while it lasts (its lifetime is 1.5 s)
    # s: the last potential_partner stays valid this long (its lifetime in the AFSM, the papers'
    # "how long an event remains valid"): potential_partner_lost goes out only when it has run out,
    # so a greeting still on its way (recognition, then the WLAN) meets the partner it belongs to.
    pp_valid: float = 1.5
    # s: ... but someone who spoke to the robot facing it and still faces it, silent, awaits its
    # answer: she stays the potential partner this long after she last spoke, so a greeting that a
    # slow dialog host or link delivers late still meets her (docs/semantics.md §2, synchronisation)
    pp_wait: float = 8.0
    partner_lost_after: float = 2.0  # s without anchored evidence of the partner (legs, frontal face, torso, voice) ...
    # ... is "lost" in Interaction and Object only with evidence of leaving (docs/subsystems.md):
    # s unseen while following: she leads, so being out of view a moment (a door frame, someone crossing,
    # walking past the robot's side) is no evidence of leaving; the follower searches where she was
    # predicted to be meanwhile (its search_time, 6 s) and this is how long it may
    follow_lost_after: float = 6.0
    # s: following, the follower's status has said "stopped" (its search over, she unseen by its
    # measure) this long: she is lost, whatever a camera sighting says (the robot never stands silent)
    follow_stopped_after: float = 2.0
    # s: following ended (a stop) while the follower searched for her: this long its next status (approaching,
    # or none) is waited for before she is taken as gone by the interaction's rule (:meth:`partner_left`)
    follow_handover: float = 1.0
    # m/s: the robot's own top speed (its configuration, robot.partner_search.robot_top_speed; None: the
    # base's default): a slow robot needs longer to drive the gap to where a far partner went out of view
    robot_top_speed: float | None = None
    interaction_radius: float = 3.0  # m: last seen further from the robot than this is outside the interaction space
    leave_speed: float = 0.3  # m/s: last seen walking away from the robot at least this fast
    # m: after a loss, someone speaking while facing the robot takes the partner's place only this
    # near (Hall's social distance: a conversation with the robot, not a chat across the room)
    retake_radius: float = 2.0
    # m: ... but one who speaks facing it in the lost partner's own clothes (the camera saw hers) is
    # she, come back: taken back this far (issue 26: a partner who calls it from across the room
    # after it lost her, 4 m away, was not heard as hers and the interaction ended)
    retake_known_radius: float = 5.0
    # s: in Interaction and Object, the partner's track seen this long in other clothes than those it showed when
    # it became hers (the camera's running colour, fresh, further off than the appearance's ``differ``) is someone
    # else: the identity went over to a bystander she walked past (generated tours 8800-01, -19: the robot stood
    # talking to a silent guest and shut her every word out of the beam as a bystander's, for the rest of the tour)
    other_clothes_after: float = 3.0
    out_of_view_after: float = 10.0  # s without any evidence: gone, wherever she was last seen
    # s after the robot asked her to step aside (the ES's order ``asked_aside``): her walking away is the step it
    # asked for, no evidence of leaving (obj24; tests/scenarios/perceive/doorway_hides_radio: asked to step aside,
    # he stepped through a door out of view and was "You left" 4 s later); the object attention waits 10 s for
    # her step and 4 s for her to stand
    aside_walk: float = 15.0
    # s: what she said weighs her walking away (aside24, fresh12 A and G). After a wait request of hers ("one moment",
    # "hang on", "wait here": the understanding's WAIT) she comes back: for ``wait_walk`` s her walking away is no
    # evidence of leaving (as the step aside the robot asked for), and a partner who asked it to wait, or whom it
    # asked to step aside, is waited for ``wait_patience`` s unseen where she was last seen within the interaction
    # space (a watering can fetched from behind the balcony wall; standing where she stepped, hidden)
    wait_walk: float = 15.0
    wait_patience: float = 30.0
    # s: after a good-bye of hers (GOODBYE, understood at any confidence: the dialog may still doubt it and ask
    # "Do you want to end the tour?"), for ``bye_walk`` s her walking away is evidence again whatever was asked or
    # said before, and unseen ``bye_patience`` s anywhere she is gone (fresh12 studio_couple_turns: he said good-bye,
    # doubted, and walked out of the front door)
    bye_walk: float = 20.0
    bye_patience: float = 4.0
    # m: leaving through the flat's exit door: last seen walking (``leave_speed`` or faster) and her way on this
    # far (at most, at her pace, over the time unseen) leads out of the map's rooms through a gap in its walls,
    # she has left after ``partner_lost_after`` s, whatever she said (the robot's map: the flat is its rooms)
    exit_reach: float = 1.2
    # m: walking away within the interaction space, her way on this far (along her last velocity) leads out of the
    # map's rooms before it meets a wall: she walks to the exit door (leaving); otherwise to somewhere in the flat
    exit_look: float = 6.0
    # s: she spoke (her voice from her track) up to this long before she was last seen: her words' frame (a wait
    # request, a good-bye: "one moment" said while she walks off behind a wall) is waited for before her walking
    # away or distance counts as evidence of leaving, at most ``words_wait`` s after her voice was last heard
    voice_hold: float = 1.5
    words_wait: float = 8.0
    # rad: in Interaction/Object, she unseen (a shelf, a wardrobe hides her), a voice nobody seen explains read from
    # where she can be (where her legs were last measured, within the reacquisition radius, ``reacquire_radius`` plus
    # ``reacquire_speed`` per s unseen, at most 2.5 m: where a new track would be taken as hers, :meth:`_reacquire`),
    # as seen from the robot now, is hers; the angle that radius spans is at most this (near the robot it would
    # take in half the room): she stands out of view and talks to the robot. It keeps her the partner
    # (:meth:`partner_left`, unseen patience counted from her last word, ``come_back_after`` s; ``wait_patience``
    # after a wait request or a step aside) and the robot turns toward it (:meth:`_toward_her_voice`)
    unseen_voice_spread: float = math.radians(50.0)
    # s with no partner at all after a loss (the robot asked her to come back): time to walk back from
    # the next room; then the interaction ends and the robot looks around (:meth:`_nobody_there`)
    come_back_after: float = 20.0
    reacquire_radius: float = 1.0  # m: a new track this near where the unseen partner was (plus ...
    reacquire_speed: float = 0.3  # ... this many m per s unseen, at most 2.5 m) is the partner again
    # following, she walks on while unseen: a track in her clothes this far from where she was last
    # measured (her last speed, at most follow_walk_speed m/s, per s unseen; at most
    # follow_reacquire_cap m) is hers again (PersonAttention._reacquire_walking)
    follow_walk_speed: float = 1.0
    follow_reacquire_cap: float = 5.0
    turn_start: float = math.radians(12.0)  # start turning when the person is further off the axis
    turn_stop: float = math.radians(4.0)  # stop turning when within this
    turn_gain: float = 1.5  # rad/s per rad of bearing
    max_turn: float = 0.8  # rad/s
    # Turning on the spot sweeps the footprint's corners round a 0.33 m circle: each turn is held to the
    # people sweep rule (robot.footprint.turn_clear) over ``turn_check`` s against everyone within
    # ``turn_reach`` m (every track, seen, hidden or dormant, and this scan's leg candidates), and a turn
    # toward a bearing the laser does not see (further off the axis than ``blind_bearing``: someone who
    # spoke from beside or behind the robot may stand there) is at most ``blind_turn`` rad/s, so that the
    # laser sees what the leading corner comes to in time to stop it (u_catch_up_slow seeds 6, 8)
    turn_check: float = 0.5  # s
    turn_reach: float = 1.5  # m
    echo_gap: float = 0.03  # m: a turn keeps the corners this far from the laser's echoes (walls, furniture), or no nearer than now
    # m: an echo this near the floor plan's walls and furniture (the map pose's error) is the flat; any other
    # echo near the robot may be a person's leg (the leg detector needs whole legs, and at the laser's edge
    # it sees half of one): a turn keeps clear of a body behind it as of a tracked one
    plan_explains: float = 0.12
    # m: the leg filter grows the walls (and furniture standing on the floor) by a leg's radius: a leg's
    # centre is never nearer a wall's surface, and a door jamb's end placed with the map pose's error of a
    # few centimetres is not a leg (robot.attention.clutter)
    leg_wall_margin: float = 0.06
    blind_bearing: float = math.radians(70.0)
    blind_turn: float = 0.4  # rad/s
    # Making room (turn21): a turn toward a person that only the sonar refuses (someone heard close behind the
    # robot, where either way round swings a rear corner nearer to them, robot.blindside.blind_clear) is preceded
    # by a creep ahead, away from them, at ``room_speed`` m/s (turning on as it creeps where that is clear, else
    # straight), at most ``room_max`` m (then it stands, as before), only where the laser's echoes ahead keep ``room_gap`` m, every body near keeps the social gap (or no
    # nearer than now), the floor plan's walls and furniture are not entered and the sonar has nothing the creep
    # comes nearer to. A partner who walked past the robot's side and stood at its back (generated tour 8900-3:
    # 0.36 m behind it, her track coasting 1 m off to its side) was never turned to: "You left", and her greetings
    # from there were never answered. A refusal that stops for ``room_reset`` s starts a new allowance
    room_speed: float = 0.15  # m/s
    room_max: float = 0.3  # m
    room_gap: float = 0.15  # m
    room_reset: float = 2.0  # s
    camera_height: float = 1.41
    # the camera's own field of view (its data sheet: 48.8 x 37.6 degrees), less a margin: a face
    # this far inside the image that the detector does not report looks away (facing="false")
    camera_hfov: float = math.radians(48.8 - 4.0)
    camera_vfov: float = math.radians(37.6 - 4.0)
    face_view_fresh: float = 0.5  # s: the latest such look at the partner's face counts this long
    heights: dict[str, float] = field(default_factory=lambda: {"face": 1.60, "hands": 1.0, "torso": 1.25})
    # Her hands in Interaction span from a hand pointing down at a table (``heights["hands"]``, the image's
    # middle) up to a hand raised to point at a high shelf: about as high as her face and up to
    # ``hand_reach`` m nearer the robot than she stands. Close to her (within about 2 m) an image centred on
    # 1.0 m ends below the camera's own height, and her raised hand was never seen (fresh8 terr_long_tour:
    # the red book on the 1.8 m bookcase, pointed at from 1.2 m, "Let me have a look." and nothing, 10/10);
    # the camera then tilts up until that raised hand is ``hand_top_margin`` inside the image's top.
    # OFF by default (lane high22): it fixes that book, but close up her face then comes into the image, the
    # robot sees whether she faces it, and the dialog's addressee rule took a bystander's words in a group as
    # addressed (flow/chat_group_bye seed 2, tests/test_flow_addressee.py); that rule must handle a known
    # facing in Interaction before this is switched on.
    raise_for_hands: bool = False
    hand_reach: float = 0.3  # m
    hand_top_margin: float = math.radians(1.0)
    ptu_deadband: float = math.radians(1.5)
    ptu_refresh: float = 1.0  # s
    steer_deadband: float = math.radians(3.0)
    dominant_max_age: float = 0.35  # s: a sound-direction frame older than this no longer steers the beam
    # m: another person standing this near the partner makes a group she may be talking with
    # (published as the partner's ``company``; the dialog's addressee rule reads it, docs/attention.md)
    group_radius: float = 1.6
    # Turned away (issue 26 item 3, the dialog's addressee rule): in Interaction a partner who walks
    # away from the robot (``leave_speed`` or faster) faces where she goes, her back to it; she is
    # turned away until the camera sees her frontal face or she walks towards the robot. Meanwhile the
    # camera looks at her face instead of her hands (beyond ~1.2 m her hands stay in the image), so
    # that it sees her turn back; the partner message says ``away="true"``.
    partner_voice_tolerance: float = math.radians(4.0)  # a direction this near the partner's bearing is her voice (beam gate)
    # Turning to a voice nobody seen explains (bottom-up, nobody selected speaks): someone greeting
    # from the side, beyond the laser's or the camera's field, or hidden from the laser:
    voice_turn_min: float = math.radians(30.0)  # turn when the voice comes from further off the axis
    voice_turn_time: float = 4.0  # s: the turn ends after this (the voice may be a radio) ...
    voice_turn_slack: float = 1.5  # s: ... or, for a turn round to a voice from behind, its angle at max_turn plus this
    # Front or back (robot.attention.looking): a voice read where the camera has just looked and seen
    # no face, and no laser track explains, came from behind: turn to its mirrored reading. A direction
    # looked at and found empty is not turned to again for this long (a radio is heard from both; a
    # person may walk up behind the robot after it looked there, so not much longer than a turn round)
    voice_look_memory: float = 10.0
    # s: a person found facing the robot where an unexplained voice came from (either reading) this
    # recently, not in view when it was heard, is the one who spoke (she greeted it from behind or
    # beside and waits, silent, for its answer): she counts as speaking (category 3 when facing)
    voice_recall: float = 4.0
    voice_refine: float = math.radians(25.0)  # a new reading this near the direction turned to refines it
    voice_recall_tolerance: float = math.radians(12.0)
    face_look_tolerance: float = math.radians(10.0)  # a face this near a direction: someone is there
    # rad: how far the pan-tilt unit pans (the EVI-D31's data sheet). In Object, a focus further round
    # than this (she points behind the robot) turns the base until it lies ``focus_margin`` inside it,
    # instead of turning to her: the camera cannot look there otherwise
    pan_limit: float = math.radians(100.0)
    # m: who addresses the robot is not only whom the camera happens to face: a person speaking out of the
    # camera's image (it cannot tell whether she faces the robot) nearer than this and markedly nearer than
    # every speaker seen facing it is looked at first (:meth:`_unseen_speaker`; Hall's social distance, as
    # ``retake_radius``): two greeting at once, the near one the robot was not looking at is not passed over
    look_radius: float = 2.0
    # ... and at most this fraction of the nearest category-3 person's distance: her voice then reaches the
    # robot at least 6 dB louder at the same effort (inverse square law), enough to dominate a beam that
    # rejects sound outside it by 6 dB (the microphones' model); a near voice no louder than the one facing
    # the camera is no reason to look away from a greeting (distractor seed 1: Tom muttering 1.97 m away,
    # turned away, while Anna greeted from 2.3 m)
    look_ratio: float = 0.5
    look_settle: float = 0.5  # s in the image: long enough for the face detector to tell (facing_on frames)
    focus_margin: float = math.radians(15.0)
    # Faces whose legs the laser cannot see (a table top or a sofa between, robot.attention.tracker FACE):
    # a frontal face no track explains, where the scan is blocked short of it, is a person candidate
    # for this long after its frame
    face_candidate_age: float = 0.15
    legs_hidden_after: float = 2.5  # s without a leg update (the tracker's death timeout): her legs are hidden, the camera keeps her face in view
    state_refresh: float = 1.0  # s
    cue_max_age: float = 0.3  # s: an odometry pose older than this is extrapolated
    max_refused: int = 32


_row = TrackRow._make


#: m: an echo is a leg's near surface: the leg's centre lies this far behind it along the beam
LEG_BEHIND = 0.06
#: s: the partner's walking pace (:meth:`PersonAttention._walk_reach`) remembers her fastest lately over this long
PACE_MEMORY = 3.0
#: s: following ended by a stop, a voice heard from a track this recently is the stop's (her "stop" ends its
#: words 1-3 s before the supervisor's order comes: recognition, understanding and the bus)
STOP_VOICE = 4.0
#: s: a good-bye frame is hers when her voice (from her track) was heard at most this long before its words began
#: (the sound frames' period and the recogniser's start mark; review25 F-B)
BYE_VOICE_SLACK = 0.3
#: s: how long a watch answer "unseen" (the way outside the laser's view) is looked along (answers come every second)
WAY_LOOK_AGE = 2.5


def _in_polygon(x: float, y: float, poly: np.ndarray) -> bool:
    """Even-odd test of one point against a polygon's outline (map frame)."""
    inside = False
    n = len(poly)
    for i in range(n):
        x1, y1 = float(poly[i][0]), float(poly[i][1])
        x2, y2 = float(poly[(i + 1) % n][0]), float(poly[(i + 1) % n][1])
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            inside = not inside
    return inside


def _crosses(ax: float, ay: float, bx: float, by: float, w: tuple[float, float, float, float]) -> bool:
    """Whether segment a-b crosses a wall's centre line (proper or touching intersection)."""
    cx, cy, ex, ey = w

    def side(px: float, py: float, qx: float, qy: float, rx: float, ry: float) -> float:
        return (qx - px) * (ry - py) - (qy - py) * (rx - px)

    d1, d2 = side(cx, cy, ex, ey, ax, ay), side(cx, cy, ex, ey, bx, by)
    d3, d4 = side(ax, ay, bx, by, cx, cy), side(ax, ay, bx, by, ex, ey)
    return d1 * d2 <= 0.0 and d3 * d4 <= 0.0 and not (d1 == d2 == 0.0)


def walking_pace(prev: tuple[float, float] | None, t: float, speed: float) -> tuple[float, float]:
    """(``t``, pace): a person's walking pace after a sighting at ``t`` with track speed ``speed`` (m/s),
    given the pace ``prev`` (when, m/s) kept so far (None: the first sighting). The faster of this speed
    and the kept pace faded by ``exp(-dt / PACE_MEMORY)``: a track slows when she turns (a constant-
    velocity filter cuts the corner), so the speed of one sighting understates how far she walks on."""
    if prev is None:
        return (t, speed)
    when, pace = prev
    return (t, max(speed, pace * math.exp(-max(0.0, t - when) / PACE_MEMORY)))


def echo_bodies(echoes: np.ndarray, explained: np.ndarray, offset: float) -> np.ndarray:
    """(K, 2) robot-frame bodies a turn keeps clear of for the ``echoes`` (robot frame) that the floor plan
    does not explain (``explained``): each a leg, its centre :data:`LEG_BEHIND` m behind the echo as seen from
    the laser (``offset`` m ahead of the centre)."""
    e = echoes[~explained] if len(echoes) else echoes
    if not len(e):
        return np.zeros((0, 2))
    dx, dy = e[:, 0] - offset, e[:, 1]
    r = np.maximum(np.hypot(dx, dy), 1e-6)
    return np.column_stack((e[:, 0] + LEG_BEHIND * dx / r, e[:, 1] + LEG_BEHIND * dy / r))


def turn_rate(b: float, bodies: np.ndarray, p: AttentionParams) -> float:
    """The rate (rad/s) person attention turns on the spot toward bearing ``b`` (rad, robot frame) with
    ``bodies`` (robot-frame centres: tracks and leg candidates) near: the turn law's (``turn_gain``, at most
    ``max_turn``), at most ``blind_turn`` toward a bearing beyond ``blind_bearing``, 0 where the footprint's
    sweep over ``turn_check`` s would come within ``TURN_GAP`` of a body it is not already nearer
    (:func:`robot.footprint.turn_clear`; u_catch_up_slow seed 0: a corner swung into Cora 0.58 m away)."""
    top = p.blind_turn if abs(b) > p.blind_bearing else p.max_turn
    w = max(-top, min(top, p.turn_gain * b))
    return w if turn_clear(w, bodies, duration=p.turn_check) else 0.0
#: the partner message's attribute while she is turned away (only then: the message keeps its size otherwise)
AWAY = ' away="true"'


#: s: an identity handed to a track on position alone (its clothes not yet seen) stays open to the camera's
#: verdict this long; unseen clothes by then, the hand-over stands
HANDOVER_CHECK = 15.0
#: s: ... and a track that goes this long without a measurement before the camera saw its clothes loses it
HANDOVER_UNMEASURED = 0.3


@dataclass
class Handover:
    """An identity handed over on position alone (:meth:`PersonAttention._reidentify`, :meth:`PersonAttention._reacquire`):
    the person's clothes were known, the track's were not yet. ``old``: the dormant track :meth:`Tracks.adopt`
    dropped (re-identification), to be put back; ``was``: the partner id before a reacquisition; ``partner``: the
    partner's evidence then (``_partner_last``, ``_partner_pace``, ``_partner_colour``), when the identity was hers."""

    since: float
    colour: tuple[float, float, float]
    old: Any = None
    old_colour: Any = None
    was: int | None = None
    partner: tuple[Any, Any, Any] | None = None
    restart: bool = False  # the tracker's "stopped" hypothesis moved her track (:meth:`PersonAttention._restarted`)


def _deg(a: float) -> str:
    return f"{math.degrees(a):.3f}"


def hands_tilt(p: AttentionParams, distance: float) -> float:
    """The camera's tilt (rad) on her hands in Interaction, her at ``distance`` m: the image's middle on
    ``heights["hands"]`` (a hand pointing at a table), but not so low that a hand raised to point at a
    high shelf (as high as her face, ``hand_reach`` m nearer than she stands) falls out of its top (the
    camera's own field, ``camera_vfov`` plus its 2 degree margin a side, less ``hand_top_margin``), as far
    as the hands' height stays as far inside its bottom (within about 1 m of her both do not fit: the
    hand at a table's height comes first)."""
    tilt = math.atan2(p.heights["hands"] - p.camera_height, max(distance, 0.3))
    if not p.raise_for_hands:
        return tilt
    half = p.camera_vfov / 2 + math.radians(2.0) - p.hand_top_margin
    raised = math.atan2(p.heights["face"] - p.camera_height, max(distance - p.hand_reach, 0.3))
    return max(tilt, min(raised - half, tilt + half))

class PersonAttention(Module):
    """Leg detection, anchoring, selection and the attention FSM on the bus (see the module docstring)."""

    #: the ES's last order was ``look_for_help`` (the robot asked for help; :meth:`_voice_heading`)
    seeking_help: bool = False
    #: asking for help: (time, odometry heading) of the mirror reading of the last voice a seen person who does
    #: not face the robot explained (:meth:`_mirror_voice`); the pair cannot tell front from back
    _mirror: tuple[float, float] | None = None
    #: nothing pressed, and never told otherwise: for unit tests that build the module without a bus (__init__
    #: gives each its own, heard on the bus)
    bumpers = own_reflex()
    #: when the beam last listened to a voice nobody seen explained (:meth:`beam`)
    _heard_voice_at: float = -math.inf
    _cats: dict[int, int] = {}  # noqa: RUF012 (read-only default for the rules' unit tests; __init__ gives each its own)
    _in_image: frozenset[int] = frozenset()  # (the same: __init__ gives each its own set)
    #: identities handed to a track on position alone, not yet checked against the clothes (:meth:`_check_handovers`)
    _handovers: dict[int, Handover] = {}  # noqa: RUF012 (read-only default for unit tests; __init__ gives each its own)
    #: tracks whose clothes showed they are not the partner they were taken for (:meth:`_give_back`)
    _not_her: frozenset[int] = frozenset()
    #: her evidence (``_partner_state``) when the camera last saw her own clothes on her track (:meth:`_on_torsos`):
    #: where she really was when her track turns out to be on someone else (:meth:`_top_down`, following)
    _her_seen: tuple[Any, Any, Any] | None = None
    #: (when, m/s): the partner's walking pace, renewed with ``_partner_last`` (:meth:`_walk_reach`)
    _partner_pace: tuple[float, float] = (-math.inf, 0.0)

    # following, the time since her last sighting spent yielding (set in __init__; here for the rule's
    # unit tests, which build the module without a bus)
    _yielded: float = 0.0
    #: in Object, the time since her last sighting the camera spent on what she shows (:meth:`_count_looked_away`)
    _looked_away: float = 0.0
    _looked_t: float | None = None
    #: when the robot last asked her to step aside (the ES's order ``asked_aside``; ``aside_walk``)
    _asked_aside: float | None = None
    #: when the partner last asked it to wait / said good-bye (the understanding's frames; ``wait_walk``, ``bye_walk``)
    _said_wait: float | None = None
    _said_bye: float | None = None
    #: the map's rooms (outlines) and walls (centre lines), map frame: the flat's exit (:meth:`_out_of_flat`)
    #: when her voice was last heard from her track, and where the latest understood or not understood utterance
    #: ended (the understanding's frames, virtual s): her words still on their way (:meth:`partner_left`)
    _her_voice: float = -math.inf
    _words_end: float = -math.inf
    #: (when, odometry heading) of the last voice heard from where the unseen partner was last measured
    #: (:meth:`_voice_from_where_she_went`), renewed only after her last sighting
    _heard_unseen: tuple[float, float] = (-math.inf, 0.0)
    _rooms: tuple[np.ndarray, ...] = ()
    _walls: tuple[tuple[float, float, float, float], ...] = ()
    _frames_sub: Any = None  # (set in __init__; here for the rule's unit tests)
    _exit_way: tuple[float, bool] | None = None  # (her last sighting's time, whether her way led to the exit)
    _drive_start: float | None = None  # (set in __init__: since when the player drives on the ES's order)
    #: following, the time since her last sighting spent on the way to where she was last seen (None: not kept)
    _closing: Closing | None = None
    #: the lost partner's clothes (retake from afar) and since when the follower stands with its search
    #: over (set in __init__; here for the unit tests that build the module without a bus)
    _lost_colour: tuple[float, float, float] | None = None
    #: her clothes as first seen once she was the partner (:meth:`_hers`; set in __init__, here for the same tests)
    _her_clothes: tuple[float, float, float] | None = None
    _follow_stopped: float | None = None
    #: since when the follower says it stands by her (``waiting``; None: it does not)
    _follow_waiting: float | None = None
    #: since when the follower says it searches for her (``searching``: she is out of its sight; None: it does not)
    _follow_searching: float | None = None
    #: when the last order ended following (:meth:`partner_left`: the follower's next status is waited for)
    _follow_ended: float = -math.inf
    #: the follower comes up to her after 'stop' (status approaching): her distance is no evidence of leaving
    #: (set in __init__ and from the follower's status; here for the unit tests that build the module without a bus)
    _follower_drives: bool = False
    #: the plan subscription while asking for help (set in __init__; here for the unit tests without a bus)
    _plan_sub: Any = None
    _yield_t: float | None = None
    #: (when, front readings) of the last sound frame with voices (:meth:`_heard_at`; set in __init__ and on the
    #: bus; here for the unit tests that build the module without one)
    _sounds: tuple[float, list[float]] | None = None
    #: the cue matching's tolerances (given to __init__; the defaults here for the same unit tests)
    cues: CueSpec = CueSpec()
    #: the ES events' subscription while following (the stood-stop's partner switch; set in __init__, here for
    #: the unit tests without a bus)
    _events_sub: Any = None

    def __init__(
        self,
        sim: Any,
        *,
        name: str = "person_attention",
        legs: LegSpec = LegSpec(),
        tracker: TrackerSpec = TrackerSpec(),
        cues: CueSpec = CueSpec(),
        selection: SelectionParams = SelectionParams(),
        params: AttentionParams = AttentionParams(),
        typed: bool = True,
    ) -> None:
        super().__init__(sim, name, host="robot")
        self.legs, self.cues, self.params = legs, cues, params
        self.tracks = Tracks(tracker)
        self.selector = Selector(selection)
        self.fsm = AttentionFSM()
        self.speaking = Hysteresis(cues.speaking_on, cues.speaking_off)
        self.facing = Hysteresis(cues.facing_on, cues.facing_off)
        self.partner: int | None = None
        self.partner_lost_sent = False
        self.colours = Colours()  # each track's torso colour (robot.attention.appearance)
        self._partner_colour: tuple[float, float, float] | None = None  # hers, kept when her track dies
        self._handovers: dict[int, Handover] = {}  # id -> an identity handed over on position alone, unchecked
        self._not_her: set[int] = set()  # tracks the camera showed not to be the partner they were taken for
        self._lost_colour: tuple[float, float, float] | None = None  # the lost partner's clothes: who may retake from afar
        #: the clothes the partner's track first showed as hers, and since when it shows others (:meth:`_her_clothes_gone`)
        self._her_clothes: tuple[float, float, float] | None = None
        self._other_clothes_since: float | None = None
        self._follow_stopped: float | None = None  # since when the follower stands with its search over (its status)
        self._follow_waiting: float | None = None  # since when the follower stands by her (its status ``waiting``)
        self._partner_face: tuple[float, int, bool] | None = None  # (frame time, partner, her face in the image)
        self._in_image: set[int] = set()  # the tracks whose face lay in the camera's latest frame
        self._cats: dict[int, int] = {}  # the tracks' categories (1-3) at the latest scan
        # the category-3 person a glance left, and when a potential_partner for him came due during the glance (None
        # while none did: he was reported already and fell silent before its repeat; then the glance owes him nothing)
        self._glanced_from: tuple[int, float | None] | None = None
        self._owed_pp: tuple[int, float] | None = None  # that person, once the glance found her turned away
        self._look: tuple[int, float] | None = None  # (track, first in the image, inf before): an unseen speaker looked at
        self.turned_away = False  # the partner walked away in Interaction, not seen facing it since (AttentionParams)
        # Where the partner was last seen (odom x, y, vx, vy; the robot's odom x, y then) and when:
        # the evidence the leaving rule reads, kept when the track itself has died.
        self._partner_last: tuple[float, float, float, float, float, float, float] | None = None
        # her walking pace: the fastest her track went lately, decaying over ``PACE_MEMORY`` s
        self._partner_pace = (-math.inf, 0.0)
        self.pp_sent: int | None = None
        self._pp_at = -math.inf
        self._last_pp: tuple[int, float] | None = None  # last potential partner and when
        self.refused: deque[str] = deque(maxlen=params.max_refused)
        self._odom: tuple[float, float, float, float, float, float] | None = None  # t, x, y, th, v, w
        self._bearings: np.ndarray | None = None
        self._bearings_key: tuple[str, str, str] | None = None
        self._detector: tuple[np.ndarray, LegSpec, LegDetector] | None = None  # bearings, spec, their detector
        self._focus: tuple[float, float, float] | None = None  # bearing (rad), distance, height (m) of the object region
        self._turning = False
        self._near: np.ndarray = np.zeros((0, 2))  # robot-frame bodies a turn must keep clear of (this scan)
        self._people: np.ndarray = np.zeros((0, 2))  # robot-frame confirmed tracks (this scan)
        self._room: tuple[float, float, float] | None = None  # making room: where the creep began (odom x, y), last asked
        self._ranges: np.ndarray | None = None  # this scan's ranges (a turn keeps off its echoes)
        self._plan_near: FurnitureLegs | None = None  # the floor plan grown by plan_explains: echoes it explains
        # the robot's map pose at this scan (the floor plan's frame: _robot_in_map), for the turn's checks; not
        # _map_pose, the localiser's pose that _robot_in_map moves on by odometry (one name for both reset the
        # localiser's pose every scan, so the floor plan was placed by dead reckoning alone)
        self._scan_pose: tuple[float, float, float] | None = None
        self._ptu_sent: tuple[float, float] | None = None
        self._ptu_at = -math.inf
        self._steer_sent: float | None | str = "unset"
        self._dominant: tuple[float, float] | None = None  # (time, front bearing rad): the loudest unexplained direction
        # (time, the partner talks, someone else does, the loudest other direction, rad): the last sound frame
        self._voices: tuple[float, bool, bool, float | None] | None = None
        self._voice_turn: tuple[float, float, float] | None = None  # (until, odom heading, heard at): turning to an unexplained voice
        self.looked = LookedAt()  # where the camera looked lately and whether it saw a face there (robot.attention.looking)
        self.heard = HeardFrom(keep=params.voice_recall)  # the last voices nobody in view explained
        self._focus_at = -math.inf
        self._focus_turning = False  # in Object: turning the base to a focus beyond the pan range (:meth:`_focus_turn`)
        # the last turn toward an unexplained voice could not be made (someone or something too near the
        # footprint's sweep): the camera then looks where a near speaker may stand (:meth:`_voice_look`)
        self._voice_blocked = False
        self._sounds: tuple[float, list[float]] | None = None  # (when, front readings): the last sound frame with voices
        self._loose_faces: tuple[float, list[tuple[float, float]]] | None = None  # (frame time, odom points): the last frame's faces
        self._state_sent: tuple[str, int | None, int | None] | None = None
        self._paused_at: float | None = None  # when the ES's last order, a pause, came (see _on_order)
        self._state_at = -math.inf
        self.scans = 0
        self._scan_id: str | None = None  # the scan being processed: the cause of the events it decides
        self.furniture: FurnitureLegs | None = None  # from map_server/map, once it answered
        self._leg_plan: FurnitureLegs | None = None  # the same plan, walls grown by leg_wall_margin: the leg filter
        self._map_pose: tuple[float, float, float, float] | None = None  # t, x, y, theta (localiser)
        self._map_odom: tuple[float, float, float] | None = None  # odometry when that pose came
        if typed:
            declare_channels(sim.bus)
        self.bus.subscribe(SCAN, self._on_scan)
        self.bus.subscribe(ODOMETRY, self._on_odometry)
        self.sonar = SonarEchoes()  # the sonar rings' echoes: the blind half a turn swings a rear corner into
        self.bus.subscribe(SONAR, lambda m: self.sonar.hear(m, self._odom_pose(), self.now))
        self.bumpers = BumperReflex()  # the bumper rings: a turn on the spot with one pressed grinds a corner (robot.bumpers)
        self.bus.subscribe(BUMPERS, lambda m: self.bumpers.update(m.xml, self.now))
        self.bus.subscribe(FACES, self._on_faces)
        self.bus.subscribe(TORSOS, self._on_torsos)
        self.bus.subscribe(SOURCES, self._on_sounds)
        self.bus.subscribe(FOCUS, self._on_focus)
        self.bus.subscribe(ORDERS, self._on_order)
        self.bus.subscribe(POSE, self._on_pose)
        # what she said weighs her leaving (:meth:`partner_left`): the understanding's frames, subscribed only while
        # the partner walks or is unseen in Interaction and Object (:meth:`_listen_to_words`; every other run's
        # deliveries stay as they were)
        self._frames_sub: Any = None
        # asking for help, the planner's watch (is the blocked way clear now?) answers "unseen" when the
        # way lies outside the laser's view: the odometry heading to look along it, and when (:meth:`_on_plan`)
        # (subscribed only while asking for help: every other run's deliveries stay as they were)
        self._way_look: tuple[float, float] | None = None
        self._plan_sub: Any = None
        # the follower comes up to the partner after "stop" and turns the base itself meanwhile
        self._follower_drives = False
        self.bus.subscribe(FOLLOW_STATUS, self._on_follow_status)
        # when the dialog last took a stop through its stood-stop exception (event stop, stood="true"):
        # only such a stop makes its speaker the partner (:meth:`_stop_speaker`, review18 F2)
        # (subscribed only while following: every other run's deliveries stay as they were)
        self._stood_stop_at = -math.inf
        self._events_sub: Any = None
        # The player drives the base in Object (the object attention moves to see what she points at):
        # no turning to her meanwhile. Subscribed only in Object: every delivery draws a network delay
        # from the run's generator, so a subscription held all the time would change every run.
        self._player_drives = False
        # The leaving rule's clock stands still while the robot drives on the ES's order (a drive to
        # a better viewpoint, up to the object attention's MOVE_TIMEOUT, 20 s): she did not leave,
        # the robot did. Drive time since her last sighting: finished legs, and the leg under way.
        self._driven = 0.0
        self._drive_start: float | None = None
        # Following, time spent yielding to someone near the robot since her last sighting does not
        # count as time unseen (robot.partner_search.yielding); the scan time it was last added up to
        self._yielded = 0.0
        self._yield_t: float | None = None
        # In Object the camera looks at what she shows, not at her: time spent there since her last sighting is no
        # evidence that she went out of view (:meth:`_count_looked_away`, the out-of-view clause of partner_left)
        self._looked_away = 0.0
        self._looked_t: float | None = None
        # when the robot last asked her to step aside (the ES's order ``asked_aside``, said): see ``aside_walk``
        self._asked_aside: float | None = None
        # ... nor the time it spends on its way to where she was last seen (robot.partner_search.Closing)
        self._closing = Closing()
        self._player_sub: Any = None
        self._alone_since: float | None = None  # since when Interaction/Object has had no partner at all
        self._caller: int | None = None  # searching: the seen person who speaks to it or comes up to it (:meth:`_find_caller`)

    async def run(self) -> None:
        await self._load_map()
        while True:
            self.beat()
            await asyncio.sleep(0.25)

    # ------------------------------------------------------------ frames
    def _pose_at(self, t: float) -> tuple[float, float, float]:
        """The odometry pose extrapolated to ``t`` with the measured velocities."""
        if self._odom is None:
            return 0.0, 0.0, 0.0
        t0, x, y, th, v, w = self._odom
        dt = min(max(t - t0, 0.0), self.params.cue_max_age)
        th2 = th + w * dt
        mid = th + w * dt / 2
        return x + v * dt * math.cos(mid), y + v * dt * math.sin(mid), th2

    def _robot_xy(self, t: float) -> list[tuple[float, float]]:
        """Every track's position in the robot frame at ``t``."""
        x, y, th = self._pose_at(t)
        c, s = math.cos(th), math.sin(th)
        out = []
        for tk in self.tracks.tracks:
            dx, dy = tk.x[0] - x, tk.x[1] - y
            out.append((c * dx + s * dy, -s * dx + c * dy))
        return out

    async def _load_map(self) -> None:
        """Ask ``map_server/map`` for the floor plan (raised furniture's legs); without it, no filtering."""
        from homesim.errors import HomesimError
        from robot.floorplan import MapFormatError, parse_map

        try:
            reply = await self.bus.call("map_server", "map", etree.Element("map_request"), timeout=2.0)
            plan = parse_map(reply.xml)
            self.furniture = FurnitureLegs(plan)
            self._leg_plan = FurnitureLegs(plan, wall_margin=self.params.leg_wall_margin)
            self._plan_near = FurnitureLegs(plan, margin=self.params.plan_explains, wall_margin=self.params.plan_explains)
            self._rooms = tuple(np.asarray(r.points, dtype=float) for r in plan.rooms if len(r.points) >= 3)
            self._walls = tuple((w.x1, w.y1, w.x2, w.y2) for w in plan.walls)
        except (HomesimError, MapFormatError, TimeoutError) as exc:
            self.refused.append(f"no floor plan, furniture legs are not filtered: {exc}")

    def _on_pose(self, msg: Message) -> None:
        el = msg.xml
        self._map_pose = (msg.created, float(el.get("x")), float(el.get("y")), float(el.get("theta")))
        self._map_odom = self._pose_at(msg.created)

    def _robot_in_map(self, t: float, odom: tuple[float, float, float] | None = None) -> tuple[float, float, float]:
        """The robot's pose in the map frame: the localiser's last pose moved on by odometry since, else start + odometry.

        ``odom``: the odometry pose at ``t`` if the caller has it already (``_pose_at(t)``)."""
        assert self.furniture is not None
        if odom is None:
            odom = self._pose_at(t)
        if self._map_pose is None or self._map_odom is None:
            return self.furniture.map_pose(odom)
        _, mx, my, mth = self._map_pose
        ox, oy, oth = self._map_odom
        # The odometry increment since the localiser's pose, in that pose's own frame.
        c, s = math.cos(oth), math.sin(oth)
        dx, dy = odom[0] - ox, odom[1] - oy
        fx, fy = c * dx + s * dy, -s * dx + c * dy
        cm, sm = math.cos(mth), math.sin(mth)
        return mx + cm * fx - sm * fy, my + sm * fx + cm * fy, mth + odom[2] - oth

    # ------------------------------------------------------------ inputs
    def _listen_to_words(self, row: int) -> None:
        """Subscribe to the understanding's frames while the partner walks (``leave_speed``) or is unseen in
        Interaction or Object: what she says then (a wait request, a good-bye) weighs the leaving rule."""
        want = False
        if self.partner is not None and not self.partner_lost_sent and self.fsm.state in ("Interaction", "Object"):
            if row < 0:
                want = True
            else:
                tk = self.tracks.tracks[row]
                want = math.hypot(tk.x[2], tk.x[3]) >= self.params.leave_speed
        if want and self._frames_sub is None and hasattr(self, "bus"):  # (the rule's unit tests run without a bus)
            self._frames_sub = self.bus.subscribe(FRAMES, self._on_frame)
        elif not want and self._frames_sub is not None and (self._partner_last is None or self.now - self._partner_last[0] < 0.5):
            # (kept until she is seen again: her words may come while she stands out of view)
            self._frames_sub.close()
            self._frames_sub = None

    def _on_frame(self, msg: Message) -> None:
        """An understood utterance heard during the interaction: a wait request or a good-bye (any confidence)
        is noted for the leaving rule (:meth:`partner_left`); nothing else changes."""
        start, end = float(msg.xml.get("start", self.now)), float(msg.xml.get("end", self.now))
        self._words_end = max(self._words_end, end)
        if msg.xml.tag != "understood" or self.fsm.state not in ("Interaction", "Object"):
            return
        # (when she began saying it: she may have walked off while she spoke)
        if msg.xml.find("SPEECH/GOODBYE") is not None:
            # only her own whole good-bye (review25 F-B): a bystander's "bye everyone" (her voice not heard from her
            # track while the words were said, the dialog's attribution) or a doubted one ("hang on, don't say goodbye
            # yet": partial) leaves the errand rule as it is; the dialog's question and her answer decide those
            if msg.xml.get("partial") != "true" and self._her_voice >= start - BYE_VOICE_SLACK:
                self._said_bye = start
        elif msg.xml.find("SPEECH/WAIT") is not None:
            self._said_wait = start

    def _odom_point_in_map(self, x: float, y: float) -> tuple[float, float]:
        """An odometry point in the map frame (the robot's current localisation)."""
        ox, oy, oth = self._pose_at(self.now)
        mx, my, mth = self._robot_in_map(self.now, (ox, oy, oth))
        c, s = math.cos(mth - oth), math.sin(mth - oth)
        dx, dy = x - ox, y - oy
        return mx + c * dx - s * dy, my + s * dx + c * dy

    def _out_of_flat(self, t: float) -> bool:
        """Whether the partner walked out of the flat: last seen walking (``leave_speed`` or faster) and her way on
        (her last velocity over the time unseen, at most ``exit_reach`` m) ends outside every room of the map and
        crosses none of its walls (through a door gap: the exit door). False without a map with rooms."""
        last = self._partner_last
        if last is None or not self._rooms or self.furniture is None:
            return False
        seen, x, y, vx, vy, _, _ = last
        speed = math.hypot(vx, vy)
        if speed < self.params.leave_speed:
            return False
        reach = min(self.params.exit_reach, speed * max(t - seen, 0.0))
        ax, ay = self._odom_point_in_map(x, y)
        bx, by = self._odom_point_in_map(x + vx / speed * reach, y + vy / speed * reach)
        if any(_in_polygon(bx, by, r) for r in self._rooms):
            return False
        return not any(_crosses(ax, ay, bx, by, w) for w in self._walls)

    def _toward_exit(self, seen: float, x: float, y: float, vx: float, vy: float) -> bool:
        """Whether her way (from where she was last seen, along her last velocity, at most ``exit_look`` m) leads
        out of the map's rooms before it meets one of its walls: she walks to the flat's exit door. True without a
        map with rooms (nothing says where the flat ends: walking away is then taken as leaving, as before)."""
        if not self._rooms or self.furniture is None:
            return True
        if self._exit_way is not None and self._exit_way[0] == seen:
            return self._exit_way[1]
        speed = math.hypot(vx, vy)
        ux, uy = (vx / speed, vy / speed) if speed > 1e-9 else (0.0, 0.0)
        ax, ay = self._odom_point_in_map(x, y)
        bx, by = self._odom_point_in_map(x + ux, y + uy)
        ux, uy = bx - ax, by - ay
        found = False
        step, n = 0.1, int(self.params.exit_look / 0.1)
        px, py = ax, ay
        for k in range(1, n + 1):
            qx, qy = ax + ux * step * k, ay + uy * step * k
            if any(_crosses(px, py, qx, qy, w) for w in self._walls):
                break
            if not any(_in_polygon(qx, qy, r) for r in self._rooms):
                found = True
                break
            px, py = qx, qy
        self._exit_way = (seen, found)
        return found

    def _on_odometry(self, msg: Message) -> None:
        el = msg.xml
        self._odom = (msg.created, float(el.get("x")), float(el.get("y")), float(el.get("theta")), float(el.get("v")), float(el.get("w")))

    def _on_focus(self, msg: Message) -> None:
        el = msg.xml
        self._focus = (math.radians(float(el.get("bearing", "0"))), float(el.get("distance", "1")), float(el.get("height", "0.8")))
        self._focus_at = msg.created

    def _on_sounds(self, msg: Message) -> None:
        t = msg.created
        tracks = self.tracks.tracks
        ids = [tk.id for tk in tracks]
        sources = list(msg.xml)
        bearings = [math.radians(float(s.get("bearing"))) for s in sources]
        if bearings:
            self._sounds = (t, bearings)  # the last voices' readings (:meth:`_heard_at`)
        # The tracks' bearings only when there is a sound to match them with (most frames are quiet).
        track_bearings = sound_bearings_from(self._robot_xy(t), self.cues) if tracks and bearings else []
        rows = match_sounds(track_bearings, bearings, self.cues.sound_tolerance) if tracks and bearings else []
        self.speaking.feed(t, ids, {ids[r] for r in rows})
        if rows and self.partner is not None and any(ids[r] == self.partner for r in rows):
            self._her_voice = t  # her words may still be on their way to the understanding (:meth:`partner_left`)
        if rows:
            self._partner_seen(rows, t)  # the partner's voice from the partner's direction keeps the partner
            if self.seeking_help:
                self._mirror_voice(t, bearings, track_bearings)
        if bearings and self.partner is not None:
            prow = self.tracks.row(self.partner)
            if prow >= 0:
                # Who talks, as the beam gate reads it: the partner only when a direction lies within
                # ``partner_voice_tolerance`` of where her voice may come from; anyone else when a
                # direction lies further off than that.
                # Her voice's bearing is known only within the span her unknown mouth height allows
                # (:func:`sound_bearing_span`): close to the robot that span is wide, and one typical
                # height put her own voice 9 deg off her, so the robot stopped listening to its
                # partner standing half a metre away (follow_while_looking seed 1).
                px, py = self._robot_xy(t)[prow]
                span = sound_bearing_span(float(px), float(py), self.cues)
                offs = [span_offset(span, b) for b in bearings]
                tol = self.params.partner_voice_tolerance
                others = [k for k, o in enumerate(offs) if o > tol]
                loud = max(others, key=lambda k: float(sources[k].get("level", "0"))) if others else None
                self._voices = (t, any(o <= tol for o in offs), bool(others), bearings[loud] if loud is not None else None)
        if bearings:
            levels = [float(s.get("level", "0")) for s in sources]
            seen = [b for b, tk in zip(track_bearings, tracks) if tk.confirmed and not tk.dormant]
            free = [k for k in range(len(bearings)) if not match_sounds(seen, bearings[k : k + 1], self.cues.sound_tolerance)]
            if free:
                self._voice_from_where_she_went(t, [bearings[k] for k in free])
                k = max(free, key=lambda j: levels[j])
                self._dominant = (t, bearings[k])
                th = self._pose_at(t)[2]
                in_view = [tk.id for tk in tracks if tk.confirmed and not tk.dormant]
                for j in free:
                    self.heard.add(t, th + bearings[j], th + math.pi - bearings[j], in_view)

    def _voice_from_where_she_went(self, t: float, free: list[float]) -> None:
        """In Interaction/Object, the partner unseen for ``partner_lost_after`` (her track gone, dormant or coasting
        unmeasured: she stepped behind a shelf or a wardrobe and talks on): a voice that nobody seen explains
        (``free``: front readings, rad), read from where she can be (as seen from the robot now, the reacquisition radius around where her legs were last measured,
        at most ``unseen_voice_spread`` off it; either reading: the pair cannot tell front from back), is hers: note
        when, and its heading (the reading nearer that point) for the turn toward it (:meth:`_toward_her_voice`). The leaving rule counts her time unseen from
        her last word (:meth:`partner_left`). A voice from elsewhere (a visitor out of view in another direction)
        is not hers; one that someone seen explains never reaches here (aside24's "Left": she was declared gone
        after the 30 s patience while she kept talking from behind the wall)."""
        last = self._partner_last
        if (self.partner is None or last is None or self.partner_lost_sent
                or self.fsm.state not in ("Interaction", "Object")):
            return
        if t - last[0] < self.params.partner_lost_after:
            return  # she is seen: her voice is matched to her track (:meth:`_partner_seen`)
        # (her track may still coast, unmeasured, its prediction drifting on where she walked: her voice from
        # where she stopped, behind the wardrobe, is not matched to it; where her legs were last measured is)
        x, y = last[1], last[2]
        px, py, th = self._pose_at(t)
        c, s = math.cos(th), math.sin(th)
        dx, dy = x - px, y - py
        d = math.hypot(dx, dy)
        if d < 1e-6:
            return
        p = self.params
        reach = min(2.5, p.reacquire_radius + p.reacquire_speed * max(0.0, t - last[0]))  # (as :meth:`_reacquire`)
        span = sound_bearing_span(c * dx + s * dy, -s * dx + c * dy, self.cues)
        tol = self.cues.sound_tolerance + min(math.asin(min(1.0, reach / d)), p.unseen_voice_spread)
        own = math.atan2(dy, dx) - th
        for b in free:
            if span_offset(span, b) <= tol:
                reading = min((b, math.pi - b), key=lambda v: angle_between(v, own))
                self._heard_unseen = (t, th + reading)
                return

    def _mirror_voice(self, t: float, bearings: list[float], track_bearings: list[float]) -> None:
        """Asking for help: a voice that a seen person who does not face the robot explains may be someone
        else's at the mirror reading (the pair cannot tell front from back). Whoever answers the call comes
        up behind the robot, where the laser does not look, and greets it; her voice was taken for the man
        in front on the phone, so it never turned round and her greeting expired (fresh3/open_island_goto).
        Keep that mirror reading (:attr:`_mirror`, odometry heading) for :meth:`_voice_heading`."""
        th = self._pose_at(t)[2]
        rxy = self._robot_xy(t)
        tracks = self.tracks.tracks
        for b in bearings:
            rows = match_sounds(track_bearings, [b], self.cues.sound_tolerance)
            if not rows:
                continue
            tk = tracks[rows[0]]
            if not tk.confirmed or tk.dormant or self.facing.on(tk.id):
                continue  # someone facing it who speaks is the one who speaks to it
            own = math.atan2(float(rxy[rows[0]][1]), float(rxy[rows[0]][0]))
            front, back = b, math.pi - b
            other = back if angle_between(own, front) <= angle_between(own, back) else front
            self._mirror = (t, th + other)

    def _partner_seen(self, rows: list[int], t: float) -> None:
        """Weak evidence (the voice from the partner's bearing) counts for the partner only."""
        if self.partner is not None:
            prow = self.tracks.row(self.partner)
            if prow >= 0 and prow in rows:
                self.tracks.seen([prow], t)

    def _on_torsos(self, msg: Message) -> None:
        """Torso blobs: each track's clothing colour where the blob is surely its own
        (:mod:`.appearance`), and a torso at the partner's bearing (the camera is on the partner
        in the top-down states) as evidence that she is there."""
        t = msg.created
        data = msg.data  # the camera's typed PerceptList (robot.percepts), else XML: the same texts
        rows = data.rows if data is not None else list(msg.xml)
        if not rows:
            return
        get = (lambda r, k: getattr(r, k)) if data is not None else (lambda r, k: r.get(k))
        bearings = [math.radians(float(get(r, "bearing"))) for r in rows]
        th = self._pose_at(t)[2]
        self.looked.bodies(t, [th + b for b in bearings], self.params.face_look_tolerance)  # someone there (:meth:`_voice_target`)
        tracks = self.tracks.tracks
        if not tracks:
            return
        tb = bearings_from(self._robot_xy(t), self.cues.camera_offset)
        for j, i in anchor_torsos(tb, bearings, self.cues.torso_bearing_tolerance):
            if tracks[i].confirmed and not tracks[i].dormant:
                r = rows[j]
                rgb = (float(get(r, "r")), float(get(r, "g")), float(get(r, "b")))
                self.colours.observe(tracks[i].id, rgb, t)
                if tracks[i].id == self.partner and self._her_clothes is not None and same_clothes(self._her_clothes, rgb):
                    self._her_seen = self._partner_state()
        if self.partner is None:
            return
        prow = self.tracks.row(self.partner)
        if prow < 0:
            return
        pb = tb[prow]
        # near the robot her track may sit on one leg beside her body (a partner at its elbow, side-on to the
        # laser): the angle ``leg_reach`` spans at her distance, when wider (as for faces: cues.match_faces)
        px, py = self._robot_xy(t)[prow]
        near = math.atan2(self.cues.leg_reach, max(math.hypot(px - self.cues.camera_offset, py), 1e-3))
        if min(abs((b - pb + math.pi) % (2 * math.pi) - math.pi) for b in bearings) <= max(self.cues.torso_bearing_tolerance, near):
            # A torso is a body (a table leg has none): strong evidence, as a frontal face, so a
            # partner standing sideways on single legs is kept while the camera sees them.
            self.tracks.support([prow], t)

    def _on_faces(self, msg: Message) -> None:
        t = msg.created
        tracks = self.tracks.tracks
        ids = [tk.id for tk in tracks]
        data = msg.data  # the camera's typed PerceptList (robot.percepts), else XML: the same texts
        faces = [(math.radians(float(f.bearing)), float(f.distance)) for f in data.rows] if data is not None else [
            (math.radians(float(f.get("bearing"))), float(f.get("distance"))) for f in msg.xml]
        xy = self._robot_xy(t)
        rows = match_faces(xy, faces, self.cues) if tracks and faces else []
        self.facing.feed(t, ids, {ids[r] for r in rows})
        tpl = data.form if data is not None else msg.xml  # the pan-tilt state the frame was taken in
        pan, tilt = math.radians(float(tpl.get("pan", "nan"))), math.radians(float(tpl.get("tilt", "nan")))
        self._looked_at(t, pan, faces, xy)
        self._in_image = {ids[r] for r, (px, py) in enumerate(xy) if self._face_in_image(px, py, pan, tilt)}
        if self.partner is not None and self.tracks.row(self.partner) >= 0:
            # was the partner's face in the image? (then a missing face means she looks away)
            self._partner_face = (t, self.partner, self.partner in self._in_image)
        self.tracks.support([r for r in rows if tracks[r].confirmed], t)

    def _face_in_image(self, px: float, py: float, pan: float, tilt: float) -> bool:
        """Whether a face at robot-frame (px, py) lies inside the image of a camera panned/tilted so (rad)."""
        if math.isnan(pan) or math.isnan(tilt):
            return False
        elev = math.atan2(self.params.heights["face"] - self.params.camera_height, max(math.hypot(px, py), 0.3))
        return (abs(math.remainder(math.atan2(py, px) - pan, 2 * math.pi)) <= self.params.camera_hfov / 2
                and abs(elev - tilt) <= self.params.camera_vfov / 2)

    def _looked_at(self, t: float, pan: float, faces: list[tuple[float, float]], xy: list[tuple[float, float]]) -> None:
        """A camera frame (pan ``pan`` rad, frontal ``faces`` as (bearing, distance) in the robot frame,
        the tracks at ``xy``): what it showed of each direction (:attr:`looked`), and where its faces are
        (:attr:`_loose_faces`, for :meth:`_face_candidates`: a person whose legs the laser may not see)."""
        if math.isnan(pan):
            return
        x, y, th = self._pose_at(t)
        self.looked.observe(t, th + pan, self.params.camera_hfov / 2, [th + b for b, _ in faces], self.params.face_look_tolerance)
        off = self.cues.camera_offset
        c, s = math.cos(th), math.sin(th)
        pts = [(x + c * (off + d * math.cos(b)) - s * d * math.sin(b), y + s * (off + d * math.cos(b)) + c * d * math.sin(b)) for b, d in faces]
        self._loose_faces = (t, pts) if pts else None

    def _face_candidates(self, t: float, hidden: Any) -> list[tuple[float, float]]:
        """The odometry points of the last camera frame's faces whose legs the laser cannot see on this
        scan (``hidden``: something nearer blocks its beams there) and that no person the laser does
        see explains (nobody it sees in that direction: a face's distance is only a guess from its
        size). A person behind a coffee table or a sofa is a person: the camera sees her face, the
        laser only the furniture (the papers' multi-modal anchoring: faces are one of a person's
        percepts); her track is then fed by her face (FACE candidates) as long as her legs stay hidden."""
        lf = self._loose_faces
        if lf is None or abs(t - lf[0]) > self.params.face_candidate_age:
            return []
        pts = [pt for pt, h in zip(lf[1], hidden(lf[1])) if h]
        if not pts:
            return []
        tracks = self.tracks.tracks
        x, y, _ = self._pose_at(t)
        seen = [math.atan2(tk.x[1] - y, tk.x[0] - x) for tk, h in zip(tracks, hidden([(tk.x[0], tk.x[1]) for tk in tracks])) if not h]
        wide = 2 * self.cues.face_bearing_tolerance
        return [pt for pt in pts if not any(angle_between(math.atan2(pt[1] - y, pt[0] - x), k) <= wide for k in seen)]

    def _on_order(self, msg: Message) -> None:
        name = msg.xml.get("name", "")
        if name == "asked_aside":
            # the dialog has asked her to step aside (said="true"): no change of state, only what her
            # walking away means for a while (``aside_walk``, :meth:`partner_left`)
            said = next((q.text for q in msg.xml.iterfind("param") if q.get("name") == "said"), None)
            if (said or "").strip() == "true":
                self._asked_aside = self.now
            return
        was = self.fsm.state
        # (a stop heard while the follower searched for her is hers just as one heard after it stood by the
        # track: whoever seen spoke it is the partner now)
        stood = self._stood(self.now) or self._follow_searching is not None
        try:
            state = self.fsm.order(name)
        except OrderRefused as exc:
            self.refused.append(str(exc))
            return
        self.seeking_help = name == "look_for_help"  # until the next order (:meth:`_voice_heading`)
        if self.seeking_help and self._plan_sub is None:
            self._plan_sub = self.bus.subscribe(PLAN, self._on_plan)  # the watch's answers (:meth:`_look_along_way`)
        elif not self.seeking_help and self._plan_sub is not None:
            self._plan_sub.close()
            self._plan_sub, self._way_look = None, None
        # a wait said while following: when the ES's pause order came (told to the follower in the state
        # message, which stands until she walks on); any other order ends it
        self._paused_at = self.now if name == "pause" else None
        self._follow_stopped = None  # (a new order: the follower's next status says where it stands)
        if was == "Follow" and state != "Follow":
            self._follow_ended = self.now
        if was == "Follow" and state == "Interaction" and stood and self._took_stood_stop():
            self._stop_speaker()
        if state in ("Interaction", "Follow", "Object"):
            # A partner unseen for a moment (stepped aside) stays the partner across the change.
            pending = self.partner is not None and self._partner_last is not None and not self.partner_lost_sent
            if self.partner is None or (self.tracks.row(self.partner) < 0 and not pending):
                before, lost = self.partner, self.partner_lost_sent
                self.partner = self._caller if self._caller is not None and self.tracks.row(self._caller) >= 0 else self._choose_partner()
                self.partner_lost_sent = False
                self._partner_last = self._partner_colour = None
                self._her_clothes = self._other_clothes_since = self._her_seen = None
                if lost and self.partner is not None and self.partner != before and self.fsm.state == "Interaction":
                    self._new_partner(self.now, self.partner, "false")  # back from a loss: who it attends to now
        else:
            self.partner = None
            self.partner_lost_sent = False
            self._partner_last = self._partner_colour = self._lost_colour = None
            self._her_clothes = self._other_clothes_since = self._her_seen = None
        self.pp_sent = None
        self._alone_since = None
        self.turned_away = False  # (leading her in Follow she walks away from it: no turning away)
        self._listen_to_player(state == "Object")
        if state == "Follow" and self._events_sub is None:
            self._events_sub = self.bus.subscribe(ES_EVENTS, self._on_es_event)
        elif state != "Follow" and self._events_sub is not None:
            self._events_sub.close()
            self._events_sub = None
        self._publish_state(self.now, force=True)

    def _stop_speaker(self) -> None:
        """Following ended (her "stop") after the follower had stood by the partner track
        :data:`~robot.partner_search.STOOD_FOR` s: if that track was silent for the last ``STOP_VOICE`` s and
        another confirmed track was heard speaking then, the stop was that person's, and that person is
        whom the robot attends to now. The track it stood by was someone else: she walked past a silent
        bystander who stood where she went, and the track went over to him (generated tours, a guest
        standing in the guest room: every later word of hers was shut out of the beam as a bystander's,
        next to a "partner" who never spoke)."""
        tr, now = self.tracks, self.now
        if self.partner is None or self.partner_lost_sent or tr.row(self.partner) < 0:
            return
        window = now - STOP_VOICE
        if self.speaking.last(self.partner) >= window:
            return  # her own voice from her track: she said it
        heard = [(self.speaking.last(tk.id), tk.id) for tk in tr.tracks
                 if tk.id != self.partner and tk.confirmed and not tk.dormant and self.speaking.last(tk.id) >= window]
        if heard:
            self.partner = max(heard)[1]
            self._partner_last = self._partner_colour = None
            self._her_clothes = self._other_clothes_since = self._her_seen = None

    def _on_es_event(self, msg: Message) -> None:
        """The dialog's stop taken from off the partner's bearing after the robot stood by her track."""
        if msg.xml.get("name") == "stop" and msg.xml.get("stood") == "true":
            self._stood_stop_at = msg.created

    def _took_stood_stop(self) -> bool:
        """Whether the dialog took a stop through its stood-stop exception in the last ``STOP_VOICE`` s (its
        event ``stop`` with ``stood="true"``): only then may the stop's speaker be someone other than the track
        the robot stood by (a stop it took from her own bearing keeps her the partner)."""
        return self.now - self._stood_stop_at <= STOP_VOICE

    def _stood(self, t: float) -> bool:
        """The follower has stood by the partner track (its status ``waiting``; ``held``, held up short of her, is
        not standing by her) at least ``STOOD_FOR`` s."""
        w = self._follow_waiting
        return w is not None and t - w >= STOOD_FOR

    def _listen_to_player(self, on: bool) -> None:
        """Follow the player's status (moving or not) while in Object, and only then."""
        if on and self._player_sub is None:
            self._player_sub = self.bus.subscribe(PLAYER_STATUS, self._on_player)
        elif not on and self._player_sub is not None:
            self._player_sub.close()
            self._player_sub = None
            self._drive(self.now, False)

    def _on_plan(self, msg: Message) -> None:
        """A watch answer: where its way lies when the laser does not see it (``look``), else nothing to look at."""
        x = msg.xml
        if x.get("watch") != "true":
            return
        look = x.get("look")
        if x.get("failed") == "unseen" and look is not None and self._odom is not None:
            self._way_look = (self.now, self._pose_at(self.now)[2] + float(look))
        else:
            self._way_look = None

    def _look_along_way(self, t: float) -> float | None:
        """Asking for help with nobody speaking to it: the bearing (robot frame) along its blocked way, which the
        laser does not see, from the planner's last watch answer (at most ``WAY_LOOK_AGE`` s old), or None.
        Turned to, the laser sees the way, and the watch finds it clear once the blocker has left
        (fresh5/stair_goto_passage_person: facing a door off its way, it never went on)."""
        w = self._way_look
        if not self.seeking_help or w is None or t - w[0] > WAY_LOOK_AGE:
            return None
        return math.remainder(w[1] - self._pose_at(t)[2], 2 * math.pi)

    def _on_player(self, msg: Message) -> None:
        self._drive(self.now, msg.xml.get("state") in ("moving", "blocked"))

    def _drive(self, t: float, drives: bool) -> None:
        """The player drives (on the ES's order) from ``t`` on, or stopped at ``t``: the time it
        drove after the partner's last sighting is not counted as her time unseen."""
        if drives and self._drive_start is None:
            self._drive_start = t
        elif not drives and self._drive_start is not None:
            seen = self._partner_last[0] if self._partner_last is not None else t
            self._driven += max(0.0, t - max(self._drive_start, seen))
            self._drive_start = None
        self._player_drives = drives

    def _on_follow_status(self, msg: Message) -> None:
        """The follower's status: approaching (the attention leaves the base to it), and since when it
        stands with its search over (``stopped``, :attr:`_follow_stopped`: a loss, :meth:`partner_left`)."""
        state = msg.xml.get("state")
        self._follower_drives = state == "approaching"
        if state != "waiting":
            self._follow_waiting = None
        elif self._follow_waiting is None:
            self._follow_waiting = msg.created
        if state != "searching":
            self._follow_searching = None
        elif self._follow_searching is None:
            self._follow_searching = msg.created
        if state == "searching" and self._closing is not None and self._partner_last is not None:
            # the follower on its way to where it looks for her (its distance to that point): not search
            # time (robot.partner_search.Closing, the follower's own clock reads the same distances)
            self._closing.update(msg.created, float(msg.xml.get("distance", "nan")))
        if state != "stopped":
            self._follow_stopped = None
        elif self._follow_stopped is None:
            self._follow_stopped = msg.created

    def _unseen(self, t: float, seen: float) -> float:
        """Seconds the partner has been unseen at ``t``, less the time the robot drove away on the ES's order."""
        driving = t - max(self._drive_start, seen) if self._drive_start is not None else 0.0
        return t - seen - self._driven - max(0.0, driving)

    def _choose_partner(self) -> int | None:
        """The partner on interact: the last potential partner if still tracked, else the selected person.

        Never a dormant track (kept while hidden, nothing seen of it now): after a loss while following,
        the ES's order back to Interaction came while her own track lay dormant beside the robot (she
        stood out of the laser's half-circle after it gave way, flow/follow_while_looking seed 1); taken
        as the "new partner" with no record of her, the leaving rule found her gone at the next scan and
        a second ``partner_lost`` 0.1 s after the first ended the interaction ("You left", review14 F6).
        Nobody chosen, whoever speaks to the robot or walks up takes the place, and the come-back time
        runs (:meth:`_nobody_there`); she is taken back when she speaks to it facing it (:meth:`_top_down`)."""
        def in_view(tid: int) -> bool:
            row = self.tracks.row(tid)
            return row >= 0 and not self.tracks.tracks[row].dormant
        if self._last_pp is not None and in_view(self._last_pp[0]):
            return self._last_pp[0]
        sel = self.selector.selected
        return sel if sel is not None and in_view(sel) else None

    # ------------------------------------------------------------ the scan
    def _on_scan(self, msg: Message) -> None:
        el = msg.xml
        t = float(el.get("time"))
        key = (el.get("beams"), el.get("min_angle"), el.get("resolution"))
        if key != self._bearings_key:
            n = int(key[0])
            self._bearings = math.radians(float(key[1])) + math.radians(float(key[2])) * np.arange(n)
            self._bearings_key = key
            self.legs = replace(self.legs, offset=float(el.get("offset", self.legs.offset)))
        self._scan_id = msg.id
        self.process(t, msg.attachments["ranges"])

    def _leg_detector(self) -> LegDetector:
        """The detector for the current scan geometry and leg parameters (built again when either changes)."""
        det = self._detector
        if det is None or det[0] is not self._bearings or det[1] is not self.legs:
            assert self._bearings is not None
            det = self._detector = (self._bearings, self.legs, LegDetector(self._bearings, self.legs))
        return det[2]

    def process(self, t: float, ranges: np.ndarray) -> None:
        """Everything one scan does (also the benchmark's entry point)."""
        self.scans += 1
        pose = self._pose_at(t)
        reject = None
        self._ranges, self._scan_pose = ranges, None
        if self.furniture is not None:
            mx, my, mth = self._scan_pose = self._robot_in_map(t, pose)
            cm, sm = math.cos(mth), math.sin(mth)
            inside = (self._leg_plan or self.furniture).inside_points

            def reject(points: list[tuple[float, float]]) -> list[bool]:  # leg candidates (robot frame) on raised furniture's footprints
                return inside([(mx + cm * x - sm * y, my + sm * x + cm * y) for x, y in points])

        det = self._leg_detector()(ranges, reject_points=reject)
        points, kinds = det.points, det.kinds
        if self._scan_pose is not None and self._plan_near is not None and SINGLE in kinds:
            # a lone leg the floor plan explains (within plan_explains of a wall, a jamb's end or a piece of
            # furniture: the map pose is a few centimetres off, a table leg or a jamb seen at a slant is a
            # leg-sized segment) keeps no track alive: a coasting partner track took such a leg and stood
            # still on it while she walked on behind the wall (hall_follow_doors seed 3: a kitchen table's
            # corner leg; seed 8 and passage_follow_doors seed 0: a door jamb, doors9, fresh9). A lone leg
            # only ever keeps a track alive; her other leg, or both, are seen again a step later
            kl = kinds.tolist() if isinstance(kinds, np.ndarray) else list(kinds)
            on_plan = self._explained(np.array(points, dtype=float).reshape(-1, 2))
            keep = [i for i, k in enumerate(kl) if not (k == SINGLE and on_plan[i])]
            if len(keep) < len(kl):
                points, kinds = [points[i] for i in keep], [kl[i] for i in keep]
        px, py, th = pose
        c, s = math.cos(th), math.sin(th)
        z = [(px + c * x - s * y, py + s * x + c * y) for x, y in points]  # into odom
        bearings = self._bearings
        assert bearings is not None

        def hidden(points: list[tuple[float, float]]) -> list[bool]:  # tracks the laser could not see on this scan
            robot = [(c * (x - px) + s * (y - py), -s * (x - px) + c * (y - py)) for x, y in points]
            return hidden_points(robot, ranges, float(bearings[0]), float(bearings[1] - bearings[0]),
                                 max_range=self.legs.max_range, offset=self.legs.offset)

        blocked = None
        if reject is not None:
            on_plan = reject

            def blocked(points: list[tuple[float, float]]) -> list[bool]:  # odom points inside a wall or raised furniture
                return on_plan([(c * (x - px) + s * (y - py), -s * (x - px) + c * (y - py)) for x, y in points])

        faces = self._face_candidates(t, hidden)
        if faces:
            z = z + faces
            kinds = list(kinds.tolist() if isinstance(kinds, np.ndarray) else kinds) + [FACE] * len(faces)
        prow = (self.tracks.row(self.partner) if self.partner is not None and self._partner_colour is not None
                and self.fsm.state == "Follow" else -1)  # (following, the camera looks at her torso)
        before = Tracks.copy(self.tracks.tracks[prow]) if prow >= 0 else None  # her track as it was (:meth:`_restarted`)
        assigned = self.tracks.step(t, z, kinds, hidden, blocked)
        if before is not None and before.id in self.tracks.restarted:
            self._restarted(t, before)
        if self.tracks.confirmed_now:
            assigned = self._reidentify(t, assigned)
        if self._handovers:
            assigned = self._check_handovers(t, assigned)
        self._keep_still_partner(t, assigned)
        tracks = self.tracks.tracks
        if self.scans % 50 == 0:
            alive = {tk.id for tk in tracks}
            self.speaking.forget(alive)
            self.facing.forget(alive)
            self.colours.forget(alive)
            self._not_her &= alive
            self.selector.forget(alive)
        # Every track in the robot frame: bearing and distance.
        rx, ry = [], []
        for tk in tracks:
            dx, dy = tk.x[0] - px, tk.x[1] - py
            rx.append(c * dx + s * dy)
            ry.append(-s * dx + c * dy)
        bearing = [math.atan2(y, x) for x, y in zip(rx, ry)]
        dist = np.hypot(rx, ry).tolist() if tracks else []
        self._near = self._bodies_near(list(zip(rx, ry)) + list(det.points))
        # the confirmed tracks (robot frame): the people whose legs the laser sees explain a sonar reading (_blind_clear)
        self._people = np.array([(x, y) for tk, x, y in zip(tracks, rx, ry) if tk.confirmed], dtype=float).reshape(-1, 2)
        cats: dict[int, int] = {}
        speaking, facing = self.speaking, self.facing
        for tk in tracks:
            if tk.confirmed and not tk.dormant:  # a dormant track's person is out of sight: nobody to attend to
                tid = tk.id
                cats[tid] = (3 if facing.on(tid) else 2) if speaking.on(tid) else 1
                if cats[tid] == 1 and len(self.heard) and facing.on(tid) and self._spoke_before(t, tk, px, py):
                    cats[tid] = 3
        if self.fsm.top_down:
            self._top_down(t, cats)
            self._turning_away(t)
            selected = self.partner
            if selected is None and self._searching() and self._caller is not None and cats.get(self._caller, 0) >= 2:
                selected = self._caller  # turn to who speaks (face to the camera, beam on the voice)
        else:
            selected = self.selector.update(t, cats, look=self._unseen_speaker(t, cats, dist))
            self.fsm.bottom_up(t, bool(cats), cats.get(selected) if selected is not None else None)
            self._bottom_up_events(t, selected, cats, bearing, dist)
        self._publish_tracks(t, cats, bearing, dist)
        self._cats = cats
        row = self.tracks.row(selected) if selected is not None else -1
        self._act(t, row, bearing, dist, cats.get(selected, 0) if selected is not None else 0)
        if self.partner is not None:
            prow = self.tracks.row(self.partner)
            # (dormant: unseen too long to be reported where she is; moved by the tracker's "stopped" hypothesis and
            # not yet seen in her clothes: perhaps someone else, not reported as her until the camera says so)
            h = self._handovers.get(self.partner)
            if prow >= 0 and not tracks[prow].dormant and not (h is not None and h.restart):
                self._publish_partner(t, prow, bearing, dist, prow in assigned)
        self._publish_state(t)

    def _keep_still_partner(self, t: float, assigned: list[int]) -> None:
        """In Object the camera looks at the thing shown, on the ES's order, not at the partner, so neither her
        face nor her torso renews her track's single-leg allowance (``single_support``). A partner who
        stands still side-on to the laser shows it one leg (the near one hides the other): her track
        died 8 s into the look although she stood 1.1 m in front of the robot, and the robot said "You
        left" (fresh5/row_partners_hand_over seeds 0, 6, 9). Her legs measured this scan where her last
        strong evidence put her (:meth:`Tracks.still`) are that evidence renewed: the camera's looking
        away is the robot's doing, not her absence. A partner who moves, or whose legs are not seen, is
        left to the tracker's rules as before."""
        if self.fsm.state != "Object" or self.partner is None:
            return
        row = self.tracks.row(self.partner)
        if row >= 0 and row in assigned and self.tracks.still(row):
            self.tracks.hold(row, t)  # (not ``support``: that would move the place she is kept near)

    # ------------------------------------------------------------ decisions
    def _unseen_speaker(self, t: float, cats: dict[int, int], dist: list[float]) -> int | None:
        """A speaker to look at before any speaker seen facing the robot (bottom-up): someone speaking
        (category 2) whose face was not in the camera's latest image, so it cannot tell whether she faces
        the robot, within ``look_radius`` m and at most ``look_ratio`` times as far as every category-3
        person (her voice markedly louder). Two people greet or
        talk at once, the camera facing the farther one: the near voice is as likely the robot's
        (chat_group_bye seed 1: Olga greeting from 1.3 m lost to Rosa chatting 3.5 m away, and her
        "Hello BIRON" went unheard, the beam on Rosa). The look lasts until her face has been in the
        image ``look_settle`` s: facing, she is category 3 and kept (the selection's rule 1); looking
        away, the look ends and the selection goes on as before. None when there is nobody such."""
        rows = {tk.id: i for i, tk in enumerate(self.tracks.tracks)}
        threes = [dist[rows[i]] for i, c in cats.items() if c == 3]
        look = self._look
        if look is not None:
            tid, since = look
            gf = self._glanced_from
            if gf is not None and gf[1] is None and cats.get(gf[0]) == 3 and self._pp_due(gf[0], t):
                self._glanced_from = gf = (gf[0], t)
            if cats.get(tid) == 2 and (tid not in self._in_image or t - since < self.params.look_settle):
                if tid in self._in_image and since == math.inf:
                    self._look = (tid, t)
                return tid
            self._look = None
            if cats.get(tid) == 2 and tid in self._in_image and gf is not None and gf[1] is not None:
                # the glance found her speaking turned away (her face in the image long enough, not frontal):
                # the person it glanced away from, seen speaking facing it, is owed his potential partner
                # (:meth:`_bottom_up_events`). Not when she fell silent before the camera could tell: she may
                # have greeted it facing it (her greeting must not back his potential partner). Only the one
                # the glance kept from him: a potential_partner that came due while he spoke facing it. One
                # sent before the glance, whose repeat he never reached (silent by then), is not owed again: a
                # second glance that began in his speech's last moments (the hysteresis) paid him one more, 1.3 s
                # after he fell silent, while a radio said "Hello BIRON" (two_people_radio, turn21's creep)
                self._owed_pp = (gf[0], gf[1])
            self._glanced_from = None
        if not threes:
            return None
        near = self.params.look_ratio * min(threes)
        cands = [(dist[rows[i]], i) for i, c in cats.items()
                 if c == 2 and i not in self._in_image and dist[rows[i]] <= self.params.look_radius and dist[rows[i]] <= near]
        if not cands:
            return None
        tid = min(cands)[1]
        self._look = (tid, math.inf)
        three = min((dist[rows[i]], i) for i, c in cats.items() if c == 3)[1]
        self._glanced_from = (three, t if self._pp_due(three, t) else None)
        return tid

    def _pp_due(self, tid: int, t: float) -> bool:
        """Whether a potential_partner for ``tid``, speaking facing the robot at ``t``, would go out now (the first,
        or a repeat ``pp_repeat`` s after the last: :meth:`_bottom_up_events`)."""
        return tid != self.pp_sent or t - self._pp_at >= self.params.pp_repeat - 1e-9

    def _bottom_up_events(self, t: float, selected: int | None, cats: dict[int, int], bearing: list[float], dist: list[float]) -> None:
        pp = selected if selected is not None and cats.get(selected) == 3 else None
        owed, self._owed_pp = self._owed_pp, None
        if pp is None and owed is not None and owed[0] in cats and t - owed[1] < self.params.pp_wait \
                and self._look is None:
            # a glance at a near voice (:meth:`_unseen_speaker`) took the selection from someone seen speaking
            # facing the robot, and found her turned away: he is the potential partner, as he would have been
            # without the glance (flow/greet_past_near_caller seed 3: Ben's "Hello BIRON" heard, Anna on the
            # phone looked at, and the greeting rejected, "I can't see you", as nobody backed it)
            pp = owed[0]
        if pp is not None:
            self._last_pp = (pp, t)
            if pp != self.pp_sent or t - self._pp_at >= self.params.pp_repeat - 1e-9:
                i = self.tracks.row(pp)
                person = etree.Element("PERSON", id=f"t{pp}", bearing=_deg(bearing[i]), distance=f"{dist[i]:.3f}", speaking="true", facing="true")
                self._event("potential_partner", (person,))
                self.pp_sent, self._pp_at = pp, t
        elif self.pp_sent is not None and t - self._pp_at >= self.params.pp_valid - 1e-9 and not self._awaits_answer(t, selected):
            self._event("potential_partner_lost")
            self.pp_sent = None

    def _new_partner(self, t: float, tid: int, speaking: str) -> None:
        """ES event ``new_partner`` (``<PERSON id bearing distance speaking facing/>``): after a loss, another
        person (track) took the partner's place, so the supervisor knows whom the robot attends to now
        (the ES paper's events carry the data the supervisor routes on; it tells the dialog)."""
        row = self.tracks.row(tid)
        if row < 0:
            return
        x, y = self._robot_xy(t)[row]
        self._event("new_partner", (etree.Element("PERSON", id=f"t{tid}", bearing=_deg(math.atan2(y, x)),
                                                   distance=f"{math.hypot(x, y):.3f}", speaking=speaking,
                                                   facing="true" if self.facing.on(tid) else "false"),))

    def _awaits_answer(self, t: float, selected: int | None) -> bool:
        """The potential partner spoke facing the robot and still faces it, silent, still selected, for
        less than ``pp_wait`` s since she last spoke: she waits for the robot's answer to what she said."""
        pp, last = self.pp_sent, self._last_pp
        return (pp is not None and pp == selected and last is not None and last[0] == pp
                and t - last[1] < self.params.pp_wait and self.facing.on(pp))

    def _top_down(self, t: float, cats: dict[int, int]) -> None:
        """The partner's evidence, and ``partner_lost`` by the leaving rule (:meth:`partner_left`)."""
        tr = self.tracks
        row = tr.row(self.partner) if self.partner is not None else -1
        if row >= 0 and tr.tracks[row].dormant:
            row = -1  # her track is kept while she is hidden, but she is unseen: as if it had died
        if self.partner is not None and not self.partner_lost_sent:
            self._count_yield(t)  # (reset below when she is seen again)
            self._count_looked_away(t)
        gone = row >= 0 and self._her_clothes_gone(t, tr.tracks[row])
        if gone and self.fsm.state == "Follow":
            # Following, her track shows another person's clothes (someone coming the other way passed her close
            # and the tracks swapped: fresh11/rail_fast_crossing seed 1): she is not there but walks on somewhere
            # else. That track is someone else's and gets an id of its own (never taken back as hers); her id has
            # no track, her evidence is what it was when the camera last saw her clothes on her track, and the
            # follower is told so (one partner message, unseen, where she was then: it searches there, not where
            # the other person went); she is found again as after any loss of sight (:meth:`_reacquire` by her
            # clothes, the camera looking at the candidates, :meth:`_candidate`; re-identification), the leaving
            # rule counting the time since she was really seen
            tid = self.partner
            fresh = tr.renew(tid)
            self.colours.put(fresh, self.colours.take(tid))
            self._not_her.add(fresh)
            if self._her_seen is not None:
                self._partner_last, self._partner_pace, _ = self._her_seen
            self._her_seen = None
            self._partner_colour = self._her_clothes or self._partner_colour
            self._other_clothes_since = None
            self._publish_unseen_partner(t, tid)
            row = -1
        elif gone:
            # her track shows another person's clothes: she is not there (where she is, the camera has not seen);
            # she may come back and is known by her own clothes (:meth:`_retake_reach`)
            if not self.partner_lost_sent:
                self._event("partner_lost")
                self.partner_lost_sent = True
            self._not_her.add(tr.tracks[row].id)
            self._partner_colour = self._her_clothes or self._partner_colour
            row = -1
        if row >= 0 and self.fsm.state in ("Interaction", "Object"):
            row = self._her_voice_on(t, row)
        if row >= 0:
            tk = tr.tracks[row]
            colour = self.colours.colour(tk.id, t)
            if colour is not None:
                self._partner_colour = colour
            if self._partner_last is None or tk.last_seen > self._partner_last[0]:
                self._partner_pace = walking_pace(self._partner_pace if self._partner_last is not None else None,
                                                  tk.last_seen, math.hypot(tk.x[2], tk.x[3]))
                ox, oy, _ = self._pose_at(tk.last_seen)
                # where her legs were last measured, not the prediction: seen by voice or torso only,
                # the track coasts, and its prediction can drift through a wall (she stopped to say
                # 'stop' behind the door; later tracks on her were then too far to be taken as her)
                zx, zy = tk.last_z
                self._partner_last = (tk.last_seen, zx, zy, tk.x[2], tk.x[3], ox, oy)
                self._driven = 0.0
                self._yielded = 0.0
                self._looked_away = 0.0
                if self._closing is not None:
                    self._closing.reset()
        elif self.partner is not None and not self.partner_lost_sent:
            row = self._reacquire(t)
        if self.partner is None and not self.partner_lost_sent:
            self._partner_last = self._partner_colour = None
        self._listen_to_words(row)
        if self.partner is not None and self.partner_left(t):
            if not self.partner_lost_sent:
                self._event("partner_lost")
                self.partner_lost_sent = True
        elif row >= 0:
            self.partner_lost_sent = False
        if row < 0 and (self.partner_lost_sent or self.partner is None):
            # (partner None: lost while following, her track died, and the ES's order back to
            # Interaction found nobody to choose: without this nobody could ever take the place)
            if self.partner is not None and self._hers() is not None:
                self._lost_colour = self._hers()  # she may come back: known by her clothes
            self.partner = None
            self._her_clothes = self._other_clothes_since = self._her_seen = None
            self._partner_last = self._partner_colour = None
            # The partner may come back: someone speaking while facing the robot takes the place.
            rx, ry, _ = self._pose_at(t)
            rows = {tk.id: tk for tk in tr.tracks}
            threes = sorted(i for i, c in cats.items() if c == 3 and i in rows
                            and math.hypot(rows[i].x[0] - rx, rows[i].x[1] - ry) <= self._retake_reach(rows[i], t))
            if threes:
                self.partner, self.partner_lost_sent, self._lost_colour = threes[0], False, None
                self._new_partner(t, threes[0], "true")
        self._caller = self._find_caller(t, cats) if self.partner is None else None
        self._nobody_there(t)

    def _count_yield(self, t: float) -> None:
        """Following with her unseen: add the time since the last scan to :attr:`_yielded` when
        someone else is near the robot (:func:`robot.partner_search.yielding`: it yields to them
        and does not search meanwhile; the follower's search clock stands still by the same rule)."""
        last, self._yield_t = self._yield_t, t
        if self.fsm.state != "Follow" or last is None or t - last > 1.0:
            return
        rx, ry, th = self._pose_at(t)
        c, s = math.cos(th), math.sin(th)
        others = [(c * (tk.x[0] - rx) + s * (tk.x[1] - ry), -s * (tk.x[0] - rx) + c * (tk.x[1] - ry))
                  for tk in self.tracks.tracks if tk.confirmed and not tk.dormant and tk.id != self.partner]
        if yielding(others):
            self._yielded += t - last

    def _count_looked_away(self, t: float) -> None:
        """In Object with her unseen: add the time since the last scan to
        :attr:`_looked_away`. The camera then looks where she points, not at her (:meth:`_act`), and when the laser
        cannot tell her legs from the furniture she stands by (behind an armchair, against a shelf: her track lives
        on her face), the robot's own look away is all that hides her (generated tours 9100-11 and -16: "You left"
        while the robot looked for what she showed, after asking her to step aside). The out-of-view clause of
        :meth:`partner_left` does not count that time; last seen walking away or outside the interaction space,
        she is still lost after ``partner_lost_after`` s."""
        last, self._looked_t = self._looked_t, t
        if self.fsm.state != "Object" or last is None or t - last > 1.0 or t <= last or self._drive_start is not None:
            return  # (a drive on the ES's order is not counted already: :meth:`_unseen`)
        self._looked_away += t - last

    def _turning_away(self, t: float) -> None:
        """Whether the partner has turned her back on the robot (:attr:`turned_away`): in Interaction,
        set when her track walks away from it at ``leave_speed`` or faster (a person walking faces
        where she goes: to a shelf, to the window), cleared when her frontal face is anchored to her
        track or she walks towards the robot as fast. The camera cannot see a turn otherwise, so while
        it is set the camera looks at her face (:meth:`_act`). Only evidence changes it: standing
        still, she stays as she was last seen."""
        row = self.tracks.row(self.partner) if self.partner is not None else -1
        if self.fsm.state != "Interaction" or row < 0:
            self.turned_away = False
            return
        tk = self.tracks.tracks[row]
        if self.facing.on(tk.id):
            self.turned_away = False
            return
        rx, ry, _ = self._pose_at(t)
        dx, dy = tk.x[0] - rx, tk.x[1] - ry
        d = math.hypot(dx, dy)
        radial = (tk.x[2] * dx + tk.x[3] * dy) / d if d > 1e-6 else 0.0
        if radial >= self.params.leave_speed:
            self.turned_away = True
        elif radial <= -self.params.leave_speed:
            self.turned_away = False

    def _retake_reach(self, tk: Any, t: float) -> float:
        """How far from the robot someone speaking facing it may take the lost partner's place:
        ``retake_radius`` (a conversation with the robot, not a chat across the room), or
        ``retake_known_radius`` when the camera sees the lost partner's own clothes on them
        (:func:`.appearance.same_clothes`): she calls it from across the room, come back."""
        p = self.params
        if self._lost_colour is not None:
            colour = self.colours.colour(tk.id, t)
            if colour is not None and same_clothes(self._lost_colour, colour):
                return p.retake_known_radius
        return p.retake_radius

    def _find_caller(self, t: float, cats: dict[int, int]) -> int | None:
        """With no partner in Interaction (she was lost, the robot asked her to come back): the seen
        person who speaks (nearest first), else one walking up to the robot (within ``retake_radius``
        for a speaker, the interaction space for one coming up to it). Someone there is no reason to
        end the interaction (:meth:`_nobody_there`), and the robot turns to a speaker so the camera
        finds the face and the beam the voice; speaking while facing it then takes the place (the
        retake rule in :meth:`_top_down`)."""
        if not self._searching():
            return None
        p = self.params
        rx, ry, _ = self._pose_at(t)
        best: tuple[int, float, int] | None = None
        for tk in self.tracks.tracks:
            if not tk.confirmed or tk.dormant:
                continue
            dx, dy = rx - tk.x[0], ry - tk.x[1]
            d = math.hypot(dx, dy)
            if d > max(p.interaction_radius, self._retake_reach(tk, t)):
                continue
            speaks = cats.get(tk.id, 1) >= 2 and d <= self._retake_reach(tk, t)  # talking to it (conversation distance)
            comes = d > 1e-6 and (tk.x[2] * dx + tk.x[3] * dy) / d >= p.leave_speed
            if speaks or comes:
                key = (0 if speaks else 1, d, tk.id)
                if best is None or key < best:
                    best = key
        return best[2] if best is not None else None

    def _searching(self) -> bool:
        """In Interaction with no partner at all (lost while following; the robot asked her to come
        back): it listens and turns to a voice as when looking around (:meth:`_voice_heading`,
        :meth:`beam`), so whoever calls it from behind or beside, beyond the laser and the camera,
        comes into view and can take the place (retake), instead of being neither seen nor heard."""
        return self.partner is None and self.fsm.state == "Interaction"

    def _nobody_there(self, t: float) -> None:
        """An interaction with nobody in it ends: with no partner at all (lost while following, asked to
        come back, and nobody took the place; nobody seen speaking near it or walking up to it:
        :meth:`_find_caller`) for ``come_back_after`` s in Interaction or Object (``follow_lost_after``
        in Follow),
        ``partner_lost`` goes out once, so the robot looks around again (bottom-up: it hears and turns
        to whoever speaks to it) instead of standing deaf in Interacting for the rest of the run."""
        state = self.fsm.state
        if self.partner is not None or state not in ("Interaction", "Object", "Follow"):
            self._alone_since = None
            return
        # Follow with nobody to follow (ordered to follow a voice no track explains, or her track died
        # and nobody was chosen): the follower only searches, so it is a loss after the follow search time
        limit = self.params.follow_lost_after if state == "Follow" else self.params.come_back_after
        if self._alone_since is None or self._voice_turn is not None or self._caller is not None:
            self._alone_since = t  # (turning to a voice, someone speaking or coming up: someone is there)
        elif t - self._alone_since >= limit and not self.partner_lost_sent:
            self._event("partner_lost")
            self.partner_lost_sent = True

    def _hers(self) -> tuple[float, float, float] | None:
        """Her clothes, the one reference of every rule that asks whether a track wears them (the hand-overs'
        colour, the reacquisition and re-identification, who may retake her place after a loss): the first
        colour her track showed once she was the partner (:meth:`_her_clothes_gone`), else, before the camera
        gave one, her track's running colour. Not the running colour once hers is known: a track drifting
        onto a bystander she walked past carries the running colour with it (review22 R5), and every
        later check would then take the bystander's clothes for hers and refuse her own."""
        return self._her_clothes or self._partner_colour

    def _her_voice_on(self, t: float, row: int) -> int:
        """Face to face (Interaction, Object): the partner's track (row ``row``) is silent and the camera, which
        looks at it, gives it no clothes, while another confirmed track near the robot speaks wearing hers: that
        track is her and the partner moves to it (its row is returned; else ``row``). Her track had gone over to
        a silent man she walked up beside as the robot followed her (generated tour 9700-03: the legs of the two
        crossed 0.5 m apart), and from then on each of her words came from another person's direction than her
        track's, so the beam gate took her for a bystander and shut her out to the end of the tour. Her own clothes
        on the speaker are the evidence: a bystander who talks, in other clothes or unseen, never takes her place,
        nor anyone while her track shows her clothes or speaks itself (docs/semantics.md §3)."""
        hers = self._her_clothes
        tracks = self.tracks.tracks
        tk = tracks[row]
        if hers is None or self.colours.colour(tk.id, t) is not None or self.speaking.on(tk.id):
            return row
        rx, ry, _ = self._pose_at(t)
        reach = self.params.interaction_radius
        for i, other in enumerate(tracks):
            if i == row or not other.confirmed or other.dormant or other.id in self._not_her or other.id in self._handovers:
                continue
            if not self.speaking.on(other.id) or math.hypot(other.x[0] - rx, other.x[1] - ry) > reach:
                continue
            colour = self.colours.colour(other.id, t)
            if colour is None or not same_clothes(hers, colour):
                continue
            self.partner = other.id
            self._other_clothes_since = None
            return i
        return row

    def _her_clothes_gone(self, t: float, tk: Any) -> bool:
        """In Interaction, Object or Follow: has the partner's track ``tk`` shown other clothes than hers for
        ``other_clothes_after`` s? Clothes do not change during a tour, so her track is then on someone else (it
        went over to a bystander she walked past). Hers are the first colour the camera gives her track once she
        is the partner (greeted, chosen, taken back after a loss, or the one who said "stop": a new partner starts
        again); her track passing to another track id (re-identification, the leaving rule's reacquisition) keeps
        them, for that is where someone else can take her place. An open hand-over is left to its own check
        (:meth:`_check_handovers`), and an unknown or stale colour is no evidence."""
        colour = self.colours.colour(tk.id, t)
        if self._her_clothes is None:
            if colour is not None and tk.id not in self._handovers:
                self._her_clothes = colour
            self._other_clothes_since = None
            return False
        if colour is None or same_clothes(self._her_clothes, colour) or tk.id in self._handovers \
                or self.fsm.state not in ("Interaction", "Object", "Follow"):
            self._other_clothes_since = None
            return False
        if self._other_clothes_since is None:
            self._other_clothes_since = t
        return t - self._other_clothes_since >= self.params.other_clothes_after

    def partner_left(self, t: float) -> bool:
        """The leaving rule (docs/attention.md): has the partner left?

        In Follow she leads and is often out of view for a moment (a door frame, someone crossing
        between, walking past the robot's side): unseen (no leg update, frontal face, torso or voice
        of theirs) for ``follow_lost_after`` s, longer when she was last seen further than the
        following band (:func:`robot.partner_search.follow_search_time`: the time to drive the
        gap, at most 15 s), while the follower drives to where she was heading and looks for her,
        she is lost. In Interaction and Object (docs/semantics.md §6, the leaving rule; docs/subsystems.md, the
        person attention) a partner unseen less than ``partner_lost_after`` s has not left; otherwise, in this
        order: unseen ``wait_patience`` s, gone whatever was said; while the follower still comes up to her after a
        stop, not gone; out through the flat's exit door (:meth:`_out_of_flat`), gone; her words on their way to
        the understanding (her voice as she went out of view), not gone yet; after her own whole good-bye
        (:meth:`_on_frame`), walking away, outside the interaction space or unseen ``bye_patience`` s is gone; after
        a wait request or a step aside asked for, only outside the interaction space or unseen ``wait_patience``
        s; last seen outside the interaction space (``interaction_radius``), gone; walking away toward the exit
        (:meth:`_toward_exit`), gone; walking to somewhere else in the flat (an errand), unseen
        ``come_back_after`` s; else (she stepped aside: found again where she went, :meth:`_reacquire`) unseen
        ``out_of_view_after`` s. Time the robot drove on the ES's order (a viewpoint drive: she stood, the robot
        moved away and may have turned its back on her) does not count as time unseen (:meth:`_unseen`).
        """
        last = self._partner_last
        if last is None:
            return True
        seen, x, y, vx, vy, ox, oy = last
        p = self.params
        unseen = self._unseen(t, seen)
        dx, dy = x - ox, y - oy
        dist = math.hypot(dx, dy)
        if self.fsm.state == "Follow":
            # the longer the further behind the robot was when she went out of view (it yielded
            # to people crossing its way): robot.partner_search, the follower's search time
            # or the follower has stood with its search over a while: her legs unseen while a camera
            # sighting (Tracks.support) kept her "seen" here, and the robot stood silent in Following
            # (fresh5/row_fast_then_waits seed 8, 25 s; issue 26 item 1: it says so instead)
            stopped = self._follow_stopped is not None and t - self._follow_stopped >= p.follow_stopped_after
            closed = self._closing.total if self._closing is not None else 0.0
            return stopped or unseen - self._yielded - closed >= follow_search_time(dist, base=p.follow_lost_after, top_speed=p.robot_top_speed,
                                                                                   pace=math.hypot(vx, vy))
        if unseen < p.partner_lost_after:
            return False
        heard = self._heard_unseen[0]
        if heard > seen:
            return self._quiet_too_long(t, seen, heard)
        if unseen - self._looked_away >= p.wait_patience:
            return True  # unseen longer than the longest patience: gone, whatever was said or asked
        if self._follower_drives or (self._follow_searching is not None and t - self._follow_ended < p.follow_handover):
            # (the follower searched for her when the stop came: its next status, a moment after the ES's order
            # reached both modules, says it comes up to where she was; fresh7 corr_fast_walker_goto seed 0:
            # "You left" 0.06 s after the stop, before that status came)
            # "Stop" ended following with her ahead and the follower comes up to her (its status
            # ``approaching``): how far ahead she stood, and her last steps before she stopped, are the
            # robot's lag, not her leaving (fresh6/div_fast_leader_stops: "You left" 1.5 s after "OK, I
            # stopped", a fast leader 4.3 m ahead past a divider). The follower keeps her last position
            # for its search time (at most 15 s) and then stands ("stopped"); then the rule below holds again.
            return False
        if self._out_of_flat(t):
            return True  # out through the flat's exit door: leaving, whatever she said
        away = (vx * dx + vy * dy) / dist if dist > 1e-6 else 0.0
        if self._her_voice >= seen - p.voice_hold and self._words_end < self._her_voice - p.voice_hold and t - self._her_voice <= p.words_wait:
            return False  # she spoke as she went out of view: what she said is waited for (a wait, a good-bye)
        if self._said_bye is not None and seen >= self._said_bye - p.partner_lost_after and seen - self._said_bye <= p.bye_walk:
            # she said good-bye (even one the dialog doubts): walking away is leaving, and so is a short time unseen
            return unseen >= p.bye_patience or dist > p.interaction_radius or away >= p.leave_speed
        waited = [w for w, walk in ((self._asked_aside, p.aside_walk), (self._said_wait, p.wait_walk))
                  if w is not None and seen >= w - p.partner_lost_after and seen - w <= walk]
        if waited:
            # last seen walking away just after the robot asked her to step aside or she asked it to wait: the step
            # it asked for, the errand she announced (a door frame or a wall may hide her where she went), not evidence
            # of leaving; she has left when last seen outside the interaction space, or unseen ``wait_patience`` s
            return dist > p.interaction_radius or unseen - self._looked_away >= p.wait_patience
        out_of_view = unseen - self._looked_away
        if dist > p.interaction_radius:
            return True  # last seen outside the interaction space
        if away >= p.leave_speed:
            # walking away within the interaction space: leaving when her way leads to the flat's exit (the map's
            # rooms end there); inside the flat (to the next room, behind a wall) she is on an errand: waited for
            # as long as it takes to walk back from the next room (``come_back_after``)
            return self._toward_exit(seen, x, y, vx, vy) or out_of_view >= p.come_back_after
        if self._rooms and self.furniture is not None and math.hypot(vx, vy) >= p.leave_speed and not self._toward_exit(seen, x, y, vx, vy):
            return out_of_view >= p.come_back_after  # last seen walking (along, across) to somewhere in the flat: an errand
        return out_of_view >= p.out_of_view_after

    def _quiet_too_long(self, t: float, seen: float, heard: float) -> bool:
        """The leaving rule for a partner unseen who has spoken since from where she went out of view
        (:meth:`_voice_from_where_she_went`, at ``heard``): she stands there, hidden, and talks to the robot, so
        how she walked when last seen (away, toward the exit, far) is no longer evidence of leaving; her time
        unseen counts from her last word: not gone within ``partner_lost_after`` s of it nor while its frame is on
        its way (``words_wait``); after a good-bye of hers, ``bye_patience`` s; after a wait request or a step
        aside, ``wait_patience`` s; otherwise ``come_back_after`` s (she is somewhere near in the flat, as on an
        errand). Talking on, she is never gone."""
        p = self.params
        quiet = t - heard
        if quiet < p.partner_lost_after:
            return False
        if self._words_end < heard - p.voice_hold and quiet <= p.words_wait:
            return False  # what she said is waited for (a good-bye, a wait request)
        if self._said_bye is not None and self._said_bye >= seen - p.partner_lost_after:
            return quiet >= p.bye_patience
        waited = [w for w, walk in ((self._asked_aside, p.aside_walk), (self._said_wait, p.wait_walk))
                  if w is not None and w >= seen - walk]
        return quiet >= (p.wait_patience if waited else p.come_back_after)

    def _reacquire(self, t: float) -> int:
        """The partner's track died while they were within the interaction space: a confirmed track
        near where they were last seen (growing with the time unseen) is taken as theirs again,
        unless the camera saw it wear other clothes than hers (:mod:`.appearance`). Following, "where
        she was last seen" is her way on (:meth:`_her_way`): she leads, and walks on out of view."""
        last = self._partner_last
        if last is None:
            return -1
        seen, x, y = last[0], last[1], last[2]
        p = self.params
        radius = min(2.5, p.reacquire_radius + p.reacquire_speed * max(0.0, t - seen))
        best, row = radius, -1
        for i, tk in enumerate(self.tracks.tracks):
            colour = self.colours.colour(tk.id, t)
            # someone in other clothes is not her, however near (a person who crossed between), nor
            # someone the camera showed to be another after taking them for her (:meth:`_give_back`)
            if tk.confirmed and not tk.dormant and same_clothes(self._hers(), colour) and tk.id not in self._not_her:
                d = self._her_way(t, (tk.x[0], tk.x[1]))
                # her colour known, this track's unseen: position alone, so only as near as she can have
                # stepped unseen, not the growing radius, unless the track was born within it (four_people seed 8: a man walking past the
                # robot 2.5 m from where she went out of view was taken as her, the search followed him)
                if colour is None and self._hers() is not None and d > p.reacquire_radius:
                    # ... or first seen where she went out of view (she comes back from there); not while she
                    # leads (Follow): she walks on, ahead, and the camera looks at such a track meanwhile
                    # (_candidate, taken by its clothes in _reacquire_walking); a track born beside her way, never
                    # seen moving, was a door jamb 6 m ahead (the localiser's heading 1.8 deg off put its echo
                    # 0.19 m off the wall), and the search drove to the jamb and stood there (fresh7
                    # corr_fast_walker_goto seeds 0, 4)
                    if self.fsm.state == "Follow" or self._her_way(t, tk.origin) > radius:
                        continue
                if d <= best:
                    best, row = d, i
        if row < 0 and self.fsm.state == "Follow":
            row = self._reacquire_walking(t, seen, x, y)
        if row >= 0:
            tid = self.tracks.tracks[row].id
            if self._hers() is not None and self.colours.colour(tid, t) is None and tid != self.partner:
                # taken on position alone: open to the camera's verdict (:meth:`_check_handovers`)
                self._open(tid, Handover(t, self._hers(), was=self.partner, partner=self._partner_state()))
            self.partner = tid
        return row

    def _her_way(self, t: float, point: tuple[float, float]) -> float:
        """Metres from ``point`` (odom) to where the unseen partner can be: where her legs were last
        measured; following (she leads), anywhere on her way on from there at her last velocity for
        the time unseen (:func:`robot.partner_search.way_distance`). A partner faster than the robot
        who went out of view in the next room was seen again 4 m on from there and not taken back,
        so the robot lost her while it saw her (u_catch_up_slow seed 0). Never further from where she was
        last measured than she can have walked (:meth:`_walk_reach`): her way on is not a line without end."""
        seen, x, y, vx, vy = self._partner_last[:5]  # type: ignore[index]
        if self.fsm.state != "Follow":
            return math.hypot(point[0] - x, point[1] - y)
        if math.hypot(point[0] - x, point[1] - y) > self._walk_reach(t, seen):
            return math.inf
        return way_distance(point, (x, y), (vx, vy), t - seen, walking=self.params.leave_speed)

    def _reacquire_walking(self, t: float, seen: float, x: float, y: float) -> int:
        """Following, she leads and walks on while out of view (through a door the robot has not
        reached yet, round a corner): the one confirmed track in her clothes (its colour seen, the same
        as hers) within :meth:`_walk_reach` of where she was last measured is hers, however far beyond
        the reacquisition radius (position history and clothes: issue 26 item 1, sq_cross_pair, where
        she was found again 4 m on, in the next room); two such tracks, or none whose colour is known:
        nobody (the camera looks at the candidates meanwhile, :meth:`_candidate`)."""
        hers = self._hers()
        if hers is None:
            return -1
        reach = self._walk_reach(t, seen)
        rows = [i for i, tk in enumerate(self.tracks.tracks)
                if tk.confirmed and not tk.dormant and tk.id not in self._not_her
                and math.hypot(tk.x[0] - x, tk.x[1] - y) <= reach
                and (c := self.colours.colour(tk.id, t)) is not None and same_clothes(hers, c)]
        return rows[0] if len(rows) == 1 else -1

    def _walk_reach(self, t: float, seen: float) -> float:
        """How far she may have walked since ``seen`` while the robot follows: her walking pace (the
        fastest her track went in the last few seconds it was seen, at least ``reacquire_speed``, at
        most ``follow_walk_speed``) for the time unseen, plus ``reacquire_radius``, at most
        ``follow_reacquire_cap``. The pace, not the track's speed when last seen: a person turning
        through a door slows her constant-velocity track just before the jamb hides her (sq_cross_pair
        seed 0: 0.32 m/s at 0.5 m/s), and 9 s later she was seen again in the next room 0.3 m beyond
        that reach, never looked at, and declared gone."""
        p = self.params
        last = self._partner_last
        speed = math.hypot(last[3], last[4]) if last is not None else 0.0
        if last is not None and self._partner_pace[0] == last[0]:
            speed = max(speed, self._partner_pace[1])
        speed = min(p.follow_walk_speed, max(p.reacquire_speed, speed))
        return min(p.follow_reacquire_cap, p.reacquire_radius + speed * max(0.0, t - seen))

    def _candidate(self, t: float) -> int:
        """Following with her unseen (and her clothes known): the row of the nearest confirmed track
        within :meth:`_walk_reach` whose clothes the camera has not seen lately, so the camera looks
        at it (:meth:`_act`) and :meth:`_reacquire_walking` can tell whether she is the one; -1 when
        there is none."""
        last = self._partner_last
        if (self.fsm.state != "Follow" or self.partner is None or self.partner_lost_sent or last is None
                or self._partner_colour is None):
            return -1
        prow = self.tracks.row(self.partner)
        if prow >= 0 and not self.tracks.tracks[prow].dormant:
            return -1
        reach = self._walk_reach(t, last[0])
        rx, ry, _ = self._pose_at(t)
        best, row = math.inf, -1
        for i, tk in enumerate(self.tracks.tracks):
            if (not tk.confirmed or tk.dormant or tk.id == self.partner or tk.id in self._not_her
                    or self.colours.colour(tk.id, t) is not None):
                continue
            if math.hypot(tk.x[0] - last[1], tk.x[1] - last[2]) > reach:
                continue
            d = math.hypot(tk.x[0] - rx, tk.x[1] - ry)
            if d < best:
                best, row = d, i
        return row

    def _could_be(self, t: float, seen: float, x: float, y: float, colour: tuple[float, float, float] | None, tk: Any,
                  way: Any = None) -> bool:
        """Could track ``tk`` be the person last seen at ``seen`` at (``x``, ``y``) (odom) wearing ``colour``?
        The reacquisition rule (:meth:`_reacquire`): within ``reacquire_radius`` plus ``reacquire_speed``
        per second unseen (at most 2.5 m), never in other clothes, and, with the colour known but the
        track's not yet, only within ``reacquire_radius`` unless first seen within the radius.
        ``way``: the distance from a point to where they can be, when not just (``x``, ``y``) (the
        partner who led the robot: :meth:`_her_way`)."""
        p = self.params
        radius = min(2.5, p.reacquire_radius + p.reacquire_speed * max(0.0, t - seen))
        theirs = self.colours.colour(tk.id, t)
        if not same_clothes(colour, theirs):
            return False
        dist = way or (lambda q: math.hypot(q[0] - x, q[1] - y))
        d = dist((tk.x[0], tk.x[1]))
        if theirs is None and colour is not None and d > p.reacquire_radius:
            return dist(tk.origin) <= radius
        return d <= radius

    def _reidentify(self, t: float, assigned: list[int]) -> list[int]:
        """Re-identification of people found again (issue 26 item 1): a track just confirmed takes the id
        of the one dormant track (kept while its person was hidden: behind a door jamb, someone else,
        the robot's back) whose person it could be by :meth:`_could_be` (where they were last measured
        and their clothes; for the partner, her evidence as the leaving rule keeps it). A person
        back in view is then the same track, not a new one: no identity switch, and a partner found
        again stays the partner the follower follows. With two candidates it decides nothing.

        The id's colour record is then the new track's own (what the camera saw of this track), not the
        person's: when the person's clothes were known and the track's not yet, the hand-over rests on
        position alone and stays open (:class:`Handover`) until the camera sees the track's clothes
        (:meth:`_check_handovers`): other clothes, and it is undone."""
        tr = self.tracks
        for nid in list(tr.confirmed_now):
            row = tr.row(nid)
            if row < 0:
                continue
            new = tr.tracks[row]
            fits = []
            for old in tr.tracks:
                if not (old.confirmed and old.dormant) or old.id == nid:
                    continue
                way = None
                if old.id == self.partner and self._partner_last is not None:
                    seen, x, y = self._partner_last[0], self._partner_last[1], self._partner_last[2]
                    colour = self._hers()
                    way = lambda q: self._her_way(t, q)  # noqa: E731 (following: her way on)
                else:
                    seen, (x, y), colour = old.last_seen, old.last_z, self.colours.colour(old.id)
                if self._could_be(t, seen, x, y, colour, new, way):
                    fits.append((old, colour))
            if len(fits) == 1:
                old, colour = fits[0]
                unseen = self.colours.colour(nid, t) is None
                gone = tr.adopt(nid, old.id)
                if gone >= 0:
                    assigned = [a - 1 if a > gone else (-1 if a == gone else a) for a in assigned]
                    record = self.colours.take(old.id)  # the person's, kept with an open hand-over
                    self.colours.put(old.id, self.colours.take(nid))  # the id's colour is the track's own from now on
                    if colour is not None and unseen:
                        self._open(old.id, Handover(t, colour, old=old, old_colour=record,
                                                    partner=self._partner_state() if old.id == self.partner else None))
        return assigned

    def _restarted(self, t: float, before: Any) -> None:
        """The tracker took a candidate for the partner's track under its "stopped" hypothesis (she stopped or
        turned while unseen, :func:`.tracker._gated`): on position alone, where she was last measured. Someone
        else may stand there: a child running past her through a door while she was hidden behind him took her
        track (fresh7/split_children_cross). With her clothes known and the camera not yet having seen the
        track's since, the hand-over stays open (:meth:`_check_handovers`); undone, her track is ``before``."""
        if self.partner in self._handovers:
            return
        record = self.colours.take(before.id)  # the clothes the track shows from now on are the track's own
        self._open(before.id, Handover(t, self._hers(), old=before, old_colour=record,  # type: ignore[arg-type]
                                       partner=self._partner_state(), restart=True))

    def _open(self, tid: int, h: Handover) -> None:
        if "_handovers" not in vars(self):  # (a module built without __init__: never the class's default)
            self._handovers = {}
        self._handovers[tid] = h

    def _partner_state(self) -> tuple[Any, Any, Any]:
        return (self._partner_last, self._partner_pace, self._partner_colour)

    def _check_handovers(self, t: float, assigned: list[int]) -> list[int]:
        """The camera's verdict on identities handed over on position alone (:class:`Handover`): the track's
        clothes seen and the same as the person's, the hand-over stands; other clothes (a child running past
        the partner through a door, taken for her while she was hidden: fresh7/split_children_cross), it
        is undone (:meth:`_give_back`). Unseen for ``HANDOVER_CHECK`` s, or the track gone, it stands."""
        for tid in sorted(self._handovers):
            h = self._handovers[tid]
            if self.tracks.row(tid) < 0 or t - h.since > HANDOVER_CHECK:
                del self._handovers[tid]
                continue
            colour = self.colours.colour(tid, t)
            if colour is None:
                tk = self.tracks.tracks[self.tracks.row(tid)]
                if h.restart and t - tk.last_update >= HANDOVER_UNMEASURED:
                    # the track's person went out of view before the camera saw them: nothing but position ever
                    # said it was this person, so the evidence goes back to what it was before
                    del self._handovers[tid]
                    assigned = self._give_back(t, tid, h, assigned, refuted=False)
                continue
            del self._handovers[tid]
            if not same_clothes(h.colour, colour):
                assigned = self._give_back(t, tid, h, assigned)
        return assigned

    def _give_back(self, t: float, tid: int, h: Handover, assigned: list[int], refuted: bool = True) -> list[int]:
        """Undo the hand-over of identity ``tid`` (:meth:`_check_handovers`): the track holding it is someone
        else and gets an id of its own; a re-identified person's dormant track is put back under ``tid``
        (:meth:`Tracks.give_back`), a reacquired partner's id goes back to the one she had; the partner's
        evidence (where and when she was last seen, her pace and clothes) is hers again, not what the wrong
        track added, so the leaving rule and the search start from where she really went out of view."""
        wrong = tid
        if h.old is not None:
            fresh, at = self.tracks.give_back(tid, h.old, h.since, t)
            if fresh >= 0:
                self.colours.put(fresh, self.colours.take(tid))
                wrong = fresh
            if at >= 0:
                self.colours.put(tid, h.old_colour)
                assigned = [a + 1 if a >= at else a for a in assigned]
        if h.partner is not None and self.partner == tid:
            if h.old is None and h.was is not None:
                self.partner = h.was
            self._partner_last, self._partner_pace, self._partner_colour = h.partner
            if refuted:
                self._not_her = self._not_her | {wrong}
        return assigned

    def _event(self, name: str, children: tuple[etree._Element, ...] = ()) -> None:
        el = etree.Element("event", name=name)
        for c in children:
            el.append(c)
        # The scan this decision was taken on is its cause: the trace links the scan to the event.
        self.bus.publish(ES_EVENTS, el, transfer=True, causes=(self._scan_id,) if self._scan_id else ())

    # ------------------------------------------------------------ actions
    def _act(self, t: float, row: int, bearing: list[float], dist: list[float], category: int) -> None:
        p = self.params
        state = self.fsm.state
        target = CAMERA[state]
        # Camera.
        pan = tilt = 0.0
        if target == "object" and self._focus is not None:
            pan, d, h = self._focus
            tilt = math.atan2(h - p.camera_height, max(d, 0.3))  # the region's height: a table top, or the floor
        elif row >= 0 and self._searching():
            pan = bearing[row]  # a caller (:meth:`_find_caller`): find the face
            tilt = math.atan2(p.heights["face"] - p.camera_height, max(dist[row], 0.3))
        elif target in p.heights and (look := self._candidate(t)) >= 0:
            # following, her unseen: look at whoever she could be, to see their clothes
            pan = bearing[look]
            tilt = math.atan2(p.heights["torso"] - p.camera_height, max(dist[look], 0.3))
        elif target in p.heights and row >= 0:
            pan = bearing[row]
            # turned away (:meth:`_turning_away`): her face, to see her turn back to the robot; her legs
            # hidden from the laser (a sofa's back, a table top: her track lives on her face alone,
            # tracker FACE): her face, or the robot loses her (beyond ~1.2 m her hands stay in the image)
            tk = self.tracks.tracks[row]
            look = "face" if tk.id == self.partner and (self.turned_away or t - tk.last_legs > p.legs_hidden_after) else target
            tilt = hands_tilt(p, dist[row]) if look == "hands" else math.atan2(p.heights[look] - p.camera_height, max(dist[row], 0.3))
        voice = self._voice_heading(t, row, category)
        if voice is None:
            self._voice_blocked = False
        else:  # look where the voice came from (the base turns there below)
            pan, tilt = self._voice_look(math.remainder(voice - self._pose_at(t)[2], 2 * math.pi))
        self._ptu(t, pan, tilt)
        # Base: turn on the spot to the person in Listen, Interaction and Object, and to an
        # unexplained voice while bottom-up (:meth:`_voice_heading`).
        if voice is not None:
            b = math.remainder(voice - self._pose_at(t)[2], 2 * math.pi)
            if abs(b) < p.turn_stop:
                self._voice_turn = None
                if self._turning:
                    self._base(0.0)
                    self._turning = False
            else:
                self._turning = True
                self._voice_blocked = self._turn(b) == 0.0
        elif (turn := self._focus_turn(target)) is not None:
            if abs(turn) < p.turn_stop:
                if self._turning:
                    self._base(0.0)
                    self._turning = False
            else:
                self._turning = True
                self._turn(turn)
        elif state in TURNS and ((voice_at := self._toward_her_voice(t)) is not None or row >= 0
                                 or (unseen_at := self._where_she_stood(t)) is not None) \
                and not self._follower_drives and not self._player_drives:
            b = voice_at if voice_at is not None else bearing[row] if row >= 0 else unseen_at
            if self._turning and abs(b) < p.turn_stop:
                self._base(0.0)
                self._turning = False
            elif self._turning or abs(b) > p.turn_start:
                self._turning = True
                self._turn(b)
        elif not self._player_drives and (way := self._look_along_way(t)) is not None:
            # asking for help, nobody speaking to it (nobody tracked, or whoever it attends to stays silent: the base
            # turns only to a speaker, Listen, above): look along the blocked way, so the watch sees it clear (facing
            # a silent bystander it never saw the way clear: nav/goto_passage_lodger_leaves). The camera stays
            # on her face as far as it pans; once she speaks, it turns to her
            if self._turning and abs(way) < p.turn_stop:
                self._base(0.0)
                self._turning = False
            elif self._turning or abs(way) > p.turn_start:
                self._turning = True
                self._turn(way)
        elif self._turning:
            self._base(0.0)
            self._turning = False
        # a speaker whose face the camera cannot see is listened to (:meth:`beam`), unless the robot waits for
        # another person's answer (she spoke facing it within ``pp_wait``): a phone call beside it is then no
        # answer to its "Did you say hello to me?" (flow/greet_beside_phone_call seed 0: Jonas' "yes I am at
        # home" confirmed Karl's greeting)
        # , nor while someone else speaks seen facing the robot (category 3): the camera's glance at a near voice
        # (:meth:`_unseen_speaker`) must not take the ears from the person seen greeting it (flow/greet_past_near_caller:
        # Ben's "Hello BIRON" cut in half when the beam went to Anna on the phone). While the selected person is
        # not listened to, the nearest such person is.
        tid = self.tracks.tracks[row].id if row >= 0 else None
        lp = self._last_pp
        cats = self._cats
        threes = [i for i, c in cats.items() if c == 3 and i != tid]
        unseen = (tid is not None and tid not in self._in_image and not threes
                  and not (lp is not None and lp[0] != tid and t - lp[1] < p.pp_wait))
        aim = self.beam(t, self._heard_at(t, bearing[row], dist[row]) if row >= 0 else None, category, unseen=unseen)
        if aim is None and threes and category != 3 and not self.fsm.top_down:
            rows = [self.tracks.row(i) for i in threes]
            near = min((r for r in rows if r >= 0), key=lambda r: dist[r], default=-1)
            if near >= 0:
                aim = self._heard_at(t, bearing[near], dist[near])
        self._steer(aim)

    def _heard_at(self, t: float, b: float, d: float) -> float:
        """The bearing (rad, front half-plane) to steer the beam at for a person at bearing ``b``, ``d`` m away:
        where the pair hears her voice, not where she stands. A delay-and-sum beam passes what its delay is
        steered at, the reading of the voice's time difference (the microphones' model), and a mouth above
        the pair close by reads nearer the axis than it stands (0.6 m away at 75 deg: about 45 deg). Her
        mouth height is unknown, so the reading she may give spans a range (:func:`sound_bearing_span`): a
        voice heard lately inside it is taken (the nearest), else the reading of a typical mouth."""
        x, y = d * math.cos(b), d * math.sin(b)
        heard = self._sounds
        if heard is not None and t - heard[0] <= self.params.dominant_max_age and heard[1]:
            span = sound_bearing_span(x, y, self.cues)
            off, near = min((span_offset(span, v), v) for v in heard[1])
            if off <= self.cues.sound_tolerance:
                return near
        return sound_bearings_from([(x, y)], self.cues)[0]

    def _where_she_stood(self, t: float) -> float | None:
        """In Interaction, the partner unseen (her track died or went dormant) with no evidence of leaving:
        the bearing (rad, robot frame) of where her legs were last measured, to turn to; else None.

        A partner beside the robot is in the interaction space (the leaving rule): after a stop the
        follower's approach may end with her 0.75 m to its side, beyond the laser's half-circle, and a
        robot that does not turn to her sees nobody there and says "You left" 10 s later
        (fresh5/row_phone_between, stair_names_snug). Turned to where she stood, the laser and the camera
        find her again (:meth:`_reacquire`); nobody there, the leaving rule ends it as before."""
        last = self._partner_last
        if self.fsm.state != "Interaction" or self.partner is None or self.partner_lost_sent or last is None:
            return None
        turn = self._toward_her_voice(t)
        if turn is not None:
            return turn
        seen, x, y, vx, vy, ox, oy = last
        p = self.params
        px, py, th = self._pose_at(t)
        row = self.tracks.row(self.partner)
        if row >= 0 and not self.tracks.tracks[row].dormant:
            return None  # she is tracked: turned to as usual
        dx, dy = x - ox, y - oy
        dist = math.hypot(dx, dy)
        away = (vx * dx + vy * dy) / dist if dist > 1e-6 else 0.0
        if dist > p.interaction_radius or away >= p.leave_speed:
            return None  # evidence of leaving: nothing to turn to
        if math.hypot(x - px, y - py) < 1e-6:
            return None
        return math.remainder(math.atan2(y - py, x - px) - th, 2 * math.pi)

    def _toward_her_voice(self, t: float) -> float | None:
        """In Interaction, the partner unseen who has spoken since from where she went out of view
        (:meth:`_voice_from_where_she_went`): the bearing (rad, robot frame) of her voice's reading nearer
        where she was, to turn to, whatever her walk said before and rather than to her track coasting on
        unmeasured; else None."""
        last = self._partner_last
        if self.fsm.state != "Interaction" or self.partner is None or self.partner_lost_sent or last is None:
            return None
        heard, heading = self._heard_unseen
        if heard <= last[0]:
            return None
        return math.remainder(heading - self._pose_at(t)[2], 2 * math.pi)

    def _spoke_before(self, t: float, tk: Any, px: float, py: float) -> bool:
        """Is the track ``tk`` (the robot at odom ``px``, ``py``) where a voice came from lately that nobody
        in view explained (:attr:`heard`, either reading, within ``voice_recall`` s)? Then it was she who
        spoke: she greeted the robot from behind or beside, out of its view, and it turned to find her."""
        p = self.params
        if self.heard.recall(t, math.atan2(tk.x[1] - py, tk.x[0] - px), tk.id, p.voice_recall, p.voice_recall_tolerance):
            return True
        # close by, her voice was read nearer the axis than she stands (her mouth above the microphones): any
        # reading the span of her unknown mouth height allows (:func:`sound_bearing_span`) is hers (a person at
        # the robot's elbow, found by the camera after the voice: :meth:`_voice_look`)
        th = self._pose_at(t)[2]
        c, s = math.cos(th), math.sin(th)
        dx, dy = tk.x[0] - px, tk.x[1] - py
        lo, hi = sound_bearing_span(c * dx + s * dy, -s * dx + c * dy, self.cues)
        return self.heard.recall_span(t, th + lo, th + hi, tk.id, p.voice_recall, p.voice_recall_tolerance)

    def _voice_target(self, t: float, heard: float, bearing: float) -> float | None:
        """Where to look for a voice heard at ``heard`` at front reading ``bearing`` that nobody seen
        explains (robot.attention.looking): the odometry heading, or None (no turn).

        Its front reading unless the camera has looked there since and seen nobody (no frontal face, no
        torso: someone with her back to it is someone); then the mirrored
        reading behind, unless that too was looked at and found empty within ``voice_look_memory``
        (a radio, heard from a direction with nobody in it, is not looked for again and again). A
        front reading the camera has not looked at since is looked at first: off the axis by a few
        degrees a short turn brings it into the image, by more than ``voice_turn_min`` a turn."""
        p = self.params
        th = self._pose_at(heard)[2]
        front, back = th + bearing, th + math.pi - bearing
        x, y, _ = self._pose_at(heard)
        legs = any(not tk.dormant and angle_between(math.atan2(tk.x[1] - y, tk.x[0] - x), front) <= p.voice_recall_tolerance
                   for tk in self.tracks.tracks)
        if self.looked.empty_since(front, heard - p.dominant_max_age) and not legs:
            return None if self.looked.empty_since(back, t - p.voice_look_memory) else back
        if self.looked.face_since(front, heard - p.dominant_max_age):
            return None  # a face there: someone whose legs the laser does not see (a FACE track)
        if abs(bearing) <= p.voice_turn_min and self.looked.body_since(front, heard - p.dominant_max_age):
            # someone in the image there, turned away (wlan_reorder: Ben steps out from behind a sideboard,
            # calling): no turn, as before the voice search; the beam follows his voice, and a turn to a
            # fixed direction while he walks on took the beam off him (seed 3)
            return None
        return front

    def _voice_look(self, b: float) -> tuple[float, float]:
        """(pan, tilt) for a voice nobody seen explains, at bearing ``b`` (rad, robot frame) to turn to: its
        reading, at a face 1.5 m away. While the base cannot turn there (:attr:`_voice_blocked`: someone
        stands so near its side that a corner would sweep into her), the camera looks for her further round:
        a mouth above the microphones close by is read nearer the axis than it stands (:func:`sound_bearing_span`;
        at 0.5 m, 88 deg reads 45 deg), so a person at the robot's elbow, beyond the laser's half circle, was
        looked for where the reading pointed and never found, and her greetings went unanswered for minutes
        (generated tours: after a drive to a viewpoint left her beside the robot). The image is centred
        between the reading and the furthest direction a voice so read can come from (:func:`voice_reach`),
        that far end kept in the image (the reading itself was looked at before the turn failed), and tilted
        for a face 1 m away."""
        p = self.params
        far_face = math.atan2(p.heights["face"] - p.camera_height, 1.5)
        if not self._voice_blocked:
            return b, far_face
        front = abs(b) <= math.pi / 2
        r = abs(b) if front else math.pi - abs(b)  # the front reading
        reach = voice_reach(r, self.cues)
        if not front:
            r, reach = math.pi - r, math.pi - reach
        mid = (r + reach) / 2
        keep = p.camera_hfov / 2 - math.radians(5.0)
        mid = max(mid, reach - keep)  # the far end in the image (the reading was looked at before the turn failed)
        pan = math.copysign(min(mid, p.pan_limit), b)
        return pan, math.atan2(p.heights["face"] - p.camera_height, 1.0)

    def _focus_turn(self, target: str) -> float | None:
        """In Object, while the object attention's focus lies beyond the pan-tilt unit's reach (she
        points beside and behind the robot): the angle (rad) still to turn the base so that it lies
        ``focus_margin`` inside the reach; 0 once it does (the turn is over while the focus stays
        there), None when no such turn is under way (the base turns to her, as in Interaction).
        Not while the player drives (a drive to a viewpoint turns the robot itself)."""
        f = self._focus
        if target != "object" or f is None or self.now - self._focus_at > 0.5 or self._player_drives or self._follower_drives:
            self._focus_turning = False
            return None
        p = self.params
        b = f[0]
        inside = p.pan_limit - p.focus_margin
        if abs(b) > p.pan_limit:
            self._focus_turning = True
        if not self._focus_turning:
            return None
        return 0.0 if abs(b) <= inside else b - math.copysign(inside, b)

    def _voice_heading(self, t: float, row: int, category: int) -> float | None:
        """The odometry heading to turn to for a voice nobody seen explains, or None.

        Bottom-up and free (no order holds the state), when nobody selected is speaking: a fresh
        unexplained sound direction (``_dominant``) further than ``voice_turn_min`` off the axis
        starts a turn towards it (its front reading: the pair cannot tell front from back, and a
        voice from behind is found in two turns as its reading moves forward), which ends when the
        robot faces it, after ``voice_turn_time`` s, or when someone seen starts to speak (Listen
        turns to them). Someone greeting from 90 deg, beyond the laser's half-circle, or whose legs
        a chair hides, is then in front of the laser and the camera.
        """
        p = self.params
        if self._searching() and row >= 0:
            self._voice_turn = None  # a seen caller speaks: turn to them (:meth:`_act`), not to the voice
            return None
        # (someone seen speaking (category 2) does not stop a turn under way: while the robot turns
        # round to a voice from behind, its front reading sweeps past the people in front, and one
        # of them, talking on the phone, is heard as its speaker: sq_goto_bedroom_door)
        m = self._mirror
        if (self.seeking_help and m is not None and self._voice_turn is None and not self.fsm.top_down
                and not self.fsm.held and t - m[0] <= p.dominant_max_age):
            # asking for help, a voice a seen person not facing it explains: look the other way too, unless
            # the camera looked there lately and saw nobody (:meth:`_mirror_voice`)
            self._mirror = None
            if not self.looked.empty_since(m[1], t - p.voice_look_memory):
                turn = angle_between(m[1], self._pose_at(t)[2])
                self._voice_turn = (t + max(p.voice_turn_time, turn / p.max_turn + p.voice_turn_slack), m[1], m[0])
        if not self._searching() and (self.fsm.top_down or self.fsm.held or (row >= 0 and (category >= 3 or category == 2 and self._voice_turn is None))):
            self._voice_turn = None
            return None
        if row >= 0 and self.tracks.tracks[row].confirmed and self._waits_facing(t, self.tracks.tracks[row].id):
            # the person it attends to faces it and has just spoken to it or just turned to it (she
            # greeted it and waits for its answer, or is about to): a voice nobody seen explains (a TV or
            # radio behind the robot, read in front by the pair) does not turn the robot away from her
            # (studio_confirm_repeat). Someone who has faced it longer without a word is not waiting
            # for an answer: a bystander looking on (tour-3000-10: after a go-to, Ben facing it from its
            # right held it while the user greeted it from behind, and every greeting expired), or,
            # asking for help, the man standing in the door it could not pass (regreet seed 2: it never
            # turned to the partner greeting it from behind)
            self._voice_turn = None
            return None
        d = self._dominant
        # Searching for her after a loss (:meth:`_searching`), or for whoever answers its call for help
        # (``seeking_help``: it drove away from its partner, who comes up behind it, the laser's blind
        # half; hall_goto_doorway_person, sq_goto_bedroom_door): a voice read near the axis that nobody
        # seen in front explains comes from behind (the pair cannot tell front from back, the laser
        # and the camera see the front): turn round to its mirrored direction.
        behind = (self._searching() or self.seeking_help) and d is not None and abs(d[1]) <= p.voice_turn_min
        if d is not None and t - d[0] <= p.dominant_max_age and (self._voice_turn is None or d[0] > self._voice_turn[2]):
            if behind:
                target = self._pose_at(d[0])[2] + math.pi - d[1]
            elif self._voice_turn is None:
                target = self._voice_target(t, d[0], d[1])
            else:
                # Turning to it already: a new reading refines the direction decided on (the reading
                # nearer it), and does not decide afresh: turning, the camera has not looked at the
                # other reading yet, and the voice sweeps across the readings as the robot turns.
                th = self._pose_at(d[0])[2]
                now = self._voice_turn[1]
                target = min((th + d[1], th + math.pi - d[1]), key=lambda h: angle_between(h, now))
                if angle_between(target, now) > p.voice_refine:
                    target = None
            if target is not None:
                turn = angle_between(target, self._pose_at(t)[2])
                self._voice_turn = (t + max(p.voice_turn_time, turn / p.max_turn + p.voice_turn_slack), target, d[0])
        vt = self._voice_turn
        if vt is None or t > vt[0]:
            self._voice_turn = None
            return None
        return vt[1]

    def _waits_facing(self, t: float, tid: int) -> bool:
        """Track ``tid`` faces the robot and waits for it: she spoke facing it less than ``pp_wait`` s
        ago, or (not while it asks for help, when whoever stands in its way faces it) turned to face it
        less than ``pp_wait`` s ago (she walked up to it and is about to speak)."""
        if not self.facing.on(tid):
            return False
        if self._spoke_lately(t, tid):
            return True
        return not self.seeking_help and t - self.facing.since(tid) < self.params.pp_wait

    def _spoke_lately(self, t: float, tid: int) -> bool:
        """Whether track ``tid`` was the potential partner (spoke facing the robot) less than ``pp_wait`` s ago."""
        last = self._last_pp
        return last is not None and last[0] == tid and t - last[1] < self.params.pp_wait

    def beam(self, t: float, bearing: float | None, category: int, unseen: bool = False) -> float | None:
        """Where the recogniser listens: the partner (top-down), the selected person while they speak
        facing the robot (``category`` 3) or speak with their face out of the camera's image (``unseen``:
        the camera cannot tell whether they face the robot, so the voice's direction is the cue), else
        the loudest sound direction that no confirmed track explains if one was heard lately, else nowhere.

        ``bearing`` is the partner's / selected person's bearing (None: no such track). A person the
        robot tracks who talks without facing it is not addressing it (gated, docs/semantics.md §3); a sound
        from where nobody is seen is unexplained, so the robot listens, and the supervisor rejects a
        greeting that no person backs (the radio, docs/semantics.md §2) instead of never hearing it.
        """
        if self._searching() and bearing is not None:
            return bearing  # a seen caller speaking (:meth:`_find_caller`)
        if self.fsm.top_down and not self._searching():
            if self.fsm.state == "Follow" and self._follow_searching is not None:
                # the follower searches for her (she is out of its sight: a fast leader gone on through a door
                # or a passage, her track coasting where it was guessed or handed to someone behind): a voice
                # from elsewhere is most likely hers, saying "here, stop" where she stopped (fresh7
                # corr_fast_walker_goto, fresh8 terr_fast_walker_passage: the beam stayed on the guess and her
                # stops were never heard). The dialog takes only a stop from off her track's bearing then
                # (:meth:`robot.dialog.module.Dialog._stop_while_searching`)
                aim = self._searched_voice(t, bearing)
                if aim is not None:
                    return aim
            if bearing is not None and self.partner is not None and self._other_talks(t):
                v = self._voices
                if self.fsm.state == "Follow" and self._stood(t) and v is not None and v[3] is not None:
                    # the follower has stood by the track it follows a while and that track is silent,
                    # while someone else talks: her walk is over and she says "stop", but the track may
                    # be someone she walked past (a guest standing in the room she led it into): her
                    # stop must be heard. The recogniser listens to that voice; the dialog takes only a
                    # stop from it (not hers by direction: :meth:`robot.dialog.module.Dialog._her_voice`)
                    return v[3]
                return None  # a bystander next to the partner talks, the partner does not: not for the robot
            if bearing is None and self.fsm.state == "Follow" and self._dominant is not None \
                    and t - self._dominant[0] <= self.params.dominant_max_age:
                # she leads out of its sight (a fast leader who turned through a door and stopped there,
                # fresh7 corr_fast_walker_goto: "Here, stop" three times, never heard): a voice nobody seen
                # explains may be hers, and her stop must be heard
                return self._dominant[1]
            return bearing
        if bearing is not None and category == 3:
            return bearing
        if bearing is not None and category == 2 and unseen:
            # someone speaking beside or behind the robot, the camera not (yet) on her face: she may well
            # face it (a greeting from the side, perceive/greet_side_kitchen: the face was seen only
            # after "Hi BIRON" had ended, unheard). Her voice is listened to while the robot turns to
            # her; whether it was for the robot is decided as before (a potential partner needs her
            # face; words nobody faces the robot for are rejected by the dialog's supervisor).
            return bearing
        vt = self._voice_turn
        if vt is not None and t <= vt[0]:
            # turning to a voice nobody seen explains (:meth:`_voice_heading`): the beam stays on the
            # direction turned to, moved against the robot's own turn, so the utterance under way stays
            # in it (a reading a frame old lags a robot turning at 45 degrees a second by more than the beam)
            return math.remainder(vt[1] - self._pose_at(t)[2], 2 * math.pi)
        if self._dominant is not None and t - self._dominant[0] <= self.params.dominant_max_age:
            self._heard_voice_at = t
            return self._dominant[1]
        if bearing is not None and category == 2 and t - self._heard_voice_at <= self.params.dominant_max_age:
            # the voice it was listening to is now explained by the person it attends to, who speaks
            # still turned away (stepping out from behind a sideboard, turning to the robot as he ends):
            # the utterance under way is followed to its end, not cut off (wlan_reorder seed 8)
            self._heard_voice_at = t
            return bearing
        return None

    def _searched_voice(self, t: float, bearing: float | None) -> float | None:
        """The follower searches for her: the loudest voice lately heard that no person seen explains, else
        the loudest voice off the followed track's bearing while that track is silent (the track may be a
        guess where she is not, or someone else: then she is the person seen speaking); None: nobody else speaks."""
        if self._dominant is not None and t - self._dominant[0] <= self.params.dominant_max_age:
            return self._dominant[1]
        v = self._voices
        if bearing is not None and self.partner is not None and self._other_talks(t) and v is not None:
            return v[3]
        return None

    def _other_talks(self, t: float) -> bool:
        """Someone else speaks while the partner is silent: in the last sound frame (at most
        ``dominant_max_age`` old) a direction further than ``partner_voice_tolerance`` off the
        partner's bearing and none within it (a bystander beside her, a person the laser does not see)."""
        v = self._voices
        return v is not None and t - v[0] <= self.params.dominant_max_age and v[2] and not v[1]

    def _ptu(self, t: float, pan: float, tilt: float) -> None:
        p = self.params
        last = self._ptu_sent
        if last is None or abs(last[0] - pan) > p.ptu_deadband or abs(last[1] - tilt) > p.ptu_deadband or t - self._ptu_at >= p.ptu_refresh:
            self.bus.publish(PTU_CMD, etree.Element("ptu", pan=_deg(pan), tilt=_deg(tilt)), transfer=True)
            self._ptu_sent, self._ptu_at = (pan, tilt), t

    def _bodies_near(self, points: list[tuple[float, float]]) -> np.ndarray:
        """(K, 2) the robot-frame ``points`` within ``turn_reach`` m: the bodies a turn must keep clear of."""
        reach = self.params.turn_reach
        near = [(x, y) for x, y in points if x * x + y * y <= reach * reach]
        return np.array(near, dtype=float) if near else np.zeros((0, 2))

    def _turn(self, b: float) -> float:
        """Turn on the spot toward bearing ``b`` (rad, robot frame), at the turn law's rate (slower toward
        a bearing the laser does not see), if the footprint's sweep keeps clear of everyone near
        (:func:`robot.footprint.turn_clear`); else stand, and try again on the next scan. The camera
        still looks at the person meanwhile (the pan-tilt unit)."""
        echoes = self._echoes()
        bodies = np.vstack((self._near, echo_bodies(echoes, self._explained(echoes), self.legs.offset)))
        w = self.turn_rate(b, bodies)
        if w and not self._flat_clear(w, echoes):
            w = 0.0
        if w and not self._blind_clear(w):
            v, wr = self._make_room(echoes, bodies, w)
            if v:
                return self._base(wr, v=v)
        return self._base(w)

    def _make_room(self, echoes: np.ndarray, bodies: np.ndarray, w: float) -> tuple[float, float]:
        """The command (m/s, rad/s) to creep ahead so that the turn at ``w`` the sonar refuses can be made (see
        ``AttentionParams.room_speed``): turning on as it creeps where that is clear, else straight ahead; (0, 0)
        when the allowance of ``room_max`` m is used up or no creep is clear."""
        p, odom = self.params, self._odom_pose()
        if odom is None:
            return 0.0, 0.0
        room = self._room
        if room is None or self.now - room[2] > p.room_reset:
            room = (odom[0], odom[1], self.now)
        self._room = (room[0], room[1], self.now)
        if math.hypot(odom[0] - room[0], odom[1] - room[1]) >= p.room_max:
            return 0.0, 0.0
        v = p.room_speed
        ahead = echoes[echoes[:, 0] >= 0.0] if len(echoes) else echoes
        for cw in (w, 0.0):
            if (points_sweep_clear(v, cw, ahead, duration=p.turn_check, gap=p.room_gap)
                    and people_sweep_clear(v, cw, bodies, duration=p.turn_check)
                    and self._flat_clear(cw, echoes, v=v) and self._blind_clear(cw, v=v)):
                return v, cw
        return 0.0, 0.0

    def _echoes(self) -> np.ndarray:
        """(N, 2) this scan's echoes within ``turn_reach`` m of the laser, robot frame."""
        ranges, bearings = self._ranges, self._bearings
        if ranges is None or bearings is None or len(ranges) != len(bearings):
            return np.zeros((0, 2))
        near = (ranges > 0.02) & (ranges < self.params.turn_reach)
        r, a = ranges[near], bearings[near]
        return np.column_stack((self.legs.offset + r * np.cos(a), r * np.sin(a)))

    def _explained(self, echoes: np.ndarray) -> np.ndarray:
        """Which ``echoes`` the floor plan explains (within ``plan_explains`` m of a wall or a piece of
        furniture, the robot's map pose as the tracker's filter uses it); none without a plan."""
        if self._plan_near is None or self._scan_pose is None or not len(echoes):
            return np.zeros(len(echoes), dtype=bool)
        mx, my, mth = self._scan_pose
        c, s = math.cos(mth), math.sin(mth)
        return np.array(self._plan_near.inside_points([(mx + c * x - s * y, my + s * x + c * y) for x, y in echoes.tolist()]), dtype=bool)

    def _blind_clear(self, w: float, v: float = 0.0) -> bool:
        """Whether turning at ``w`` keeps the corners off what the sonar hears beside and behind that the floor
        plan does not explain (:func:`robot.blindside.blind_clear`): the last check of every turn it sends."""
        arcs = self.sonar.arcs(self._odom_pose(), self.now)
        if not arcs:
            return True
        # a reading near the legs the laser sees of a tracked person is that person (robot.blindside.seen_legs, the
        # rule the follower keeps too): a flank transducer hears the partner standing beside the robot's front, and
        # its arc runs on round the flank where the turn toward her swings a corner; her body is kept clear by the
        # turn's own sweep of the bodies near (turn_rate, echo_bodies): face20, the turn to her stopped at 65 deg
        legs = seen_legs(self._echoes(), self._people)
        by_legs = explained_by_points(legs)
        pts = blind_points(arcs, lambda arc: bool(self._explained(arc).any()) or by_legs(arc))
        return blind_clear(v, w, pts, duration=self.params.turn_check)

    def turn_rate(self, b: float, bodies: np.ndarray) -> float:
        """:func:`turn_rate` with this module's parameters."""
        return turn_rate(b, bodies, self.params)

    def _flat_clear(self, w: float, echoes: np.ndarray, v: float = 0.0) -> bool:
        """Whether turning at ``w`` for ``turn_check`` s keeps the corners off this scan's echoes (``echo_gap``,
        or no nearer than now) and off the floor plan's walls and furniture (no outline point comes to lie
        inside one that did not already: the laser does not look behind, the plan does; hall_goto_doors
        seed 7, a turn to a voice in the hall swung a rear corner into the wall)."""
        p = self.params
        if not points_sweep_clear(v, w, echoes, duration=p.turn_check, gap=p.echo_gap):
            return False
        if self.furniture is not None and self._scan_pose is not None:
            mx, my, mth = self._scan_pose
            x, y, th = sweep_poses(v, w, p.turn_check)
            ring = outline()
            inside = []
            for px, py, pth in zip(x.tolist(), y.tolist(), th.tolist()):
                c, s = math.cos(mth + pth), math.sin(mth + pth)
                ox, oy = mx + math.cos(mth) * px - math.sin(mth) * py, my + math.sin(mth) * px + math.cos(mth) * py
                inside.append(sum(self.furniture.inside_points([(ox + c * u - s * v, oy + s * u + c * v) for u, v in ring.tolist()])))
            if max(inside) > inside[0]:
                return False
        return True

    def _odom_pose(self) -> tuple[float, float, float] | None:
        o = self._odom
        return None if o is None else (o[1], o[2], o[3])

    def _base(self, w: float, v: float = 0.0) -> float:
        """Send the turn rate ``w`` (rad/s; or, making room, the creep ``v`` m/s straight ahead) after the bumpers'
        and the blind side's checks; the rate sent."""
        if v:
            v, w = self.bumpers.command(v, w, self.now)
            if (v or w) and not self._blind_clear(w, v=v):
                v = w = 0.0
            self.bus.publish(BASE_CMD, etree.Element("velocity", v=f"{v:.4f}", w=f"{w:.4f}"), transfer=True)
            return w
        if w:
            w = self.bumpers.command(0.0, w, self.now)[1]
        if w and not self._blind_clear(w):
            w = 0.0
        self.bus.publish(BASE_CMD, etree.Element("velocity", v="0", w=f"{w:.4f}"), transfer=True)
        return w

    def _steer(self, bearing: float | None) -> None:
        last = self._steer_sent
        if bearing is None:
            if last is not None:
                self.bus.publish(STEER, etree.Element("steer", off="true"), transfer=True)
                self._steer_sent = None
            return
        if not isinstance(last, float) or abs(last - bearing) > self.params.steer_deadband:
            b = math.remainder(bearing, 2 * math.pi)
            self.bus.publish(STEER, etree.Element("steer", bearing=_deg(b)), transfer=True)
            self._steer_sent = bearing

    # ------------------------------------------------------------ outputs
    def _publish_tracks(self, t: float, cats: dict[int, int], bearing: list[float], dist: list[float]) -> None:
        # A typed record (records.TracksRecord): its XML is written only when somebody reads it.
        facing = self.facing
        rows = []
        degrees = math.degrees
        for i, tk in enumerate(self.tracks.tracks):
            tid = tk.id
            x0, x1, x2, x3 = tk.x
            P = tk.P
            cat = cats.get(tid, 0)
            # a dormant track (its person hidden longer than the death timeout) is kept to be found again
            # under its id, but is not reported as a person seen (confirmed="false")
            rows.append(_row((f"t{tid}", x0, x1, x2, x3, P[0], P[1], P[4], degrees(bearing[i]), dist[i],
                              tk.confirmed and not tk.dormant, cat >= 2, bool(cat) and facing.on(tid))))
        self.bus.publish(TRACKS, TracksRecord(t, tuple(rows)))

    def _publish_partner(self, t: float, row: int, bearing: list[float], dist: list[float], visible: bool) -> None:
        tk = self.tracks.tracks[row]
        x = tk.x
        # facing: her frontal face is anchored to her track now (the camera detects frontal faces
        # only); company: other confirmed people within group_radius of her (a group she may be
        # talking with). The dialog decides from both whether an utterance is addressed to it.
        r2 = self.params.group_radius ** 2
        company = sum(1 for o in self.tracks.tracks if o.confirmed and not o.dormant and o.id != tk.id
                      and (o.x[0] - x[0]) ** 2 + (o.x[1] - x[1]) ** 2 <= r2)
        # others: every other confirmed person it tracks (the dialog's voice-level rule takes a quieter voice
        # from her direction as another's only when someone else is there: review18 F1). Not only those in
        # line behind her: her own legs hide a person standing right behind her from the laser
        # (flow/chat18_remarks_behind_partner: the guest behind her is never tracked, his companion is)
        others = sum(1 for o in self.tracks.tracks if o.confirmed and not o.dormant and o.id != tk.id)
        self.bus.publish(PARTNER, _own_document(  # as text: see _publish_tracks
            f'<partner id="t{tk.id}" bearing="{math.degrees(bearing[row]):.3f}" distance="{dist[row]:.3f}"'
            f' x="{x[0]:.3f}" y="{x[1]:.3f}" vx="{x[2]:.3f}" vy="{x[3]:.3f}" visible="{"true" if visible else "false"}"'
            f' lost_for="{max(0.0, t - tk.last_update):.3f}" facing="{self._facing(t, tk.id, self._walks_away(t, x))}"'
            f' company="{company}" others="{others}"{AWAY if self.turned_away else ""}/>'
        ), transfer=True)

    def _publish_unseen_partner(self, t: float, tid: int) -> None:
        """The partner message for identity ``tid`` when no track holds it: where she was last seen (``_partner_last``,
        odom), unseen since then."""
        last = self._partner_last
        if last is None or "bus" not in vars(self):
            return
        seen, x, y, vx, vy = last[:5]
        px, py, th = self._pose_at(t)
        dx, dy = x - px, y - py
        b = math.atan2(dy, dx) - th
        b = (b + math.pi) % (2 * math.pi) - math.pi
        self.bus.publish(PARTNER, _own_document(
            f'<partner id="t{tid}" bearing="{math.degrees(b):.3f}" distance="{math.hypot(dx, dy):.3f}"'
            f' x="{x:.3f}" y="{y:.3f}" vx="{vx:.3f}" vy="{vy:.3f}" visible="false" lost_for="{max(0.0, t - seen):.3f}"'
            f' facing="unknown" company="0" others="{sum(1 for o in self.tracks.tracks if o.confirmed and not o.dormant)}"/>'
        ), transfer=True)

    def _walks_away(self, t: float, x: Any) -> bool:
        """Does the track (odom state ``x``: x, y, vx, vy) walk away from the robot at ``leave_speed``
        or faster? A person walking faces where she goes: her face is turned from the robot."""
        rx, ry, _ = self._pose_at(t)
        dx, dy = x[0] - rx, x[1] - ry
        d = math.hypot(dx, dy)
        return d > 1e-6 and (x[2] * dx + x[3] * dy) / d >= self.params.leave_speed

    def _facing(self, t: float, tid: int, walks_away: bool = False) -> str:
        """Does the partner face the robot? ``true``: her frontal face is anchored to her track;
        ``false``: the camera's latest frame had her face in the image (within ``face_view_fresh``)
        and the detector, which sees frontal faces only, found none there, or she walks away from
        the robot (``walks_away``): she looks away; ``unknown``: the camera looks elsewhere (at her
        hands, at an object), so it cannot tell."""
        if self.facing.on(tid):
            return "true"
        if walks_away:
            return "false"
        pf = self._partner_face
        if pf is not None and pf[1] == tid and pf[2] and t - pf[0] <= self.params.face_view_fresh:
            return "false"
        return "unknown"

    def _publish_state(self, t: float, *, force: bool = False) -> None:
        sel = self.partner if self.fsm.top_down else self.selector.selected
        key = (self.fsm.state, sel, self.partner)
        if force or key != self._state_sent or t - self._state_at >= self.params.state_refresh:
            msg = etree.Element(
                "attention", state=key[0], selected=f"t{sel}" if sel is not None else "", partner=f"t{self.partner}" if self.partner is not None else "", time=f"{t:.6f}",
            )
            if self._paused_at is not None:
                msg.set("paused", f"{self._paused_at:.6f}")  # Follow paused by a wait (the follower's rule)
            self.bus.publish(ATTENTION_STATE, msg, transfer=True)
            self._state_sent, self._state_at = key, t
