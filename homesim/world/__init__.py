"""The simulated flat: raycasting, pymunk physics, sound, ground truth.

Submodules: ``raycast`` (the vectorised ray kernel), ``bodies`` (robot and
people in pymunk), ``world`` (the flat), ``acoustics`` (who says what),
``reference_legs`` (the evaluation's leg detector), ``truth`` (the ground-truth
recorder) and ``chipmunk`` (fast pymunk accessors). Pure 2D geometry is
:mod:`homesim.geometry`, the walkers' grid planner
:mod:`homesim.scenario.pathplan`; a world with its people and robot
hardware on a Simulation is the run package's ``Stage``.
Import the submodule you need; this package imports nothing eagerly.
"""
