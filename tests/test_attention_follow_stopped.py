"""Following, the follower's search over is a loss even while a camera sighting keeps her "seen"
(issue 26 item 1: a follower that cannot go on says so, never stands silent).

fresh5/row_fast_then_waits seed 8: Kai's legs went out of view behind an armchair; the camera's face
sightings above it kept his track's last_seen fresh, so the attention's leaving rule held back the
loss for 25 s while the follower, whose partner message said unseen, stood with its search over,
silent. The attention now also reads the follower's status: "stopped" for follow_stopped_after s
is a loss."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from robot.attention.fsm import AttentionFSM
from robot.attention.module import AttentionParams, PersonAttention


def _following(seen_ago: float) -> PersonAttention:
    a = PersonAttention.__new__(PersonAttention)
    a.params = AttentionParams()
    a.fsm = AttentionFSM()
    a.fsm.order("interact")
    a.fsm.order("follow")
    a._partner_last = (100.0 - seen_ago, 1.2, 0.0, 0.0, 0.0, 0.0, 0.0)  # seen 1.2 m ahead, standing
    a._driven, a._drive_start, a._yielded = 0.0, None, 0.0
    a._follow_stopped = None
    a._follower_drives = False
    return a


class _Status:
    def __init__(self, state: str, t: float) -> None:
        from lxml import etree
        self.xml = etree.Element("follow", state=state)
        self.created = t


def test_the_follower_stopped_for_two_seconds_is_a_loss_though_she_was_seen_a_moment_ago():
    a = _following(seen_ago=0.5)  # a camera sighting half a second ago
    assert not a.partner_left(100.0)
    a._on_follow_status(_Status("stopped", 100.0))
    a._on_follow_status(_Status("stopped", 101.0))  # (still stopped: the clock runs from its first report)
    assert not a.partner_left(101.9)
    assert a.partner_left(102.0)


@settings(max_examples=60, deadline=None)
@given(states=st.lists(st.sampled_from(["following", "waiting", "searching", "stopped", "approaching"]), min_size=1, max_size=40))
def test_a_loss_by_the_status_only_after_it_said_stopped_two_seconds_on_end(states):
    """At 0.1 s a report, with her seen just now: she is lost exactly when the follower has said
    "stopped" in every report for follow_stopped_after s (no other state in between)."""
    a = _following(seen_ago=0.0)
    since = None  # when the current run of "stopped" reports began
    for k, state in enumerate(states):
        t = 100.0 + 0.1 * k
        a._partner_last = (t, 1.2, 0.0, 0.0, 0.0, 0.0, 0.0)
        a._on_follow_status(_Status(state, t))
        since = (since if since is not None else t) if state == "stopped" else None
        assert a.partner_left(t) == (since is not None and t - since >= a.params.follow_stopped_after)
