"""``linear_sum_assignment``: SciPy's own compiled solver, without importing ``scipy.optimize``.

The tracker and the tracking metric assign tracks to detections and people with SciPy's
LSAP solver (``scipy.optimize.linear_sum_assignment``, a C extension of its own,
``scipy/optimize/_lsap``). Importing it the usual way runs ``scipy.optimize``'s package
initialiser, which loads every optimiser, ``scipy.linalg`` and more: ~0.11 s of CPU at every
start for one function (a home tour's start-up is ~0.7 s). This module loads that one
extension file as it is: the same compiled function, so the same assignments bit for bit.
If the file is not where SciPy keeps it (another SciPy layout) or cannot be loaded, the
usual import is used. Nothing here is robot-specific (kernel layer).
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

_NAME = "scipy.optimize._lsap"


def _load() -> Callable[..., Any]:
    loaded = sys.modules.get(_NAME)
    if loaded is not None:  # scipy.optimize is imported already: its own copy
        return loaded.linear_sum_assignment
    try:
        spec_scipy = importlib.util.find_spec("scipy")  # where it is, without running its __init__
        if spec_scipy is None or spec_scipy.origin is None:
            raise ImportError("scipy")
        folder = Path(spec_scipy.origin).parent / "optimize"
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            path = folder / f"_lsap{suffix}"
            if path.is_file():
                loader = importlib.machinery.ExtensionFileLoader(_NAME, str(path))
                spec = importlib.util.spec_from_file_location(_NAME, str(path), loader=loader)
                if spec is None:
                    break
                module = importlib.util.module_from_spec(spec)
                loader.exec_module(module)
                return module.linear_sum_assignment
    except (ImportError, OSError, AttributeError):
        pass
    from scipy.optimize import linear_sum_assignment as usual

    return usual


#: ``linear_sum_assignment(cost, maximize=False) -> (rows, cols)``, as ``scipy.optimize``'s.
linear_sum_assignment: Callable[..., Any] = _load()
