"""``homesim export TRACE [--perfetto FILE] [--mcap FILE]``: a recorded run for Perfetto and Foxglove.

TRACE is a JSON Lines trace (``--mcap`` re-creates its run, checked line by line) or a recording
(``homesim run --record``): its embedded trace gives the Perfetto file, and it is the MCAP file already.
"""

from __future__ import annotations

import argparse
import os
import shutil
from pathlib import Path

from .. import cliargs
from ..cliargs import OptionError
from ..errors import HomesimError
from ..progress import VirtualSeconds


def _check_recording(path: Path) -> None:
    """A recording that cannot be read fails here, before anything is written."""
    try:
        from .recorded import Recording
    except ModuleNotFoundError as exc:
        if exc.name != "mcap":
            raise
        raise HomesimError(f"{path} is an MCAP recording; reading it needs the mcap library: pip install 'homesim[export]'") from exc
    with Recording(path) as rec:
        rec.trace_header()


def export_command(a: argparse.Namespace) -> int:
    """Write the asked exports; at least one."""
    if a.perfetto is None and a.mcap is None:
        raise OptionError("--perfetto/--mcap", "say what to export (--perfetto FILE.json and/or --mcap FILE.mcap)")
    for opt, out in (("--perfetto", a.perfetto), ("--mcap", a.mcap)):
        if out is not None and out.exists() and a.trace.exists() and out.samefile(a.trace):
            raise OptionError(opt, f"{out} is the trace being exported; writing there would destroy it")
    if a.perfetto is not None and a.mcap is not None and a.perfetto.absolute() == a.mcap.absolute():
        raise OptionError("--perfetto/--mcap", "the two exports need two files")
    from ..traceview import channel_stats
    from .recorded import as_trace, is_mcap, is_recording

    for opt, out in (("--perfetto", a.perfetto), ("--mcap", a.mcap)):
        if out is not None and is_recording(out):  # an export can be made again; a recording only by running again
            raise OptionError(opt, f"{out} is a recording of 'homesim run --record'; an export does not write over it "
                                   "(name another file, e.g. out/tour-export.mcap)")

    recording = is_mcap(a.trace)
    if recording:
        _check_recording(a.trace)
    else:
        channel_stats(a.trace)  # a file that is not a trace fails here, before anything is written
    if a.perfetto is not None:
        from ..export.perfetto import export_perfetto

        with as_trace(a.trace) as trace, VirtualSeconds("perfetto") as bar:
            c = export_perfetto(trace, a.perfetto, progress=bar)
        print(f"wrote {a.perfetto} (Perfetto / Chrome trace events: {c['threads']} module threads, {c['slices']} work slices, "
              f"{c['instants']} message instants, {c['flows']} cause flows, {c['phases']} phases)")
    if a.mcap is not None:
        try:
            from .mcap_export import export_mcap
        except ModuleNotFoundError as exc:
            if exc.name != "mcap":
                raise
            raise HomesimError("--mcap needs the mcap library: pip install 'homesim[export]'") from exc

        if recording:  # already the Foxglove file (with homesim's own channels beside): copied whole
            tmp = a.mcap.with_name(a.mcap.name + ".part")
            a.mcap.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(a.trace, tmp)
            os.replace(tmp, a.mcap)
            print(f"wrote {a.mcap} (a copy of the recording {a.trace}: it is MCAP for Foxglove already)")
            return 0
        with VirtualSeconds("mcap: re-creating the run") as bar:
            c = export_mcap(a.trace, a.mcap, progress=bar)
        print(f"wrote {a.mcap} (MCAP for Foxglove: {c['channels']} channels, {c['messages']} messages, "
              f"{c['scans']} laser scans, {c['frames']} world frames)")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim export``."""
    p = sub.add_parser("export", help="export a recorded run for Perfetto (trace events) or Foxglove (MCAP)",
                       examples=["homesim export out/tour.jsonl --perfetto out/tour.perfetto.json",
                                 "homesim export out/tour.jsonl --mcap out/tour.mcap",
                                 "homesim export out/tour.mcap --perfetto out/tour.perfetto.json"])
    p.add_argument("trace", type=Path, help="a trace ('homesim run --trace', e.g. out/tour.jsonl; --mcap re-creates the run) "
                                            "or a recording ('homesim run --record', e.g. out/tour.mcap; read alone)")
    p.add_argument("--perfetto", type=cliargs.output_file, default=None, metavar="FILE",
                   help="Chrome trace-event JSON: each module's work on its thread, messages as instants, cause -> message flows (open in ui.perfetto.dev)")
    p.add_argument("--mcap", type=cliargs.output_file, default=None, metavar="FILE",
                   help="MCAP with every bus channel, poses, laser scans, tracks and the map (open in Foxglove); re-creates the run")
    p.set_defaults(func=export_command)
