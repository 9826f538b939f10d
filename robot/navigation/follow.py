"""The follower: drives after the communication partner at a social distance while the attention says Follow.

Inputs (docs/robot-contract.md): ``/robot/attention/state`` (only ``Follow``
lets it drive; its ``partner`` attribute is the track to follow),
``/robot/attention/partner`` (that track's bearing, distance, position and
velocity in ``odom``; messages about any other track are ignored, so a
person crossing between the robot and the partner never becomes the
followed one), ``/robot/laser/scan`` (obstacles) and ``/robot/odometry``
(the robot's own pose in ``odom`` and speed).

Control, every ``1/rate`` seconds:

* The partner's position is predicted to now from the last track message
  (constant velocity), and its path is kept as a *trail* of odom-frame points
  (every 15 cm). The robot steers along the trail, not straight at the partner,
  so it goes round furniture and through door frames where the partner went.
* Speed: ``v = v_partner,radial + gain (d - distance)``, clipped to the base's
  limits: it closes in when the partner is beyond 1.2 m and waits inside the
  1.0-1.5 m band; below 1.0 m (a partner who turns back) it backs off
  slowly, turning to face them, so it never approaches closer than 0.8 m;
  only while she is ahead (:func:`back_off_away`): beside or behind it
  (walking past its side) it stands and turns to her.
  The laser does not see behind: it backs off only where its centre has
  been driving forwards (the last ``BREADCRUMBS`` odometry positions, every
  5 cm) or where its footprint, 10 cm further back, lies on ground the laser
  saw free while following (:class:`~robot.navigation.seen.SeenGround`, a scan
  every 0.5 s); elsewhere it stands (against a wall it never saw, it waits
  instead of backing into it).
* Obstacles: the dynamic window (:mod:`robot.navigation.local`) on the laser
  echoes, without the echoes of the partner's own legs.
* Too fast: while the commanded speed is at the limit for ``too_fast_time``, the
  distance is beyond ``too_fast_distance`` and still growing, and her tracked speed
  (averaged over that time) exceeds the robot's top speed (``max_speed``, a scenario
  value) by the factor :data:`TOO_FAST_RATIO`, the ES gets ``partner_too_fast`` with ``@distance``
  (at most every ``warn_every`` s). A partner walking at its top speed is not told to slow down.
* Catching up (issue 26 item 10): when following ends with the partner still tracked
  ("stop", the attention back in ``Interaction`` with the same partner) and she stands
  further than ``approach_to`` (the band's far end, 1.5 m) or out of the robot's line of
  sight on the floor plan (in the next room), it goes on driving the same way (the floor
  plan's path through the door, the dynamic window, everyone's space) for at most
  ``approach_time`` s until she is that close, it stands in her room (the floor plan's rooms;
  or it is within the band's near end of her) and it does not stand in a door frame or a
  passage (its centre ``APPROACH_ROOM`` m from the walls; closer to her than the band's near
  end it stops anyway), then turns to face her and stops, so it stands at a comfortable
  interaction distance facing her before her next request is handled (a robot lagging at a
  door frame would teach from the other room). Once come up to her it drives at her no more (it
  gives way if it must, then faces her), with at least :data:`ARRIVED_TIME` s for that; giving way
  there it keeps her within :data:`APPROACH_VIEW`, ahead of the laser's line. Its status says ``approaching`` meanwhile;
  the attention leaves turning the base to it, and the dialog holds her requests, until
  then. No too-fast warnings while approaching. She stands, so her last position holds while
  she is unseen (behind a table's or a chair's legs, the door frame) as long as following would
  search for her (:meth:`Follower.search_for`: ``search_time`` s, longer when she was last seen far ahead).
  Any other state (a go-to) ends it.
* Paused (a wait said while she leads: the attention state's ``paused``): only following on is
  paused. It comes up to her by the same rule as the catch-up (status ``paused``), then stands
  turning to face her until she walks on (:data:`PAUSE_WALK_ON`), and follows again.
* Searching: not seen for ``lost_after`` s (a door frame, someone crossing between, a partner
  who walked past the robot's side, out of the laser's half-circle) it does not stop: it drives,
  at most ``search_speed``, to where she was heading (her last track message carried on with its
  velocity for at most :data:`SEARCH_HORIZON` s, along the floor plan's way through doors), comes no
  closer than ``search_reach`` to that point, once the floor plan says it is in sight (not behind
  a wall), and turns to face it, so it sees round the corner or past the person in between.
  Status ``searching``. Her track gone quiet longer than that (it yielded to people crossing and fell
  behind, she went on through a door), the point walks on at her pace when last seen (a coasting track's
  velocity decays) up to :data:`SEARCH_WALK_ON` s,
  never through a wall of the floor plan, so it looks into the room she went on into. A point the
  latest scan looks at and sees through (:func:`robot.navigation.local.looked_empty`) is not where she
  is: the search looks where her last measured velocity carried her on from where she was last seen
  (beside or behind the robot when she walked past its side: it turns there), and such a point, or a
  coasting track the scan sees through, refuses no turn (:meth:`Follower._bodies`). Searching, her guessed
  point is a body only where the laser looks and has an echo near it; looking for her beside or behind,
  where only the sonar hears, it looks at the unexplained echo nearest to that point: it stands and turns
  there (the other way round when the sonar refuses the short way), so the laser and the camera find
  her again (:meth:`Follower._heard_there`, :meth:`Follower._search_turn`).
* Yielding is not searching: time in which someone other than her is near it
  (:func:`robot.partner_search.yielding`, the attention's rule too) does not count as time unseen.
* Lost: not seen for ``search_time`` s (6 s; longer when she was last seen beyond the band, by the
  time it takes to drive the gap at 0.4 m/s or its lower top speed, at most 15 s, or the time to drive the same gap
  at a top speed below 0.4 m/s: :mod:`robot.partner_search`):
  it stops (the attention's ``partner_lost``, by the same rule with its ``follow_lost_after`` = the
  same 6 s, makes the ES stop the player and the dialog ask). Should the attention still hold her
  (a camera sighting keeps her "seen" while her legs stay hidden), the status ``stopped`` it reads
  makes it declare the loss 2 s later (``AttentionParams.follow_stopped_after``): the robot never
  stands silent in Following.
* Inside the flat: it never drives its front out of the floor plan's rooms (the map's ``<room>``
  outlines), so after a partner who leaves through the exit door it stops in the door, inside;
  when following ends with it facing out of the flat (an opening, the outer wall beside it), it turns back toward the middle of
  its room, so the people in the flat can speak to it.
* Backing off (from a partner too close, or wedged) never reverses toward a person the attention
  tracks behind it (within the back-off's reach plus 0.45 m: ``people.behind_clear``).
* Wedged (a jamb at a front corner in a 0.9 m door): when it should drive (a crawl slower than
  :data:`CRAWL` is no driving) but has neither moved
  :data:`STUCK_MOVE` nor turned :data:`STUCK_TURN` net for :data:`STUCK_TIME` s, it backs for
  :data:`UNSTICK_TIME` s over ground it drove or saw free. Close to the floor plan already, its own
  commands may keep their distance (:func:`sweep_allowed`: the sweep's start pose is not "closer").

``/robot/follow/status`` (``<follow distance speed at_limit state/>``) goes out
every control step while following. The follower drives only in Follow, and
sends one zero command when it stops driving.
"""

from __future__ import annotations

import asyncio
import math
from collections import deque
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from homesim.message import Message
from homesim.module import Module

from homesim.errors import BusError, HomesimError
from robot import floorplan
from robot.blindside import BLIND_X, LEGS_NEAR, SONAR_REACH, SonarEchoes, blind_clear, blind_points, explained_by_points, seen_legs
from robot.partner_search import Closing, follow_search_time, yielding
from robot.bumpers import BumperReflex, own_reflex
from robot.footprint import contact_speed_limit
from robot.contract import ATTENTION_STATE, BASE_CMD, BUMPERS, ES_EVENTS, FOLLOW_STATUS, ODOMETRY, PARTNER, POSE, SCAN, SONAR, TRACKS

from .config import Limits
from .grid import MapError, OccupancyGrid, parse_map
from .local import (BODY, SOCIAL_GAP, TURN_GAP, DWAParams, LatestScan, arcs, carrot, dwa, footprint_distance, heading_speed,
                    people_gaps, people_sweep_clear, social_speed_limit, sweep_clearance, turn_clear)
from .blind import follow_blind_limit, scan_corners
from .giveway import LATERAL, NARROW, axis_offset, back_out_spot, give_way_spot, passage_axis, reverse_command, way_distance
from .people import People, behind_clear, in_the_way, nearest
from .route import Route
from .seen import SeenGround, footprint_samples

#: m: following, people standing (slower than 0.2 m/s) this close to the robot's centre are kept clear
#: of as people (their space, the social speed limit), as walking ones are everywhere: someone
#: crossing who stopped in its way (held up by the robot) is still a person
STANDING_NEAR = 1.2
#: s: searching, where she was heading is her last message carried on with its velocity this long at most
SEARCH_HORIZON = 1.5
#: s: ... and, her track gone quiet longer than that (unseen through a door: the robot yielded to people
#: crossing and fell behind), she walks on: the point moves on along her velocity up to this long, but
#: never through a wall of the floor plan (issue 26 item 1, sq_cross_pair: the search stopped at the
#: spot 1.5 s past where she went out of view while she stood in the next room, in view from a step on)
SEARCH_WALK_ON = 5.0
#: rad: the search point walking on turns, where a wall stops its step, to a heading in steps of this:
#: she walks along the passage, round its bend (:meth:`Follower._walk_on`)
WALK_STEP = math.radians(22.5)
#: rad: ... of the headings never further than this off her heading when last seen (round a bend, not back the way
#: she came; her track's heading a little off the passage's, round the bend is more than 90 degrees off it)
WALK_BACK = math.radians(135)
#: m: a searched point nearer the floor plan's walls or furniture than this is no place a person stands
#: (:meth:`Follower._not_there`: a track coasting on into the passage's wall at its blind bend, bend23)
WALL_BODY = 0.15
#: quarter-second steps: the free run ahead looked along for each heading (:meth:`Follower._walk_turn`)
WALK_RUN = 8
#: m: ... a heading whose run goes this far free (or all :data:`WALK_RUN` steps) is a way on, and of the ways on
#: she takes the least turn from where she was walking, not the longest run: round the bend of a 1.0 m L passage
#: the way back down its first leg ran 2 m free where the way on up its other leg, beside its wall, ran 1.5 m
#: (search25); with no such way on, the longest run
WALK_AHEAD = 1.0
#: s: ... and where that point is seen empty too (:meth:`Follower._not_there`), on up to this long (the longest
#: follow search, :func:`robot.partner_search.follow_search_time`'s cap)
SEARCH_WALK_FAR = 15.0
#: m/s: searching, a partner last seen slower than this was standing: her velocity is no heading to look along
WALKING = 0.3
#: rad: searching, a point further off the heading than this is beside or behind: refused the short way
#: round (the sonar hears her there), the turn toward it goes the other way (:meth:`Follower._search_turn`)
SEARCH_BACK = math.radians(90)
#: m: searching, her guessed point where the laser looks is a body only with an echo this near (legs, a body's ring)
GUESS_ECHO = 0.5
#: s: searching, someone the sonar heard beside or behind is looked for there this long after the echo has gone
#: (she walked on out of its reach: the turn toward where she was heard still brings the laser to her way)
HEARD_KEEP = 2.0
#: m, m/s, m: ... and only an echo she can have walked to from where a scan last saw her: this near, plus her
#: walk (this fast) for the time since, at most this far
HEARD_NEAR = 0.6
HEARD_WALK = 0.8
HEARD_REACH = 2.0
#: s and m/s: wedged this long (it should drive, the dynamic window finds nothing), it backs this slowly
STUCK_TIME = 1.0
UNSTICK_SPEED = 0.1
#: m, rad: within STUCK_TIME it moved less than this far and turned less than this much net: no progress
#: (the dynamic window turning a little to and fro with a jamb at its front corner is as stuck as standing)
STUCK_MOVE = 0.05
STUCK_TURN = math.radians(15)
#: s: once stuck, it backs this long (10 cm at UNSTICK_SPEED) unless a way forward opens
UNSTICK_TIME = 1.0
#: m/s: a forward command slower than this would not take it :data:`STUCK_MOVE` in :data:`STUCK_TIME` s: a crawl the
#: dynamic window alternates with standing (0.025 m/s, 0, 0.025, turning to and fro) at a jamb is no drive that
#: makes progress, and the wedge rule still counts (fresh10 hall_child_remotes seed 9: 13 s so in a 0.95 m door)
CRAWL = STUCK_MOVE / STUCK_TIME
#: m: paused by a wait said while she leads, she has walked on (following again) once she is this far from
#: where she stood when the pause began (a step to a shelf beside her is no walking on; her walker's pace,
#: 0.3 m/s, crosses it in under 2 s)
PAUSE_WALK_ON = 0.5
#: m/s: paused, out of view for a moment while walking at least this fast: she walked on (round a corner)
PAUSE_WALKING = 0.2
#: rad: the partner too close, it backs off only while she is within this of straight ahead (her estimate
#: lags a partner walking past its side: ring_long_tour seed 3 backed to 0.03 m of her as she passed behind)
BACK_OFF_BEARING = math.radians(60)
SCHEMA = Path(__file__).resolve().parent.parent / "schemas" / "navigation" / "follow-status.xsd"
#: how many of the robot's own past positions (odometry, every CRUMB m) the back-off may retrace
BREADCRUMBS = 200
CRUMB = 0.05
#: m: backing off, the robot's centre a step back must stay this close to a past position of its own
CRUMB_NEAR = 0.15
#: m: the base's footprint (length, width) and the margin kept backing over seen ground
FOOTPRINT = (0.51, 0.43)
BACK_MARGIN = 0.05
#: m: beyond its front edge the robot keeps this much of the flat (plus what it covers in
#: :data:`INSIDE_TIME` s): it never drives out through an exit door after someone who left.
INSIDE_AHEAD = 0.05
INSIDE_TIME = 0.6
#: m: looking this far past its front edge through an opening and out of the flat, it faces out of an exit door.
FACING_OUT = 0.8
#: m: how far a back-off may take the robot before it checks again (the people behind are kept clear of it).
BACK_REACH = 0.3
#: s and m: a waiting command's sweep is checked this far ahead, and must keep this far from the floor plan's obstacles
SWEEP_TIME = 0.5
SWEEP_MARGIN = 0.05
#: poses along a waiting command's sweep after the start that are checked (as many as sweep_clearance's)
SWEEP_STEPS = 5
#: s: the first instants of a sweep, checked as well when the footprint is closer than the margin already:
#: a command whose first motion swings an edge nearer and then away (backing while turning, 2 mm from a
#: wall's end) dips between the evenly spaced poses (tests/test_nav_wedged's dev-profile counterexample)
SWEEP_START = (0.001, 0.004, 0.016, 0.05)
#: she is too fast for the robot when her tracked speed exceeds its top speed this many times (the track's speed
#: runs 20 % over hers for a second after she is found again: 0.6 m/s for a partner at 0.5 m/s)
TOO_FAST_RATIO = 1.2
#: m: the dynamic window's goal along the route's direction at least this far out
WAY_GOAL = 1.0
#: m: the approach does not end where the robot's centre is closer than this to a wall (a door frame, a passage)
APPROACH_ROOM = 0.5
#: m: backing off must leave the centre this far from the floor plan's obstacles (the footprint's corners reach 0.34 m)
TURN_ROOM = 0.40
#: m: a stalled give-way's step back (Follower._step_back) takes the footprint at least this much further from her
STEP_BACK_GAIN = 0.01
#: m: with the partner inside the near band and its centre closer than this to the floor plan's walls (a door
#: frame, a passage), the robot gives way (:mod:`robot.navigation.giveway`)
GIVE_WAY_ROOM = 0.45
#: s, m/s: a give-way spot is driven to for at most this long, this slowly
GIVE_WAY_TIME = 8.0
GIVE_WAY_SPEED = 0.35
#: m: she walks at the robot when her line of walking passes its centre closer than this (half its
#: width, her body and a margin); a partner passing beside it is not walking at it
WALKS_AT = 0.55
#: s: the forward give-way's command zero this long (every step swings a corner into her), it backs out instead
GIVE_WAY_STALL = 2.0
#: s, m: a back-out search that found no way is not repeated for this long while neither the robot nor she
#: has moved this far (the search plans over the whole grid: a stuck follower repeated it every stall)
BACKOUT_RETRY, BACKOUT_MOVED = 10.0, 0.2
#: s: backing out of her way, every reverse step refused this long (a corner at a jamb of the door it stands in,
#: turned toward her), it turns on the spot or creeps back to get clear of the frame (:meth:`Follower._free_turn`)
BACKOUT_ALIGN = 1.0
#: m: ... a step of that kind must leave the footprint at least this much further from the floor plan
BACKOUT_GAIN = 0.002
#: s: when there is no give-way spot, it looks again after this long (the search plans on the grid)
GIVE_WAY_RETRY = 1.0
#: m/s: it gives way to a partner slower than this (held up in front of it), never into a walking one
GIVE_WAY_STILL = 0.2
#: s: following, a partner standing that close this long is held up by the robot, wherever it stands
GIVE_WAY_HELD = 1.5
#: m: backing out of her way into a corridor, where it came from is its own position this far back (see _came_from)
CAME_FROM = 1.5
#: m: following, a partner walking toward its way out (the door the robot came in by) within this distance, with
#: the robot standing on that way, is made way for before she reaches it (Follower._leaving)
LEAVE_NEAR = 2.5
#: rad: ... her walking direction at most this far off the direction from her to that way out
LEAVE_HEADING = math.radians(45)
#: making way so (Follower._leaving) is OFF by default: give24 built it off because it lost her in library goto_blocked
#: seed 2 as she passed close beside it once it had stepped aside; give24b keeps her bearing a moment ahead within
#: LEAVE_VIEW while it steps aside (Follower._bearing_ahead), which mends that seed (the library then passes: goto and
#: goto_blocked change, 10/10 each), but a fast partner passing within 0.6 m of its centre still leaves its view (her body
#: refuses the turn to her) and is lost: tests/scenarios/follow/give24_box_room_wide_hall.xml seeds 3, 5 (seed 5 passes
#: with it off), so it stays off until the search after such a pass looks where she walks (reports/give24b.md); switched on
#: in session 14's merge it also came within 0.68 m of a partner turning back toward the door behind it (scenarios/
#: follow_turn_back.xml, tests/test_nav_follow.py: never nearer than 0.8 m), where backing off had kept its distance
MAKE_WAY_LEAVING = False
#: rad: making way so, her bearing a moment ahead (her walk past its side, its own turn) is kept within this
LEAVE_VIEW = math.radians(60)
#: rad: giving way, the partner is kept within this bearing (turned to when further off)
GIVE_WAY_BEARING = math.radians(80)
#: rad: standing in a door frame or a passage (its centre within ``NARROW`` of the floor plan) with her within the
#: near band, its turns (the wait's turn to face her, the give-way's turn to keep her in view, the back-out's steering)
#: keep its heading within this of the passage's axis (:func:`~robot.navigation.giveway.passage_axis`), or turn it
#: back toward it: turned 43 degrees off a 0.9 m door's axis to face her, it stood wedged in the door mouth, every
#: back-out step refused (the jamb behind, her in front), her only way out blocked for the rest of the run
#: (review24 F0: tests/scenarios/follow/way23_box_room_back_out.xml seeds 2 and 9). She stays in view at 20 degrees
AXIS_TURN = math.radians(20)
#: m, s: following, when every give-way and back-out command has stayed zero (``GIVE_WAY_STALL`` s: a step back
#: first, :meth:`Follower._step_back`) for IN_WAY_ASK s with her within IN_WAY_NEAR and the robot in a door frame or a
#: passage, it asks her to step back a little (ES event ``in_her_way``), at most every IN_WAY_EVERY s
IN_WAY_NEAR, IN_WAY_ASK, IN_WAY_EVERY = 0.8, 4.0, 10.0
#: m/s: a give-way step slower than this turns on the spot (held to :data:`AXIS_TURN`); a faster one drives out
AXIS_CREEP = 0.05
#: rad: the catch-up's end faces her when she is within this bearing
FACED = math.radians(8)
#: m: laser echoes this close to the partner's track are her legs (the rule shared with person attention:
#: :func:`robot.blindside.seen_legs`)
HER_LEGS = LEGS_NEAR
#: s: the catch-up come up to her, it has at least this long to give way (``GIVE_WAY_TIME``) and face her: her
#: request is held until then (the approach's own time running out mid give-way let her request be handled with her
#: at its side)
ARRIVED_TIME = GIVE_WAY_TIME + 3.0
#: rad: giving way at the catch-up's end (she stands close, it is about to face her), she is kept within this
#: bearing instead: ahead of the laser's line (``BLIND_X``) with her legs, so the laser and camera see her and a turn
#: back to her is not refused by the sonar's blind-half check (her legs heard at 0.65 m beside it lie within
#: ``BLIND_GAP`` of a swung corner: face19's lflat_crossing_pair seed 7, left standing sideways to her). At the
#: band's near end less her legs' reach (1.0 - 0.16 m) the legs stay ahead of the line up to 76 degrees; 60 leaves room
#: for a step's turn and a coasting track
APPROACH_VIEW = math.radians(60)
#: Held up (issue 26, "excuse me"): it should drive after her, but someone standing (slower than
#: GIVE_WAY_STILL) in its way, ahead within HELD_UP_NEAR m and HELD_UP_LANE m of its line to the goal,
#: or beside it closer than HELD_UP_BESIDE m (not behind: a person's space that wedges it against a
#: door's jamb), keeps it stopped or crawling for HELD_UP_TIME s: the ES gets ``way_blocked`` (the
#: dialog asks to pass), at most every ``warn_every`` s; no "slow down" to her meanwhile
HELD_UP_NEAR = 1.6
HELD_UP_LANE = 0.6
HELD_UP_BESIDE = 1.2
HELD_UP_GAP = 1.0  # s: a blocker unseen this long no longer holds it up
#: s, m: someone seen standing near it is remembered this long where the laser still has an echo within
#: HELD_UP_ECHO m of the spot (standing still beside it, at the laser's edge, a person's track dies)
HELD_UP_MEMORY = 10.0
HELD_UP_ECHO = 0.3
HELD_UP_SPEED = 0.05
#: m/s and share: ... or crawls (slower than HELD_UP_CRAWL and than this share of the speed it should drive)
HELD_UP_CRAWL = 0.25
HELD_UP_SHARE = 0.5
HELD_UP_TIME = 2.0
#: m: a stander this close to the partner is her, never someone in the way (issue 26, fresh12 defect
#: 0: a second track on her legs, her own track's ghost, or a spot remembered standing where her legs
#: now echo made the robot say "Excuse me, may I pass" to her, alone in the flat, after "Stop")
HELD_UP_SELF = 0.8
#: m^2: only a track measured now holds it up (position variance cxx + cyy at most this; a measured
#: track has 0.002-0.013). A track coasting without echoes grows by 0.01-0.2 per 0.1 s: 25b2ff0
#: fresh3 open_two_cups_rooms seed 1, a short-lived track 0.55 m beside it, coasting 2 s after "Stop"
#: (variance 0.02 -> 1.9), made it ask its partner, alone in the flat, to let it pass
HELD_UP_SURE = 0.02


