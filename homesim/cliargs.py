"""Command-line values checked at the boundary, each refusal naming its option.

argparse calls these ``type=`` functions while parsing; an
``ArgumentTypeError`` becomes ``homesim ...: error: argument --until: ...``
after the subcommand's usage (see :mod:`homesim.cliparse`) and exit status 2. The ranges are
documented in ``docs/running.md`` ("Input limits and what homesim
refuses"):

- virtual times (``--duration``, ``--until``, ``--at``): finite decimal
  seconds, 0 ≤ t ≤ :data:`MAX_VIRTUAL_SECONDS` (``--duration`` > 0);
- ``--seed``: an integer 0 ≤ seed ≤ :data:`MAX_SEED` (at most 19 digits);
- ``--realtime``: a finite scale in [:data:`MIN_REALTIME_SCALE`, :data:`MAX_REALTIME_SCALE`];
- output files (``--trace``, ``-o``): not a directory, in a directory that
  exists (or can be created) and is writable;
- store directories (``--memory DIR``): a writable directory, or a path that
  does not exist yet in a writable directory (the run creates it); never an
  existing file. The second run with the same ``DIR`` loads what the first wrote.
"""

from __future__ import annotations

import argparse
import math
import os
import re
from collections.abc import Callable
from pathlib import Path

from .errors import HomesimError, OptionError  # noqa: F401 (OptionError: re-exported)

#: Longest virtual run accepted from the command line (seconds; about 11.6 days).
MAX_VIRTUAL_SECONDS = 1_000_000.0
#: Largest seed (numpy seeds any non-negative integer; 63 bits keep traces and logs readable).
MAX_SEED = 2**63 - 1
MIN_REALTIME_SCALE = 0.01
MAX_REALTIME_SCALE = 1000.0
_MAX_NUMBER_TEXT = 40  # characters: a longer "number" is refused before conversion
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]{1,3})?")


def _number(text: str) -> float:
    if len(text) > _MAX_NUMBER_TEXT:
        raise argparse.ArgumentTypeError(f"{text[:20]!r}... is too long for a number")
    if not _DECIMAL.fullmatch(text.strip()):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite decimal number")
    value = float(text)
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def seconds(*, positive: bool = False, high: float = MAX_VIRTUAL_SECONDS) -> Callable[[str], float]:
    """A type for virtual seconds: finite, ≥ 0 (> 0 when ``positive``), ≤ ``high``."""

    def parse(text: str) -> float:
        value = _number(text)
        if value < 0 or (positive and value == 0) or value > high:
            low = "0 <" if positive else "0 ≤"
            raise argparse.ArgumentTypeError(f"{text!r} is out of range ({low} seconds ≤ {high:g})")
        return value

    parse.__name__ = "seconds"  # argparse names the type in some messages
    return parse


_SEED_TEXT = re.compile(r"[0-9]{1,19}")


def seed(text: str) -> int:
    """A type for seeds: a decimal integer 0 ≤ seed ≤ 2**63 - 1."""
    # ASCII digits only: str.isdigit() also takes '²' (int() then fails) and '٣' or '０' (a seed nobody typed)
    if not _SEED_TEXT.fullmatch(text.strip()):
        raise argparse.ArgumentTypeError(f"{text[:25]!r} is not a seed (a decimal integer 0 ≤ seed ≤ {MAX_SEED})")
    value = int(text)
    if value > MAX_SEED:
        raise argparse.ArgumentTypeError(f"{text!r} is out of range (0 ≤ seed ≤ {MAX_SEED})")
    return value


def realtime_scale(text: str) -> float:
    """A type for the real-time pacing scale."""
    value = _number(text)
    if not MIN_REALTIME_SCALE <= value <= MAX_REALTIME_SCALE:
        raise argparse.ArgumentTypeError(f"{text!r} is out of range ({MIN_REALTIME_SCALE:g} ≤ scale ≤ {MAX_REALTIME_SCALE:g})")
    return value


def output_file(text: str) -> Path:
    """A type for a file to write: not a directory; its nearest existing ancestor is a writable directory."""
    if not text or len(text) > 4096 or "\x00" in text:
        raise argparse.ArgumentTypeError("not a usable file name")
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a directory, not a file")
    if path.exists() and not path.is_file():
        raise argparse.ArgumentTypeError(f"{text!r} exists and is not a regular file")
    if path.exists() and not os.access(path, os.W_OK):
        raise argparse.ArgumentTypeError(f"{text!r} is not writable")
    _check_creatable(text, path)
    return path


def _check_creatable(text: str, path: Path) -> None:
    """The nearest existing ancestor of ``path`` is a directory we may create entries in."""
    parent = path.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r}: {str(parent)!r} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise argparse.ArgumentTypeError(f"{text!r}: directory {str(parent)!r} is not writable")


def store_dir(text: str) -> Path:
    """A type for a directory a run keeps its store in: an existing writable directory, or a new one to create."""
    if not text or len(text) > 4096 or "\x00" in text:
        raise argparse.ArgumentTypeError("not a usable directory name")
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} exists and is not a directory")
    if path.is_dir():
        if not os.access(path, os.W_OK | os.X_OK):
            raise argparse.ArgumentTypeError(f"directory {text!r} is not writable")
        return path
    _check_creatable(text, path)
    return path


def count(n: int, one: str, many: str | None = None) -> str:
    """``"1 person"``, ``"2 people"``, ``"0 places"``: a number and its noun, in the singular for one."""
    return f"{n} {one if n == 1 else (many or one + 's')}"
