"""A readable transcript of an interaction from trace records (what was heard, understood, decided, said).

Works on the records of :class:`homesim.trace.TraceRecorder` (or the JSON lines
of a trace file): the user's recognised words, the understanding's frames, the
dialog's events to the supervisor, the supervisor's decisions and rejections,
and what the robot said. For notebooks, reports and tests; it reads only what
was on the bus.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from homesim.xmlio import parse_bytes
from robot.contract import ES_EVENTS, ES_LOG, FRAMES, SAY, SPEECH


def transcript(records: Iterable[dict[str, Any]]) -> list[str]:
    """One line per relevant message: ``time  who  what``."""
    lines: list[str] = []
    for r in records:
        if r.get("kind") not in ("publish", "request"):
            continue
        ch = r.get("channel", "")
        t = float(r["t"])
        if ch == SPEECH:
            x = parse_bytes(r["xml"])
            if x.get("self") != "true":
                lines.append(f"{t:8.3f}  user        \"{x.text or ''}\"")
        elif ch == FRAMES:
            x = parse_bytes(r["xml"])
            what = r["xml"][r["xml"].find("<SPEECH>"):r["xml"].find("</SPEECH>") + 9] if x.tag == "understood" else "not understood"
            lines.append(f"{t:8.3f}  understood  {what}")
        elif ch == ES_EVENTS and r.get("sender") == "dialog":
            lines.append(f"{t:8.3f}  dialog      -> ES event {parse_bytes(r['xml']).get('name')}")
        elif ch == ES_LOG:
            x = parse_bytes(r["xml"])
            if x.get("kind") == "applied":
                lines.append(f"{t:8.3f}  ES          {x.get('name')}: {x.get('state')} -> {x.get('to')}")
            elif x.get("kind") == "rejected":
                lines.append(f"{t:8.3f}  ES          rejected {x.get('name')} ({x.get('reason')}) in {x.get('state')}")
        elif ch == SAY:
            lines.append(f"{t:8.3f}  BIRON       \"{parse_bytes(r['xml']).get('text', '')}\"")
    return lines
