"""A following robot in someone's way makes way; it asks to pass only when it needs to pass (issue 26 item 1).

fresh10/hall_crossing_kids (fresh22's defect F): following along a 1.2 m hall, the robot came up to the
bathroom door just as two children ran out of the music room ahead of it toward that door; they were held
back 0.5 m in front of it and it said "Excuse me, may I pass, please?" three or four times over 15-20 s,
crawling back only by its wedged back-off (0.1 m/s for 1 s at a time), while nobody moved; the partner's
"stop" said over it was not understood. They had walked at it and stood in front of it: it was in their
way, not they in its.

Now (``robot.navigation.follow``, ``MAKE_WAY_*``): someone other than the partner who walked at the robot and
then stands close in front of it is held back by it; it backs straight out of their way, the way it came,
and does not ask them to let it pass. Closed loop, end to end (the real attention, dialog and people), in a
flat of its own: Ute leads the robot along a 1.1 m corridor, and Max and Pia walk out of the study ahead of
it, across the corridor toward the utility room's door the robot is about to pass.
"""

from __future__ import annotations

import math
from pathlib import Path

from homesim.tour.runner import Run, RunOptions

SCENE = Path(__file__).resolve().parent / "scenarios" / "follow" / "held_back_at_door.xml"


def _in_utility_room(x: float, y: float) -> bool:
    return 3.0 < x < 7.0 and 0.0 < y < 2.0


def test_held_back_flatmates_are_made_way_for_not_asked_to_let_it_pass():
    """Max and Pia, held back at the door by the following robot, reach the utility room within 12 s of
    meeting it (about 30 s; on main it asked them four times to let it pass and they got in at 48 s), the robot is
    never heard asking to pass, touches nobody, and follows Ute on (it has come within 2 m of her by 52 s)."""
    with Run.from_file(SCENE, RunOptions(seed=0, until=52.0)) as run:
        world = run.world
        reached: dict[str, float] = {}

        def watch(_: object) -> None:
            for name in ("max", "pia"):
                if name not in reached and _in_utility_room(*world.humans[name].position):
                    reached[name] = run.sim.now

        world.add_listener(watch)
        run.run()
        said = [u.text for u in world.sound.all() if u.source == "robot"]
        rx, ry, _ = world.robot.pose
        ux, uy = world.humans["ute"].position
        contacts = list(world.contacts)
    assert not any("pass" in t.lower() for t in said), said
    assert set(reached) == {"max", "pia"} and max(reached.values()) <= 42.0, reached
    assert contacts == []
    assert math.hypot(ux - rx, uy - ry) <= 2.0, (rx, ry, ux, uy)
