"""BIRON's bus contract as code: every ``/robot/...`` channel, its payload schema and who publishes it.

One name per channel, used by the modules, the run package and the docs
(``docs/robot-contract.md``'s channel table is checked against :data:`CHANNELS`
by ``tests/test_robot_contract.py``). The robot modules' one shared module
besides :mod:`robot.floorplan`: importing it couples no module to another's code.

A :class:`Channel` says what the bus carries, not how a module uses it:
``schema`` is the XSD under ``robot/schemas/`` that types the channel (the
declaring module declares it before any module starts; ``None``: untyped),
``publishers`` the bus participants that send on it and ``root`` the payload's
root element. The supervisor's per-module channels (orders, conditions,
rejections) are families: ``ES_ORDERS + "/" + module``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

#: Where the robot's XSDs live (package data of ``robot.schemas``).
SCHEMA_DIR = Path(__file__).resolve().parent / "schemas"

# ------------------------------------------------------------------ hardware (robot/hardware/)
SCAN = "/robot/laser/scan"
SONAR = "/robot/sonar"
FACES = "/robot/camera/faces"
TORSOS = "/robot/camera/torsos"
GESTURES = "/robot/camera/gestures"
OBJECTS = "/robot/camera/objects"
PTU_CMD = "/robot/ptu/cmd"
PTU_STATE = "/robot/ptu/state"
SOURCES = "/robot/audio/sources"
SPEECH = "/robot/audio/speech"
STEER = "/robot/audio/steer"
BASE_CMD = "/robot/base/cmd"
ODOMETRY = "/robot/odometry"
BUMPERS = "/robot/bumpers"
SAY = "/robot/speaker/say"
SPEAKER_STATUS = "/robot/speaker/status"
DISPLAY_CMD = "/robot/display/cmd"
DISPLAY_STATE = "/robot/display/state"
# ---------------------------------------------------------------------- BIRON's modules
TRACKS = "/robot/attention/tracks"
ATTENTION_STATE = "/robot/attention/state"
PARTNER = "/robot/attention/partner"
FRAMES = "/robot/speech/frames"
POSE = "/robot/localisation/pose"
FOCUS = "/robot/objects/focus"
FOLLOW_STATUS = "/robot/follow/status"
PLAN = "/robot/navigation/plan"
REPLAN = "/robot/navigation/replan"
PLAYER_STATUS = "/robot/player/status"
SCENE_MODEL_REFUSED = "/robot/scene_model/refused"
# ------------------------------------------------------------------ the execution supervisor
ES_EVENTS = "/robot/es/events"
ES_LOG = "/robot/es/log"
ES_STATUS = "/robot/es/status"
#: An arrival the ES inserted ahead of queued events (created before them): its timestamp ordering at work.
ES_SORTED = "/robot/es/sorted"
#: Families: one channel per module (``ES_ORDERS + "/player"``).
ES_ORDERS = "/robot/es/orders"
ES_CONDITIONS = "/robot/es/conditions"
ES_REJECTED = "/robot/es/rejected"


@dataclass(frozen=True)
class Channel:
    """One channel of the contract: name, schema (under ``robot/schemas/``), publishers, payload root."""

    name: str
    schema: str | None
    publishers: tuple[str, ...]
    root: str
    family: bool = False  # a prefix: one channel per module below it

    @property
    def schema_path(self) -> Path | None:
        return None if self.schema is None else SCHEMA_DIR / self.schema


_EVENT_SOURCES = ("dialog", "person_attention", "follower", "object_attention", "scene_model", "sequencer")

#: Every channel of the contract, in the order of ``docs/robot-contract.md``'s table.
CHANNELS: tuple[Channel, ...] = (
    Channel(SCAN, "hardware/laser-scan.xsd", ("laser",), "scan"),
    Channel(SONAR, "hardware/sonar.xsd", ("sonar",), "sonar"),
    Channel(FACES, "hardware/camera-faces.xsd", ("camera",), "faces"),
    Channel(TORSOS, "hardware/camera-torsos.xsd", ("camera",), "torsos"),
    Channel(GESTURES, "hardware/camera-gestures.xsd", ("camera",), "gestures"),
    Channel(OBJECTS, "hardware/camera-objects.xsd", ("camera",), "objects"),
    Channel(PTU_STATE, "hardware/ptu-state.xsd", ("camera",), "ptu"),
    Channel(PTU_CMD, "hardware/ptu-cmd.xsd", ("person_attention",), "ptu"),
    Channel(SOURCES, "hardware/audio-sources.xsd", ("microphones",), "sources"),
    Channel(SPEECH, "hardware/audio-speech.xsd", ("microphones",), "utterance"),
    Channel(STEER, "hardware/audio-steer.xsd", ("person_attention",), "steer"),
    Channel(BASE_CMD, "hardware/base-cmd.xsd", ("person_attention", "follower", "player"), "velocity"),
    Channel(ODOMETRY, "hardware/odometry.xsd", ("base",), "odometry"),
    Channel(BUMPERS, "hardware/bumpers.xsd", ("base",), "bumpers"),
    Channel(SAY, "hardware/speaker-say.xsd", ("dialog",), "say"),
    Channel(SPEAKER_STATUS, "hardware/speaker-status.xsd", ("speaker",), "speaking"),
    Channel(DISPLAY_CMD, "hardware/display-cmd.xsd", ("player", "dialog"), "gaze|expression"),
    Channel(DISPLAY_STATE, "hardware/display-state.xsd", ("display",), "display"),
    Channel(TRACKS, "attention-tracks.xsd", ("person_attention",), "tracks"),
    Channel(ATTENTION_STATE, "attention-state.xsd", ("person_attention",), "attention"),
    Channel(PARTNER, "attention-partner.xsd", ("person_attention",), "partner"),
    Channel(FRAMES, "speech-frames.xsd", ("understanding",), "understood|not_understood"),
    Channel(POSE, "localisation-pose.xsd", ("localiser",), "pose"),
    Channel(FOCUS, "objects-focus.xsd", ("object_attention",), "focus"),
    Channel(FOLLOW_STATUS, "navigation/follow-status.xsd", ("follower",), "follow"),
    Channel(PLAN, "navigation/plan.xsd", ("planner",), "plan"),
    Channel(REPLAN, "navigation/replan.xsd", ("sequencer",), "replan"),
    Channel(PLAYER_STATUS, "navigation/player-status.xsd", ("player",), "player"),
    Channel(SCENE_MODEL_REFUSED, "knowledge.xsd", ("scene_model",), "refused"),
    Channel(ES_EVENTS, "es-event.xsd", _EVENT_SOURCES, "event"),
    Channel(ES_LOG, "es-log.xsd", ("supervisor",), "es_record"),
    Channel(ES_STATUS, "es-status.xsd", ("supervisor",), "es_status"),
    Channel(ES_SORTED, "es-sorted.xsd", ("supervisor",), "es_sorted"),
    Channel(ES_ORDERS, "es-order.xsd", ("supervisor",), "order", family=True),
    Channel(ES_CONDITIONS, "es-condition.xsd", ("supervisor",), "condition", family=True),
    Channel(ES_REJECTED, "es-rejected.xsd", ("supervisor",), "rejected", family=True),
)

#: name -> channel
BY_NAME: dict[str, Channel] = {c.name: c for c in CHANNELS}


def channel(name: str) -> Channel:
    """The contract's entry for a channel name (a family member by its family: ``/robot/es/orders/player``)."""
    found = BY_NAME.get(name)
    if found is not None:
        return found
    family = name.rsplit("/", 1)[0]
    found = BY_NAME.get(family)
    if found is None or not found.family:
        raise KeyError(f"{name} is not a channel of BIRON's contract (robot/contract.py)")
    return found


def markdown_table() -> str:
    """The channel table of ``docs/robot-contract.md`` (``channel | publishers | schema | root``)."""
    rows = ["| channel | published by | schema (`robot/schemas/`) | payload root |", "|---|---|---|---|"]
    for c in CHANNELS:
        name = f"`{c.name}/<module>`" if c.family else f"`{c.name}`"
        roots = " or ".join(f"`<{r}>`" for r in c.root.split("|"))
        rows.append(f"| {name} | {', '.join(c.publishers)} | `{c.schema}` | {roots} |")
    return "\n".join(rows) + "\n"