#: Making way (issue 26, fresh10 hall_crossing_kids: two children held back 0.5 m in front of it at the door
#: they ran to while it asked them three times to let it pass): someone other than the partner who walked at
#: the robot (toward its centre at MAKE_WAY_WALK m/s or faster, ahead within MAKE_WAY_SEEN m, in the last
#: MAKE_WAY_MEMORY s) and then stands (slower than GIVE_WAY_STILL) ahead within MAKE_WAY_NEAR m for
#: MAKE_WAY_HELD s is held back by it: the robot is in their way, so it backs straight out of it the way it
#: came (MAKE_WAY_SPEED, at most MAKE_WAY_TIME s) and does not ask them to let it pass
MAKE_WAY_WALK = 0.3
MAKE_WAY_SEEN = 2.0
MAKE_WAY_MEMORY = 10.0
MAKE_WAY_NEAR = 1.0
MAKE_WAY_HELD = 1.5
MAKE_WAY_SPEED = 0.2  # m/s backing
MAKE_WAY_TIME = 10.0  # s: one back-out at most this long

#: Asking to pass at most twice (review23 N7, fresh10 hall_crossing_kids with children who no longer stand inside
#: each other: a boy held back 0.55 m in front of it, his sister behind him, and it said "Excuse me, may I pass,
#: please?" up to 31 times in 150 s inside his personal space, its partner's stop, place and good-bye unheard under
#: it): for one blockage (whoever holds it up standing within BLOCK_SAME m of where the last blocker stood, seen again
#: within BLOCK_FORGET s) it asks at most ASK_MAX times; still held up when the next ask would be due, it makes room
#: instead: it backs along its own trail (ground it drove over; :meth:`Follower._make_room`) at MAKE_WAY_SPEED, each
#: step leaving every person's body (the partner's too) no nearer than it is (:func:`backs_away`), until everyone
#: standing ahead is ROOM_CLEAR m off (centre to centre: outside their personal space, within the yielding rule's
#: 1.2 m, so the wait is yielding, not search time) or it has backed ROOM_BACK m, and waits there, listening as ever,
#: until nobody has stood within BLOCK_SAME m of the blockage for ROOM_FREE s (the way has cleared): then it follows
#: on. Held up at the same place again, it asks no more: it makes room again
ASK_MAX = 2
BLOCK_SAME = 0.8
BLOCK_FORGET = 30.0
ROOM_CLEAR = 1.1
ROOM_BACK = 2.0
ROOM_CARROT = 0.4  # m: the point of its own trail it backs toward
ROOM_FREE = 1.0


def speed_law(d: float, v_radial: float, *, distance: float, band: tuple[float, float], minimum: float,
              gain: float, limits: Limits) -> float:
    """The forward speed that keeps a partner ``d`` metres away (moving away at ``v_radial``) at ``distance``.

    Inside the band it only matches the partner's own motion away (never
    closes in toward them); beyond it, it also closes the gap; below the
    band's lower end it backs off (faster below ``minimum``).
    """
    v = v_radial + gain * (d - distance)
    if d < band[0]:
        v = min(v, -0.5 * (band[0] - d) - (0.1 if d < minimum else 0.0))
    elif d <= band[1]:
        v = min(v, max(v_radial, 0.0))
    return float(min(max(v, -limits.max_reverse), limits.max_speed))


def back_off_away(rx: float, ry: float) -> bool:
    """Whether backing straight off moves the robot away from a partner at (``rx``, ``ry``) (robot frame)
    with a margin for her lagging estimate: she is within :data:`BACK_OFF_BEARING` of straight ahead."""
    return rx > 0.0 and abs(math.atan2(ry, rx)) <= BACK_OFF_BEARING


def sweep_allowed(v: float, w: float, mapped: np.ndarray, here: float | None = None) -> bool:
    """Whether the command (``v``, ``w``) held :data:`SWEEP_TIME` s keeps the footprint off the floor plan's
    obstacles (``mapped``, robot frame): :data:`SWEEP_MARGIN` all along, or, closer than that already
    (``here``, the footprint's distance now) but not touching, no pose after the start closer than now
    (its first instants included, :data:`SWEEP_START`: an edge that swings nearer first and then away).

    The sweep's first pose is the start, so "further off than now" measured on the whole sweep
    never held: wedged 2 cm from a table's corner, every command, backing away included, was refused
    and the robot stood there until its partner was lost (issue 26 item 2, hall_follow_doors)."""
    if not len(mapped):
        return True
    if sweep_clearance(v, w, mapped, SWEEP_TIME, steps=SWEEP_STEPS) >= SWEEP_MARGIN:
        return True
    if here is None:
        here = sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1)
    if here <= 0.0:
        return False  # touching already: only standing
    t = np.concatenate((SWEEP_START, np.linspace(SWEEP_TIME / SWEEP_STEPS, SWEEP_TIME, SWEEP_STEPS)))
    x, y, th = arcs(np.array([v]), np.array([w]), t)
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = mapped[None, :, 0] - x[0][:, None], mapped[None, :, 1] - y[0][:, None]
    return float(footprint_distance(c * dx + s * dy, -s * dx + c * dy).min()) >= here - 1e-9


def _crowds(v: float, bodies: np.ndarray) -> bool:
    """Whether driving at ``v`` (m/s, robot frame) goes toward a body (``bodies``: (P, 2) robot-frame centres)
    whose air gap to the footprint is below :data:`~robot.navigation.local.SOCIAL_GAP` now and whose centre
    lies ahead of the robot's centre in the direction of ``v`` (the social metric's "person it drives
    toward", ``social.min_person_clearance_moving_m``). Turning on the spot (``v`` = 0) crowds nobody here."""
    if v == 0.0 or not len(bodies):
        return False
    gaps = footprint_distance(bodies[:, 0], bodies[:, 1]) - BODY
    return bool(np.any((gaps < SOCIAL_GAP) & (bodies[:, 0] * v > 0.0)))


