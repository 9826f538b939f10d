"""Selecting the person of interest (bottom-up attention, the papers' section 4.2).

Categories: 1 not speaking; 2 speaking but not facing the robot (or the
camera cannot tell); 3 speaking and facing the robot: a potential
communication partner. Rules, in order:

1. A category-3 person is selected at once and stays selected as long as
   they stay in category 3 (no time limit, no inhibition).
2. Otherwise the highest category wins: a person of a higher category than
   the selected one takes the selection at once.
3. Among equals, the one not selected for the longest time (never selected
   counts as longest). The current selection keeps its place among equals
   (rule 4 ends it) except when the tie arises because someone *starts
   speaking* (rises into category 2 to join the selected one): then the
   tie is decided at once, so a second talker whose face the camera cannot
   see yet gets a look (they may be a potential partner) instead of waiting
   out the first talker's ``max_selection``.
4. A person of category 1 or 2 stays selected at most ``max_selection``
   seconds, then is blocked for ``inhibition`` seconds (inhibition of
   return) so the robot looks at the others; a blocked person is selected
   only when nobody else is there. Starting to speak (rising into category
   2) lifts the block: someone who was just looked at and then greets the
   robot must not wait out the inhibition while the robot looks at a
   silent person.
5. A speaker whom the camera cannot see (her face is not in its image, so
   it cannot tell whether she faces the robot), within 2 m and at most half
   as far as every category-3 person, is looked at first (``look``: the person attention
   system decides who, PersonAttention._unseen_speaker): two people speak
   at once and the camera happens to face the farther one.

:class:`Selector` is a pure state machine over (time, {track id: category}),
with no bus or geometry, so the rules can be property-tested.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(frozen=True)
class SelectionParams:
    max_selection: float = 5.0  # s: longest a category 1/2 person stays selected
    inhibition: float = 3.0  # s: how long they are then blocked


@dataclass
class Selector:
    params: SelectionParams = SelectionParams()
    selected: int | None = None
    since: float = -math.inf  # when the current selection began
    last_selected: dict[int, float] = field(default_factory=dict)  # id -> last time it was selected
    blocked_until: dict[int, float] = field(default_factory=dict)
    previous: dict[int, int] = field(default_factory=dict)  # the categories of the last update

    def update(self, now: float, categories: dict[int, int], look: int | None = None) -> int | None:
        """Select among ``categories`` (track id -> 1, 2 or 3) at ``now``; returns the selected id.
        ``look``: a speaker to look at first (rule 5), if she is among ``categories``."""
        previous, self.previous = self.previous, dict(categories)
        cur = self.selected
        if cur is not None:
            self.last_selected[cur] = now
            if cur not in categories:
                cur = None
        if look is not None and look in categories:  # 5. before anyone else
            self.blocked_until.pop(look, None)
            return self._switch(now, look)
        # 1. Category 3: at once, and kept while it lasts.
        if cur is not None and categories[cur] == 3:
            return self._keep(now, cur)
        threes = [i for i, c in categories.items() if c == 3]
        if threes:
            return self._switch(now, self._longest_unselected(threes))
        if not categories:
            return self._switch(now, None)
        # 4. Time limit, then inhibition of return (lifted by a speech onset: starting to speak is news).
        for i, c in categories.items():
            if c >= 2 and previous.get(i, 0) < 2:
                self.blocked_until.pop(i, None)
        if cur is not None and now - self.since >= self.params.max_selection and len(categories) > 1:
            self.blocked_until[cur] = now + self.params.inhibition
            cur = None
        free = [i for i in categories if self.blocked_until.get(i, -math.inf) <= now]
        pool = free or list(categories)
        best = max(categories[i] for i in pool)
        # 2. The highest category; the current selection stays if it is among the best.
        if cur is not None and cur in pool and categories[cur] == best:
            risen = best == 2 and any(categories[i] == best and previous.get(i, 0) < best for i in pool if i != cur)
            if not risen:
                return self._keep(now, cur)
        return self._switch(now, self._longest_unselected([i for i in pool if categories[i] == best]))

    def _longest_unselected(self, ids: list[int]) -> int:
        """3. Ties: the one whose last selection lies furthest back (never: first; then lowest id)."""
        return min(ids, key=lambda i: (self.last_selected.get(i, -math.inf), i))

    def _keep(self, now: float, i: int) -> int:
        self.last_selected[i] = now
        return i

    def _switch(self, now: float, i: int | None) -> int | None:
        if i != self.selected:
            self.since = now
        self.selected = i
        if i is not None:
            self.last_selected[i] = now
        return i

    def forget(self, alive: set[int]) -> None:
        """Drop the memory of tracks that no longer exist (bounded memory)."""
        for d in (self.last_selected, self.blocked_until):
            for k in [k for k in d if k not in alive]:
                del d[k]
