"""``homesim run``, ``homesim replay`` and ``homesim scenario run|plot``.

``homesim run SCENARIO`` builds the whole run (:mod:`homesim.tour.runner`),
prints a live transcript (virtual time, speaker, words; supervisor state
changes; rejections with their reasons; faults and heartbeat failures), a
progress bar when stdout is a terminal, one line per expectation and the
verdict; exit status 0 when every expectation holds (or the scenario
states none: the verdict is then "no expectations", never PASS 0/0), 1 when
one fails, 2 for bad input (a message naming file and line). ``--summary FILE`` writes
the run summary as JSON, ``--trace FILE`` the bus trace (JSON Lines) whose
header lets ``homesim replay TRACE`` run the same scenario, seed and
options again and compare every line: the first differing line is printed
and the exit status is 1 (also when the scenario file has changed since).
``homesim scenario run`` is the same as ``homesim run``; ``homesim scenario
plot FILE --at T -o out.png`` draws the flat at one moment.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import IO, Any

from .. import cliargs
from ..cliargs import OptionError
from ..errors import HomesimError
from ..message import Message
from ..progress import VirtualSeconds, write
from robot.profiles import PROFILES
from .runheader import RATES
from .runner import Run, RunOptions, file_digest, store_digest
from .tracerun import next_line, read_header, run_options, store_copy, trace_lines

class Console:
    """Transcript lines on ``out`` and a progress bar in virtual seconds on a terminal's stderr (tqdm)."""

    def __init__(self, out: IO[str], *, quiet: bool) -> None:
        self.out = out
        self.quiet = quiet
        self.bar = VirtualSeconds("run")

    def line(self, t: float, who: str, text: str) -> None:
        if self.quiet:
            return
        write(f"{t:8.2f}  {who:>12}: {text}", file=self.out)

    def progress(self, now: float, end: float) -> None:
        if not self.quiet:
            self.bar(now, end)

    def close(self) -> None:
        """Remove the bar (the run has ended or failed)."""
        self.bar.close()

    def text(self, s: str) -> None:
        write(s, file=self.out)


_count = cliargs.count


def _options(a: argparse.Namespace) -> RunOptions:
    """The run's options; --until, --realtime and --seed were checked by their argparse types (homesim.cliargs)."""
    return RunOptions(seed=a.seed, until=a.until, trace=a.trace, memory=a.memory, realtime=a.realtime, strict=a.strict or None,
                      profile=a.profile, rates=a.rates)


def run_command(a: argparse.Namespace) -> int:
    """``homesim run``: transcript, verdict, summary; the exit status says whether every expectation held."""
    out = sys.stdout
    console = Console(out, quiet=a.quiet)
    _check_outputs(a)
    run = Run.from_file(a.scenario, _options(a), on_line=console.line)
    with run:
        recorder = _start_recording(run, getattr(a, "record", None))
        try:
            status = _run_and_report(a, run, console, out)
        except BaseException as exc:
            if recorder is not None:  # what was recorded is kept, marked partial (the trace keeps its lines too)
                _close_partial(recorder, "interrupted (Ctrl-C)" if isinstance(exc, KeyboardInterrupt) else f"{type(exc).__name__}: {exc}")
            raise
        if recorder is not None:
            c = recorder.close()
            print(f"wrote {a.record} (MCAP recording: {c['channels']} channels, {c['messages']} messages, {c['scans']} laser scans)", file=out)
        return status


def _check_outputs(a: argparse.Namespace) -> None:
    """Before the run: no output file is the scenario, the memory directory (or in it), or another output."""
    def same(p: Path, q: Path) -> bool:
        return p.resolve() == q.resolve()

    outs = [(opt, path) for opt, path in (("--trace", a.trace), ("--summary", a.summary), ("--record", getattr(a, "record", None)))
            if path is not None]
    for i, (opt, path) in enumerate(outs):
        if same(path, a.scenario):
            raise OptionError(opt, f"{path} is the scenario file; writing there would destroy it")
        if a.memory is not None and (same(path, a.memory) or a.memory.resolve() in path.resolve().parents):
            raise OptionError(opt, f"{path} is the --memory directory {a.memory} or in it; the run writes its store there")
        for other, q in outs[:i]:
            if same(path, q):
                raise OptionError(opt, f"{path} is also the {other} file; each output needs a file of its own")


