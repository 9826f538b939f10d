"""The hardware's typed channels: which XSD each channel's messages must satisfy.

Every channel the PeopleBot's hardware publishes on ("out") or takes
commands from ("in") has a schema in ``robot/schemas/hardware/``, one file
per channel. :func:`declare_channels` types them on a bus (the installer
calls it before any module starts), so the bus validates every message when
it is sent: a malformed sensor message fails its sensor at once, and a
malformed command (``<velocity v="fast"/>``) is refused at the sender with a
:class:`~homesim.errors.MessageValidationError` naming the channel and the
schema, and reaches no device.

The heartbeat channels the modules also publish on (``/system/heartbeat/<name>``)
belong to the kernel and are not typed here.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from robot.contract import (
    BASE_CMD, BUMPERS, DISPLAY_CMD, DISPLAY_STATE, FACES, GESTURES, OBJECTS, ODOMETRY, PTU_CMD, PTU_STATE, SAY, SCAN, SONAR, SOURCES, SPEAKER_STATUS, SPEECH,
    STEER, TORSOS,
)

#: Where the hardware's XSDs live (package data of ``robot.schemas.hardware``).
SCHEMA_DIR = Path(__file__).resolve().parent.parent / "schemas" / "hardware"


@dataclass(frozen=True)
class TypedChannel:
    """One hardware channel: its name, schema file, direction and device module."""

    channel: str
    schema: str  # file name in SCHEMA_DIR
    direction: str  # "out": the device publishes; "in": the device receives commands
    device: str  # the module's (bus participant's) default name

    @property
    def path(self) -> Path:
        return SCHEMA_DIR / self.schema


CHANNELS: tuple[TypedChannel, ...] = (
    TypedChannel(SCAN, "laser-scan.xsd", "out", "laser"),
    TypedChannel(SONAR, "sonar.xsd", "out", "sonar"),
    TypedChannel(FACES, "camera-faces.xsd", "out", "camera"),
    TypedChannel(TORSOS, "camera-torsos.xsd", "out", "camera"),
    TypedChannel(GESTURES, "camera-gestures.xsd", "out", "camera"),
    TypedChannel(OBJECTS, "camera-objects.xsd", "out", "camera"),
    TypedChannel(PTU_STATE, "ptu-state.xsd", "out", "camera"),
    TypedChannel(PTU_CMD, "ptu-cmd.xsd", "in", "camera"),
    TypedChannel(SOURCES, "audio-sources.xsd", "out", "microphones"),
    TypedChannel(SPEECH, "audio-speech.xsd", "out", "microphones"),
    TypedChannel(STEER, "audio-steer.xsd", "in", "microphones"),
    TypedChannel(BASE_CMD, "base-cmd.xsd", "in", "base"),
    TypedChannel(ODOMETRY, "odometry.xsd", "out", "base"),
    TypedChannel(BUMPERS, "bumpers.xsd", "out", "base"),
    TypedChannel(SAY, "speaker-say.xsd", "in", "speaker"),
    TypedChannel(SPEAKER_STATUS, "speaker-status.xsd", "out", "speaker"),
    TypedChannel(DISPLAY_CMD, "display-cmd.xsd", "in", "display"),
    TypedChannel(DISPLAY_STATE, "display-state.xsd", "out", "display"),
)

#: channel -> schema path
SCHEMAS: dict[str, Path] = {c.channel: c.path for c in CHANNELS}


def declare_channels(bus: Any) -> None:
    """Type every hardware channel on ``bus`` (schemas are compiled once per process)."""
    for c in CHANNELS:
        bus.declare_channel(c.channel, c.path)
