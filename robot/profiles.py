"""Robot profiles: which BIRON a run simulates.

- ``full`` (the default): every capability of docs/semantics.md §6, as homesim's robot
  has them: objects taught by pointing and speech, resolved with gesture
  detection, object recognition and the speech's type, and stored with their
  position, size and colour.
- ``biron-2005``: the demonstrator of the COGNIRON deliverable D7.1.2 (the
  "Robot Home-Tour" report): "BIRON currently only
  processes the verbal information and does not have the COGNIRON functions for
  gesture recognition (CF-GR) and object recognition (CF-OR) as well as the
  overall component for resolving object references (CF-ROR) on-board". An
  object is taught from what the user says only (type, name, owner, use and
  attributes, a colour only if the user says one; no position, no size, nothing
  seen), and the Object attention state looks at a fixed position (ahead of the
  robot, at table height) instead of where the user points. docs/deployment.md
  ("Robot profiles") says what else differs and why.

Modules read ``run.config.profile`` at install time; the run refuses a name
not in :data:`PROFILES`.
"""

from __future__ import annotations

#: Profile name -> what it simulates (the run's summary names the profile).
PROFILES: dict[str, str] = {
    "full": "BIRON with every capability of the home tour (gesture and object recognition when teaching objects)",
    "biron-2005": "the 2005 demonstrator: objects taught from the verbal information only; "
                  "the Object state looks at a fixed position",
}

#: The profile of a run that names none.
DEFAULT_PROFILE = "full"

#: The profile that teaches objects from speech alone.
VERBAL_ONLY = "biron-2005"


def verbal_only(run: object) -> bool:
    """Whether ``run``'s robot teaches objects from the verbal information only."""
    config = getattr(run, "config", None)
    return getattr(config, "profile", DEFAULT_PROFILE) == VERBAL_ONLY
