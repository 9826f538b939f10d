"""The pan-tilt camera as a bus module (kernels in :mod:`robot.hardware.camera`).

Takes ``<ptu pan="deg" tilt="deg"/>`` on ``/robot/ptu/cmd`` (targets; the
unit moves there at its speeds). At its rate it moves the unit and
publishes, all bearings in degrees in the robot frame:

- ``/robot/ptu/state``: ``<ptu pan tilt target_pan target_tilt/>``
- ``/robot/camera/faces``: ``<faces><face bearing distance height/>...</faces>``
- ``/robot/camera/torsos``: ``<torsos><torso bearing r g b/>...</torsos>``
- ``/robot/camera/gestures``: ``<gestures><pointing bearing distance direction elevation hand_height/>...</gestures>``
- ``/robot/camera/objects``: ``<objects><object type bearing distance r g b width height/>...</objects>``
  (``width``, ``height``: the object's extent across and up the image, degrees)

Every message carries the capture time and the pan/tilt it was taken with.
Ground-truth identities never leave this module.
"""

from __future__ import annotations

import asyncio
import math
from typing import TYPE_CHECKING, Any

from lxml import etree

from homesim.message import Frozen, Message
from homesim.module import Module

from robot.contract import FACES, GESTURES, OBJECTS, PTU_CMD, PTU_STATE, TORSOS

from robot.percepts import FaceRow, PerceptForm, PerceptList, TorsoRow

from .camera import CameraSpec, PanTilt, detect_frame, ptu_step

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World



def _deg(a: float) -> str:
    return f"{math.degrees(a):.3f}"


class Camera(Module):
    """Publishes the camera's detections and the pan-tilt state at ``spec.rate``."""

    def __init__(self, sim: Simulation, world: World, spec: CameraSpec | None = None, *, confusion: float = 0.05, name: str = "camera") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.spec = spec or CameraSpec()
        self.confusion = confusion
        self.ptu = PanTilt()
        # The frame's elements as last built for a pan-tilt state (see _elements).
        self._templates: tuple[tuple[str, str, str, str], Frozen, tuple[Any, ...]] | None = None
        self.bus.subscribe(PTU_CMD, self._on_cmd)

    def _on_cmd(self, msg: Message) -> None:
        pan = float(msg.xml.get("pan", "nan"))
        tilt = float(msg.xml.get("tilt", "nan"))
        self.ptu = PanTilt(
            self.ptu.pan,
            self.ptu.tilt,
            math.radians(pan) if math.isfinite(pan) else self.ptu.target_pan,
            math.radians(tilt) if math.isfinite(tilt) else self.ptu.target_tilt,
        )

    async def run(self) -> None:
        period = 1.0 / self.spec.rate
        while True:
            self.beat()
            self.ptu = ptu_step(self.ptu, period, self.spec)
            self.world.ptu = (self.ptu.pan, self.ptu.tilt)
            self.publish_frame()
            await asyncio.sleep(period)

    def publish_frame(self) -> None:
        """Detect in the current world and publish one message per kind."""
        pose, ptu, w = self.world.robot.pose, self.ptu, self.world
        # Every kind's sight lines in one pass, against the people as they are now (their occluding
        # cylinders built in that pass, once, and only when some percept is a candidate).
        frame = detect_frame(w, pose, ptu, self.spec, self.rng, confusion=self.confusion)
        ptu_state, faces, torsos, gestures, objects = self._elements(ptu)
        time = f"{self.now:.6f}"
        self.bus.publish(PTU_STATE, ptu_state)  # (its XML is copied from the template only if somebody reads it)
        # Faces and torsos as typed records (robot.percepts): their one reader, person attention,
        # reads the rows; the lists' XML is built from the templates only if somebody reads it.
        self.bus.publish(FACES, PerceptList(faces, time, tuple(
            FaceRow(_deg(f.bearing), f"{f.distance:.3f}", f"{f.height:.3f}") for f in frame.faces)))
        self.bus.publish(TORSOS, PerceptList(torsos, time, tuple(
            TorsoRow(_deg(t.bearing), f"{t.colour[0]:.3f}", f"{t.colour[1]:.3f}", f"{t.colour[2]:.3f}") for t in frame.torsos)))
        gestures.set("time", time)
        for g in frame.gestures:
            etree.SubElement(gestures, "pointing", bearing=_deg(g.bearing), distance=f"{g.distance:.3f}", direction=_deg(g.direction), elevation=_deg(g.elevation),
                hand_height=f"{g.hand_height:.3f}")
        self.bus.publish(GESTURES, gestures, transfer=True)
        objects.set("time", time)
        for o in frame.objects:
            etree.SubElement(objects, "object", type=o.type, bearing=_deg(o.bearing), distance=f"{o.distance:.3f}", r=f"{o.colour[0]:.3f}", g=f"{o.colour[1]:.3f}",
                b=f"{o.colour[2]:.3f}", width=_deg(o.width), height=_deg(o.height))
        self.bus.publish(OBJECTS, objects, transfer=True)

    def _elements(self, ptu: PanTilt) -> tuple[Any, ...]:
        """For a frame: ``<ptu pan tilt target_pan target_tilt/>`` as a typed record
        (:class:`~homesim.message.Frozen`, kept per state: nobody subscribes to it in a run, so
        its XML is copied only for the trace) and fresh elements of the four percept lists'
        ``<faces time pan tilt/>`` (etc.; ``time`` to be set), each a copy of a template kept for
        the pan-tilt state as formatted (for faces and torsos the :class:`~robot.percepts.PerceptForm`
        itself: a :class:`~robot.percepts.PerceptList` copies its template only when its XML is read). The unit mostly holds still between frames, and a copy
        with one attribute set costs a third of building an element with its three (same
        attributes, same order: the same message)."""
        key = (_deg(ptu.pan), _deg(ptu.tilt), _deg(ptu.target_pan), _deg(ptu.target_tilt))
        kept = self._templates
        if kept is None or kept[0] != key:
            pan, tilt, target_pan, target_tilt = key
            stamp = {"time": "", "pan": pan, "tilt": tilt}
            kept = self._templates = (key, Frozen(
                etree.Element("ptu", pan=pan, tilt=tilt, target_pan=target_pan, target_tilt=target_tilt),
            ), (PerceptForm("faces", "face", stamp), PerceptForm("torsos", "torso", stamp))
              + tuple(etree.Element(tag, stamp) for tag in ("gestures", "objects")))
        faces, torsos, gestures, objects = kept[2]
        return kept[1], faces, torsos, gestures.__copy__(), objects.__copy__()
