"""Loading the optional compiled kernels (C extensions built by ``pip install -e .``, see setup.py).

A kernel replaces a module's inner loops and gives the same floats as its pure-Python/numpy path,
which stays the reference: :func:`load` returns the extension module, or None when it was not
built (no compiler on the machine), was built from another version of its source (a checkout
changed since the last ``pip install -e .``: rebuild), or when the environment variable
``HOMESIM_PURE_PYTHON`` is set to anything but ``""``/``0`` (to compare both paths, e.g. trace
digests). Callers keep their Python path and use the kernel only when ``load`` gives one.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType

__all__ = ["load", "pure_python"]


def pure_python() -> bool:
    """Whether ``HOMESIM_PURE_PYTHON`` asks for the Python paths only."""
    return os.environ.get("HOMESIM_PURE_PYTHON", "") not in ("", "0")


def load(name: str, version: int) -> ModuleType | None:
    """The compiled kernel module ``name`` if it is built at ``version`` and allowed, else None.

    ``version`` is the ``VERSION`` constant its C source defines; the Python side names the one
    it was written against, so a stale build is never used with newer Python code.
    """
    if pure_python():
        return None
    try:
        mod = importlib.import_module(name)
    except ImportError:
        return None
    return mod if getattr(mod, "VERSION", None) == version else None
