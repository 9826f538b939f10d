"""What the simulated users did (metric ``users``): profiles, reactions, repairs, giving up.

Read from the people themselves at the end of the run (the actors of ``humans.install``, ground
truth about the users, never about the robot): ``reactions`` (times a person answered the robot
with an ``<on>``), ``repairs`` (turns done again because the robot asked or did not answer),
``gave_up`` (times a person's patience ran out), ``stopped`` (people whose script ended early:
they gave up by stopping or leaving), ``blocked`` (walks given up because the robot stood in
the way, humans/person.py), ``confirmed_wrongly`` (wrong guesses of the robot's a person said
yes to), ``misnamed`` (rooms or things named wrongly when taught) and ``self_corrected`` (of
those, the slips corrected at once), and ``profiles`` (each profiled person's profile). A study
tells failures that follow a user giving up or getting things wrong from the others with it.
"""

from __future__ import annotations

from typing import Any

from . import Observer


class Users(Observer):
    """Sums over the people of the run, taken once at the end (constant memory)."""

    def summary(self) -> dict[str, Any]:
        stage = getattr(self.run, "stage", None)
        actors = getattr(stage, "actors", {}) if stage is not None else {}
        people = [a for a in actors.values() if hasattr(a, "spec")  and hasattr(a, "gave_up") and getattr(a.spec, "script", None) is not None and hasattr(a.spec, "profile")]
        return {
            "reactions": sum(sum(a.fired) + getattr(a, "scoped_fired_total", 0) for a in people),
            "repairs": sum(a.repairs for a in people),
            "gave_up": sum(a.gave_up for a in people),
            "stopped": sum(1 for a in people if getattr(a, "stopped_early", False)),
            "blocked": sum(getattr(a, "blocked_walks", 0) for a in people),
            "confirmed_wrongly": sum(getattr(a, "confirmed_wrongly", 0) for a in people),
            "misnamed": sum(getattr(a, "misnamed", 0) for a in people),
            "self_corrected": sum(getattr(a, "self_corrected", 0) for a in people),
            "profiles": {a.name: a.traits.profile for a in people if a.traits.profile},
        }


OBSERVERS = {"users": Users}
