"""PeopleBot hardware models (Player-like): laser, sonar rings, pan-tilt camera, microphones,
base with odometry, speaker and display.

Each device has pure, vectorised kernels (geometry in, measurements out,
noise from a numpy Generator handed in) and a thin :class:`~homesim.module.Module`
that reads the world at its rate and publishes on the bus. Hardware models
are the only robot code that touches the world; everything above them sees
only their messages. :func:`robot.hardware.install.install` wires all of
them for a stage.
"""
