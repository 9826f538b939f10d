"""``homesim plot TRACE``: pictures of a recorded run.

``homesim plot TRACE [--at T] [--out FILE]`` re-creates the run to time T
(checking it against the trace line by line, :mod:`homesim.tour.tracerun`) and
draws the flat then, with the robot's percepts over the truth; without
``--at`` it shows the last moment of the recorded run. ``homesim plot TRACE
--timeline [--from T0] [--to T1] [--out FILE]`` draws the module
communication in the style of the papers' Fig. 6 from the trace alone (no
re-run). The file's suffix chooses the format (``.png`` or ``.svg``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import cliargs
from ..errors import HomesimError
from ..cliargs import OptionError
from ..viz.files import save

FORMATS = (".png", ".svg")


def _check_output(out: Path) -> None:
    if out.suffix.lower() not in FORMATS:
        raise OptionError("--out", f"{out}: the file name must end in {' or '.join(FORMATS)} (the format)")


def plot_moment_of_trace(trace: Path, at: float | None):  # noqa: ANN201 (a matplotlib Figure)
    """Re-create ``trace``'s run to ``at`` (default: its end) and draw that moment with the percepts."""
    from .tracerun import rerun
    from ..progress import VirtualSeconds
    from ..viz.moment import plot_moment
    from .percepts import CHANNELS, PerceptCollector

    run, check = rerun(trace, until=at)
    try:
        with run:
            seen = PerceptCollector()
            run.dispatcher.add(CHANNELS, seen)
            with VirtualSeconds("re-creating the run") as bar:
                run.run(progress=bar)
            now = run.sim.now
            what = f"t = {now:.2f} s" if at is None or abs(now - at) < 1e-9 else f"t = {now:.2f} s (asked for {at:g} s)"
            if at is None:
                what += ", the end of the recorded run"
            title = f"{run.scenario.name} (seed {run.sim.seed}) at {what}"
            return plot_moment(run.world, percepts=seen.percepts(now, run.world.robot.pose), title=title)
    except HomesimError as exc:
        check.reraise(exc)
        raise
    finally:
        check.close()


def plot_command(a: argparse.Namespace) -> int:
    """``homesim plot``: one moment (default) or the timeline."""
    if a.timeline:
        if a.at is not None:
            raise OptionError("--at", "draws one moment of the flat; --timeline draws a window (choose it with --from/--to)")
        from ..traceview import read_timeline
        from ..viz.timeline import plot_timeline

        out = a.out or Path("out/timeline.png")
        _check_output(out)
        from ..progress import VirtualSeconds

        with VirtualSeconds("reading the trace") as bar:
            tl = read_timeline(a.trace, start=a.start, end=a.end, progress=bar)
        fig = plot_timeline(tl)
        what = f"{len(tl.lanes)} modules, {len(tl.messages)} messages, {len(tl.spans)} processing spans, {tl.start:g}-{tl.end:g} s"
    else:
        if a.start is not None or a.end is not None:
            raise OptionError("--from/--to", "only with --timeline (a moment is chosen with --at)")
        out = a.out or Path("out/plot.png")
        _check_output(out)
        fig = plot_moment_of_trace(a.trace, a.at)
        what = fig.axes[0].get_title()
    out.parent.mkdir(parents=True, exist_ok=True)
    save(fig, out)
    print(f"wrote {out} ({what})")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim plot``."""
    p = sub.add_parser("plot", help="draw a recorded run: the flat at a moment, or the module timeline (Fig. 6)",
                       examples=["homesim plot out/tour.jsonl --at 12 -o out/tour-12s.png",
                                 "homesim plot out/tour.jsonl --timeline --from 0 --to 15 -o out/timeline.svg"])
    p.add_argument("trace", type=Path, help="a trace written by 'homesim run --trace', e.g. out/tour.jsonl")
    p.add_argument("--at", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="the moment to draw (virtual seconds; default: the end of the recorded run; not with --timeline)")
    p.add_argument("-o", "--out", type=cliargs.output_file, default=None, metavar="FILE",
                   help="the picture, .png or .svg (default: out/plot.png, with --timeline out/timeline.png)")
    p.add_argument("--output", dest="out", type=cliargs.output_file, help=argparse.SUPPRESS)  # the spelling of 'scenario plot' before
    p.add_argument("--timeline", action="store_true", help="draw the module communication (Fig. 6) instead of the flat")
    p.add_argument("--from", dest="start", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="timeline: start (virtual seconds; default: the trace's first message)")
    p.add_argument("--to", dest="end", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="timeline: end (virtual seconds; default: the trace's last message)")
    p.set_defaults(func=plot_command)
