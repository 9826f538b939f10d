"""Scenario files: the plain model, the checked loader and the expectations.

``model`` holds the data classes, ``loader`` turns a file into a checked
:class:`~homesim.scenario.model.Scenario` (``load_scenario``), ``checks``
holds the semantic rules and ``expect`` evaluates expectations after a run.
"""