class Follower(Module):
    """Follows the partner track in Follow (see the module docstring)."""

    # (set in __init__; here too for the rules' unit tests, which build a follower without a bus)
    _aside_stall: tuple[float, float] | None = None
    _turn_way = 0.0
    _heard: tuple[float, float, float] | None = None
    #: the scan whose blind corners are in ``_corners`` (:meth:`_blind_corners`)
    _corners_of: Any = None
    _corners: np.ndarray = np.zeros((0, 2))
    _seen_v: tuple[float, float] = (0.0, 0.0)
    _walked_far: float | None = None  # when she was last seen, if the point she walked on to was seen empty since
    _closing: Closing | None = None  # (__init__ gives each follower its own)
    _backout_failed: tuple[float, float, float, float, float] | None = None
    _oncoming: dict[str, float] = {}  # (replaced by _make_way, never mutated)
    _held_back: dict[str, tuple[float, float]] = {}
    _making_way: tuple[float] | None = None
    _block: list[Any] | None = None  # (__init__ sets it; _held_up replaces it, _make_room updates it)
    _backout_refused: tuple[float, float] | None = None
    _in_way_since: float | None = None
    _in_way_last = -math.inf
    _in_way_asked = -math.inf
    _aside_moving: tuple[float, float, float, float, float] | None = None
    #: nothing pressed, and never told otherwise (__init__ gives each follower its own, heard on the bus)
    bumpers = own_reflex()

    def __init__(self, sim: Any, *, name: str = "follower", limits: Limits | None = None, rate: float = 10.0,
                 distance: float = 1.2, band: tuple[float, float] = (1.0, 1.5), minimum: float = 0.8,
                 gain: float = 0.8, lost_after: float = 1.0, too_fast_distance: float = 2.0,
                 too_fast_time: float = 1.0, warn_every: float = 5.0, params: DWAParams = DWAParams(),
                 approach_time: float = 15.0, approach_to: float = 1.5, search_time: float = 6.0,
                 search_speed: float = 0.4, search_reach: float = 0.6) -> None:
        super().__init__(sim, name)
        self.limits = limits or Limits()
        self.period = 1.0 / rate
        self.distance, self.band, self.minimum, self.gain = distance, band, minimum, gain
        self.lost_after = lost_after
        self.too_fast_distance, self.too_fast_time, self.warn_every = too_fast_distance, too_fast_time, warn_every
        self.params = params
        self.approach_time, self.approach_to = approach_time, approach_to
        self.search_time, self.search_speed, self.search_reach = search_time, search_speed, search_reach
        self.approach_until: float | None = None  # coming up to the partner after following, until then
        sim.bus.declare_channel(FOLLOW_STATUS, SCHEMA)
        self.following = False
        self.partner_id: str | None = None
        self.track: dict[str, float] | None = None  # the partner's last message (odom frame) and when
        self._seen_distance = 0.0  # how far she was when a scan last saw her (the search's length grows with it)
        self._seen_v = (0.0, 0.0)  # her velocity (odom) when a scan last saw her: where the search walks on
        self._seen_pos: tuple[float, float, float] | None = None  # where (odom) and when a scan last saw her
        self.odom: tuple[float, float, float] | None = None
        self.v = self.w = 0.0
        self.scan = LatestScan()
        self.seen = SeenGround()
        self._seen_at = -math.inf
        self.trail: deque[tuple[float, float]] = deque(maxlen=200)
        self.crumbs: deque[tuple[float, float]] = deque(maxlen=BREADCRUMBS)  # where the robot itself has been (odom)
        self.driving = False
        self._limit_since: float | None = None
        self._stuck_since: float | None = None  # since when it should drive but cannot (see _unstick)
        self._stuck_at: tuple[float, float, float] | None = None  # where it was then (odom)
        self._unstick_until = -math.inf  # backing out of a wedge until then
        self._history: deque[tuple[float, float, float]] = deque(maxlen=64)  # (t, d, her speed) at the limit
        self._warned_at = -math.inf
        self._held_since: float | None = None  # since when someone standing in its way has held it up
        self._held_last = -math.inf  # when it last saw them there
        self._standers: deque[tuple[float, float, float]] = deque(maxlen=32)  # (t, odom x, y) of people seen standing near
        self._excused_at = -math.inf  # when it last asked to pass (way_blocked)
        self._yielded = 0.0  # s since she was last seen spent yielding to someone near it (not search time)
        self._yield_t: float | None = None
        self._closing = Closing()  # s since she was last seen spent on the way to where it looks for her (not search time)
        self._turn_way = 0.0  # searching, the way round (+1 left, -1 right) it turns toward a point behind
        self._heard: tuple[float, float, float] | None = None  # searching, where (odom) and when the sonar last heard her
        self.bus.subscribe(ATTENTION_STATE, self._on_state)
        self.bus.subscribe(PARTNER, self._on_partner)
        self.bus.subscribe(SCAN, self._on_scan)
        self.bus.subscribe(ODOMETRY, self._on_odometry)
        self.people = People()  # everyone else the attention tracks, while following
        self._tracks_sub: Any = None
        self._sonar_sub: Any = None
        self.sonar = SonarEchoes()  # the sonar rings' echoes, while following (robot.blindside)
        self.bumpers = BumperReflex()  # the bumper rings (robot.bumpers): sent on a change and while one stays pressed
        self.bus.subscribe(BUMPERS, lambda m: self.bumpers.update(m.xml, self.now))
        self.route = Route()  # the way to the partner on the floor plan (through doors)
        self._aside: tuple[list[tuple[float, float]], float, bool] | None = None  # give-way path (odom), until when, reversing
        self._close_since: float | None = None  # following, since when she has stood close in front
        self._no_spot_until = -math.inf  # no give-way spot found: the next search not before then
        self._no_leave_spot_until = -math.inf  # ... nor one off her way out (making way before she reaches it)
        self._leave_aside = False  # the give-way under way makes way for her walking out (Follower._leaving)
        self._leave_way = (0.0, 0.0)  # ... to this point (odom)
        self._aside_stall: tuple[float, float] | None = None  # (since, last): the forward give-way's command zero
        self._in_way_since: float | None = None  # following, since when every give-way command has been zero, her close
        self._in_way_last = -math.inf  # ... the last such command
        self._in_way_asked = -math.inf  # when it last asked her to step back (in_her_way)
        self._backout_failed: tuple[float, float, float, float, float] | None = None  # (when, robot x y, her x y): a back-out search found no way
        self._backout_refused: tuple[float, float] | None = None  # (since, last): every back-out step refused
        self._aside_moving: tuple[float, float, float, float, float] | None = None  # (since, x, y, heading, last): forward give-way progress
        self._map_asked = False
        self._pose_sub: Any = None
        self._turn_in = False  # following ended: turn back into the flat if it faces out of an exit door
        self.paused = False  # a wait said while following: it stands facing her until she walks on
        self._pause_seen: str | None = None  # the attention's pause (when its order came) last acted on
        self._pause_from: tuple[float, float] | None = None  # where she stood when the pause began (odom)
        self._pause_reached = False  # paused and come up to her: it stands there (turning to her) while the pause lasts
        self._approach_reached = False  # the catch-up came up to her: it gives way and faces her there, no more driving at her
        self._aside_refused = False  # ... and its step aside was refused: it only faces her (no to and fro)
        self._oncoming: dict[str, float] = {}  # track id -> when it last walked at the robot (making way; replaced, never mutated)
        self._held_back: dict[str, tuple[float, float]] = {}  # track id -> (since, last) it has stood close ahead after that (replaced, never mutated)
        self._making_way: tuple[float] | None = None  # (since when) backing out of the way of someone held back
        # the blockage it last asked to pass (ASK_MAX): [spot x, spot y (odom), asks, last seen, phase ("asking" | "backing" |
        # "waiting"), where it began backing (x, y odom) or None, since when the spot has been free (or None)]
        self._block: list[Any] | None = None

    def respawn(self) -> Follower:
        return Follower(self.sim, name=self.name, limits=self.limits, rate=1.0 / self.period, distance=self.distance,
                        band=self.band, minimum=self.minimum, gain=self.gain, lost_after=self.lost_after,
                        too_fast_distance=self.too_fast_distance, too_fast_time=self.too_fast_time,
                        warn_every=self.warn_every, params=self.params, approach_time=self.approach_time,
                        approach_to=self.approach_to, search_time=self.search_time, search_speed=self.search_speed,
                        search_reach=self.search_reach)

    # ------------------------------------------------------------- inputs
    def _on_state(self, msg: Message) -> None:
        state = msg.xml.get("state")
        follow = state == "Follow"
        partner = msg.xml.get("partner") or None
        if self.following and not follow:
            self._turn_in = True
            # following ended ("stop", or she stopped to talk): come up to her first when she is
            # further than a comfortable interaction distance (issue 26 item 10)
            same = partner is not None and partner == self.partner_id
            self.approach_until = self.now + self.approach_time if state == "Interaction" and same else None
            self._approach_reached = False
            self._aside_refused = False
        elif state != "Interaction":
            self.approach_until = None
        elif self.approach_until is not None and partner is not None and partner != self.partner_id:
            # coming up to her after "stop", the attention found her again under a new track (she turned into a room
            # out of view and stood still): that track is the one it comes up to, not her old track's last guess
            # (corr_hallway_crossing: it stood at the dining room's door 1.8 m from her, facing where a sonar echo
            # had put her). Her old track keeps the approach going until the new one's first message.
            self.partner_id = partner
        if follow and not self.following:
            self._block = None  # (a new follow: no blockage asked about yet)
            self.trail.clear()
            self.route.clear()
            self._history.clear()
            self._limit_since = None
        if follow and partner != self.partner_id:
            self.partner_id = partner
            if self.track is not None and self.track.get("id") != partner:
                self.track = None
        self.following = follow
        # a wait said while she leads (the ES's pause order, docs/subsystems.md "Following"): a new pause
        # stands until she walks on; the pause is no longer in the message once any other order came
        paused = msg.xml.get("paused") if follow else None
        if paused is None:
            self.paused, self._pause_seen = False, None
        elif paused != self._pause_seen:
            self.paused, self._pause_seen, self._pause_from, self._pause_reached = True, paused, None, False
        self._listen_to_people(follow or self.approach_until is not None)

    def _listen_to_people(self, on: bool) -> None:
        """Read the person tracks while following, and only then (every delivery draws a network
        delay from the run's generator: a standing subscription would change every run)."""
        if on and self._tracks_sub is None:
            self._tracks_sub = self.bus.subscribe(TRACKS, lambda m: self.people.update(m.xml))
            self._pose_sub = self.bus.subscribe(POSE, self._on_pose)
            self._sonar_sub = self.bus.subscribe(SONAR, lambda m: self.sonar.hear(m, self.odom, self.now))
        elif not on and self._tracks_sub is not None:
            self._tracks_sub.close()
            self._tracks_sub = None
            self.people.clear()
            self._pose_sub.close()
            self._pose_sub = None
            self._sonar_sub.close()
            self._sonar_sub = None
            self.sonar = SonarEchoes()

    def _on_pose(self, msg: Message) -> None:
        x = msg.xml
        self.route.on_pose((float(x.get("x")), float(x.get("y")), float(x.get("theta"))), self.odom)

    async def _fetch_map(self) -> None:
        """The floor plan, once (the planner's grid): without it the follower steers along the trail only."""
        self._map_asked = True
        try:
            reply = await self.bus.call("map_server", "map", etree.Element("request"), timeout=2.0)
            self.route.set_grid(OccupancyGrid(parse_map(reply.xml), radius=self.limits.radius))
            rooms = floorplan.parse_map(reply.xml).rooms
            self.route.set_rooms(tuple(np.array(r.points, dtype=float) for r in rooms))
        except (BusError, MapError, HomesimError, asyncio.TimeoutError):
            pass

    def _on_partner(self, msg: Message) -> None:
        x = msg.xml
        pid = x.get("id")
        if self.partner_id is not None and pid != self.partner_id:
            return  # another track: never followed
        if self.partner_id is None and self.following:
            self.partner_id = pid
        self.track = {
            "id": pid, "t": self.now, "x": float(x.get("x")), "y": float(x.get("y")),
            "vx": float(x.get("vx", "0")), "vy": float(x.get("vy", "0")),
            "visible": x.get("visible", "true") == "true", "lost_for": float(x.get("lost_for", "0")),
        }  # type: ignore[dict-item]
        if self.track["visible"]:
            self._seen_distance = float(x.get("distance", "0"))
            self._seen_v = (self.track["vx"], self.track["vy"])  # her pace when last seen (a quiet track's decays)
            self._seen_pos = (self.track["x"], self.track["y"], self.now)

    def _on_scan(self, msg: Message) -> None:
        self.scan.update(msg)  # turned into points only when a control step needs them
        if self.following and self.odom is not None and self.now - self._seen_at >= 0.5:
            self._seen_at = self.now
            x = msg.xml
            ox, oy, oth = self.odom
            off = float(x.get("offset", "0"))
            self.seen.add(msg.attachments["ranges"], math.radians(float(x.get("min_angle"))),
                          math.radians(float(x.get("resolution"))), float(x.get("max_range")),
                          (ox + off * math.cos(oth), oy + off * math.sin(oth), oth))

    def _on_odometry(self, msg: Message) -> None:
        x = msg.xml
        self.odom = (float(x.get("x")), float(x.get("y")), float(x.get("theta")))
        self.v, self.w = float(x.get("v", "0")), float(x.get("w", "0"))
        # ground covered driving forwards (the laser saw it first) and where the robot started; never what
        # backing covers, or backing would lay its own way back
        if not self.crumbs or (self.v > 0.0 and math.hypot(self.odom[0] - self.crumbs[-1][0],
                                                           self.odom[1] - self.crumbs[-1][1]) >= CRUMB):
            self.crumbs.append(self.odom[:2])

    def can_back_off(self) -> bool:
        """Whether backing a little is safe: onto ground it drove over, or ground the laser saw free (no laser behind)."""
        if self.odom is None or not self.crumbs:
            return False
        x, y, th = self.odom
        bx, by = x - CRUMB * math.cos(th), y - CRUMB * math.sin(th)
        # nobody the attention tracks stands behind within reach (a bystander it drove past; the
        # partner too, should she have walked round it): the laser does not look there
        pts = self.scan.points()
        people = self.people.around(self.odom, self.now, echoes=pts if len(pts) else None)
        if not behind_clear(people, length=FOOTPRINT[0], width=FOOTPRINT[1], reach=BACK_REACH):
            return False
        if any(math.hypot(bx - cx, by - cy) <= CRUMB_NEAR for cx, cy in self.crumbs):
            return True
        back = 2 * CRUMB
        return self.seen.clear(*footprint_samples(x - back * math.cos(th), y - back * math.sin(th), th,
                                                  length=FOOTPRINT[0], width=FOOTPRINT[1], margin=BACK_MARGIN))

    def search_for(self) -> float:
        """How long it searches for her (s unseen): ``search_time``, longer when she was last seen
        beyond the band (it fell behind yielding to people crossing; :mod:`robot.partner_search`,
        the rule the attention's leaving rule reads too)."""
        # the rule's own band end and speed, as the attention reads it: one rule, not two settings of it
        return follow_search_time(self._seen_distance, base=self.search_time, top_speed=self.limits.max_speed,
                                  pace=math.hypot(*self._seen_v))

    # ------------------------------------------------------------- control
    def _to_robot(self, px: float, py: float) -> tuple[float, float]:
        ox, oy, oth = self.odom  # type: ignore[misc]
        c, s = math.cos(oth), math.sin(oth)
        return c * (px - ox) + s * (py - oy), -s * (px - ox) + c * (py - oy)

    def _command(self, v: float, w: float) -> None:
        v, w = self.bumpers.command(v, w, self.now, self._may_back)  # a pressed bumper first (robot.bumpers), then the blind half
        if not self._blind_clear(v, w):
            v, w = 0.0, 0.0
        self.bus.publish(BASE_CMD, etree.Element("velocity", v=f"{v:.4f}", w=f"{w:.4f}"))
        self.driving = True

    def _may_back(self, speed: float) -> bool:
        """The bumper reflex's back-off (straight, at ``speed``) held to the follower's own rules: backing onto
        ground it drove over or saw free with nobody behind (:meth:`can_back_off`), driving forward clear of
        the laser's echoes and the people it tracks, and either way clear of the floor plan
        (:func:`sweep_allowed`)."""
        if self.odom is None:
            return False
        mapped = self.route.obstacles_near(self.odom)
        if speed < 0.0:
            return self.can_back_off() and sweep_allowed(speed, 0.0, mapped)
        pts = self.scan.points()
        ahead = np.concatenate((mapped, pts)) if len(pts) else mapped
        bodies = self.people.around(self.odom, self.now, echoes=pts if len(pts) else None)
        return sweep_allowed(speed, 0.0, ahead) and people_sweep_clear(speed, 0.0, bodies, duration=SWEEP_TIME)

    def _blind_clear(self, v: float, w: float) -> bool:
        """Whether (v, w) keeps the footprint off what the sonar hears in the blind half that the floor plan
        does not explain (:func:`robot.blindside.blind_clear`): the last check of every command it sends."""
        if v == 0.0 and w == 0.0:
            return True
        arcs = self.sonar.arcs(self.odom, self.now)
        if not arcs:
            return True
        mapped = self.route.obstacles_near(self.odom) if self.odom is not None else np.zeros((0, 2))
        # and her legs where the laser sees them ahead of its line (within HER_LEGS of her track): a flank
        # transducer hears the partner standing beside its front across its cone, and its arc runs on round the
        # flank; the reading is her legs, seen, as a reading near a wall is the wall's, and her body is kept
        # clear by the follower's own checks (face20: the turn back to her refused while she stood at 40-60 deg)
        her = self._her_legs_seen()
        if len(her):
            mapped = np.concatenate((mapped, her)) if len(mapped) else her
        return blind_clear(v, w, blind_points(arcs, explained_by_points(mapped)), duration=SWEEP_TIME)

    def _her_legs_seen(self) -> np.ndarray:
        """The laser's echoes (robot frame) ahead of its line (``BLIND_X``) within :data:`HER_LEGS` m of the partner's
        track (its position now, constant velocity), an empty array without a track."""
        tr = self.track
        pts = self.scan.points()
        if tr is None or self.odom is None or not len(pts):
            return np.zeros((0, 2))
        age = min(max(self.now - tr["t"], 0.0), 0.5)
        hx, hy = self._to_robot(tr["x"] + tr["vx"] * age, tr["y"] + tr["vy"] * age)
        return seen_legs(pts, np.array([(hx, hy)]), HER_LEGS)

    def _halt(self) -> None:
        if self.driving:
            self.bus.publish(BASE_CMD, etree.Element("velocity", v="0", w="0"))
            self.driving = False

    def _status(self, d: float, at_limit: bool, state: str) -> None:
        self.bus.publish(FOLLOW_STATUS, etree.Element("follow", distance=f"{max(d, 0.0):.4f}", speed=f"{self.v:.4f}",
                                               at_limit="true" if at_limit else "false", state=state))

    def control_step(self) -> tuple[float, float] | None:
        """One control step; returns the command sent (None when not driving)."""
        approaching = not self.following and self.approach_until is not None and self.now < self.approach_until
        if not self.following and not approaching:
            if self.approach_until is not None:
                self._end_approach()
            if self._turn_in:
                turn = self._face_in()
                if turn is not None:
                    return turn
                self._turn_in = False
            self._halt()
            return None
        tr = self.track
        if tr is None or self.odom is None:
            return self._stand(approaching, "searching")
        age = self.now - tr["t"]
        unseen = (0.0 if tr["visible"] else tr["lost_for"]) + age
        yielded = self._count_yield(approaching, tr["visible"] and age < 2 * self.period)
        yielded += self._closed(tr["visible"] and age < 2 * self.period)
        # approaching, she stands: unseen a moment (behind a table's legs, a chair, the door frame) is
        # no reason to give up the approach and teach from across the room; her last position holds,
        # as long as following would search for her there (longer when the robot had fallen behind: a
        # fast leader stopped out of sight past a divider, fresh6/div_fast_leader_stops, and the
        # approach gave up 3 s after "stop", still 3.6 m short of him)
        if unseen - yielded > self.search_for():
            turn = None if approaching else self._face_in()
            if turn is not None:  # the search ended at an exit door: back to the room first
                self._status(0.0, False, "searching")
                return turn
            return self._stand(approaching, "stopped")
        searching = unseen > self.lost_after  # not approaching: out of view a while, look where she went
        # the partner now (constant velocity over the message's age), in odom and robot frames
        horizon = min(age, SEARCH_HORIZON if searching else 0.5)
        px, py = tr["x"] + tr["vx"] * horizon, tr["y"] + tr["vy"] * horizon
        if searching and age > SEARCH_HORIZON:
            px, py = self._walk_on((px, py), self._seen_v, min(age, SEARCH_WALK_ON) - SEARCH_HORIZON)
        heard = False
        if not searching:
            self._heard = None
        else:
            px, py = self._not_there(px, py)
            echo = self._heard_there(px, py)
            if echo is not None:  # the sonar hears someone beside or behind, where the laser does not look
                px, py, heard = echo[0], echo[1], True
        if not self.trail or math.hypot(px - self.trail[-1][0], py - self.trail[-1][1]) > 0.15:
            self.trail.append((px, py))
        rx, ry = self._to_robot(px, py)
        d = math.hypot(rx, ry)
        if (searching or approaching) and self._closing is not None and not heard:
            self._closing.update(self.now, d)  # on its way to where it looks for her: not search time
        # radial speed: the partner's velocity along the line robot -> partner
        c, s = math.cos(self.odom[2]), math.sin(self.odom[2])
        vrx, vry = c * tr["vx"] + s * tr["vy"], -s * tr["vx"] + c * tr["vy"]
        v_radial = (vrx * rx + vry * ry) / d if d > 1e-6 else 0.0
        bearing = math.atan2(ry, rx)
        # paused (a wait said while she leads): only following on is paused; it still comes up to her
        # as the approach does (issue 26 item 10: not 3.5 m behind her, not in a door frame), gives
        # way there, and keeps every rule of driving (the dynamic window, everyone's space, the floor plan)
        paused = self.paused and not approaching and self._pause_holds(px, py, d, searching,
                                                                       math.hypot(tr["vx"], tr["vy"]))
        if approaching or paused:
            # she stands: close in to the band's near part, the far end no further than approach_to;
            # near enough, in sight (not behind a wall) and not in a door frame or a passage (where
            # it would teach from the other room and block the way), face her and stop
            # and in the room she stands in (the floor plan's rooms): short of a wide door with her just
            # inside, it would teach "kitchen" from the living room (issue 26 item 10); within the band's
            # near end it stops wherever it is (rooms with no wall between, a kitchen corner)
            same_room = self.route.room_at(self.odom[:2]) is self.route.room_at((px, py))
            near = (d <= self.approach_to and self.route.in_sight(self.odom[:2], (px, py))
                    and (same_room or d <= self.band[0]))
            arrived = near and (d <= self.band[0] or self.route.clearance(self.odom[:2]) >= APPROACH_ROOM)
            # paused, come up to her (or stepping out of her way): it holds there while the pause lasts, not
            # creeping after her as she shifts where she stands, nor back into the door it gave way from
            stepping_aside = paused and self._aside is not None and self.now <= self._aside[1]
            if paused and (self._pause_reached or stepping_aside):
                arrived = True
            # come up to her once, it stays there: it gives way (if it must) and turns to face her; backing out
            # of her way just past the band's near end it drove at her again, to and fro until the approach's
            # time ran out with her 20-30 degrees off (face20: face19_stop_past_opening seed 1)
            if approaching and self._approach_reached:
                arrived = True
            elif approaching and arrived and not searching:
                # come up to her where it sees her: near a guess (her walked-on point, a sonar echo beside it) it
                # faces that way, and drives on to her once she is seen elsewhere (in the room past the door)
                self._approach_reached = True
                # and time to give way and turn to her there: her request is held until it faces her
                self.approach_until = max(self.approach_until, self.now + ARRIVED_TIME)  # type: ignore[type-var]
            if arrived:
                # so close to her in a door frame or a passage: out of her way first (her next
                # "follow me" walks her through it), then face her
                aside = (self._give_way(px, py, self.route.obstacles_near(self.odom),
                                        view=GIVE_WAY_BEARING if paused else APPROACH_VIEW)
                         if (d <= self.band[0] or stepping_aside) and (paused or not self._aside_refused) else None)
                # after the catch-up, a step aside that is refused (its sweep, her body, the sonar) leaves it
                # free to turn to her meanwhile: stood 10 s in a 0.9 m door with her 26 deg off, retrying the
                # give-way until the approach's time ran out (face20_stop_past_narrow_door seed 1)
                if aside is not None and (paused or aside != (0.0, 0.0) or abs(bearing) < FACED):
                    self._command(*aside)
                    self._status(d, False, "paused" if paused else "approaching")
                    return aside
                if aside is not None:  # refused: it faces her from here on (stepping and turning back to and fro
                    self._aside_refused, self._aside = True, None  # on the spot: library home_tour seed 4)
                if paused:
                    self._pause_reached = True
                    return self._pause(px, py, d, bearing)
                return self._face(bearing)
            v_des = speed_law(d, 0.0, distance=self.distance, band=(self.band[0], self.distance), minimum=self.minimum,
                              gain=self.gain, limits=self.limits)
            v_des = max(v_des, 0.15)  # in the next room (near but out of sight): on through the door
        elif searching:
            # to where she was heading, slowly, no closer than search_reach (she may stand there unseen);
            # behind a wall (she went through a door) on through the door until the point is in sight;
            # someone the sonar hears beside or behind: it only turns to look (never driven at unseen)
            if heard:
                v_des = 0.0
            elif not self.route.in_sight(self.odom[:2], (px, py)):
                v_des = self.search_speed
            else:
                v_des = min(self.search_speed, self.gain * (d - self.search_reach)) if d > self.search_reach else 0.0
        else:
            v_des = speed_law(d, v_radial, distance=self.distance, band=self.band, minimum=self.minimum,
                              gain=self.gain, limits=self.limits)
        mapped = self.route.obstacles_near(self.odom)  # walls and furniture all round (the laser looks ahead)
        close = v_des <= 0.05 and not approaching and not searching and d < self.band[0] and math.hypot(tr["vx"], tr["vy"]) < GIVE_WAY_STILL
        if not close:
            self._close_since = None
        elif self._close_since is None:
            self._close_since = self.now
        # she walks at it while it stands in a door frame or a passage: it backs out of her way at
        # once (away from her, never into her path), before she stands pressed against its front
        # (her line of walking passes the robot's body: someone walking past it beside a bed is not
        # walking at it, and backing out then turned it away from her as she passed)
        speed = math.hypot(vrx, vry)
        miss = abs(rx * vry - ry * vrx) / speed if speed > 1e-6 else math.inf
        coming = (v_des <= 0.05 and not approaching and not searching and d < self.band[0]
                  and v_radial < -GIVE_WAY_STILL and miss < WALKS_AT and self.route.clearance(self.odom[:2]) < NARROW)
        # she walks toward the way out the robot came in by (the door of the room it followed her into) and it
        # stands on that way: out of it to a spot beside it before she reaches it (then it faces her, as waiting
        # does, and follows her out); a give-way begun so goes on while it lasts
        # (until she has passed it: then it follows her out)
        way_out = None if approaching or paused or searching or not MAKE_WAY_LEAVING else self._leaving(px, py, tr)
        if self._leave_aside and self._aside is not None:
            if approaching or paused or searching or not self._before_her(px, py):
                self._aside = None  # she has passed it (or following is over): no more stepping aside
        if way_out is not None or (self._leave_aside and self._aside is not None and self.now <= self._aside[1]):
            aside = self._give_way(px, py, mapped, held=True, step_back=True, way=way_out)
            if aside is not None:
                self._command(*aside)
                self._status(d, False, "giving_way")
                return aside
        if self._aside is None:
            self._leave_aside = False
        if not (close or coming):
            self._in_way_since = None
        if close or coming:
            # she stands close in front of it while it follows: it is in her way (in a door frame or a
            # passage at once; anywhere once she has stood there GIVE_WAY_HELD s, held up): step aside;
            # while she walks, it stands (moving into a walking person's path is how one is touched)
            # or, in a door frame or passage, backs out
            aside = self._give_way(px, py, mapped, held=close and self.now - self._close_since >= GIVE_WAY_HELD,
                                   back_only=not close, step_back=True)
            aside = self._still_in_her_way(aside, d, px, py, mapped)
            if aside is not None:  # she is close and it stands in her way in a door or passage: step aside
                self._command(*aside)
                self._status(d, False, "giving_way")
                return aside
        if not approaching and not paused:
            way = self._make_way(px, py, mapped)
            if way is not None:  # someone stands held back in front of it: out of their way
                self._command(*way)
                self._status(d, False, "searching" if searching else "giving_way")
                return way
            room = self._make_room(px, py, mapped)
            if room is not None:  # asked twice to pass, still held up: it backs out of the way and waits
                self._command(*room)
                self._status(d, False, "searching" if searching else ("giving_way" if room[0] < 0.0 else "held"))
                return room
        held = False
        if v_des <= 0.05:
            self._stuck_since, self._stuck_at, self._unstick_until = None, None, -math.inf
            # wait (or back off) facing the partner; reversing is slow and straight (no laser behind)
            w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.8 * bearing))
            # backing straight off takes it away from her only while she is ahead: beside or behind it (she
            # walks past its side) it would reverse into her, so it stands and turns to her (back_off_away)
            v = v_des if v_des < 0 and back_off_away(rx, ry) and self.can_back_off() else 0.0
            backing = v_des < 0 and back_off_away(rx, ry)  # (its trail is ground it drove over)
            v, w = self._swept(v, w, mapped)
            if v != 0.0:
                v, w = self._back_off_clear(v, w, self._bodies(rx, ry), mapped)
            if backing and v == 0.0:
                # straight back refused (turned to her, the corner of a 1.0 m corridor's wall behind it): back
                # along its own trail instead, the rear steered onto it (:meth:`_trail_back`, :meth:`_room_step`)
                v, w = self._trail_reverse(v, w, rx, ry, mapped)
            if v == 0.0 and w != 0.0:  # turning to her: no corner swung into her (she may stand close) or anyone
                w = w if turn_clear(w, self._bodies(rx, ry, guess=searching), duration=SWEEP_TIME) else 0.0
            if (v == 0.0 and w != 0.0 and not searching and d < self.band[0]
                    and math.hypot(tr["vx"], tr["vy"]) < GIVE_WAY_STILL):
                # turning on the spot to face her standing close while it stands in a door frame: not across it
                # (AXIS_TURN). Not for one walking: backing off from her while turning to her, held straight, it came
                # within 0.12 m of a partner walking back past it (library goto seed 8; main 0.50 m)
                w = self._axis_turn(w)
            if searching and v == 0.0:
                w = self._search_turn(w, bearing, rx, ry, mapped)
            elif not searching:
                self._turn_way = 0.0
            state = "waiting"
            # the robot stands and sees the partner: the way to them is the straight line. Older trail
            # points are stale (a partner who turned back and walked past would otherwise be
            # "followed" to where they came from, away from them)
            self.trail.clear()
            self.trail.append((px, py))
        else:
            # steer along the partner's trail (round furniture, through doors), dodging laser echoes
            self._trim_trail(rx)
            goal = self._to_robot(*self.trail[0]) if self.trail else (rx, ry)
            # through a door or round a corner: the planned path's middle of the door, not the trail
            # that hugs the jamb (see robot.navigation.route)
            way = self.route.goal(self.now, self.odom[:2], (px, py), standing=self._standing((px, py)))
            if way is not None:
                # the pure-pursuit point gives the direction; the dynamic window's goal lies further
                # out along it (a goal 0.35 m ahead would make it prefer arcs that stop there: slow)
                gx, gy = self._to_robot(*way)
                n = math.hypot(gx, gy)
                goal = (gx * WAY_GOAL / n, gy * WAY_GOAL / n) if 1e-6 < n < WAY_GOAL else (gx, gy)
            # a goal off to the side (a partner who walked past): turn toward it first, and keep the
            # partner in the laser's field of view, instead of driving a wide arc forwards
            v_pref = heading_speed(v_des, math.atan2(goal[1], goal[0]))
            pts = self.scan.points()
            if len(pts) and not searching:
                pts = pts[np.hypot(pts[:, 0] - rx, pts[:, 1] - ry) > 0.45]  # not the partner's own legs
            if len(mapped):
                pts = np.concatenate((pts, mapped))
            # everyone else: keep out of their personal space, and pass them slowly (yield: slow,
            # stop and wait while they cross, then go on)
            # people walking about (a standing track may be a table's legs, which the laser keeps it
            # off anyway); no lost tracks (a partner's second track lost at a door frame would live on
            # as a phantom in the door)
            others = self.people.around(self.odom, self.now, exclude=self.partner_id, near=(px, py), moving=0.2)
            # and anyone standing close by: someone crossing who stopped in front of it (held up by
            # the robot, or waiting for it) is standing, and still a person to keep clear of
            close = self.people.around(self.odom, self.now, exclude=self.partner_id, near=(px, py), standing=0.2)
            close = close[np.hypot(close[:, 0], close[:, 1]) < STANDING_NEAR] if len(close) else close
            if len(close):
                others = np.concatenate((others, close)) if len(others) else close
            capped = others  # whose nearness slows it (the social speed limit)
            if searching:  # unseen, where she is heading: her body too (she may stand there, out of view)
                others = np.concatenate((others, [(rx, ry)])) if len(others) else np.array([(rx, ry)])
                # but only where that point is in sight: behind a wall (she went through a door) the
                # limit round it held the robot to 0.2 m/s in a 1.0 m hall until the search ran out
                # short of the door (issue 26, hall_follow_doors); in the door it is in sight again
                if self.route.in_sight(self.odom[:2], (px, py)):
                    capped = others
            limits = self.limits
            if searching:  # slowly: she may step out from behind whatever hid her
                limits = replace(limits, max_speed=min(limits.max_speed, self.search_speed))
            if len(capped):
                cap = social_speed_limit(nearest(capped), self.limits.max_speed)
                if cap < limits.max_speed:
                    limits = replace(limits, max_speed=cap)
                    v_pref = min(v_pref, cap)
            # in a passage (a hallway, a door frame: its centre within NARROW of the floor plan, no room to swerve),
            # past an opening it cannot see into (a side door, a corner: the scan's range jumps at the floor plan's
            # corners), no faster than it can stand from short of someone stepping out there
            # (robot.navigation.blind.follow_blind_limit): a boy running out of a side door of a 1.1 m hallway is
            # first seen 0.6-0.7 m ahead, already in its lane (corr_hallway_crossing). In a room it has room to
            # give way and the contact limit below reckons with whoever it sees (everywhere, the limit held it so
            # far back that its partners, walking at its top speed, never stopped for it: library goto seed 7)
            in_passage = self.route.clearance(self.odom[:2]) < NARROW
            blind = (follow_blind_limit(self._blind_corners(mapped), limits.max_speed, decel=self.limits.max_accel)
                     if in_passage else limits.max_speed)
            if blind < limits.max_speed:
                limits = replace(limits, max_speed=blind)
                v_pref = min(v_pref, blind)
            # and never faster than it can stop from before anyone walking into its way (the partner too;
            # time to contact from the tracks' velocities: robot.footprint.contact_speed_limit), on any turn rate
            # the base reaches in one step (the window may turn toward someone the present arc passes: review18 F4)
            # and someone first seen close ahead (a tentative track's first sighting: no velocity yet), not
            # beside anyone known, as running at it (People.newborn: a boy out of a side door of a 1.1 m hallway
            # at 1.5 m/s, first seen 1.13 m off, was left out for that scan and touched; corr_hallway_crossing)
            way = in_the_way(self.people, self.odom, self.now, echoes=self.scan.points(), first_seen=True,
                             exclude=self.partner_id, gone=self._nobody_there(tr, searching))
            contact = contact_speed_limit(way,
                                          limits.max_speed, decel=self.limits.max_accel, w=self.w,
                                          dw=self.limits.max_turn_accel * self.period)
            if contact < limits.max_speed:
                limits = replace(limits, max_speed=contact)
                v_pref = min(v_pref, contact)
            cmd = dwa(self.v, self.w, goal, pts, limits, v_pref=v_pref, params=self.params, people=others)
            v, w = cmd.v, cmd.w
            if v == 0.0 and w != 0.0 and not turn_clear(w, self._bodies(rx, ry, guess=searching), duration=SWEEP_TIME):
                # the window's turn on the spot is exempt from people's space (the laser's leg echoes
                # guard its corners, but a body is wider than its legs): a corner swung into a man
                # held up beside it while a couple crossed (cross_studio_four seeds 0, 3, 5, 8)
                w = 0.0
            # no admissible way to her (she is beyond the band, people or furniture hold it): ``held``, never
            # ``waiting``, which says it stands by her (the dialog's and the attention's "her walk is over" read
            # only that one; review22 R4: a teaching said while held up in a door ended the walk)
            state = "following" if cmd.ok else "held"
            v, w = self._unstick(v, w, mapped)
            held = self._held_up(v, v_des, goal, px, py, may_room=not approaching and not paused)
        v = self._keep_inside(v, w)
        self._command(v, w)
        if approaching or paused:
            self._status(d, False, "paused" if paused else "approaching")
            return v, w
        if searching:
            self._too_fast(d, False)
            self._status(d, False, "searching")
            return v, w
        at_limit = v_des >= self.limits.max_speed - 1e-6
        self._too_fast(d, at_limit and not held, math.hypot(tr["vx"], tr["vy"]))
        self._status(d, at_limit, state if tr["visible"] else "searching")
        return v, w

    def _pause_holds(self, px: float, py: float, d: float, unseen: bool, speed: float) -> bool:
        """Whether the pause (a wait said while she leads) still holds: until she walks on, that is she is
        :data:`PAUSE_WALK_ON` from where she stood when the pause began, she comes closer than ``minimum``
        (the follower's own rules give her way), or she went out of view walking. Then following goes on
        (``paused`` false; the way to her is the straight line from here)."""
        if self._pause_from is None:
            self._pause_from = (px, py)
        walked = math.hypot(px - self._pause_from[0], py - self._pause_from[1])
        if walked > PAUSE_WALK_ON or d < self.minimum or (unseen and speed >= PAUSE_WALKING):
            self.paused, self._pause_reached, self._aside = False, False, None
            self.trail.clear()
            self.trail.append((px, py))
            return False
        return True

    def _pause(self, px: float, py: float, d: float, bearing: float) -> tuple[float, float]:
        """Paused and come up to her (the approach's end: near, in sight, in her room, not in a door
        frame): stand there turned to face her (no corner swung into her or anyone, none into the floor
        plan) while the pause holds; she may shift where she stands without it creeping after her."""
        w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.8 * bearing)) if abs(bearing) > math.radians(8) else 0.0
        if w != 0.0:
            rx, ry = self._to_robot(px, py)
            _, w = self._swept(0.0, w, self.route.obstacles_near(self.odom))  # type: ignore[arg-type]
            if w != 0.0 and not turn_clear(w, self._bodies(rx, ry), duration=SWEEP_TIME):
                w = 0.0
        if w == 0.0:
            self._halt()
        else:
            self._command(0.0, w)
        self._status(d, False, "paused")
        return 0.0, w

    def _trim_trail(self, rx: float) -> None:
        """Drop the trail's points the robot is past: those before its point nearest the robot (pure
        pursuit: they are where she walked while it stood, wedged, approached or gave way), with her
        ahead (``rx`` > 0, robot frame) those behind it, and those within reach. Steering back to such a
        point turned the robot away from her in the door she had led it to, then into her (issue 26,
        hall_follow_doors). Her own latest point is always kept."""
        trail = self.trail
        if len(trail) > 2:
            near = [math.hypot(*self._to_robot(*p)) for p in trail]
            for _ in range(min(near.index(min(near)), len(trail) - 1)):
                trail.popleft()
        while len(trail) > 1:
            x, y = self._to_robot(*trail[0])
            if not ((rx > 0.0 and x < 0.0) or math.hypot(x, y) < 0.6):
                break
            trail.popleft()

    def _bodies(self, rx: float, ry: float, *, guess: bool = False) -> np.ndarray:
        """Robot-frame centres of everyone near (confirmed tracks) and of the partner at (``rx``, ``ry``),
        but not where the latest scan looks and finds nobody (:meth:`LatestScan.sees_through`): a coasting
        track, or her predicted point, beside the robot after she walked past its side and on behind
        it refused every turn toward where she went (flow/follow_while_looking, 9d2dc38's seed 8).
        ``guess`` (searching: unseen, her point is where she might be): her own coasting track is always
        left out, and the search point (``rx``, ``ry``: where it looks for her, which need not be where her
        track coasts) stands for her: it too is left out in the blind half (behind the laser's line,
        :data:`BLIND_X`), where the sonar is what knows who stands there and every command keeps clear of
        what it hears (:meth:`_blind_clear`), and where the laser looks and has no echo within
        :data:`GUESS_ECHO` m of it. Her guessed point 0.6 m beside the robot refused the turn toward where she went on behind
        it until the search ran out (flow/follow_while_looking seed 1)."""
        # searching, her own track is her guessed point (the same message): one body, where the laser looks
        # and has an echo near it (nobody stands where the laser looks and hears nothing)
        near = (self.people.around(self.odom, self.now, exclude=self.partner_id) if guess
                else self.people.around(self.odom, self.now))
        own = [(rx, ry)]
        if guess:
            pts = self.scan.points() if rx >= BLIND_X else np.zeros((0, 2))
            if not len(pts) or float(np.hypot(pts[:, 0] - rx, pts[:, 1] - ry).min()) > GUESS_ECHO:
                own = []
        bodies = near[:, :2] if len(near) else np.zeros((0, 2))
        if own:
            bodies = np.concatenate((bodies, own)) if len(bodies) else np.array(own)
        if not len(bodies):
            return bodies
        keep = [not self.scan.sees_through(float(bx), float(by)) for bx, by in bodies]
        return bodies[np.array(keep, dtype=bool)] if not all(keep) else bodies

    def _heard_there(self, px: float, py: float) -> tuple[float, float] | None:
        """Searching, where the sonar says she may be (odom), or None: when the point she is looked for at
        (odom ``px, py``) lies near the robot (within the sonar's reach, plus :data:`HEARD_NEAR`) where the
        laser does not look (behind its line, :data:`BLIND_X`) or where the latest scan sees through it
        (:meth:`LatestScan.sees_through`), the middle of the unexplained echo
        in the blind half (not the floor plan's, :func:`robot.blindside.explained_by_points`) nearest to
        that point, among those she can have walked to from where a scan last saw her (:data:`HEARD_REACH`).
        The laser looks ahead only: a partner who stepped past the robot's side and stands
        beside or behind it is heard there, not seen; the robot turns to look (the laser and the camera
        then find her again)."""
        if self.odom is None:
            return None
        rx, ry = self._to_robot(px, py)
        kept = self._heard if self._heard is not None and self.now - self._heard[2] <= HEARD_KEEP else None
        if rx >= BLIND_X and not self.scan.sees_through(rx, ry):  # ahead, where she may stand unseen
            return kept[:2] if kept is not None else None
        if math.hypot(rx, ry) > SONAR_REACH + HEARD_NEAR:  # looked for out of the sonar's hearing: she went on there
            return kept[:2] if kept is not None else None
        arcs = self.sonar.arcs(self.odom, self.now)
        if not arcs:
            return kept[:2] if kept is not None else None
        explains = explained_by_points(self.route.obstacles_near(self.odom))
        # only where she can have walked to from where a scan last saw her (an echo behind the robot is no
        # partner last seen 3 m ahead: a jamb it drove past, u_catch_up_slow seed 3 turned round to one)
        if self._seen_pos is None:
            return kept[:2] if kept is not None else None
        sx, sy = self._to_robot(self._seen_pos[0], self._seen_pos[1])
        reach = min(HEARD_REACH, HEARD_NEAR + HEARD_WALK * max(0.0, self.now - self._seen_pos[2]))
        best, near = None, math.inf
        for arc in arcs:
            blind = arc[arc[:, 0] < BLIND_X]
            if not len(blind) or explains(arc):
                continue
            bx, by = (float(c) for c in blind.mean(axis=0))
            gap = math.hypot(bx - rx, by - ry)
            if gap < near and math.hypot(bx - sx, by - sy) <= reach:
                best, near = (bx, by), gap
        if best is None:
            return kept[:2] if kept is not None else None
        ox, oy, oth = self.odom
        c, s = math.cos(oth), math.sin(oth)
        self._heard = (ox + c * best[0] - s * best[1], oy + s * best[0] + c * best[1], self.now)
        return self._heard[:2]

    def _search_turn(self, w: float, bearing: float, rx: float, ry: float, mapped: np.ndarray) -> float:
        """Searching and standing, the turn toward where she is looked for (``bearing``; ``w`` the short way's
        rate, already held to the floor plan and the people it knows): when that way is refused (zero, or the
        sonar hears someone in the blind half it would swing a corner toward: :meth:`_blind_clear`) and she
        is looked for beside or behind (beyond :data:`SEARCH_BACK`), the other way round, so the laser comes
        to look where she is. She walked past its side and on behind it: turning toward her swung the
        rear corner at her own legs, which the sonar heard, and the robot stood until the search ran out
        (flow/follow_while_looking seed 1). The way chosen is kept while it is turned (no to and fro)."""
        if abs(bearing) <= SEARCH_BACK:
            self._turn_way = 0.0
            return w
        if self._turn_way == 0.0 and w != 0.0 and self._blind_clear(0.0, w):
            return w
        rate = min(self.limits.max_turn, 1.8 * abs(bearing))
        ways = (self._turn_way,) if self._turn_way != 0.0 else (-math.copysign(1.0, bearing),)
        if self._turn_way != 0.0:
            ways = (self._turn_way, -self._turn_way)
        for way in ways:
            cand = way * rate
            _, cand = self._swept(0.0, cand, mapped)
            if cand == 0.0 or not turn_clear(cand, self._bodies(rx, ry, guess=True), duration=SWEEP_TIME):
                continue
            if not self._blind_clear(0.0, cand):
                continue
            self._turn_way = way
            return cand
        return 0.0

    def _not_there(self, px: float, py: float) -> tuple[float, float]:
        """Searching: where to look for her when the point her track predicts (odom ``px, py``) is in the
        laser's view and empty (:meth:`LatestScan.sees_through`): she is not there. Then where her last
        measured velocity carried her on from where she was last seen (:meth:`_walk_on`, never through a
        wall), which may be beside or behind the robot (she walked past its side: it turns there
        instead of standing at the stale point); the point as it was when she was slower than
        :data:`WALKING` (no heading to go by)."""
        if self._seen_pos is None or self.odom is None:
            return px, py
        rx, ry = self._to_robot(px, py)
        # nobody stands with their centre on a wall or outside the floor plan's rooms: a track coasting on into
        # the wall (she turned round a blind bend, her track went on straight) is no place she can be (bend23);
        # nor is the point already seen empty for this sighting (the far walk begun): come up to it, the robot no
        # longer sees it (beside it, under the laser's reach) and had gone back to stand there until it declared
        # her lost while she walked on up the passage's other leg (search25, fresh11 twin_passage_chat)
        if (self._walked_far != self._seen_pos[2] and not self.scan.sees_through(rx, ry)
                and self.route.clearance((px, py)) >= WALL_BODY and self.route.inside((px, py))):
            return px, py
        vx, vy = self._seen_v
        if math.hypot(vx, vy) < WALKING:
            return px, py
        sx, sy, st = self._seen_pos
        q = self._walk_on((sx, sy), (vx, vy), min(self.now - st, SEARCH_WALK_ON))
        if self.now - st > SEARCH_WALK_ON:
            # that point seen empty too: she walked on further (round the blind bend of a passage and up its
            # other leg, bend23), as far as her pace carries her in the time unseen (at most SEARCH_WALK_FAR)
            # (once seen empty, it stays so until she is seen again: the robot come up to that point no longer
            # sees it, standing on it)
            qx, qy = self._to_robot(*q)
            radius = min(0.25, max(0.1, self.route.clearance(q) - 0.05))
            if self._walked_far != st and self.scan.sees_through(qx, qy, radius):
                self._walked_far = st
            if self._walked_far == st:
                q = self._walk_on((sx, sy), (vx, vy), min(self.now - st, SEARCH_WALK_FAR))
        return q

    def _nobody_there(self, tr: dict[str, Any], searching: bool) -> str | None:
        """Searching (her track unmeasured over :attr:`lost_after`), her coasting track's id when its centre lies within
        :data:`WALL_BODY` of the floor plan, or the latest scan looks at the disc round it and finds it empty
        (:meth:`LatestScan.sees_through`, the disc kept off the floor plan's walls as in :meth:`_not_there`): nobody
        stands there, so the contact limit leaves it out; else None. Her track stood where she was last measured, beside the wall at a passage's blind bend, kept "standing"
        by the wall's echo; the contact limit took it for her standing in its way, brought the robot to a halt 0.7 m
        from it and the search ran out there while she walked on up the passage's other leg (search25)."""
        if not searching or self.partner_id is None:
            return None
        age = max(0.0, self.now - tr["t"])  # where the contact limit puts it: predicted by its velocity to now
        x, y = tr["x"] + tr["vx"] * age, tr["y"] + tr["vy"] * age
        clearance = self.route.clearance((x, y))
        if clearance < WALL_BODY:  # nobody stands with their centre on a wall (as in _not_there)
            return self.partner_id
        radius = min(0.25, max(0.1, clearance - 0.05))
        return self.partner_id if self.scan.sees_through(*self._to_robot(x, y), radius) else None

    def _give_way(self, px: float, py: float, mapped: np.ndarray, *, held: bool = False,
                  back_only: bool = False, view: float = GIVE_WAY_BEARING, step_back: bool = False,
                  way: tuple[float, float] | None = None) -> tuple[float, float] | None:
        """The command that takes the robot aside when the partner (odom ``px, py``) is too close and
        it stands in a door frame or a passage, or anywhere when ``held`` (she has stood held up in
        front of it a while) (:mod:`robot.navigation.giveway`), None otherwise (no floor plan, room
        enough here and she is not held up, or nowhere to go). ``back_only``: she walks at it, so
        only backing out the way it came (away from her) will do. ``view``: she is kept within this bearing
        (turned to first when further off). ``step_back``: following (not the catch-up, whose request
        distance a step back would lengthen), a stall with no way out steps back off her way (:meth:`_step_back`).
        ``way``: she walks to that point (odom; :meth:`_leaving`): a new spot is only one ahead, off her way there."""
        if not self.route.ready or self.odom is None:
            self._aside = None
            return None
        if self._aside is None or self.now > self._aside[1]:
            self._aside = None
            if way is not None:
                if self.now < self._no_leave_spot_until:
                    return None
                grid = self.route.grid
                assert grid is not None
                path = give_way_spot(grid, self.route.to_map(self.odom[:2]), self.route.to_map((px, py)),
                                     keep=self.band[0], way=self.route.to_map(way))
                if path is None:
                    self._no_leave_spot_until = self.now + GIVE_WAY_RETRY
                    return None
                self._aside = ([self.route.to_odom(p) for p in path], self.now + GIVE_WAY_TIME, False)
                self._leave_aside, self._leave_way = True, way
                return self._give_way(px, py, mapped, step_back=step_back)
            if self.now < self._no_spot_until:
                return None
            if not held and self.route.clearance(self.odom[:2]) >= GIVE_WAY_ROOM:
                return None
            grid = self.route.grid
            assert grid is not None
            here, her = self.route.to_map(self.odom[:2]), self.route.to_map((px, py))
            path, back = (None, False) if back_only else (give_way_spot(grid, here, her, keep=self.band[0]), False)
            if path is None:  # nowhere ahead (a storeroom): back out the way it came, facing her
                path, back = back_out_spot(grid, here, her, keep=self.band[0], came=self._came_from()), True
            if path is None:
                self._no_spot_until = self.now + GIVE_WAY_RETRY  # up to 24 grid searches: not every step
                return None
            self._aside = ([self.route.to_odom(p) for p in path], self.now + GIVE_WAY_TIME, back)
        way = self._aside[0]
        ox, oy = self.odom[0], self.odom[1]
        while len(way) > 1 and math.hypot(way[1][0] - ox, way[1][1] - oy) < 0.2:
            way.pop(0)  # a vertex reached: on along the next leg
        end = way[-1]
        if math.hypot(end[0] - ox, end[1] - oy) < 0.15:
            self._aside = None  # there: wait (and face her) as before
            return None
        cx, cy = carrot(way[0], way[1], (ox, oy), 0.35) if len(way) > 1 else end
        gx, gy = self._to_robot(cx, cy)
        rx, ry = self._to_robot(px, py)
        if self._aside[2]:
            return self._back_out((gx, gy), (rx, ry), mapped)
        bearing = math.atan2(ry, rx)
        if self._leave_aside:
            # making way for her walking out, she walks past its side: where she will be in view a moment
            # from now (its own turn and her walk), kept within LEAVE_VIEW; the step's turn away from her
            # carried her out of the laser's view as she passed, and close beside it her body then refused
            # the turn back: lost (library goto_blocked seed 2 with the make-way on, reports/give24.md)
            bearing = self._bearing_ahead(rx, ry)
            view = min(view, LEAVE_VIEW)
        if abs(bearing) > view:
            # keep her in view (the laser and the camera look ahead; the attention lets a partner go
            # who is not seen for a while): turn towards her, then go on aside; not while a corner
            # would swing into her or anyone
            w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.8 * bearing))
            # not across a door frame it stands in (AXIS_TURN): turned as far as that allows, it goes on aside
            w = self._axis_turn(w)
            if w != 0.0:
                bodies = self._bodies(rx, ry)
                v, w = self._swept(0.0, w, mapped)
                return (v, w) if people_sweep_clear(v, w, bodies, duration=SWEEP_TIME, gap=TURN_GAP) else (0.0, 0.0)
        pts = self.scan.points()
        if len(mapped):
            pts = np.concatenate((pts, mapped))
        people = self.people.around(self.odom, self.now, near=(px, py))
        partner = np.array([(rx, ry)])
        people = np.concatenate((people, partner)) if len(people) else partner
        limits = replace(self.limits, max_speed=min(self.limits.max_speed, GIVE_WAY_SPEED))
        v_pref = heading_speed(GIVE_WAY_SPEED, math.atan2(gy, gx))
        cmd = dwa(self.v, self.w, (gx, gy), pts, limits, v_pref=v_pref, params=self.params, people=people)
        out = self._aside_clear(cmd.v, cmd.w, self._bodies(rx, ry), pts)
        if abs(out[0]) < AXIS_CREEP:  # turning on the spot toward the spot: not across a door frame (AXIS_TURN)
            out = (out[0], self._axis_turn(out[1]))
            if abs(out[0]) < 1e-9 and abs(out[1]) < 1e-9:
                out = (0.0, 0.0)
        return self._unstall(out, px, py, mapped, step_back=step_back)

    def _make_way(self, px: float, py: float, mapped: np.ndarray) -> tuple[float, float] | None:
        """The command that backs the robot out of the way of someone held back by it (they walked at it,
        :data:`MAKE_WAY_WALK`, then stood close in front for :data:`MAKE_WAY_HELD` s; never the partner at
        odom ``px, py``, nor anyone no nearer than she is), None when nobody is or it cannot back. It backs
        straight the way it came (ground it drove over or saw free, nobody tracked behind, the floor plan's
        sweep and everyone's body kept clear) while they stay close ahead and follow it no faster than
        :data:`MAKE_WAY_WALK` (held back, they keep up with it) for at most :data:`MAKE_WAY_TIME` s: the way
        they came from is free, and where they go (a door beside it) it cannot know, so no spot beside."""
        if self.odom is None:
            return None
        rows = self.people.tracks(self.odom, self.now, exclude=self.partner_id)
        echoes = self.scan.points()
        prx, pry = self._to_robot(px, py)
        her = math.hypot(prx, pry)
        held: dict[str, tuple[float, float]] = {}
        oncoming = {k: t for k, t in self._oncoming.items() if self.now - t <= MAKE_WAY_MEMORY}  # (bounded: recent walkers)
        best = None
        backing = self._making_way is not None and self.now - self._making_way[0] <= MAKE_WAY_TIME
        for tid, x, y, vx, vy, var in rows:
            r = math.hypot(x, y)
            if math.hypot(x - prx, y - pry) < HELD_UP_SELF or r >= her:
                continue  # her (a second track on her legs), or nobody between them
            if x > 0.0 and r < MAKE_WAY_SEEN and -(x * vx + y * vy) / max(r, 1e-6) >= MAKE_WAY_WALK:
                oncoming[tid] = self.now
            came = oncoming.get(tid)
            if came is None or x <= 0.0 or r >= MAKE_WAY_NEAR:
                continue
            if var > HELD_UP_SURE and not (len(echoes) and float(np.min(np.hypot(echoes[:, 0] - x, echoes[:, 1] - y))) < HELD_UP_ECHO):
                continue  # coasting where the laser sees nothing: nobody there (a child's legs hidden by her brother's: an echo)
            if math.hypot(vx, vy) < GIVE_WAY_STILL:
                since = self._held_back.get(tid, (self.now, self.now))[0]
                held[tid] = (since, self.now)
                if self.now - since >= MAKE_WAY_HELD and (best is None or r < best[0]):
                    best = (r, x, y)
            elif backing and math.hypot(vx, vy) < MAKE_WAY_WALK and (best is None or r < best[0]):
                best = (r, x, y)  # following it as it backs: still held back
        for tid, (since, last) in self._held_back.items():  # a moment unsure or unseen (legs hidden): still there
            if tid not in held and self.now - last <= HELD_UP_GAP:
                held[tid] = (since, last)
        self._held_back, self._oncoming = held, oncoming
        if best is None:
            self._making_way = None
            return None
        if not backing:
            self._making_way = (self.now,)
        self._aside = None  # (no step toward her meanwhile)
        if not self.can_back_off():
            return None
        v, w = self._swept(-min(self.limits.max_reverse, MAKE_WAY_SPEED), 0.0, mapped)
        if v >= 0.0:
            return None
        v, w = self._back_off_clear(v, 0.0, self._bodies(prx, pry), mapped)
        return (v, w) if v < 0.0 else None

    def _make_room(self, px: float, py: float, mapped: np.ndarray) -> tuple[float, float] | None:
        """The command that makes room for someone who would not let it pass (asked :data:`ASK_MAX` times; see
        :data:`ASK_MAX`), None when it is not making room (it follows). It backs along its own trail (the crumbs it
        left driving forward: ground it drove over) toward the point :data:`ROOM_CARROT` m back, at
        :data:`MAKE_WAY_SPEED`, gentler turns tried first, each step's sweep kept off the floor plan, nobody tracked
        behind it, and every person's body (the partner's, odom ``px, py``, too) left no nearer than now
        (:func:`backs_away`), until everyone standing ahead is :data:`ROOM_CLEAR` m off or it has backed
        :data:`ROOM_BACK` m (or its trail ends); then it stands (0, 0). It follows on once nobody has stood within
        :data:`BLOCK_SAME` m of the blockage for :data:`ROOM_FREE` s; someone standing there (the blocker shuffling,
        the one behind him now in front) keeps it."""
        b = self._block
        if b is None or b[4] == "asking" or self.odom is None:
            return None
        ox, oy, oth = self.odom
        c, s = math.cos(oth), math.sin(oth)
        prx, pry = self._to_robot(px, py)
        pts = self.scan.points()
        standing = self.people.around(self.odom, self.now, exclude=self.partner_id, near=(px, py), standing=GIVE_WAY_STILL,
                                      echoes=pts if len(pts) else None)
        here = [(float(x), float(y)) for x, y in standing[:, :2]] if len(standing) else []
        for t, sx, sy in self._standers:  # remembered standing where the laser still sees something (_held_up's memory)
            x, y = self._to_robot(sx, sy)
            if self.now - t <= HELD_UP_MEMORY and len(pts) and float(np.min(np.hypot(pts[:, 0] - x, pts[:, 1] - y))) < HELD_UP_ECHO:
                here.append((x, y))
        there = None
        ahead = math.inf  # the nearest person ahead, walking or standing (held back, they follow it as it backs)
        everyone = self.people.around(self.odom, self.now, exclude=self.partner_id, near=(px, py),
                                      echoes=pts if len(pts) else None)
        for x, y in [(float(x), float(y)) for x, y in everyone[:, :2]] + here if len(everyone) else here:
            if x > 0.0 and math.hypot(x - prx, y - pry) >= HELD_UP_SELF:
                ahead = min(ahead, math.hypot(x, y))
        for x, y in here:
            if math.hypot(x - prx, y - pry) < HELD_UP_SELF:
                continue  # her
            sx, sy = ox + c * x - s * y, oy + s * x + c * y
            gap = math.hypot(sx - b[0], sy - b[1])
            if gap < BLOCK_SAME and (there is None or gap < there[0]):
                there = (gap, sx, sy)
        if there is None:
            b[6] = self.now if b[6] is None else b[6]
            if self.now - b[6] >= ROOM_FREE:
                b[4], b[6] = "asking", None  # the way has cleared: it follows on (asks no more for this blockage)
                return None
        else:
            b[0], b[1], b[3], b[6] = there[1], there[2], self.now, None
        if b[4] == "waiting" and ahead < ROOM_CLEAR - 0.2:
            b[4] = "backing"  # they came after it: a little further, if its trail allows
        if b[4] == "backing":
            backed = math.hypot(ox - b[5][0], oy - b[5][1])
            goal = self._trail_back()
            if ahead >= ROOM_CLEAR or backed >= ROOM_BACK or goal is None:
                b[4] = "waiting"
            else:
                cmd = self._room_step(goal, prx, pry, mapped)
                if cmd is not None:
                    return cmd
        return 0.0, 0.0

    def _trail_back(self) -> tuple[float, float] | None:
        """The point of its own trail (the crumbs, odom) :data:`ROOM_CARROT` m back from the one nearest it, robot
        frame; None when the trail ends sooner (it has not driven there) or it stands off its trail."""
        if self.odom is None or not self.crumbs:
            return None
        x, y = self.odom[0], self.odom[1]
        crumbs = list(self.crumbs)
        k = min(range(len(crumbs)), key=lambda i: (math.hypot(crumbs[i][0] - x, crumbs[i][1] - y), -i))
        if math.hypot(crumbs[k][0] - x, crumbs[k][1] - y) > CRUMB_NEAR + CRUMB:
            return None
        for j in range(k, -1, -1):
            if math.hypot(crumbs[j][0] - x, crumbs[j][1] - y) >= ROOM_CARROT:
                return self._to_robot(*crumbs[j])
        return None

    def _trail_reverse(self, v: float, w: float, rx: float, ry: float, mapped: np.ndarray) -> tuple[float, float]:
        """Backing off from her (robot frame ``rx, ry``) with the straight reverse refused by the floor plan or a
        body: a step back along its own trail (:meth:`_trail_back`; of the reverse toward it and gentler turns,
        the first whose sweep keeps off the floor plan and brings nobody nearer, nobody tracked behind:
        :meth:`_room_step`), else ``(v, w)`` unchanged. Turned to her as she walked back at it along a 1.0 m
        corridor, its straight reverse led onto the corridor's wall and it stood there, her way back through
        the corridor blocked for the rest of the run (fresh13 rail_walk_back_pass seed 0)."""
        goal = self._trail_back()
        if goal is None:
            return v, w
        step = self._room_step(goal, rx, ry, mapped)
        if step is None or step[0] >= 0.0:
            return v, w
        return step

    def _room_step(self, goal: tuple[float, float], prx: float, pry: float, mapped: np.ndarray) -> tuple[float, float] | None:
        """One step back toward ``goal`` (robot frame, behind it on its trail): of the reverse command and gentler
        turns, the first whose sweep keeps off the floor plan and brings nobody's body nearer (:func:`backs_away`,
        her at ``prx, pry`` included), with nobody tracked behind; None when none is."""
        v, w = reverse_command(goal, speed=min(self.limits.max_reverse, MAKE_WAY_SPEED), max_turn=self.limits.max_turn)
        pts = self.scan.points()
        people = self.people.around(self.odom, self.now, echoes=pts if len(pts) else None)  # type: ignore[arg-type]
        if v < 0.0 and not behind_clear(people, length=FOOTPRINT[0], width=FOOTPRINT[1], reach=BACK_REACH):
            return None
        bodies = np.concatenate((people[:, :2], [(prx, pry)])) if len(people) else np.array([(prx, pry)])
        here = sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1) if len(mapped) else math.inf
        for cand in ((v, w), (v, w / 2), (v, w / 4), (v, 0.0), (0.0, w)):
            if cand == (0.0, 0.0):
                continue
            if len(mapped) and not sweep_allowed(cand[0], cand[1], mapped, here):
                continue
            if not backs_away(cand[0], cand[1], bodies):
                continue
            return cand
        return None

    def _unstall(self, cmd: tuple[float, float], px: float, py: float, mapped: np.ndarray,
                 step_back: bool = False) -> tuple[float, float]:
        """The forward give-way's command ``cmd``; when it has stayed zero for :data:`GIVE_WAY_STALL` s
        (the spot lies beside her and every step toward it swings a corner into her: galley_follow_bend,
        the approach ended just inside a dead-end room's door with her 0.5 m in front), or has got it nowhere
        for that long (:meth:`_aside_stuck`), the robot backs out of her way instead (:func:`~robot.navigation.giveway.back_out_spot`), if there is a way."""
        stall = self._aside_stall
        stuck = self._aside_stuck()  # commands, but no progress
        if cmd != (0.0, 0.0) and not stuck:
            self._aside_stall = None
            return cmd
        if not stuck:
            if stall is None or self.now - stall[1] > 0.5:  # (a new stall, not one from an earlier give-way)
                self._aside_stall = (self.now, self.now)
                return cmd
            self._aside_stall = (stall[0], self.now)
            if self.now - stall[0] < GIVE_WAY_STALL:
                return cmd
        if self.route.grid is None or self.odom is None:
            return cmd
        if not step_back:
            self._aside_stall = None
        failed = self._backout_failed
        rx_, ry_ = self.odom[0], self.odom[1]
        if (failed is not None and self.now - failed[0] < BACKOUT_RETRY
                and math.hypot(rx_ - failed[1], ry_ - failed[2]) < BACKOUT_MOVED
                and math.hypot(px - failed[3], py - failed[4]) < BACKOUT_MOVED):
            # the same search found no way out a moment ago from here with her there: not again every
            # stall (fresh hall_catch_up_fast seed 1: 39 searches of ~33 whole-grid plans each, half the run)
            return self._step_back(cmd, px, py, mapped) if step_back else cmd
        path = back_out_spot(self.route.grid, self.route.to_map(self.odom[:2]), self.route.to_map((px, py)),
                             keep=self.band[0], came=self._came_from())
        if path is None:
            self._backout_failed = (self.now, rx_, ry_, px, py)
            return self._step_back(cmd, px, py, mapped) if step_back else cmd
        self._aside_stall = None
        self._backout_failed = None
        self._aside = ([self.route.to_odom(p) for p in path], self.now + GIVE_WAY_TIME, True)
        return cmd

    def _step_back(self, cmd: tuple[float, float], px: float, py: float, mapped: np.ndarray) -> tuple[float, float]:
        """The stalled give-way's last resort when no back-out spot exists either: a step back that takes its
        footprint away from her (odom ``px, py``) while she stands ahead (:func:`back_off_away`), onto ground it
        drove over or saw free (:meth:`can_back_off`): of straight back and backing while turning either way, at
        the back-off's speed, a half or a quarter of it, the one that leaves the footprint furthest from her way
        out (:meth:`_her_way`: from her to the door it came through), at least :data:`STEP_BACK_GAIN` m further than now, its sweep kept off the floor plan
        (:func:`sweep_allowed`) and everyone's body (the social gap, or no nearer than now); else ``cmd``. The
        stall is kept (it goes on step by step while the give-way is asked for).
        tests/scenarios/follow/long23_hall_rooms_both_sides.xml on integ: come up to her just inside a 0.9 m
        door, the spot deeper in the room, its first turn refused by her body, no back-out path: it stood in her
        way out at speed 0 for the rest of the run (straight back away from her led along her way onto the
        door's jamb: backing while turning takes it off her way)."""
        rx, ry = self._to_robot(px, py)
        if not back_off_away(rx, ry) or not self.can_back_off():
            return cmd
        here = sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1) if len(mapped) else math.inf
        her = self._her_way(rx, ry)
        now = float(footprint_distance(her[:, 0], her[:, 1]).min())
        bodies = self._bodies(rx, ry)
        v, turn = -min(self.limits.max_reverse, MAKE_WAY_SPEED), self.limits.max_turn
        best, score = cmd, now + STEP_BACK_GAIN
        for k in (1.0, 0.5, 0.25):
            for w in (0.0, turn / 4, -turn / 4, turn / 2, -turn / 2):
                x, y, th = arcs(np.array([v * k]), np.array([w]), np.array([SWEEP_TIME]))
                c, s_ = math.cos(float(th[0][0])), math.sin(float(th[0][0]))
                dx, dy = her[:, 0] - float(x[0][0]), her[:, 1] - float(y[0][0])
                after = float(footprint_distance(c * dx + s_ * dy, -s_ * dx + c * dy).min())
                if after <= score:
                    continue
                if len(mapped) and not sweep_allowed(v * k, w, mapped, here):
                    continue
                if not people_sweep_clear(v * k, w, bodies, duration=SWEEP_TIME):
                    continue
                best, score = (v * k, w), after
        return best

    def _leaving(self, px: float, py: float, tr: dict[str, Any]) -> tuple[float, float] | None:
        """Where (odom) she walks out to when she walks toward the way the robot came in by and the robot stands on
        it (following her into a small room, it stands in the door's mouth; she turns to leave), else None.
        Her way out is the segment from her (odom ``px, py``) to the robot's own position :data:`CAME_FROM` m back
        along where it drove (the door it came through); she walks toward it (at least :data:`WALKING`,
        within :data:`LEAVE_HEADING` of it) within :data:`LEAVE_NEAR` m of the robot but not yet within the near band
        (``band[0]``: there the near band's give-way acts; long23 seed 3: begun with her 0.84 m off, the turn aside took
        her out of view as she passed its side, and it lost her at the next door), and the robot's centre lies
        between her and that point, closer to the segment than :data:`~robot.navigation.giveway.LATERAL` (where
        she could not pass it). Only its own odometry and her track go into it."""
        if self.odom is None or not self.route.ready:
            return None
        vx, vy = tr["vx"], tr["vy"]
        speed = math.hypot(vx, vy)
        if speed < WALKING:
            return None  # (turning round where she stopped moves her track too: library home_tour seed 2 on ea4daf0)
        x, y = self.odom[0], self.odom[1]
        if not self.band[0] < math.hypot(px - x, py - y) <= LEAVE_NEAR:
            return None  # (closer, the near band's give-way and back-off act: turning aside then turned her out of view)
        out = None
        for cx, cy in reversed(self.crumbs):
            if math.hypot(cx - x, cy - y) >= CAME_FROM:
                out = (cx, cy)
                break
        if out is None:
            return None
        wx, wy = out[0] - px, out[1] - py
        n = math.hypot(wx, wy)
        if n < 1e-6 or (vx * wx + vy * wy) < math.cos(LEAVE_HEADING) * speed * n:
            return None
        along = ((x - px) * wx + (y - py) * wy) / n
        if not 0.0 < along < n:
            return None
        if float(way_distance(np.array([x]), np.array([y]), (px, py), out)[0]) >= LATERAL:
            return None
        return out

    def _bearing_ahead(self, rx: float, ry: float) -> float:
        """Her bearing (robot frame; she is at ``rx, ry``) :data:`SWEEP_TIME` s from now, from her track's velocity and
        the robot's own turn rate (odometry): she walks past its side while it turns away from her."""
        tr = self.track
        if tr is None or self.odom is None:
            return math.atan2(ry, rx)
        c, s = math.cos(self.odom[2]), math.sin(self.odom[2])
        vrx, vry = c * tr["vx"] + s * tr["vy"], -s * tr["vx"] + c * tr["vy"]
        d2 = max(rx * rx + ry * ry, 1e-6)
        ahead = math.atan2(ry, rx) + ((rx * vry - ry * vrx) / d2 - self.w) * SWEEP_TIME
        return math.atan2(math.sin(ahead), math.cos(ahead))

    def _before_her(self, px: float, py: float) -> bool:
        """Whether the robot still lies between her (odom ``px, py``) and the way out it makes way for (not passed)."""
        wx, wy = self._leave_way[0] - px, self._leave_way[1] - py
        n = math.hypot(wx, wy)
        if self.odom is None or n < 1e-6:
            return False
        return ((self.odom[0] - px) * wx + (self.odom[1] - py) * wy) / n > 0.0

    def _her_way(self, rx: float, ry: float) -> np.ndarray:
        """Robot-frame points every 0.1 m along her way out as far as the robot can tell: from her (``rx, ry``)
        to where the robot drove from, :data:`CAME_FROM` m back along its own trail (she leads it back out the
        way they came: the door it came through); her point alone when it has not driven that far."""
        if self.odom is None:
            return np.array([(rx, ry)])
        x, y = self.odom[0], self.odom[1]
        for cx, cy in reversed(self.crumbs):
            if math.hypot(cx - x, cy - y) >= CAME_FROM:
                bx, by = self._to_robot(cx, cy)
                n = max(2, int(math.hypot(bx - rx, by - ry) / 0.1) + 1)
                t = np.linspace(0.0, 1.0, n)
                return np.stack((rx + t * (bx - rx), ry + t * (by - ry)), axis=1)
        return np.array([(rx, ry)])

    def _aside_stuck(self) -> bool:
        """Whether the forward give-way has got nowhere for :data:`GIVE_WAY_STALL` s although it sends commands:
        it neither moved :data:`STUCK_MOVE` nor turned :data:`STUCK_TURN` net (the dynamic window turning a little
        to and fro, a corner at a jamb, her 0.5 m in front: tests/scenarios/follow/laundry_stop_in_door.xml seed 3
        on integ stood so in the door for the rest of the run, its command never quite zero, so :meth:`_unstall`
        never backed it out). A new window opens on progress or when the give-way was not asked for 0.5 s."""
        if self.odom is None:
            return False
        x, at = self.odom, self._aside_moving
        if (at is None or self.now - at[4] > 0.5 or math.hypot(x[0] - at[1], x[1] - at[2]) > STUCK_MOVE
                or abs(math.remainder(x[2] - at[3], math.tau)) > STUCK_TURN):
            self._aside_moving = (self.now, x[0], x[1], x[2], self.now)
            return False
        self._aside_moving = (at[0], at[1], at[2], at[3], self.now)
        return self.now - at[0] >= GIVE_WAY_STALL

    def _walk_on(self, start: tuple[float, float], v: tuple[float, float], duration: float) -> tuple[float, float]:
        """``start`` (odom) carried on at velocity ``v`` for ``duration`` s, in steps of a quarter second,
        never through a wall or furniture of the floor plan. A step that would cross one turns, as a person
        walking along a passage does, to the heading whose way on runs furthest free (:meth:`_walk_turn`:
        :data:`WALK_RUN` steps at most; of equal runs the lesser turn), and she walks on that way;
        never more than :data:`WALK_BACK` off her heading (she does not walk back); where no step is free she stops
        (bend23, fresh11 twin_passage_chat: she turned round the blind bend of a 1.0 m passage, the point
        stopped on the passage's wall short of the bend and the robot stood in the straight leg until it
        declared her lost)."""
        x, y = start
        vx, vy = v
        for _ in range(int(max(0.0, duration) / 0.25)):
            nx, ny = x + vx * 0.25, y + vy * 0.25
            if not self._step_free((x, y), (nx, ny)):
                turned = self._walk_turn((x, y), (vx, vy), v)
                if turned is None:
                    break
                vx, vy = turned
                nx, ny = x + vx * 0.25, y + vy * 0.25
            x, y = nx, ny
        return x, y

    def _step_free(self, a: tuple[float, float], b: tuple[float, float]) -> bool:
        """A step of the walked-on search point from ``a`` to ``b`` (odom): through no wall or furniture of the
        floor plan, and ending no nearer to them than :data:`WALL_BODY` unless it comes no nearer than it was
        (a person's centre keeps off the walls: a point on a wall is never seen empty, nor someone's place)."""
        if not self.route.in_sight(a, b):
            return False
        cb = self.route.clearance(b)
        return cb >= WALL_BODY or cb >= self.route.clearance(a)

    def _walk_turn(self, at: tuple[float, float], v: tuple[float, float],
                   first: tuple[float, float]) -> tuple[float, float] | None:
        """Where she walks on from ``at`` when the step at velocity ``v`` is not free: of the headings within
        :data:`WALK_BACK` of her heading when last seen (``first``, in :data:`WALK_STEP` steps: she does not walk
        back), those whose quarter-second steps run :data:`WALK_AHEAD` free or all :data:`WALK_RUN` of them
        without crossing the floor plan are ways on, and of those she takes the one nearest ``v`` (the least
        turn), of equal turns the longer run, then the one ending furthest off the walls; with no way on, the
        longest run (of equal runs the least turn); None when no heading has a free step (a dead end)."""
        best: tuple[float, float] | None = None
        rank: tuple[int, float, float, float] = (0, 0.0, 0.0, 0.0)
        speed, base, now = math.hypot(*v), math.atan2(first[1], first[0]), math.atan2(v[1], v[0])
        n = int(round(WALK_BACK / WALK_STEP))
        for i in range(-n, n + 1):
            h = base + i * WALK_STEP
            tv = (speed * math.cos(h), speed * math.sin(h))
            k, (x, y) = 0, at
            while k < WALK_RUN:
                nx, ny = x + tv[0] * 0.25, y + tv[1] * 0.25
                if not self._step_free((x, y), (nx, ny)):
                    break
                k, x, y = k + 1, nx, ny
            # a way on: the least turn, of equal turns the longer run, of equal runs (either way) the one that ends
            # furthest off the walls (along a wall met head-on: the way she drifted); else the longest run
            turn = -round(abs(math.remainder(h - now, math.tau)), 6)
            on = k == WALK_RUN or k * speed * 0.25 >= WALK_AHEAD - 1e-9
            key = (1, turn, k, self.route.clearance((x, y))) if on else (0, k, turn, self.route.clearance((x, y)))
            if k > 0 and (best is None or key > rank):
                best, rank = tv, key
        return best

    def _count_yield(self, approaching: bool, seen: bool) -> float:
        """Seconds since she was last seen that the robot spent yielding to someone near it
        (:func:`robot.partner_search.yielding`, the attention's rule: held up by a person crossing its
        way it does not search, so that time is not search time); reset when she is seen."""
        last, self._yield_t = self._yield_t, self.now
        if seen or approaching or self.odom is None:
            self._yielded = 0.0
        elif last is not None and self.now - last <= 1.0:
            others = self.people.around(self.odom, self.now, exclude=self.partner_id)
            if yielding(others[:, :2] if len(others) else ()):
                self._yielded += self.now - last
        return self._yielded

    def _closed(self, seen: bool) -> float:
        """Seconds since she was last seen that the robot spent on its way to where it looks for her, still
        further than :data:`~robot.partner_search.CLOSING_NEAR` from that point and coming nearer
        (:class:`robot.partner_search.Closing`; the attention reads the same rule from this module's status,
        whose distance is to that point): the search proper begins there, so it ends on evidence, not on a
        clock set when she went out of view. Reset when she is seen. Approaching her after a stop (she stands
        where she was last seen) the same: on its way there."""
        if self._closing is None:
            return 0.0
        if seen or self.odom is None:
            self._closing.reset()
        return self._closing.total

    def _came_from(self) -> tuple[float, float] | None:
        """Where the robot drove from (map frame): its latest own position (odometry, driving forwards)
        at least :data:`CAME_FROM` m from where it stands, None when it has not driven that far. Backing
        out into a corridor, it waits on the other side (:func:`~robot.navigation.giveway.back_out_spot`)."""
        if self.odom is None:
            return None
        x, y = self.odom[0], self.odom[1]
        for cx, cy in reversed(self.crumbs):
            if math.hypot(cx - x, cy - y) >= CAME_FROM:
                return self.route.to_map((cx, cy))
        return None

    def _back_off_clear(self, v: float, w: float, bodies: np.ndarray, mapped: np.ndarray) -> tuple[float, float]:
        """Backing off while turning to face her, made safe against everyone's body (``bodies``, robot
        frame, hers included): the footprint swept :data:`SWEEP_TIME` s keeps
        :data:`~robot.navigation.local.SOCIAL_GAP` from each, or no nearer than now
        (:func:`~robot.navigation.local.people_sweep_clear`); else straight back, else the turn alone
        (held to :func:`~robot.navigation.local.turn_clear` by the caller). Backing at 0.2 m/s while
        turning at 1.75 rad/s toward her as she walked up swung a front corner into her
        (u_catch_up_slow seed 5, 92.44 s): the wait's turn was checked only when it stood."""
        if people_sweep_clear(v, w, bodies, duration=SWEEP_TIME):
            return v, w
        if w != 0.0 and self._swept(v, 0.0, mapped) == (v, 0.0) and people_sweep_clear(v, 0.0, bodies, duration=SWEEP_TIME):
            return v, 0.0
        return self._swept(0.0, w, mapped)

    def _aside_clear(self, v: float, w: float, bodies: np.ndarray, pts: np.ndarray) -> tuple[float, float]:
        """The dynamic window's give-way command (``v``, ``w``) made safe against everyone's body
        (``bodies``, robot frame, the partner's included): its footprint swept :data:`SWEEP_TIME` s, at
        poses dense enough for any turn rate, keeps :data:`~robot.navigation.local.SOCIAL_GAP` from each
        (:data:`~robot.navigation.local.TURN_GAP` turning on the spot), or no nearer than now
        (:func:`~robot.navigation.local.people_sweep_clear`). The window checks people at six poses over
        1.6 s and exempts turns on the spot: giving way forwards at 1.4 rad/s with the partner
        0.6-0.9 m away, a corner touched her (u_catch_up_slow seed 5). Gentler turns first (they swing
        the corners less), kept off the laser's echoes and the floor plan (``pts``); else it stands.
        Never driving toward someone whose body is already nearer than
        :data:`~robot.navigation.local.SOCIAL_GAP` to the footprint and ahead of its centre in the
        direction it would drive (:func:`_crowds`): "no nearer than now" let it creep forward past the
        partner who stood 0.1-0.2 m from its side at a shelf (follow/stops_beside_shelf seed 1, 0.124 m
        while moving); it stands instead, and backs out of her way if that lasts (:meth:`_unstall`)."""
        here = sweep_clearance(0.0, 0.0, pts, 0.0, steps=1) if len(pts) else math.inf
        for k, cand in enumerate(((v, w), (v, w / 2), (v, w / 4), (v, 0.0))):
            if cand == (0.0, 0.0):
                break
            if _crowds(cand[0], bodies):
                break  # the same v for every candidate
            if k and not sweep_allowed(cand[0], cand[1], pts, here):
                continue  # the window's own choice is already kept off the echoes
            if people_sweep_clear(cand[0], cand[1], bodies, duration=SWEEP_TIME,
                                  gap=TURN_GAP if cand[0] == 0.0 else SOCIAL_GAP):
                return cand
        return 0.0, 0.0

    def _back_out(self, goal: tuple[float, float], partner: tuple[float, float], mapped: np.ndarray) -> tuple[float, float]:
        """Reversing along a back-out path (``goal``: its pure-pursuit point, robot frame): slowly, the
        footprint's sweep kept off the floor plan's walls and furniture (no laser behind) and no
        closer to anyone's body (``partner`` in front included: turning swings the corners) than
        :data:`~robot.navigation.local.SOCIAL_GAP` or than it is, never toward a person the
        attention tracks behind it."""
        v, w = reverse_command(goal, speed=min(self.limits.max_reverse, GIVE_WAY_SPEED), max_turn=self.limits.max_turn)
        w = self._axis_turn(w)  # straight out of a door frame, not across it (AXIS_TURN)
        pts = self.scan.points()
        people = self.people.around(self.odom, self.now, echoes=pts if len(pts) else None)  # type: ignore[arg-type]
        if v < 0.0 and not behind_clear(people, length=FOOTPRINT[0], width=FOOTPRINT[1], reach=BACK_REACH):
            v = 0.0
        bodies = np.concatenate((people[:, :2], [partner])) if len(people) else np.array([partner])
        here = sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1) if len(mapped) else math.inf
        for cand in ((v, w), (v, w / 2), (v, w / 4), (v, 0.0), (0.0, w)):  # gentler turns swing the front less
            if cand == (0.0, 0.0):
                continue
            if not sweep_allowed(cand[0], cand[1], mapped, here):
                continue
            # per body and at poses dense enough for the turn rate (six over 0.5 s missed corners)
            if not people_sweep_clear(cand[0], cand[1], bodies, duration=SWEEP_TIME):
                continue
            self._backout_refused = None
            return cand
        refused = self._backout_refused
        if refused is None or self.now - refused[1] > 0.5:  # a new refusal, not one of an earlier back-out
            self._backout_refused = (self.now, self.now)
            return 0.0, 0.0
        self._backout_refused = (refused[0], self.now)
        if self.now - refused[0] < BACKOUT_ALIGN or not len(mapped):
            return 0.0, 0.0
        return self._free_turn(v, bodies, mapped, here)

    def _still_in_her_way(self, aside: tuple[float, float] | None, d: float, px: float, py: float,
                          mapped: np.ndarray) -> tuple[float, float] | None:
        """Following, the give-way's command ``aside`` (None: no give-way here) with her (odom ``px, py``) ``d`` m
        off: when every give-way and back-out command has stayed zero for :data:`GIVE_WAY_STALL` s with her within
        :data:`IN_WAY_NEAR` and the robot in a door frame or a passage, a step back off her way (:meth:`_step_back`);
        with none either for :data:`IN_WAY_ASK` s, the ES event ``in_her_way`` (the dialog: "I am in your way. Could
        you step back a little, please?"), at most every :data:`IN_WAY_EVERY` s. review24 F0: no step it can take
        must leave it standing in her only way out without a word."""
        if (aside not in (None, (0.0, 0.0)) or d >= IN_WAY_NEAR or self.odom is None
                or self.route.clearance(self.odom[:2]) >= NARROW):
            self._in_way_since = None
            return aside
        if self._in_way_since is None or self.now - self._in_way_last > 0.5:  # (a new stand, not an old one)
            self._in_way_since = self.now
        self._in_way_last = self.now
        if self.now - self._in_way_since < GIVE_WAY_STALL:
            return aside
        if aside is not None:
            out = self._step_back(aside, px, py, mapped)
            if out != aside:
                self._in_way_since = self.now  # it moves: the stand begins again
                return out
        if self.now - self._in_way_since >= IN_WAY_ASK and self.now - self._in_way_asked >= IN_WAY_EVERY:
            self._in_way_asked = self.now
            rx, ry = self._to_robot(px, py)
            self.bus.publish(ES_EVENTS, etree.Element("event", name="in_her_way", bearing=f"{math.degrees(math.atan2(ry, rx)):.1f}",
                                                      distance=f"{d:.2f}"))
        return aside

    def _axis_turn(self, w: float) -> float:
        """The turn rate ``w`` limited so that, standing in a door frame or a passage (:func:`passage_axis` on the
        floor plan), its heading a sweep from now (:data:`SWEEP_TIME`) stays within :data:`AXIS_TURN` of the passage's
        axis (either way along it); a turn back toward the axis is never limited; ``w`` itself off a passage or
        without a floor plan."""
        if w == 0.0 or self.odom is None:
            return w
        route = getattr(self, "route", None)  # (tests build followers without one)
        grid = getattr(route, "grid", None)
        if not isinstance(grid, OccupancyGrid) or not getattr(route, "ready", True):
            return w
        x, y, th = self.odom
        a = self.route.to_map((x, y))
        axis = passage_axis(grid, a)
        if axis is None:
            return w
        b = self.route.to_map((x + math.cos(th), y + math.sin(th)))
        heading = math.atan2(b[1] - a[1], b[0] - a[0])  # (map frame)
        off = axis_offset(heading, axis)
        after = axis_offset(heading + w * SWEEP_TIME, axis)  # (either way along the axis: past 90 degrees it nears the other)
        if abs(after) <= AXIS_TURN or abs(after) <= abs(off):
            return w
        w2 = (math.copysign(AXIS_TURN, off + w * SWEEP_TIME) - off) / SWEEP_TIME
        return w2 if w2 * w > 0.0 else 0.0

    def _free_turn(self, v: float, bodies: np.ndarray, mapped: np.ndarray, here: float) -> tuple[float, float]:
        """Backing out of her way with every reverse step refused for :data:`BACKOUT_ALIGN` s: a slower step,
        kept as every back-out step is (:func:`sweep_allowed`, no nearer to anyone's ``bodies`` than the social
        gap or than now, the partner's included): backing at a half or a quarter of the back-out's speed ``v``
        (0 when someone is behind) while turning either way, the one that leaves the footprint furthest from
        the floor plan (``mapped``, robot frame); else a turn on the spot either way that takes it at least
        :data:`BACKOUT_GAIN` m further from the floor plan than now (``here``); else (0, 0).
        In a 0.9 m door it had come through, turned toward her with a rear corner 9 cm from a jamb and her
        0.5 m off its front corner, every step at the back-out's speed dipped under the sweep's margin at the
        jamb and every turn toward clearer ground swung a front corner toward her: it stood there, her only
        way out blocked, for the rest of the run (long22's cause B, fresh7/corr_long_tour seed 0, where a
        creep back at 0.05 m/s was allowed all along)."""
        turn = self.limits.max_turn
        best: tuple[float, float] = (0.0, 0.0)
        score = -math.inf
        backs = [(v * k, w) for k in (0.5, 0.25) for w in (0.0, turn / 4, -turn / 4, turn / 2, -turn / 2)] if v < 0.0 else []
        turns = [(0.0, w) for w in (turn / 4, -turn / 4, turn / 2, -turn / 2)]
        for group, floor in ((backs, -math.inf), (turns, here + BACKOUT_GAIN)):
            for cand in group:
                if self._axis_turn(cand[1]) != cand[1]:
                    continue  # not across a door frame (AXIS_TURN)
                x, y, th = arcs(np.array([cand[0]]), np.array([cand[1]]), np.array([SWEEP_TIME]))
                c, s_ = math.cos(float(th[0][0])), math.sin(float(th[0][0]))
                dx, dy = mapped[:, 0] - float(x[0][0]), mapped[:, 1] - float(y[0][0])
                after = float(footprint_distance(c * dx + s_ * dy, -s_ * dx + c * dy).min())
                if after <= max(score, floor) or not sweep_allowed(cand[0], cand[1], mapped, here):
                    continue
                if not people_sweep_clear(cand[0], cand[1], bodies, duration=SWEEP_TIME,
                                          gap=TURN_GAP if cand[0] == 0.0 else SOCIAL_GAP):
                    continue
                best, score = cand, after
            if best != (0.0, 0.0):
                return best
        return best

    def _unstick(self, v: float, w: float, mapped: np.ndarray) -> tuple[float, float]:
        """Wedged (issue 26: a chair's corner beside the robot when the way turns off; a door jamb at
        its front corner in a 0.9 m door): it should drive but the dynamic window finds no forward arc,
        and in :data:`STUCK_TIME` s it has neither moved :data:`STUCK_MOVE` nor turned :data:`STUCK_TURN`
        net (standing, or turning a little to and fro). Then it backs for :data:`UNSTICK_TIME` s over
        ground it drove or saw free (never where the laser did not look), which gives the corners room
        to turn, unless a forward arc opens first; nothing when backing is unsafe."""
        if abs(v) >= CRAWL or self.odom is None:
            self._stuck_since, self._stuck_at, self._unstick_until = None, None, -math.inf
            return v, w
        if self.now < self._unstick_until and self.can_back_off():
            back = self._swept(-UNSTICK_SPEED, 0.0, mapped)
            if back[0] < 0.0:
                return back
        self._unstick_until = -math.inf
        at, x = self._stuck_at, self.odom
        if (self._stuck_since is None or at is None or math.hypot(x[0] - at[0], x[1] - at[1]) > STUCK_MOVE
                or abs(math.remainder(x[2] - at[2], math.tau)) > STUCK_TURN):
            self._stuck_since, self._stuck_at = self.now, x  # progress (or a first step): a new window
            return v, w
        if self.now - self._stuck_since < STUCK_TIME or not self.can_back_off():
            return v, w
        back = self._swept(-UNSTICK_SPEED, 0.0, mapped)
        if back[0] < 0.0:
            self._unstick_until = self.now + UNSTICK_TIME
            self._stuck_since, self._stuck_at = None, None
        return back

    def _ahead(self, reach: float) -> tuple[float, float]:
        """The odom point ``reach`` m past the robot's front edge, straight ahead."""
        x, y, th = self.odom  # type: ignore[misc]
        r = FOOTPRINT[0] / 2 + reach
        return x + r * math.cos(th), y + r * math.sin(th)

    def _keep_inside(self, v: float, w: float) -> float:
        """``v``, or 0 where driving on would take the robot's front out of the flat (past the
        rooms of its floor plan: through an exit door after a partner who left, review of issue
        26). It stops in the door, inside; turning stays allowed."""
        if v <= 0.0 or self.route.inside(self._ahead(INSIDE_AHEAD + v * INSIDE_TIME)):
            return v
        return 0.0

    def _face_in(self) -> tuple[float, float] | None:
        """Facing out of the flat (through an exit door the search took it to, or at the outer wall
        beside it; a point :data:`FACING_OUT` m past its front is in none of the rooms): the
        command that turns it on the spot back toward the middle of the room it stands in, so
        the people in the flat can speak to it; None when it faces the flat (or cannot turn)."""
        if self.odom is None or not self.route.ready:
            return None
        ahead = self._ahead(FACING_OUT)
        # out of the flat, through an opening or at the outer wall beside it (a longer search takes
        # it into the exit door's corner, facing the jamb): the people are in the flat, behind it
        if self.route.inside(ahead):
            return None
        room = self.route.room_at(self.odom[:2])
        if room is None:
            return None
        cx, cy = self.route.to_odom((float(room[:, 0].mean()), float(room[:, 1].mean())))
        gx, gy = self._to_robot(cx, cy)
        bearing = math.atan2(gy, gx)
        w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.8 * bearing))
        if abs(bearing) < math.radians(8):
            return None
        _, w = self._swept(0.0, w, self.route.obstacles_near(self.odom))
        if w == 0.0:
            return None
        # no corner swung into anyone, her above all: she has just said stop standing close in front of it (held
        # back in a door it stood in); this turn at full rate, never checked against bodies, swung its corner
        # into her (fresh13 rail_wrong_corrections seeds 2 and 4: the only contacts with a person of that set)
        if not turn_clear(w, self._near_bodies(), duration=SWEEP_TIME):
            return None
        self._command(0.0, w)
        return 0.0, w

    def _near_bodies(self) -> np.ndarray:
        """Robot-frame centres of everyone near and of the partner's track where it was last seen (:meth:`_bodies`);
        everyone near alone without her track."""
        tr = self.track
        if tr is not None:
            return self._bodies(*self._to_robot(tr["x"], tr["y"]))
        near = self.people.around(self.odom, self.now)
        return near[:, :2] if len(near) else np.zeros((0, 2))

    def _standing(self, partner: tuple[float, float]) -> np.ndarray:
        """Odom-frame centres of the people standing about (not the partner, nor a second track on
        her legs): the route plans round them (robot.navigation.route)."""
        pts = self.scan.points()
        rel = self.people.around(self.odom, self.now, exclude=self.partner_id, near=partner,  # type: ignore[arg-type]
                                 echoes=pts if len(pts) else None, standing=0.2)
        if not len(rel):
            return rel
        ox, oy, oth = self.odom  # type: ignore[misc]
        c, s = math.cos(oth), math.sin(oth)
        return np.column_stack((ox + c * rel[:, 0] - s * rel[:, 1], oy + s * rel[:, 0] + c * rel[:, 1]))

    def _stand(self, approaching: bool, state: str) -> None:
        """Stop driving; following, say why (``state``); approaching, the approach is over."""
        self._halt()
        if approaching:
            self._end_approach()
        else:
            self._status(0.0, False, state)
        return None

    def _face(self, bearing: float) -> tuple[float, float] | None:
        """The approach's end: turn on the spot to face her (within :data:`FACED`), then stop."""
        if abs(bearing) < FACED:
            return self._stand(True, "")
        w = max(-self.limits.max_turn, min(self.limits.max_turn, 1.8 * bearing))
        v, w = self._swept(0.0, w, self.route.obstacles_near(self.odom))  # type: ignore[arg-type]
        if w == 0.0:
            return self._stand(True, "")  # no room to turn: the attention turns it when it can
        self._command(0.0, w)
        self._status(0.0, False, "approaching")
        return 0.0, w

    def _end_approach(self) -> None:
        self.approach_until = None
        self._status(0.0, False, "stopped")  # the attention may turn the base again
        self._listen_to_people(self.following)

    def _swept(self, v: float, w: float, mapped: np.ndarray) -> tuple[float, float]:
        """The wait's command made safe against the floor plan's walls and furniture (the corners
        sweep ground behind the laser): its footprint must keep :data:`SWEEP_MARGIN` from them, or
        (closer already) come no closer than it is (:func:`sweep_allowed`), and a back-off must leave room to turn on the spot (the centre :data:`TURN_ROOM` m from them; the
        attention turns the robot to face the partner once she stops), unless the command takes the
        robot further off than it is. Backing is dropped first, then turning."""
        if not len(mapped) or (v == 0.0 and w == 0.0):
            return v, w
        here = sweep_clearance(0.0, 0.0, mapped, 0.0, steps=1)
        room = float(np.hypot(mapped[:, 0], mapped[:, 1]).min())
        for cand in ((v, w), (v, 0.0), (0.0, w)):
            if cand == (0.0, 0.0):
                continue
            if not sweep_allowed(cand[0], cand[1], mapped, here):
                continue
            if cand[0] < 0.0:
                x, y, _ = arcs(np.array([cand[0]]), np.array([cand[1]]), np.array([SWEEP_TIME]))
                after = float(np.hypot(mapped[:, 0] - x[0, 0], mapped[:, 1] - y[0, 0]).min())
                if after < TURN_ROOM and after < room + 1e-3:
                    continue
            return cand
        return 0.0, 0.0

    def _blind_corners(self, mapped: np.ndarray) -> np.ndarray:
        """The floor plan's corners (``mapped``: its outline near the robot, robot frame) in the latest scan that the
        laser does not see round (robot frame; :func:`robot.navigation.blind.scan_corners`, once per scan)."""
        msg = self.scan.latest
        if msg is not self._corners_of:
            self._corners_of = msg
            self._corners = scan_corners(msg, mapped)
        return self._corners

    def _held_up(self, v: float, v_des: float, goal: tuple[float, float], px: float, py: float, *,
                 may_room: bool = True) -> bool:
        """Is someone standing in its way holding it up (it should drive, it does not)? After
        ``HELD_UP_TIME`` s of it, ``way_blocked`` goes to the ES with that person's bearing and
        distance (the dialog says "excuse me"), at most every ``warn_every`` s and at most
        :data:`ASK_MAX` times for one blockage; when the next ask would be due it makes room instead
        (``may_room``: following, not the catch-up; :meth:`_make_room`)."""
        blocker = None
        if v_des > HELD_UP_SPEED and v < min(HELD_UP_CRAWL, HELD_UP_SHARE * v_des) and self.odom is not None:
            n = math.hypot(*goal)
            ux, uy = (goal[0] / n, goal[1] / n) if n > 1e-6 else (1.0, 0.0)
            standing = self.people.around(self.odom, self.now, exclude=self.partner_id, near=(px, py), standing=GIVE_WAY_STILL,
                                          sure=HELD_UP_SURE)
            ox, oy, oth = self.odom
            c, s = math.cos(oth), math.sin(oth)
            here = [(float(x), float(y)) for x, y in standing[:, :2]] if len(standing) else []
            for x, y in here:
                if math.hypot(x, y) < HELD_UP_NEAR:
                    self._standers.append((self.now, ox + c * x - s * y, oy + s * x + c * y))
            while self._standers and self.now - self._standers[0][0] > HELD_UP_MEMORY:
                self._standers.popleft()
            echoes = self.scan.points()
            if self._standers and len(echoes):  # remembered where the laser still sees something (all at once:
                # up to HELD_UP_MEMORY s of them, each its nearest echo; the same differences, hence the same answers)
                them = [self._to_robot(sx, sy) for _, sx, sy in self._standers]
                xs, ys = np.array([[x] for x, _ in them]), np.array([[y] for _, y in them])
                seen = np.hypot(echoes[:, 0] - xs, echoes[:, 1] - ys).min(axis=1) < HELD_UP_ECHO
                here.extend(p for p, k in zip(them, seen.tolist()) if k)
            blocker = way_blocker(here, (ux, uy), self._to_robot(px, py))
        if blocker is None:
            return False
        if self._held_since is None or self.now - self._held_last > HELD_UP_GAP:
            self._held_since = self.now  # (gaps shorter than HELD_UP_GAP are bridged: a track beside it flickers at the laser's edge)
        self._held_last = self.now
        if self._held_back:  # someone who walked at it stands close in front: it is in their way, not they in its
            return True        # (it makes way once they have stood MAKE_WAY_HELD s; it asks nobody to let it pass)
        _, x, y = blocker
        ox, oy, oth = self.odom  # type: ignore[misc]
        c, s = math.cos(oth), math.sin(oth)
        sx, sy = ox + c * x - s * y, oy + s * x + c * y
        b = self._block
        if b is None or self.now - b[3] > BLOCK_FORGET or math.hypot(sx - b[0], sy - b[1]) > BLOCK_SAME:
            b = self._block = [sx, sy, 0, self.now, "asking", None, None]  # someone else, somewhere else: a new blockage
        b[0], b[1], b[3] = sx, sy, self.now
        if b[2] >= ASK_MAX and self.now - self._held_since >= HELD_UP_TIME and (
                self.now - self._excused_at >= self.warn_every or b[2] > ASK_MAX):
            if may_room:  # asked twice and still held up: it makes room (at once when held up there again)
                b[2], b[4], b[5], b[6] = ASK_MAX + 1, "backing", (ox, oy), None
            return True
        if self.now - self._held_since >= HELD_UP_TIME and self.now - self._excused_at >= self.warn_every:
            self._excused_at = self.now
            b[2] += 1
            self.bus.publish(ES_EVENTS, etree.Element("event", name="way_blocked", bearing=f"{math.degrees(math.atan2(y, x)):.1f}",
                                                      distance=f"{math.hypot(x, y):.2f}"))
        return True

    def _too_fast(self, d: float, at_limit: bool, speed: float = 0.0) -> None:
        """Warn (``partner_too_fast``) when she walks away faster than the robot can drive: at its
        speed limit for ``too_fast_time`` s, further than ``too_fast_distance`` and the gap still
        growing, and her tracked speed (``speed``, averaged over that time) above its top speed by
        20 % (:data:`TOO_FAST_RATIO`; issue 26 item 10: a partner at its own top speed was told to slow
        down; the gap then grows only on turns and in door frames, and it catches up when she stops)."""
        now = self.now
        if not at_limit:
            self._limit_since = None
            self._history.clear()
            return
        if self._limit_since is None:
            self._limit_since = now
        self._history.append((now, d, speed))
        while self._history and now - self._history[0][0] > self.too_fast_time:
            self._history.popleft()
        d0 = self._history[0][1]
        mean_speed = sum(h[2] for h in self._history) / len(self._history)
        if (now - self._limit_since >= self.too_fast_time and d > self.too_fast_distance and d - d0 > 0.05
                and mean_speed > self.limits.max_speed * TOO_FAST_RATIO and now - self._warned_at >= self.warn_every):
            self._warned_at = now
            self.bus.publish(ES_EVENTS, etree.Element("event", name="partner_too_fast", distance=f"{d:.2f}"))

    async def run(self) -> None:
        while True:
            self.beat()
            if self.following and not self._map_asked:
                await self._fetch_map()
            self.control_step()
            await asyncio.sleep(self.period)