def _close_partial(recorder: Any, reason: str) -> None:
    try:
        recorder.close(stopped=reason)
    except Exception:  # the recorder itself failed: no whole file can be written
        recorder.abandon()
        return
    print(f"homesim: kept the partial recording {recorder.path} (stopped: {reason})", file=sys.stderr)


def _start_recording(run: Run, path: Path | None) -> Any:
    if path is None:
        return None
    try:
        from .recording import record
    except ModuleNotFoundError as exc:
        if exc.name != "mcap":
            raise
        raise HomesimError("--record needs the mcap library: pip install 'homesim[export]'") from exc
    return record(run, path)


def _run_and_report(a: argparse.Namespace, run: Run, console: Console, out: IO[str]) -> int:
    """Run, print the verdict; the exit status says whether every expectation held."""
    sc = run.scenario
    if not a.quiet:
        console.text(f"scenario {sc.name} ({a.scenario}): seed {run.sim.seed}, {run.end:g} of {sc.duration:g} s, "
                     f"{_count(len(sc.humans), 'person', 'people')}, {_count(len(sc.sources), 'other sound source')}, "
                     f"robot modules: {', '.join(sorted(run.modules)) or 'none'}")
        console.text(f"robot profile {run.profile}; deployment {run.deployment.name}: "
                     + ", ".join(f"{h.name} ({h.link}" + (f", sends over {h.uplink}" if h.uplink else "") + ")"
                                 for h in run.deployment.hosts)
                     + "".join(f"; {r.src} -> {r.dst} over {r.link}" for r in run.deployment.routes))
    try:
        run.run(progress=console.progress)
    finally:
        console.close()
    verdicts = run.finish()
    summary = run.summary()
    if a.summary is not None:
        a.summary.parent.mkdir(parents=True, exist_ok=True)
        a.summary.write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    written = [f"{path} ({what})" for path, what in ((a.trace, "trace"), (a.summary, "summary")) if path is not None]
    if written:
        print("wrote " + ", ".join(written), file=out)
    if not run.complete():
        print(f"verdict: not checked (stopped at {summary['sim_time_s']:g} s of {sc.duration:g} s)", file=out)
        return 0
    for v in verdicts:
        if not a.quiet or not v.passed:
            print("  " + v.line(), file=out)
    if not a.quiet:
        print(network_line(summary), file=out)
    if not verdicts:
        print("verdict: no expectations (the run completed; the scenario states no <expect>, so nothing was "
              "checked: it neither passed nor failed)", file=out)
        return 0
    passed = sum(v.passed for v in verdicts)
    print(f"verdict: {summary['verdict']} ({passed}/{len(verdicts)} expectations hold)", file=out)
    return 0 if summary["verdict"] == "PASS" else 1


def network_line(summary: dict[str, Any]) -> str:
    """One line of the summary's network figures: per link mean / p95 / max ms, and the ES's arrivals."""
    links = summary.get("deployment", {}).get("links", {})
    parts = [f"{name} {st['mean_ms']:.2f}/{st['p95_ms']:.2f}/{st['max_ms']:.1f} ms ({st['deliveries']})"
             for name, st in links.items() if st.get("deliveries")]
    es = summary.get("es", {})
    line = "network (mean/p95/max, deliveries): " + ", ".join(parts)
    if "events_received" in es:
        line += f"; ES: {es['events_received']} events, {es['received_out_of_order']} out of creation order"
        if "sorted_ahead" in es:
            line += f" ({es['sorted_ahead']} sorted ahead of queued events)"
    return line


# ------------------------------------------------------------------ replay
class Comparison:
    """A text stream that compares each trace line written to it with the original file's."""

    def __init__(self, path: Path) -> None:
        self.fh = trace_lines(path)
        self.line = 0
        self.diverged: tuple[int, str, str] | None = None

    def write(self, s: str) -> int:
        if self.diverged is None:  # the recorder writes one whole line per call
            self.line += 1
            want, utf8 = next_line(self.fh)
            if want != s:
                self.diverged = (self.line, want.rstrip("\n") + ("" if utf8 else "  <- not UTF-8 text"), s.rstrip("\n"))
        return len(s)

    def flush(self) -> None:
        pass

    def rest(self) -> str:
        """The original's next line, if any (a replay that ends early differs there)."""
        return next_line(self.fh)[0].rstrip("\n")

    def close(self) -> None:
        self.fh.close()


