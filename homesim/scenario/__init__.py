"""Scenario files: the plain model, the checked loader and the expectations.

``model`` holds the data classes (the bottom of the world's layers: the
world imports it, it imports no world), ``loader`` turns a file into a
checked :class:`~homesim.scenario.model.Scenario` (``load_scenario``),
``checks`` holds the semantic rules, ``pathplan`` the walkable grid of a
floor plan (reachability checks, the simulated people's paths) and
``expectations`` the streaming checks of expectations with the registry
of their kinds (the run package adds the robot's).
"""
