"""The follower's status tells "it stands by her" (``waiting``) from "held up on its way to her" (``held``).

review22 R4: the follower said ``waiting`` both when she stood within its band (it stands by her: her walk is
over) and when the dynamic window found no admissible motion while she was beyond it (held up in a door, by
people crossing, she walking on). The dialog's "a teaching ends the walk after 2 s of ``waiting``"
(corr22, ``Dialog._walk_over``), its stood-stop rule and the attention's ``_stood`` read the first meaning only,
so a teaching said while held up ended the walk and taught the place wherever the robot was held. Now the
second is ``held``, and those rules never count it.
"""

from __future__ import annotations

import pytest

import robot.navigation.follow as follow_mod
from robot.navigation.local import Command
from tests.test_nav_follow import _follow


def test_no_admissible_motion_with_her_beyond_the_band_is_held_never_waiting(monkeypatch):
    # the window admits nothing (a door full of people, say): it stands while she walks on into the study
    monkeypatch.setattr(follow_mod, "dwa", lambda v, w, *a, **k: Command(0.0, 0.0, False, 0.0))
    run = _follow("follow_door", 8.0)
    try:
        states = [(st["state"], float(st["distance"])) for _, st in run.status]
        assert any(s == "held" and d > 1.6 for s, d in states)  # she walked on; it could not: held up
        assert all(d < 1.5 for s, d in states if s == "waiting")  # "waiting" only while it stands by her
    finally:
        run.close()


def test_when_it_can_drive_on_to_her_it_is_never_held():
    run = _follow("follow_door", 8.0)
    try:
        assert run.status and not any(st["state"] == "held" for _, st in run.status)
    finally:
        run.close()
