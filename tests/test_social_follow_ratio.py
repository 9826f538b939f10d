"""The following path ratio compares the robot's path and the partner's over the same steps
(review of issue 26 item 5): a search after the partner left the flat does not inflate it."""

from __future__ import annotations

from types import SimpleNamespace

from homesim.tour.metrics.social import Social


class _World:
    dt = 0.1
    time = 0.0

    def __init__(self) -> None:
        self.robot = SimpleNamespace(pose=(0.0, 0.0, 0.0), v=0.5)
        self.humans = {"nina": SimpleNamespace(present=True, position=(1.0, 0.0))}

    def add_contact_listener(self, f) -> None:
        pass


def test_the_robots_path_after_the_partner_left_is_not_in_the_following_ratio():
    world = _World()
    social = Social(SimpleNamespace(world=world, scenario=None))
    social.mode, social.partner = "following", "nina"
    for k in range(21):  # both walk 2 m side by side
        world.robot.pose = (0.1 * k, 0.0, 0.0)
        world.humans["nina"].position = (1.0 + 0.1 * k, 0.0)
        social.on_step(world)
    world.humans["nina"].present = False  # she left the flat; the robot drives on 3 m looking for her
    for k in range(1, 31):
        world.robot.pose = (2.0 + 0.1 * k, 0.0, 0.0)
        social.on_step(world)
    fol = social.summary()["following"]
    assert abs(fol["partner_path_length_m"] - 2.0) < 1e-6
    assert abs(fol["path_length_m"] - 5.0) < 1e-6  # everything it drove following
    assert abs(fol["path_ratio"] - 1.0) < 1e-3  # over the same steps: the same path
