"""The text messages of the ``/sync`` topic (std_msgs/String), parsed and formatted.

``test R1``            R1 asks who hears it (published at 10 Hz by ``network_test``)
``test R1 R2``         R2 heard R1 and echoes it back (R1 then knows the link works both ways)
``sync R1 1732.25``    R1 proposes to start at 1732.25 s (its clock, seconds since the epoch)

Roles are the scenario's robot names (no spaces). Anything else is rejected with a
:class:`SyncMessageError` that says what was expected, so a node can log it and go on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["EchoMessage", "StartProposal", "SyncMessageError", "format_message",
           "parse_message"]


@dataclass(frozen=True, slots=True)
class EchoMessage:
    """A network-test message: ``origin`` asks; ``echoed_by`` is set on the echo."""

    origin: str
    echoed_by: str | None = None


@dataclass(frozen=True, slots=True)
class StartProposal:
    """``role`` proposes to start the show at ``start`` (s, the robots' common clock)."""

    role: str
    start: float


class SyncMessageError(ValueError):
    """A /sync message that is not one of the three forms; ``text`` is what was received."""

    def __init__(self, text: str, reason: str) -> None:
        super().__init__(f"bad /sync message {text!r}: {reason}; expected 'test ROLE', "
                         "'test ROLE ECHOER' or 'sync ROLE SECONDS'")
        self.text = text
        self.reason = reason


def parse_message(text: str) -> EchoMessage | StartProposal:
    """The message a /sync text carries (see the module's docstring for the forms)."""
    words = text.split()
    if not words:
        raise SyncMessageError(text, "it is empty")
    kind, rest = words[0], words[1:]
    if kind == "test":
        if len(rest) == 1:
            return EchoMessage(rest[0])
        if len(rest) == 2:
            return EchoMessage(rest[0], rest[1])
        raise SyncMessageError(text, f"'test' takes 1 or 2 roles, not {len(rest)}")
    if kind == "sync":
        if len(rest) != 2:
            raise SyncMessageError(text, f"'sync' takes a role and a time, not {len(rest)} words")
        try:
            start = float(rest[1])
        except ValueError:
            raise SyncMessageError(text, f"{rest[1]!r} is not a time in seconds") from None
        if not math.isfinite(start):
            raise SyncMessageError(text, f"{rest[1]!r} is not a finite time")
        return StartProposal(rest[0], start)
    raise SyncMessageError(text, f"unknown kind {kind!r}")


def format_message(message: EchoMessage | StartProposal) -> str:
    """The /sync text of a message (inverse of :func:`parse_message`; times in full
    precision, so every robot holds the very same proposal)."""
    if isinstance(message, StartProposal):
        return f"sync {message.role} {message.start!r}"
    if message.echoed_by is None:
        return f"test {message.origin}"
    return f"test {message.origin} {message.echoed_by}"
