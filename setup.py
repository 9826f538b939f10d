"""Build of homesim's optional compiled kernels (everything else is in pyproject.toml).

Each kernel is a C extension next to the Python module whose inner loops it replaces, built by
``pip install -e .`` (or any install) with the machine's C compiler. They are optional: where the
build fails (no compiler, no Python headers) the install still succeeds and the pure-Python/numpy
paths run, which give the same floats (each kernel's tests compare the two on random geometry).

Flags: ``-ffp-contract=off`` so the compiler never fuses a multiply and an add (a fused one
rounds once where numpy rounds twice), and no ``-ffast-math`` or ``-Ofast`` (they reorder and
drop IEEE rules). To add a kernel: append a ``kernel(...)`` to ``KERNELS`` and load it from its
Python module with a fallback (see ``homesim/world/raycast.py``'s ``_kernels``).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from setuptools import Extension, setup

# No FMA contraction, IEEE semantics kept; -O2 (SSE2 on x86-64: no x87 extended precision).
CFLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-Wall"]


def kernel(name: str, source: str) -> Extension:
    """An optional C extension ``name`` built from ``source`` with the project's flags.

    The build records the SHA-256 of the source it compiled (the module's ``SOURCE_SHA256``):
    an editable install builds once, and a later checkout that changes the C file would otherwise
    leave the old build running (``homesim.kernels.load`` refuses it; reinstall to rebuild)."""
    digest = hashlib.sha256((Path(__file__).parent / source).read_bytes()).hexdigest()
    return Extension(name, [source], extra_compile_args=CFLAGS, optional=True,
                     define_macros=[("KERNEL_SOURCE_SHA256", f'"{digest}"')])


KERNELS = [
    kernel("homesim.world._raykernels", "homesim/world/_raykernels.c"),
    kernel("robot.attention._legkernel", "robot/attention/_legkernel.c"),
    kernel("homesim._gridkernels", "homesim/_gridkernels.c"),
]

setup(ext_modules=KERNELS)
