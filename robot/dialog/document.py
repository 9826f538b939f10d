"""The dialog document as a kind ``homesim check`` knows (entry point ``homesim.documents``: ``dialog``).

``homesim check robot/dialog/biron-dialogs.xml`` runs the dialog's whole loading
pipeline (hardened parse, ``dialogs.xsd``, model, semantic checks) and prints
every problem with file and line.
"""

from __future__ import annotations

from homesim.documents import DocumentType
from homesim.errors import InputError

from .loader import ROOT, check_file


def _check(path: str) -> list[InputError]:
    return list(check_file(path))


DOCUMENT_TYPE = DocumentType(ROOT, "dialogs", _check)
