"""Named colours as people say them, RGB in [0, 1]: one table for the scenario format and the robot.

A scenario file names an object's or a person's colour with one of these
words (or ``#rrggbb``); the robot's object attention uses the same words as
its colour vocabulary (what a person may say: "the red cup"). Pure data.
"""

from __future__ import annotations

RGB = tuple[float, float, float]

#: Colour names, as RGB in [0, 1].
COLOURS: dict[str, RGB] = {
    "black": (0.05, 0.05, 0.05),
    "white": (0.95, 0.95, 0.95),
    "grey": (0.5, 0.5, 0.5),
    "red": (0.85, 0.1, 0.1),
    "green": (0.1, 0.65, 0.2),
    "blue": (0.1, 0.25, 0.85),
    "yellow": (0.95, 0.85, 0.1),
    "orange": (0.95, 0.55, 0.1),
    "purple": (0.55, 0.2, 0.7),
    "pink": (0.95, 0.55, 0.7),
    "brown": (0.5, 0.3, 0.15),
    "beige": (0.9, 0.85, 0.7),
}
