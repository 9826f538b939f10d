"""Exports of a recorded run for other viewers: Perfetto (Chrome trace events) and Foxglove (MCAP).

:mod:`.perfetto` reads the trace alone; :mod:`.mcap` re-creates the run
(checked against the trace line by line) for what the trace does not hold:
the laser ranges and where the people truly were. :mod:`.cli` is
``homesim export``.
"""
