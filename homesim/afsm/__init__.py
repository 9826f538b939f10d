"""Augmented finite state machines (AFSMs) for an execution supervisor.

A generic package (it knows nothing of BIRON): ``model`` holds the machine
as plain data with its semantic validation, ``loader`` the checked pipeline
from SCXML text to a model (and back), ``engine`` the event queue and
processing of docs/semantics.md §2 with time injected, ``render`` DOT/Mermaid
export, ``strategies`` Hypothesis strategies for random machines and event
streams, ``cli`` the ``homesim afsm`` subcommand.
"""

from .engine import Applied, Engine, Event, Output, Rejected, Retained, record_dict
from .loader import check, check_file, dumps, load, loads
from .model import Machine, State, Transition, validate

__all__ = [
    "Applied", "Engine", "Event", "Machine", "Output", "Rejected", "Retained", "State", "Transition",
    "check", "check_file", "dumps", "load", "loads", "record_dict", "validate",
]
