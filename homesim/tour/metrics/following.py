"""Following: how well the robot kept its partner at a social distance (ground truth).

The robot follows while the person attention says ``Follow`` on
``/robot/attention/state`` (the follower drives only then); in a run without
an attention module, while the supervisor is in ``Following``. Every world
step while following, from the true positions (robot centre to the followed
person's centre):

* distance mean / std / min / max (``distance_m``) and ``mean_distance_m``;
* the share of time in each proxemic zone (as HuNavSim's evaluator reports
  them): intimate < 0.45 m, personal 0.45-1.2 m, social 1.2-3.6 m, public beyond;
* ``share_in_band`` (the scenario option ``follow-band="lo hi"``, default
  0.8-2.0 m) and the time outside the 1.0-1.5 m band person-following robots keep;
* identity switches: each ``/robot/attention/partner`` message of the track
  the attention names as partner points (bearing, distance) at the true person
  nearest to it (within 0.7 m); a change of that person within one following
  episode is a switch. Without partner messages the partner is the person
  nearest the robot when following starts;
* time to reacquire after a loss: from the partner message that says
  ``visible="false"`` to the next that says it is seen again (count, mean,
  max), when the partner was out of sight at least :data:`LOSS` s (the
  follower's timeout: it stops); shorter gaps (a missed detection or two)
  are counted as ``dropouts`` and are no loss;
* the ``partner_too_fast`` warnings the robot raised.

Constant memory: running sums only.
"""

from __future__ import annotations

import math
from typing import Any

from . import Observer
from .stats import Running

ZONES = (("intimate", 0.0, 0.45), ("personal", 0.45, 1.2), ("social", 1.2, 3.6), ("public", 3.6, math.inf))
BAND = (1.0, 1.5)
MATCH = 0.7
#: s: out of sight this long is a loss (the follower stops); shorter gaps are dropouts
LOSS = 1.0


class Following(Observer):
    channels = ("/robot/es/events", "/robot/attention/")
    step_every = 1

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        options = getattr(getattr(run, "config", None), "options", {}) or {}
        lo, hi = (float(v) for v in options.get("follow-band", "0.8 2.0").split())
        self.band = (lo, hi)
        self.distance = Running()
        self.inside = 0
        self.zone_steps = {z: 0 for z, _, _ in ZONES}
        self.outside = 0
        self.warnings = 0
        self.episodes = 0
        self.attention_seen = False  # an attention module reports its state: trust it, not the ES
        self.attention_follow = False
        self.partner_id: str | None = None
        self.partner: str | None = None  # the true person followed in this episode
        self.current: str | None = None  # whom the latest partner message points at
        self.switches = 0
        self._was_following = False
        self._lost_at: float | None = None
        self.reacquire = Running()
        self.dropouts = 0

    # --------------------------------------------------------------- bus
    def on_message(self, m: Any) -> None:
        ch = m.channel
        if ch == "/robot/es/events":
            if m.xml.get("name") == "partner_too_fast":
                self.warnings += 1
        elif ch == "/robot/attention/state":
            self.attention_seen = True
            self.attention_follow = m.xml.get("state") == "Follow"
            self.partner_id = m.xml.get("partner") or None
        elif ch == "/robot/attention/partner" and self._following() and m.xml.get("id") == self.partner_id:
            self._on_partner(m.xml, m.created)

    def _following(self) -> bool:
        return self.attention_follow if self.attention_seen else self.run.es_state == "Following"

    def _on_partner(self, xml: Any, t: float) -> None:
        if xml.get("visible", "true") != "true":
            if self._lost_at is None:
                self._lost_at = t
            return
        if self._lost_at is not None:
            gap = t - self._lost_at
            if gap >= LOSS:
                self.reacquire.add(gap)
            else:
                self.dropouts += 1
            self._lost_at = None
        try:
            bearing, dist = math.radians(float(xml.get("bearing"))), float(xml.get("distance"))
        except (TypeError, ValueError):
            return
        world = self.run.world
        rx, ry, rth = world.robot.pose
        px, py = rx + dist * math.cos(rth + bearing), ry + dist * math.sin(rth + bearing)
        near = [(math.hypot(h.position[0] - px, h.position[1] - py), n) for n, h in world.humans.items() if h.present]
        if not near or min(near)[0] > MATCH:
            return
        who = min(near)[1]
        if self.partner is None:
            self.partner = who
        if self.current is not None and who != self.current:
            self.switches += 1
        self.current = who

    # ------------------------------------------------------------- world
    def on_step(self, world: Any) -> None:
        following = self._following()
        if following and not self._was_following:
            self.episodes += 1
            self.partner = self.current = None
        self._was_following = following
        if not following:
            return
        rx, ry, _ = world.robot.pose
        if self.partner is None:
            if self.attention_seen:
                return  # the first partner message names whom it follows
            near = [(math.hypot(h.position[0] - rx, h.position[1] - ry), n) for n, h in world.humans.items() if h.present]
            if not near:
                return
            self.partner = min(near)[1]
        h = world.humans[self.partner]
        if not h.present:
            return
        d = math.hypot(h.position[0] - rx, h.position[1] - ry)
        self.distance.add(d)
        self.inside += self.band[0] <= d <= self.band[1]
        self.outside += not BAND[0] <= d <= BAND[1]
        for z, lo, hi in ZONES:
            if lo <= d < hi:
                self.zone_steps[z] += 1
                break

    def summary(self) -> dict[str, Any]:
        n = self.distance.n
        dt = self.run.world.dt
        return {
            "episodes": self.episodes,
            "partner": self.partner,
            "time_s": round(n * dt, 3),
            "distance_m": self.distance.as_dict(3),
            "mean_distance_m": round(self.distance.mean, 3) if n else None,
            "band_m": list(self.band),
            "share_in_band": round(self.inside / n, 4) if n else None,
            "zone_share": {z: round(c / n, 4) if n else 0.0 for z, c in self.zone_steps.items()},
            "time_outside_1_0_1_5_s": round(self.outside * dt, 3),
            "identity_switches": self.switches,
            "reacquisitions": self.reacquire.n,
            "time_to_reacquire_s": self.reacquire.as_dict(3),
            "dropouts": self.dropouts,
            "too_fast_warnings": self.warnings,
        }


OBSERVERS = {"following": Following}
