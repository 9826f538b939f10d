"""One error hierarchy for the whole project.

Every error that comes from user input names where the problem is (file,
line, element) and which rule was broken, so that a researcher can fix a
scenario or a state machine without reading our code.
"""

from __future__ import annotations


class HomesimError(Exception):
    """Base of every error homesim raises on purpose."""


class InputError(HomesimError):
    """Bad input: a file or document that cannot be accepted.

    ``source`` is the file name (or a label such as ``<bus:/camera/faces>``),
    ``line`` the 1-based line number when known, ``element`` the tag or id
    concerned when known.
    """

    def __init__(
        self,
        message: str,
        *,
        source: str | None = None,
        line: int | None = None,
        element: str | None = None,
    ) -> None:
        self.message = message
        self.source = source
        self.line = line
        self.element = element
        super().__init__(self._format())

    def _format(self) -> str:
        where = self.source or "<input>"
        if self.line is not None:
            where += f":{self.line}"
        if self.element:
            where += f": <{self.element}>"
        return f"{where}: {self.message}"


class XMLInputError(InputError):
    """An XML document is malformed, unsafe or too large."""


class SchemaValidationError(InputError):
    """A document does not satisfy its XML Schema."""


class ScenarioError(InputError):
    """A scenario file cannot be loaded."""


class AFSMError(InputError):
    """A state machine document cannot be loaded or is semantically invalid."""


class SimulationError(HomesimError):
    """The simulation itself cannot go on."""


class DeadlockError(SimulationError):
    """Nothing is ready, no timer is pending, yet tasks are still waiting."""


class LivelockError(DeadlockError):
    """Very many scheduling rounds ran without virtual time moving (``sleep(0)`` loops, call_soon chains)."""


class RealIOError(SimulationError):
    """Real I/O (threads, sockets, subprocesses) was requested inside a simulation."""


class TaskFailedError(SimulationError):
    """A simulated task or callback raised an exception that nobody handled."""


class ClockError(SimulationError):
    """Virtual time was asked to go backwards or to an invalid value."""


class BusError(HomesimError):
    """A message could not be sent or a call could not be made."""


class SubscriptionClosed(BusError):
    """The subscription was closed while a reader waited for a message."""


class MessageValidationError(BusError):
    """A message does not match the schema of its channel or method."""


class BadMessageError(BusError):
    """A receiver cannot handle a message another participant sent (wrong type, absurd value).

    Raised by a subscription handler, it does not fail the run: the bus
    records the message as dropped with this reason (seen in the trace) and
    goes on. Any other exception from a handler is a bug and fails the run.
    """


class UnknownParticipantError(BusError):
    """A call named a server or method that is not registered."""


class RemoteCallTimeout(BusError):
    """A remote procedure call got no reply within its virtual-time timeout."""


class RemoteCallFailed(BusError):
    """The server of a remote procedure call raised an error."""


class AFSMProblems(AFSMError):
    """A state machine document has several problems; ``problems`` lists every one.

    The message is the first problem plus a count, so a single-line report
    still says where to start; ``homesim afsm check`` prints them all.
    """

    def __init__(self, problems: list[AFSMError]) -> None:
        if not problems:
            raise ValueError("AFSMProblems needs at least one problem")
        self.problems = list(problems)
        first = problems[0]
        more = len(problems) - 1
        msg = first.message + (f" (and {more} more problem{'s' if more > 1 else ''})" if more else "")
        super().__init__(msg, source=first.source, line=first.line, element=first.element)


class AFSMModificationRefused(AFSMError):
    """A run-time replacement or extension of a running AFSM was refused (the reason says why)."""


class SupervisorError(HomesimError):
    """The execution supervisor was used wrongly (e.g. the same event queued twice)."""


class MemoryQueryError(InputError):
    """An active-memory request cannot be carried out: a bad XPath, an unknown document id,
    a document that is not acceptable (the message says which rule)."""


class MemoryStoreError(InputError):
    """A memory store on disk cannot be used: corrupt, from a newer homesim, or unwritable.

    ``kept_at`` is where the refused file now is (moved aside when corrupt, left in
    place when it comes from a newer version); nothing was overwritten.
    """

    def __init__(self, message: str, *, source: str | None = None, kept_at: str | None = None) -> None:
        self.kept_at = kept_at
        super().__init__(message, source=source)


class OptionError(HomesimError):
    """A command-line value found wrong after parsing (e.g. a state name that does not exist)."""

    def __init__(self, option: str, message: str) -> None:
        super().__init__(f"argument {option}: {message}")
