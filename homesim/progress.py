"""Progress bars for the slow commands (run, replay, plot --at, timeline, export, sweep, study), drawn by tqdm.

Why tqdm: it replaces three hand-written bars (run, study, and the sweep's
lines) with one well-kept implementation that sizes itself to the terminal,
shows the rate and the time left, and keeps other output readable
(:func:`write` clears the bar, prints, redraws it).

Bars go to stderr and only when stderr is a terminal (tqdm's
``disable=None``): a command piped into a file or another program, a test, a
CI log stays free of carriage returns. They show wall-clock rate and ETA,
which is display only: nothing in the simulation reads it.
"""

from __future__ import annotations

import sys
from typing import IO, TYPE_CHECKING, Any

if TYPE_CHECKING:  # tqdm is imported with the first bar drawn: a run piped into a file never loads it (start-up)
    from tqdm import tqdm

_drawn: list[bool] = []  # one item once any bar was made (tqdm imported): write() must then go through it

#: A bar over virtual seconds: "replay  42%|████      | 63.0/150 s [00:05<00:07]".
_SECONDS = "{desc}: {percentage:3.0f}%|{bar}| {n:.1f}/{total:g} s [{elapsed}<{remaining}]"


def bar(total: float, *, desc: str, unit: str = "it", file: IO[str] | None = None, **kwargs: Any) -> tqdm:
    """A tqdm bar on ``file`` (default stderr), silent when that is not a terminal, gone when closed."""
    from tqdm import tqdm

    if not _drawn:
        _drawn.append(True)
    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr if file is None else file, disable=None,
                leave=False, dynamic_ncols=True, **kwargs)


class VirtualSeconds:
    """A ``progress(now, end)`` callback (:meth:`homesim.tour.runner.Run.run`, trace walks) drawing a bar in virtual seconds.

    Use it as a context manager so the bar is removed when the work ends or fails.
    """

    def __init__(self, desc: str, *, file: IO[str] | None = None) -> None:
        self.desc = desc
        self.file = file
        self._bar: tqdm | None = None

    def __call__(self, now: float, end: float) -> None:
        if self._bar is None:
            f = sys.stderr if self.file is None else self.file
            if hasattr(f, "isatty") and not f.isatty():  # tqdm's own rule for disable=None: nothing would be drawn
                return
            self._bar = bar(max(end, 1e-9), desc=self.desc, unit="s", file=self.file, bar_format=_SECONDS)
        self._bar.update(min(now, end) - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> VirtualSeconds:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def write(text: str, *, file: IO[str] | None = None) -> None:
    """Print a line without tearing a bar that is being drawn (tqdm clears it, prints, redraws)."""
    out = sys.stdout if file is None else file
    if not _drawn:  # no bar yet, so none to clear: tqdm.write's two writes
        out.write(text)
        out.write("\n")
        return
    from tqdm import tqdm

    tqdm.write(text, file=out)
