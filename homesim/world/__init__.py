"""The simulated flat: geometry, raycasting, pymunk physics, sound, ground truth.

Submodules: ``geometry`` (pure 2D maths), ``raycast`` (the vectorised ray
kernel), ``bodies`` (robot and people in pymunk), ``world`` (the flat),
``acoustics`` (who says what), ``pathplan`` (paths around obstacles),
``truth`` (the ground-truth recorder), ``stage`` (one scenario's world,
people and hardware on a Simulation) and ``cli`` (``homesim scenario``).
Import the submodule you need; this package imports nothing eagerly.
"""
