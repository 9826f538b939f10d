"""After "stop" the robot comes up to her where she is seen, not where it last guessed her (issue 26 item 10).

fresh7/corr_hallway_crossing (seeds 1 and 3 on main 89146ce): the robot, 3 m behind, lost Sven from view when he
turned into the dining room; his "stop here" came while it searched the hallway. The catch-up drove to its guess
of him (a sonar echo at the dining room's door), took that for having come up to him and held to it; a moment
later the attention saw him in the room under a new track, and the follower, still on the old track's id, never
read it: it stood in the hallway 1.8 m from him, facing the guess, and taught "dining room" from outside the room.

Now: while it comes up to her, the attention's partner is the one it comes up to (a new track of hers replaces the
old), and an arrival at a guess (she unseen) is not held to: once she is seen elsewhere it drives on to her.
A closed loop over a small flat (the oracle stands in for the attention: her first track goes out of view before
she turns into the room, and she is found there under a new track after the stop).
"""

from __future__ import annotations

import math

from tests.nav_helpers import start_run

FLAT = """<?xml version="1.0" encoding="UTF-8"?>
<scenario name="approach_new_track" seed="{seed}" duration="40">
  <flat>
    <room name="hallway" points="0,0 10,0 10,1.2 0,1.2"/>
    <room name="dining room" points="0,1.2 5,1.2 5,6 0,6"/>
    <room name="study" points="5,1.2 10,1.2 10,6 5,6"/>
    <walls thickness="0.1">
      <wall from="0 0" to="10 0"/>
      <wall from="10 0" to="10 6"/>
      <wall from="10 6" to="0 6"/>
      <wall from="0 6" to="0 0"/>
      <wall from="0 1.2" to="10 1.2">
        <door name="dining door" at="2.5" width="1.1"/>
        <door name="study door" at="7.0" width="0.95"/>
      </wall>
      <wall from="5 1.2" to="5 6"/>
    </walls>
  </flat>
  <robot x="8.0" y="0.6" heading="180"/>
  <humans>
    <human name="sven" x="6.6" y="0.6" heading="180" speed="0.5">
      <script>
        <wait for="1"/>
        <walk-to point="2.5 0.6"/>
        <walk-to point="2.5 1.8"/>
        <walk-to point="3.8 2.7"/>
        <face angle="-120"/>
      </script>
    </human>
  </humans>
</scenario>
"""



def _in_dining_room(x: float, y: float) -> bool:
    return 0.0 < x < 5.0 and 1.2 < y < 6.0


def _run(seed: int):
    run = start_run("approach_new_track", tracks={"sven": "t1"}, text=FLAT.format(seed=seed))
    run.at(0.3, lambda: run.oracle.follow("t1"))

    def out_of_view() -> None:  # his track ends in the hallway, 1 m before he turns into the room
        run.oracle.tracks = {}

    def stop() -> None:  # "stop here": the attention keeps him (his old track) as the one it talks to
        run.oracle.interact()

    def found_again() -> None:  # the attention sees him in the room under a new track
        run.oracle.tracks = {"sven": "t8"}
        run.oracle.partner = "t8"
        run.oracle.interact()

    run.at(7.0, out_of_view)  # he is at x ~3.6, walking west along the hallway
    run.at(14.0, stop)  # he stands in the room
    run.at(16.0, found_again)
    return run


def test_after_stop_it_comes_up_to_her_new_track_in_the_room_not_to_its_guess_in_the_hallway():
    run = _run(3)
    try:
        run.until(34.0)
        rx, ry, _ = run.world.robot.pose
        hx, hy = run.world.humans["sven"].position
        assert _in_dining_room(rx, ry), (rx, ry)  # in his room, not at its door
        assert math.hypot(hx - rx, hy - ry) <= 1.6, (rx, ry, hx, hy)
        assert run.world.contacts == []
    finally:
        run.close()