def backs_away(v: float, w: float, bodies: np.ndarray, duration: float = SWEEP_TIME, steps: int = 5) -> bool:
    """Whether the command (``v``, ``w``) held ``duration`` s brings the footprint no nearer to any of ``bodies``
    (robot-frame centres of people, the partner included) than it is now, at every one of ``steps`` poses (making
    room for someone who will not let it pass: it never backs toward anyone)."""
    if not len(bodies):
        return True
    pts = np.asarray(bodies, dtype=float)[:, :2]
    here = footprint_distance(pts[:, 0], pts[:, 1])
    t = np.linspace(0.0, duration, steps + 1)[1:]
    x, y, th = arcs(np.array([v]), np.array([w]), t)
    c, s = np.cos(th[0])[:, None], np.sin(th[0])[:, None]
    dx, dy = pts[None, :, 0] - x[0][:, None], pts[None, :, 1] - y[0][:, None]
    after = footprint_distance(c * dx + s * dy, -s * dx + c * dy)
    return bool(np.all(after >= here[None, :] - 1e-9))


def way_blocker(standers: list[tuple[float, float]], lane: tuple[float, float],
                partner: tuple[float, float]) -> tuple[float, float, float] | None:
    """Who of ``standers`` (robot-frame people standing near it) holds the robot up on its way along
    ``lane`` (a unit vector, robot frame) after the partner at ``partner`` (robot frame): the nearest
    one ahead in its lane (``HELD_UP_NEAR``, ``HELD_UP_LANE``) or beside it (``HELD_UP_BESIDE``), as
    (distance, x, y), or None. Never the partner herself: a stander within ``HELD_UP_SELF`` of her
    (her legs' second track, her track's ghost, a remembered spot she stands on) is her, and one no
    nearer the robot than she is does not stand between them (it stops before her anyway). The
    robot must never ask its partner to let it pass."""
    ux, uy = lane
    px, py = partner
    her = math.hypot(px, py) if math.isfinite(px) and math.isfinite(py) else math.inf
    best = None
    for x, y in standers:
        r = math.hypot(x, y)
        if her < math.inf and (math.hypot(x - px, y - py) < HELD_UP_SELF or r >= her):
            continue
        along, lateral = x * ux + y * uy, abs(x * uy - y * ux)
        ahead = 0.0 < along < HELD_UP_NEAR and lateral < HELD_UP_LANE
        beside = along > -0.3 and r < HELD_UP_BESIDE
        if (ahead or beside) and (best is None or r < best[0]):
            best = (r, float(x), float(y))
    return best
