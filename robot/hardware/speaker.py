"""The robot's loudspeaker and its display with the avatar face.

The speaker takes ``<say text="..."/>`` on ``/robot/speaker/say``, puts the
utterance into the world's air (people's scripts hear it and can react) and
publishes ``<speaking text start end level/>`` (``level``: its loudness, dB
SPL at 1 m) when it starts and ``<done text/>``
when it ends on ``/robot/speaker/status``; a new utterance cuts the previous
one short. The duration comes from the word count. A say with no words
(``<say/>``, ``<say text=""/>``) only silences the robot: the utterance in
progress is cut (``<interrupted text/>``) and nothing new is said (the
dialog's barge-in).

The display takes ``<gaze pan="deg" tilt="deg"/>`` (where the avatar's eyes
look, robot frame) or ``<expression name="..."/>`` on ``/robot/display/cmd``
and reports its state on ``/robot/display/state`` at every change.
"""

from __future__ import annotations

import asyncio
import math
from typing import TYPE_CHECKING

from lxml import etree

from homesim.message import Message
from homesim.module import Module
from robot.contract import DISPLAY_CMD, DISPLAY_STATE, SAY, SPEAKER_STATUS

if TYPE_CHECKING:
    from homesim.sim import Simulation
    from homesim.world.world import World



class Speaker(Module):
    """Says what it is told into the world's sound field."""

    def __init__(self, sim: Simulation, world: World, *, loudness: float = 62.0, name: str = "speaker") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.loudness = loudness
        self.queue = self.bus.subscribe(SAY)

    async def run(self) -> None:
        while True:
            self.beat()
            try:
                async with asyncio.timeout(0.25):
                    msg = await self.queue.get()
            except TimeoutError:
                continue
            await self.say(msg)

    async def say(self, msg: Message) -> None:
        text = msg.xml.get("text") or (msg.xml.text or "")
        if not text.strip():
            return  # silence: nothing in progress (a cut utterance was handled by the loop below)
        u = self.world.sound.say("robot", text, self.now, loudness=self.loudness)
        status = etree.Element("speaking", text=text, start=f"{u.start:.6f}", end=f"{u.end:.6f}", level=f"{self.loudness:.1f}")
        self.bus.publish(SPEAKER_STATUS, status, causes=(msg.id,))
        while self.now < u.end - 1e-6:  # (virtual time is integer ns: never sleep 0)
            self.beat()
            nxt = self.queue.get_nowait()
            if nxt is not None:  # a new utterance interrupts this one
                self.bus.publish(SPEAKER_STATUS, etree.Element("interrupted", text=text), causes=(msg.id,))
                if not (nxt.xml.get("text") or (nxt.xml.text or "")).strip():
                    self.world.sound.cut("robot", self.now)  # barge-in: stop talking, say nothing
                await self.say(nxt)
                return
            await asyncio.sleep(min(0.1, u.end - self.now))
        self.bus.publish(SPEAKER_STATUS, etree.Element("done", text=text), causes=(msg.id,))


class Display(Module):
    """The touch screen's avatar face: gaze direction and expression."""

    def __init__(self, sim: Simulation, world: World, *, name: str = "display") -> None:
        super().__init__(sim, name, host="robot")
        self.world = world
        self.gaze = (0.0, 0.0)
        self.expression = "neutral"
        self.cmds = self.bus.subscribe(DISPLAY_CMD)

    async def run(self) -> None:
        while True:
            self.beat()
            try:
                async with asyncio.timeout(0.25):
                    msg = await self.cmds.get()
            except TimeoutError:
                continue
            if msg.xml.tag == "gaze":
                pan = math.radians(float(msg.xml.get("pan", "0")))
                tilt = math.radians(float(msg.xml.get("tilt", "0")))
                self.gaze = (max(-math.pi / 2, min(math.pi / 2, pan)), max(-math.pi / 4, min(math.pi / 4, tilt)))
            elif msg.xml.tag == "expression":
                self.expression = msg.xml.get("name", "neutral")
            self.world.avatar = {"pan": self.gaze[0], "tilt": self.gaze[1], "expression": self.expression}
            self.bus.publish(
                DISPLAY_STATE,
                etree.Element("display", pan=f"{math.degrees(self.gaze[0]):.2f}", tilt=f"{math.degrees(self.gaze[1]):.2f}", expression=self.expression),
                causes=(msg.id,),
            )
