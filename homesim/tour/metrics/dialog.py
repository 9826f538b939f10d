"""Dialog metrics: what was said and understood, and which instructions were refused.

Counts people's utterances (ground truth: the world's sound field, by
source), recognised utterances (``/robot/audio/speech``), frames understood
and not understood (``/robot/speech/frames``), what the robot said
(``/robot/speaker/say``), and the supervisor's rejections returned to the
dialog by reason (``/robot/es/rejected/dialog``); ``subdialogs`` is the dialog
module's own ``summary()`` (turns, repairs, rejections explained, task success
per sub-dialog).
"""

from __future__ import annotations

from typing import Any

from . import Observer


class Dialog(Observer):
    channels = ("/robot/audio/speech", "/robot/speech/frames", "/robot/speaker/say", "/robot/es/rejected/dialog")

    def __init__(self, run: Any) -> None:
        super().__init__(run)
        self.recognised = 0
        self.understood = 0
        self.not_understood = 0
        self.robot_said = 0
        self.rejected: dict[str, int] = {}

    def on_message(self, m: Any) -> None:
        ch = m.channel
        if ch == "/robot/audio/speech":
            self.recognised += m.xml.get("self") != "true"
        elif ch == "/robot/speech/frames":
            if m.xml.tag == "understood":
                self.understood += 1
            else:
                self.not_understood += 1
        elif ch == "/robot/speaker/say":
            self.robot_said += bool((m.xml.get("text") or m.xml.text or "").strip())  # <say/> only silences
        else:
            key = f"{m.xml.get('name')}:{m.xml.get('reason')}"
            self.rejected[key] = self.rejected.get(key, 0) + 1

    def summary(self) -> dict[str, Any]:
        by_source = self.run.world.sound.said_by()
        heard = self.understood + self.not_understood
        return {
            "utterances_by_source": dict(sorted(by_source.items())),
            "recognised": self.recognised,
            "understood": self.understood,
            "not_understood": self.not_understood,
            "understood_share": round(self.understood / heard, 4) if heard else None,
            "robot_said": self.robot_said,
            "rejected_returned": dict(sorted(self.rejected.items())),
            # The dialog module's own record (turns, repairs, rejections explained, task success
            # per sub-dialog), when the run has one that offers summary().
            "subdialogs": self._module_summary(),
        }

    def _module_summary(self) -> dict[str, Any] | None:
        module = (getattr(self.run, "modules", None) or {}).get("dialog")
        summary = getattr(module, "summary", None)
        return summary() if callable(summary) else None


OBSERVERS = {"dialog": Dialog}
