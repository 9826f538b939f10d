"""Loading the optional compiled kernels (C extensions built by ``pip install -e .``, see setup.py).

A kernel replaces a module's inner loops and gives the same floats as its pure-Python/numpy path,
which stays the reference: :func:`load` returns the extension module, or None when it was not
built (no compiler on the machine), was built from another version of its source (its
``VERSION`` is not the one the Python side names, or its C file beside it, as in a checkout, is
not the file it was compiled from: the checkout changed since the last ``pip install -e .``,
which rebuilds it), or when the environment variable
``HOMESIM_PURE_PYTHON`` is set to anything but ``""``/``0`` (to compare both paths, e.g. trace
digests). Callers keep their Python path and use the kernel only when ``load`` gives one.
"""

from __future__ import annotations

import hashlib
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
    if getattr(mod, "VERSION", None) != version:
        return None
    return mod if _built_from_source_beside(mod) else None


def _built_from_source_beside(mod: ModuleType) -> bool:
    """Whether ``mod`` was compiled from the C file beside it (``pkg/_name.c`` next to
    ``pkg/_name.*.so``), by the SHA-256 setup.py records in it. No C file beside it (an installed
    wheel): nothing to compare, the VERSION check stands. A build that recorded no hash (older
    setup.py) is refused where a source is there to compare with."""
    path = getattr(mod, "__file__", None)
    if not path:
        return True
    source = os.path.join(os.path.dirname(path), mod.__name__.rpartition(".")[2] + ".c")
    try:
        with open(source, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()
    except OSError:
        return True
    return getattr(mod, "SOURCE_SHA256", "") == digest