def replay(trace: Path, *, out: IO[str] | None = None) -> int:
    """Re-run what ``trace``'s header names; 0 when the new trace is identical, 1 otherwise."""
    out = sys.stdout if out is None else out
    h = read_header(trace)  # the whole header checked before anything in it is used
    path = Path(h["scenario_file"])
    if not path.is_file():
        raise HomesimError(f"{trace}:1: the scenario file {path} named in the header does not exist")
    digest = file_digest(path)
    if digest != h["scenario_digest"]:
        print(f"replay: {path} has changed since the trace was written ({h['scenario_digest']} then, {digest} now)", file=out)
        return 1
    if h["memory"] is not None:
        now = store_digest(h["memory"])
        if now != h["memory_digest"]:
            print(f"replay: the store {h['memory']} has changed since the trace was written ({h['memory_digest']} then, "
                  f"{now} now; a run with --memory writes what it learned to its store: replay it from a copy of the "
                  "store made before the run)", file=out)
            return 1
    cmp = Comparison(trace)
    store = store_copy(h)  # the re-run writes what it learns to a copy, never to the store the trace names
    try:
        with Run.from_file(path, run_options(h, until=h["until"], trace=cmp,
                                             store=None if store is None else Path(store.name))) as run:
            with VirtualSeconds("replay") as bar:
                run.run(progress=bar, stop=lambda: cmp.diverged is not None)
            if cmp.diverged is None:
                run.finish()  # the closing questions to the scene model are in the trace too
        if cmp.diverged is None:
            extra = cmp.rest()
            if extra:
                cmp.diverged = (cmp.line + 1, extra, "<the replay's trace ends here>")
    finally:
        cmp.close()
        if store is not None:
            store.cleanup()
    if cmp.diverged is not None:
        n, want, got = cmp.diverged
        print(f"replay: {trace}:{n} differs\n  trace:  {want[:400]}\n  replay: {got[:400]}", file=out)
        return 1
    print(f"replay: identical ({cmp.line} lines; {h['scenario_file']}, seed {h['seed']})", file=out)
    return 0


# -------------------------------------------------------------------- plot
def plot_command(a: argparse.Namespace) -> int:
    """Run to ``--at`` and save the top-down view of that moment with the latest scan and sounds."""
    from .. import viz  # noqa: F401 (the package)

    latest: dict[str, Message] = {}
    run = Run.from_file(a.file, RunOptions(seed=a.seed, until=a.at))
    with run:
        if a.at is not None and a.at > run.scenario.duration:
            raise OptionError("--at", f"{a.at:g} s is outside the scenario ({run.scenario.name}: 0 to {run.scenario.duration:g} s)")
        run.dispatcher.add(("/robot/laser/scan", "/robot/audio/sources"), lambda m: latest.__setitem__(m.channel, m))
        with VirtualSeconds("simulating") as bar:
            run.run(progress=bar)
        scan: Any = None
        sounds: list[float] = []
        if "/robot/laser/scan" in latest:
            m = latest["/robot/laser/scan"]
            ranges = m.attachments["ranges"]
            start = math.radians(float(m.xml.get("min_angle")))
            step = math.radians(float(m.xml.get("resolution")))
            import numpy as np

            scan = (start + step * np.arange(len(ranges)), np.asarray(ranges))
        src = latest.get("/robot/audio/sources")
        if src is not None and run.sim.now - src.created < 0.2:
            sounds = [math.radians(float(s.get("bearing"))) for s in src.xml.iterfind("source")]
        fig = viz.plot_moment(run.world, scan=scan, sound_bearings=sounds)
        a.out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(a.out, dpi=120)
        print(f"wrote {a.out} ({run.scenario.name} at t = {run.sim.now:g} s)")
    return 0


