"""Scripted people and other sound sources (a radio, a TV).

``script`` runs the talking/waiting actions shared by every actor,
``person`` adds walking, facing, pointing and leaving, ``install`` puts a
scenario's actors on a :class:`~homesim.tour.stage.Stage`. Scripts react
to the robot (what it says, how close it comes), not only to the clock.
"""
