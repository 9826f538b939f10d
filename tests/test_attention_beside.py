"""A partner beside the robot after a stop is in the interaction space: the robot turns to her.

fresh5/row_phone_between seeds 7, 9 and stair_names_snug seed 5: after "stop" the follower's approach
ended with her 0.75 m to the robot's side (38-97 degrees off its axis, beyond the laser's half-circle);
her track died, nothing turned the robot to her, and 10 s later it said "You left, so I will look around"
while she stood there speaking to it. The leaving rule decides "gone" from evidence of leaving (last seen
outside the interaction space or walking away, or out of view for a while); meanwhile the attention turns
to where her legs were last measured, so the laser and the camera find her again."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention
from robot.attention.tracker import Tracks, TrackerSpec


def _interacting(her: tuple[float, float], velocity: tuple[float, float], robot_heading: float) -> PersonAttention:
    """The attention in Interaction, the robot at the odom origin heading ``robot_heading``, its partner
    (track 7) unseen: her track died, last measured at ``her`` walking at ``velocity``."""
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.order("interact")
    a.tracks = Tracks(TrackerSpec())
    a.partner = 7
    a.partner_lost_sent = False
    a._odom = (0.0, 0.0, 0.0, robot_heading, 0.0, 0.0)
    a._partner_last = (1.0, her[0], her[1], velocity[0], velocity[1], 0.0, 0.0)
    a._driven, a._drive_start, a._yielded = 0.0, None, 0.0
    a._follower_drives = False  # the follower's status: not approaching
    return a


@settings(max_examples=80, deadline=None)
@given(st.floats(0.5, 2.9), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi))
def test_a_partner_unseen_where_she_stood_within_the_interaction_space_is_turned_to(d, where, heading):
    a = _interacting((d * math.cos(where), d * math.sin(where)), (0.0, 0.0), heading)
    b = a._where_she_stood(3.0)
    assert b is not None
    # the bearing to turn to brings her onto the robot's axis
    assert abs(math.remainder(heading + b - where, 2 * math.pi)) < 1e-9
    assert a.partner_left(3.0) is False  # and she has not left (unseen 2 s, beside it, standing)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.5, 2.5), st.floats(-math.pi, math.pi), st.floats(0.31, 1.2))
def test_one_who_walked_away_or_was_outside_is_not_turned_to(d, where, speed):
    ux, uy = math.cos(where), math.sin(where)
    walked = _interacting((d * ux, d * uy), (speed * ux, speed * uy), 0.0)
    assert walked._where_she_stood(3.0) is None
    outside = _interacting((3.2 * ux, 3.2 * uy), (0.0, 0.0), 0.0)
    assert outside._where_she_stood(3.0) is None


def test_nothing_to_turn_to_once_she_was_declared_gone_or_outside_interaction():
    a = _interacting((0.2, 0.75), (0.0, 0.0), 0.0)
    a.partner_lost_sent = True
    assert a._where_she_stood(3.0) is None
    b = _interacting((0.2, 0.75), (0.0, 0.0), 0.0)
    b.fsm.order("follow")
    assert b._where_she_stood(3.0) is None


@settings(max_examples=60, deadline=None)
@given(st.floats(0.5, 6.5), st.floats(-math.pi, math.pi), st.floats(0.0, 1.2), st.floats(2.0, 15.0))
def test_a_leader_the_follower_still_comes_up_to_after_stop_has_not_left(d, where, speed, unseen):
    # fresh6/div_fast_leader_stops: "Stop, here we are" from 4-6 m ahead past a divider, his last steps
    # still walking on; the follower approaches (status approaching): his distance and his last steps
    # are the robot's lag, not his leaving, until the approach ends (then the rule holds as before)
    her = (d * math.cos(where), d * math.sin(where))
    a = _interacting(her, (speed * math.cos(where), speed * math.sin(where)), 0.0)
    a._follower_drives = True
    assert not a.partner_left(1.0 + unseen)
    a._follower_drives = False
    leaving = d > a.params.interaction_radius or speed >= a.params.leave_speed
    assert a.partner_left(1.0 + unseen) == (leaving or unseen >= a.params.out_of_view_after)