def _run_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scenario", type=Path, help="a scenario file, e.g. scenarios/home_tour.xml")
    p.add_argument("--seed", type=cliargs.seed, default=None, help="override the scenario's seed (default: the scenario's)")
    p.add_argument("--until", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="stop early (virtual seconds; expectations are not checked; default: the scenario's duration)")
    p.add_argument("--trace", type=cliargs.output_file, default=None, metavar="FILE",
                   help="write the bus trace (JSON Lines; replay it with 'homesim replay')")
    p.add_argument("--summary", type=cliargs.output_file, default=None, metavar="FILE", help="write the run summary (JSON)")
    p.add_argument("--record", type=cliargs.output_file, default=None, metavar="FILE.mcap",
                   help="record the run to MCAP as it runs: every bus message with the laser's ranges, the world's truth, "
                        "the map and the trace, with scenario, seed, profile and versions as metadata (plot, export and "
                        "'homesim trace' read it without the scenario file)")
    p.add_argument("--memory", type=cliargs.store_dir, default=None, metavar="DIR",
                   help="the robot's knowledge store (a directory, created if missing): load it at the start, save to it")
    p.add_argument("--profile", default=None, choices=sorted(PROFILES),
                   help="which robot (overrides the scenario's <robot profile>; default: the scenario's, else full)")
    p.add_argument("--rates", choices=sorted(RATES), default=None,
                   help="sensor rates: hardware runs the laser at 37.5 Hz and the camera at 25 Hz as on BIRON's "
                        "PeopleBot (default: the scenario's <robot laser-rate camera-rate>, 10 Hz each)")
    p.add_argument("--realtime", type=cliargs.realtime_scale, default=None, metavar="X", help="pace the run at X times real time")
    p.add_argument("--quiet", action="store_true", help="print the verdict (and failed expectations) only")
    p.add_argument("--strict", action="store_true",
                   help="validate every bus message on a typed channel (default: only documents sent as text; "
                        "the modules' own messages are validated by the test suite)")
    p.set_defaults(func=run_command)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``homesim run``, ``homesim replay`` and ``homesim scenario run|plot``."""
    run_examples = ["homesim run scenarios/home_tour.xml",
                    "homesim run scenarios/home_tour.xml --seed 3 --until 15 --trace out/tour.jsonl",
                    "homesim run scenarios/home_tour.xml --until 15 --record out/tour.mcap",
                    "homesim run scenarios/later_visit.xml --memory out/memory"]
    _run_arguments(sub.add_parser("run", help="run a scenario: transcript, expectations, verdict", examples=run_examples))
    r = sub.add_parser("replay", help="re-run a trace's scenario and check the new trace is identical",
                       examples=["homesim replay out/tour.jsonl"])
    r.add_argument("trace", type=Path, help="a trace written by 'homesim run --trace', e.g. out/tour.jsonl")
    r.set_defaults(func=lambda a: replay(a.trace))
    p = sub.add_parser("scenario", help="run or plot a scenario file",
                       examples=["homesim scenario run scenarios/home_tour.xml", "homesim scenario plot scenarios/radio.xml --at 9 -o out/radio.png"])
    ssub = p.add_subparsers(dest="scenario_command", metavar="ACTION")
    _run_arguments(ssub.add_parser("run", help="the same as 'homesim run'", examples=[e.replace("homesim run", "homesim scenario run") for e in run_examples]))
    q = ssub.add_parser("plot", help="draw the top-down view at one moment",
                        examples=["homesim scenario plot scenarios/radio.xml --at 9 -o out/radio.png",
                                  "homesim scenario plot scenarios/home_tour.xml -o out/tour-end.svg"])
    q.add_argument("file", type=Path, help="a scenario file, e.g. scenarios/radio.xml")
    q.add_argument("--at", type=cliargs.seconds(), default=None, metavar="SECONDS",
                   help="virtual time in seconds, within the scenario (default: its end)")
    q.add_argument("-o", "--out", type=cliargs.output_file, default=Path("out/scenario.png"), metavar="FILE",
                   help="the picture (.png or .svg)")
    q.add_argument("--output", dest="out", type=cliargs.output_file, help=argparse.SUPPRESS)  # the old spelling
    q.add_argument("--seed", type=cliargs.seed, default=None, help="override the scenario's seed (default: the scenario's)")
    q.set_defaults(func=plot_command)
    p.set_defaults(func=lambda a: (p.print_help(), 2)[1])
