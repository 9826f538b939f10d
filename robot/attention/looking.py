"""Where the robot has looked and heard lately: the memory behind turning to a voice (issue 26).

Two microphones 28 cm apart hear a direction, not a side: a voice read at ``b`` comes from ``b``
in front or from ``180 - b`` behind (front/back ambiguity, docs/semantics.md §3). A person
greeting the robot from behind or from beside, out of the laser's half circle or the camera's
field, is found as a person finds a voice: look where it seemed to come from; nobody there, look
the other way. Two memories make that search, both in the odometry frame (a direction stays a
direction while the robot turns on the spot to look):

- :class:`LookedAt`: per direction (5 degree bins of odometry heading), when the camera last had
  it in its field with no frontal face there, and when it last saw a face or a torso there. "Looked, nobody"
  sends the robot to the mirrored reading; "looked at both, nobody" (a radio) ends the search, so
  a voice nobody explains never spins the robot round and round.
- :class:`HeardFrom`: the last few voices that no person the robot saw explained: when, the two
  directions they may have come from, and who was in view then. A person found afterwards in one of
  those directions, facing the robot, is the one who spoke (she greeted it and now waits, silent, for
  its answer): the attention counts her as speaking while the memory lasts (``recall``).

Both are bounded (fixed bins; a deque pruned by age, with a cap): nothing grows with the length of a run.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable

_TWO_PI = 2 * math.pi


def angle_between(a: float, b: float) -> float:
    """|a - b| wrapped into [0, pi]."""
    return abs((a - b + math.pi) % _TWO_PI - math.pi)


class LookedAt:
    """When the camera last looked at each direction (odometry heading) and what it saw there."""

    def __init__(self, bin_deg: float = 5.0) -> None:
        if not 0 < bin_deg <= 90:
            raise ValueError(f"LookedAt: bin_deg = {bin_deg}, not in (0, 90]")
        self.n = int(round(360.0 / bin_deg))
        self.width = _TWO_PI / self.n
        self._empty = [-math.inf] * self.n  # last time looked at with no face there
        self._face = [-math.inf] * self.n  # last time a face was seen there
        self._body = [-math.inf] * self.n  # last time a body (a torso, any side of it) was seen there

    def _bin(self, heading: float) -> int:
        return int((heading % _TWO_PI) / self.width) % self.n

    def observe(self, t: float, centre: float, half_width: float, faces: Iterable[float], face_tolerance: float) -> None:
        """A camera frame at ``t``: its optical axis at odometry heading ``centre``, ``half_width`` either
        side of it in view, frontal faces at odometry headings ``faces``."""
        faces = list(faces)
        k = int(math.floor(half_width / self.width))
        c = self._bin(centre)
        for i in range(c - k, c + k + 1):
            b = i % self.n
            mid = (b + 0.5) * self.width
            if angle_between(mid, centre) > half_width:
                continue
            if any(angle_between(mid, f) <= face_tolerance for f in faces):
                self._face[b] = t
            else:
                self._empty[b] = t

    def bodies(self, t: float, headings: Iterable[float], tolerance: float) -> None:
        """A camera frame at ``t`` showed torsos at odometry ``headings``: someone is there, facing the
        camera or not. A person who calls the robot with her back to it (busy at a shelf, stepping out
        from behind a sideboard: wlan_reorder) shows no frontal face, so "no face" alone is not "nobody"."""
        for h in headings:
            k = int(math.ceil(tolerance / self.width))
            c = self._bin(h)
            for i in range(c - k, c + k + 1):
                b = i % self.n
                if angle_between((b + 0.5) * self.width, h) <= tolerance + self.width / 2:
                    self._body[b] = t

    def empty_since(self, heading: float, since: float) -> bool:
        """Has the camera looked at ``heading`` at ``since`` or later and seen nobody there (no frontal
        face, no torso) since it last saw someone?"""
        b = self._bin(heading)
        return self._empty[b] >= since and self._empty[b] > self._face[b] and self._empty[b] > self._body[b]

    def body_since(self, heading: float, since: float) -> bool:
        """Has the camera seen a torso at ``heading`` at ``since`` or later?"""
        return self._body[self._bin(heading)] >= since

    def face_since(self, heading: float, since: float) -> bool:
        """Has the camera seen a frontal face at ``heading`` at ``since`` or later?"""
        return self._face[self._bin(heading)] >= since


class HeardFrom:
    """The last voices no person in view explained (see the module docstring)."""

    def __init__(self, keep: float = 4.0, cap: int = 1024) -> None:
        """``keep``: seconds a voice is remembered (the longest ``within`` a caller recalls, the attention's
        ``voice_recall``); voices older than that are dropped as new ones come (review9 item 3: a count
        bound of 32 readings, 3.2 s at the microphones' 10 Hz, forgot her before ``voice_recall`` while a
        radio talked on). ``cap``: a safety bound only, above what ``keep`` holds (up to 20 Hz x 4 s x 12
        directions a frame: 960; 512 dropped her voice at 20 Hz with 7 readings a frame, test_turn_to_voice),
        so a flood of readings cannot grow it either."""
        self.keep = keep
        self._heard: deque[tuple[float, float, float, frozenset[int]]] = deque(maxlen=cap)

    def add(self, t: float, front: float, back: float, in_view: Iterable[int]) -> None:
        """A voice at ``t`` from odometry heading ``front`` or its mirror ``back``; ``in_view``: the
        ids of the people the robot saw then (none of whom it was)."""
        while self._heard and t - self._heard[0][0] > self.keep:
            self._heard.popleft()
        self._heard.append((t, front, back, frozenset(in_view)))

    def recall(self, t: float, heading: float, track_id: int, within: float, tolerance: float) -> bool:
        """Did a voice come from ``heading`` (either reading, within ``tolerance``) in the last ``within``
        seconds (at most ``keep``), while the person ``track_id`` was not in view (so it may have been
        theirs)?"""
        for heard, front, back, seen in reversed(self._heard):
            if t - heard > within:
                break
            if heard <= t and track_id not in seen and min(angle_between(heading, front), angle_between(heading, back)) <= tolerance:
                return True
        return False

    def recall_span(self, t: float, lo: float, hi: float, track_id: int, within: float, tolerance: float) -> bool:
        """As :meth:`recall`, for a person whose voice may be read anywhere between odometry headings ``lo`` and
        ``hi`` (``lo`` counter-clockwise to ``hi``, less than pi apart: near the robot, her unknown mouth height
        spreads the pair's reading): a voice's front reading within ``tolerance`` of that arc."""
        mid, half = lo + ((hi - lo) % _TWO_PI) / 2, ((hi - lo) % _TWO_PI) / 2
        for heard, front, _back, seen in reversed(self._heard):
            if t - heard > within:
                break
            if heard <= t and track_id not in seen and angle_between(front, mid) <= half + tolerance:
                return True
        return False

    def __len__(self) -> int:
        return len(self._heard)
