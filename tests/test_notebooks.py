"""Notebooks run top to bottom inside a running asyncio loop, as in a Jupyter kernel.

We execute each code cell in one namespace from inside ``asyncio.run``: that is
the situation a Jupyter kernel creates (a loop already running in the
thread), which is what the stepping API must survive.
"""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))
#: What each notebook must have printed, beyond running without error.
EXPECTED_OUTPUT = {"01_stepping_the_kernel.ipynb": ["module_failed", "caused by ['sensor#"]}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs_inside_a_running_event_loop(path, capsys):
    nb = json.loads(path.read_text(encoding="utf-8"))
    cells = ["".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code"]
    assert cells, "a notebook without code"

    async def kernel():
        namespace: dict = {"__name__": "__notebook__"}
        for i, src in enumerate(cells):
            exec(compile(src, f"{path.name}[cell {i}]", "exec"), namespace)

    asyncio.run(kernel())
    out = capsys.readouterr().out
    for marker in EXPECTED_OUTPUT.get(path.name, []):
        assert marker in out
