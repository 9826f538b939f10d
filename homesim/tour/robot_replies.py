"""Reactions that could answer the robot's own replies for ever, refused (a ``homesim.scenario_checks`` entry point).

humans/checks.py refuses a reaction without ``max=`` that could trigger itself
when the robot echoes her words; it cannot know the rest of what the robot
says (the people never read the robot's files). But the robot answers a
request with its own sentences too: "Hello BIRON" gets "Hello, I am BIRON.
What can I do for you?" and, once greeted, "We are already talking. What can
I do for you?"; "follow me" while following gets "I am still following you;
say stop first.". A reaction that hears such a reply and speaks again gets it
again, every few seconds, to the end of the run. The run package composes the
robot and may read its dialog file: this check takes every sentence BIRON says
in reply to a request (its speech-triggered dialogs, rejections and own
sentences; not what it says on its own, such as "I have lost you") and
refuses a speaking reaction without ``max=`` that hears one of them, with
file:line and the sentence.
"""

from __future__ import annotations

import re
from functools import lru_cache

from humans.checks import spoken
from robot.dialog.loader import BIRON_DIALOGS

from ..errors import ScenarioError
from ..scenario.model import Action, Handler, Repeat, Scenario, WaitFor
from ..scenario.wordpattern import compile_words
from ..xmlio import parse_file


def _render(text: str) -> str:
    """A template's sentence as heard: each ``{slot:path|default}`` as its default (or "it")."""
    return " ".join(re.sub(r"\{([^}]*)\}", lambda m: m.group(1).rpartition("|")[2] if "|" in m.group(1) else "it", text).split())


@lru_cache(maxsize=1)
def replies() -> tuple[str, ...]:
    """Every sentence BIRON says in answer to something a person said (its dialog file's wording)."""
    root = parse_file(BIRON_DIALOGS)
    els = list(root.iter("rejection", "sentence", "state-phrase"))
    for d in root.iter("dialog"):
        if d.get("condition") is None:  # a dialog started by her words, not by an event of the robot's own
            els += list(d.iter("say", "ask", "confirm"))
    return tuple(dict.fromkeys(t for t in (_render(e.text or "") for e in els) if t))


def check_scenario(sc: Scenario) -> list[ScenarioError]:
    """Each speaking reaction without ``max=`` that hears one of the robot's replies."""
    out: list[ScenarioError] = []
    seen: set[int] = set()
    for h in sc.humans:
        for hd in _handlers(h.handlers, h.script):
            if id(hd) in seen or hd.max is not None:
                continue
            seen.add(id(hd))
            pattern = compile_words(hd.hears)
            reply = next((r for r in replies() if pattern.search(r)), None)
            if reply is not None and spoken(hd.body):
                out.append(ScenarioError(
                    f"<on hears={hd.hears!r}> without max= speaks and hears what the robot says in reply to a request "
                    f"({reply!r}, {BIRON_DIALOGS.name}): what she says may get that reply again, so it could fire for ever; give max=",
                    source=sc.source, line=hd.line, element="on"))
    return out


def _handlers(handlers: tuple[Handler, ...], script: tuple[Action, ...]) -> list[Handler]:
    """Her reactions and every wait's own reactions (in reactions and repeats too)."""
    out = list(handlers)
    todo = list(script) + [a for hd in handlers for a in hd.body]
    while todo:
        a = todo.pop(0)
        if isinstance(a, Repeat):
            todo += list(a.body)
        elif isinstance(a, WaitFor):
            for hd in a.handlers:
                out.append(hd)
                todo += list(hd.body)
    return out
