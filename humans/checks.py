"""The simulated people's checks of a scenario (``homesim.scenario_checks`` entry point).

What the kernel's checks cannot see because the data lives here: a
``profile=`` names a profile of ``humans/profiles.xml``; ``phrasing=`` a
style of the paraphrase bank; every ``<say request=...>`` names a request of
``humans/phrasings.xml`` and gives ``about=`` when its phrasings have the slot;
and no reaction can go on for ever. A reaction without ``max=`` is refused
when what it says could trigger a reaction again, assuming the robot echoes
a person's words (it does: "Is this the kitchen?", "OK, I have learned your
cup"): an ``<on>`` whose pattern matches its own words, or a cycle of
reactions each of which says words the next one hears, or a pattern that
matches whatever the robot says (``*``), or a reaction that speaks and hears
the robot ask her to say it again (:data:`REPAIR_REQUESTS`): a robot may
answer anything she says that way, whatever her words, so it fires again.
Each problem names file and line.
"""

from __future__ import annotations


from homesim.scenario.checks import walk_actions
from homesim.errors import ScenarioError
from homesim.scenario.model import Action, Handler, Say, Scenario, WaitFor
from homesim.scenario.wordpattern import compile_words

from .phrasings import STYLES, default_bank
from .profiles import default_profiles

#: How a robot asks a person to say it again (what BIRON and most spoken-dialogue systems say
#: when they did not understand): the answer anything she says can get, whatever her words.
REPAIR_REQUESTS = (
    "Sorry, I did not understand you. Could you say that again?",
    "Sorry, I didn't catch that. Please say it again.",
    "Pardon?",
    "Could you repeat that, please?",
)


def check_scenario(sc: Scenario) -> None:
    """Raise ScenarioError for the first problem of ``sc``'s people that needs the profiles or banks."""
    profiles = default_profiles()
    bank = default_bank()
    for h in sc.humans:
        if h.profile is not None and h.profile not in profiles:
            raise ScenarioError(f"{h.name!r}: unknown profile {h.profile!r}; profiles: {', '.join(profiles)}", source=sc.source, line=h.line, element="human")
        for key, raw in h.traits:
            if key == "phrasing" and raw not in STYLES:
                raise ScenarioError(f"phrasing={raw!r}: one of {', '.join(STYLES)}", source=sc.source, line=h.line, element="human")
        acts = list(walk_actions(h.script)) + [a for hd in h.handlers for a in walk_actions(hd.body)]
        for act in acts:
            if isinstance(act, Say) and act.request is not None:
                if act.request not in bank.requests:
                    raise ScenarioError(f"request={act.request!r} is not in the paraphrase bank; requests: {', '.join(sorted(bank.requests))}",
                                        source=sc.source, line=act.line, element="say")
                if act.about is None and act.side_of is None and any(p.has_slot for p in bank.phrasings(act.request)):
                    raise ScenarioError(f"request={act.request!r} has phrasings with a slot: give about= (e.g. about=\"the kitchen\") or side-of=",
                                        source=sc.source, line=act.line, element="say")
        _loops(sc, h.handlers)
        for act in walk_actions(h.script + tuple(a for hd in h.handlers for a in hd.body)):
            if isinstance(act, WaitFor) and act.handlers:  # a wait's reactions, with hers, during the wait
                _loops(sc, act.handlers + h.handlers)


def spoken(actions: tuple[Action, ...]) -> list[str]:
    """Everything a person could say doing ``actions``: texts and every phrasing of their requests."""
    bank = default_bank()
    out: list[str] = []
    for act in walk_actions(actions):
        if isinstance(act, Say):
            if act.text is not None:
                out.append(act.text)
            if act.request is not None and act.request in bank.requests:
                out += [p.render(act.about) for p in bank.phrasings(act.request)]
        if isinstance(act, WaitFor) and act.give_up in ("stop", "leave"):
            out += [p.render(None) for p in bank.phrasings("give-up")]
    return out


def _loops(sc: Scenario, handlers: tuple[Handler, ...]) -> None:
    """Refuse unbounded reactions that can trigger themselves or each other for ever."""
    free = [h for h in handlers if h.max is None]
    for h in free:
        if () in compile_words(h.hears).phrases():
            raise ScenarioError(f"<on hears={h.hears!r}> without max= matches whatever the robot says, its answer to this very reaction too: "
                                "it could fire for ever; give max= or a pattern with words", source=sc.source, line=h.line, element="on")
    for h in free:
        pattern = compile_words(h.hears)
        asked = next((r for r in REPAIR_REQUESTS if pattern.search(r)), None)
        if asked is not None and spoken(h.body):
            raise ScenarioError(f"<on hears={h.hears!r}> without max= speaks and hears the robot ask her to say it again ({asked!r}): "
                                "whatever she says may get that answer, so it could fire for ever; give max=",
                                source=sc.source, line=h.line, element="on")
    # edges: a -> b when a says words b hears (the robot may echo them)
    says = {id(h): spoken(h.body) for h in free}
    edges = {id(a): [b for b in free if any(compile_words(b.hears).search(t) for t in says[id(a)])] for a in free}
    for start in free:
        path = _cycle(start, edges)
        if path:
            lines = " -> ".join(f"line {x.line}" for x in path + [path[0]])
            what = "its own words" if len(path) == 1 else "each other's words"
            raise ScenarioError(f"<on hears={start.hears!r}> without max= can never end: the robot echoing {what} triggers it again "
                                f"({lines}); give max= or reword the reaction", source=sc.source, line=start.line, element="on")


def _cycle(start: Handler, edges: dict[int, list[Handler]]) -> list[Handler] | None:
    """A cycle through ``start`` (depth-first, in file order), or None."""
    stack: list[tuple[Handler, list[Handler]]] = [(start, [start])]
    seen: set[int] = set()
    while stack:
        node, path = stack.pop()
        for nxt in reversed(edges[id(node)]):
            if nxt is start:
                return path
            if id(nxt) not in seen:
                seen.add(id(nxt))
                stack.append((nxt, path + [nxt]))
    return None
