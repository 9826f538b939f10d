"""A thing she named, seen just beside the strip the user's body hides, is not stored before she steps aside
(fresh9 bay_three_books: the east one of three books behind him stored in 6 of 10 runs); a teaching said again
while the robot looks for it does not restart the look nor lose "OK, I have learned"."""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from lxml import etree

from robot.dialog.loader import load
from robot.dialog.manager import DialogManager, Say, Send
from robot.objects.attention import BODY_HALF_WIDTH, ROW_GAP, beside_her_shadow, on_her_ray
from robot.objects.resolve import Pointing

CAM = (0.0, 0.0)


def _at(dist: float, across: float, heading: float) -> tuple[float, float]:
    """A point ``dist`` along the direction ``heading`` from the camera and ``across`` to its left."""
    c, s = math.cos(heading), math.sin(heading)
    return dist * c - across * s, dist * s + across * c


headings = st.floats(-math.pi, math.pi)
her_dist = st.floats(0.6, 3.0)


@settings(max_examples=200, deadline=None)
@given(headings, her_dist, st.floats(0.1, 3.0), st.floats(-1.0, 1.0))
def test_a_thing_straight_behind_her_or_at_her_side_behind_her_is_beside_her_shadow(h, d, behind, share):
    # the strip she hides widens with the distance: at ``d + behind`` it is BODY_HALF_WIDTH * (d + behind) / d wide
    half = BODY_HALF_WIDTH * (d + behind) / d
    thing = _at(d + behind, share * (half + ROW_GAP) * 0.999, h)
    assert beside_her_shadow(CAM, _at(d, 0.0, h), thing)


@settings(max_examples=200, deadline=None)
@given(headings, her_dist, st.floats(0.1, 3.0), st.floats(0.01, 2.0), st.booleans())
def test_a_thing_well_to_the_side_of_her_strip_is_not(h, d, behind, extra, left):
    half = BODY_HALF_WIDTH * (d + behind) / d
    across = (half + ROW_GAP + extra) * (1 if left else -1)
    assert not beside_her_shadow(CAM, _at(d, 0.0, h), _at(d + behind, across, h))


@settings(max_examples=200, deadline=None)
@given(headings, her_dist, st.floats(0.0, 1.0), st.floats(-2.0, 2.0))
def test_nothing_in_front_of_her_is_hidden_by_her(h, d, share, across):
    # between the camera and her (or level with her): she hides nothing next to it (a thing inside her body, where
    # nothing stands, is no case: Hypothesis once put it at her very place)
    assume(math.hypot(d * (1.0 - share), across) >= 0.25)
    assert not beside_her_shadow(CAM, _at(d, 0.0, h), _at(d * share, across, h))


def test_three_books_behind_him_the_one_at_the_end_is_doubted():
    # bay_three_books seed 0 (traced): camera, Dominik, the east book the search round him found
    assert beside_her_shadow((4.58, 1.76), (4.48, 0.60), (4.81, -0.70))
    # standing 1.2 m aside, he hides none of them
    assert not any(beside_her_shadow((4.58, 1.76), (5.70, 0.60), (x, -0.72)) for x in (4.2, 4.5, 4.8))


# ------------------------------------------------------------------ seen where her ray points: not doubted


@settings(max_examples=200, deadline=None)
@given(headings, st.floats(0.6, 3.0), st.floats(-1.0, 1.0), st.floats(0.005, 0.2))
def test_a_thing_within_her_rays_spread_is_on_it_and_one_a_little_beyond_is_not(direction, reach, share, sigma):
    ray = Pointing(0.0, 0.0, 1.1, direction, -0.4, sigma)
    # ``reach`` out along her arm, ``share`` of the spread to one side, and just beyond the spread
    assert on_her_ray(ray, _at(reach, reach * math.tan(share * ray.spread * 0.999), direction))
    assert not on_her_ray(ray, _at(reach, reach * math.tan(ray.spread * 1.01) * (1 if share >= 0 else -1), direction))


def test_his_mug_seen_where_he_points_is_on_his_ray_the_jar_beside_hers_is_not():
    # tests/scenarios/lang_names seed 0 (traced): Ben's ray comes down on the desk behind him (his body hides that
    # spot by the robot's reckoning), and the camera saw his mug there, 1 deg off the ray: no look-alike to doubt
    ben = Pointing(1.109, 3.326, 1.08, 1.959, -0.780, 0.0235)
    assert on_her_ray(ben, (0.982, 3.616))
    # perceive/jars_behind_her seed 1 (traced): Hilde hides the middle jar she points at; the camera saw the
    # right-hand one, 0.3 m beside it (30 deg off her ray): still doubted (she is asked to step aside)
    hilde = Pointing(2.905, 0.676, 1.116, -1.551, -0.516, 0.0194)
    assert not on_her_ray(hilde, (3.2, 0.351))


# ------------------------------------------------------------------ the dialog: the same teaching said again

DOC = load()
BOOK = '<OBJECT type="book"><TITLE name="book"/></OBJECT>'


def frame(act: str, confidence: float = 0.9) -> etree._Element:
    return etree.fromstring(f'<understood start="0" end="1" confidence="{confidence}"><SPEECH>{act}</SPEECH><words>w</words></understood>')


def cond(name: str, *params: str) -> etree._Element:
    return etree.fromstring(f'<condition name="{name}" target="dialog" event="e1" state="S">{"".join(params)}</condition>')


@pytest.fixture
def dm() -> DialogManager:
    m = DialogManager(DOC)
    m.es_state = "Interacting"
    return m


def test_the_same_teaching_said_again_while_it_looks_keeps_the_look_and_the_confirmation(dm):
    out = dm.on_frame(frame(BOOK))
    assert [o.event for o in out if isinstance(o, Send)] == ["object_teaching"]
    dm.es_state = "ObjectTeaching"
    again = dm.on_frame(frame(BOOK))  # "I have learned" has not come: she says it again
    assert [o for o in again if isinstance(o, Send)] == []  # no second look
    assert [o.text for o in again if isinstance(o, Say)] == ["I am still looking at the object you showed me. Please wait a moment."]
    learned = cond("object_learned", '<param name="object"><OBJECT type="book" name="book"/></param>')
    assert [o.text for o in dm.on_condition(learned) if isinstance(o, Say)] == ["OK, I have learned the book."]
    assert dm.summary()["dialogs"]["object_teaching"] == {"started": 1, "succeeded": 1, "failed": 0, "abandoned": 0}


def test_another_thing_shown_while_it_looks_still_replaces_the_look(dm):
    dm.on_frame(frame(BOOK))
    dm.es_state = "ObjectTeaching"
    out = dm.on_frame(frame('<OBJECT type="cup"><TITLE name="cup"/></OBJECT>'))
    assert [o.event for o in out if isinstance(o, Send)] == ["object_teaching"]
