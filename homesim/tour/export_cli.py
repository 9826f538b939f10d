"""``homesim export TRACE [--perfetto FILE] [--mcap FILE]``: a recorded run for Perfetto and Foxglove."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import cliargs
from ..cliargs import OptionError
from ..errors import HomesimError
from ..progress import VirtualSeconds


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

    channel_stats(a.trace)  # a file that is not a trace fails here, before anything is written
    if a.perfetto is not None:
        from ..export.perfetto import export_perfetto

        with VirtualSeconds("perfetto") as bar:
            c = export_perfetto(a.trace, a.perfetto, progress=bar)
        print(f"wrote {a.perfetto} (Perfetto / Chrome trace events: {c['threads']} modules, {c['slices']} messages, "
              f"{c['spans']} processing spans, {c['flows']} cause flows)")
    if a.mcap is not None:
        try:
            from .mcap_export import export_mcap
        except ModuleNotFoundError as exc:
            if exc.name != "mcap":
                raise
            raise HomesimError("--mcap needs the mcap library: pip install 'homesim[export]'") from exc

        with VirtualSeconds("mcap: re-creating the run") as bar:
            c = export_mcap(a.trace, a.mcap, progress=bar)
        print(f"wrote {a.mcap} (MCAP for Foxglove: {c['channels']} channels, {c['messages']} messages, "
              f"{c['scans']} laser scans, {c['frames']} world frames)")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim export``."""
    p = sub.add_parser("export", help="export a recorded run for Perfetto (trace events) or Foxglove (MCAP)",
                       examples=["homesim export out/tour.jsonl --perfetto out/tour.perfetto.json",
                                 "homesim export out/tour.jsonl --mcap out/tour.mcap"])
    p.add_argument("trace", type=Path, help="a trace written by 'homesim run --trace', e.g. out/tour.jsonl")
    p.add_argument("--perfetto", type=cliargs.output_file, default=None, metavar="FILE",
                   help="Chrome trace-event JSON: module processing spans and cause -> message flows (open in ui.perfetto.dev)")
    p.add_argument("--mcap", type=cliargs.output_file, default=None, metavar="FILE",
                   help="MCAP with every bus channel, poses, laser scans, tracks and the map (open in Foxglove); re-creates the run")
    p.set_defaults(func=export_command)
