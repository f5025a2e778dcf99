"""The text messages of the ``/sync`` topic (std_msgs/String), parsed and formatted.

``test R1``            R1 asks who hears it (published at 10 Hz by ``network_test``)
``test R1 R2``         R2 heard R1 and echoes it back (R1 then knows the link works both ways)
``sync R1 1732.25``    R1 proposes to start at 1732.25 s (its clock, seconds since the epoch)
``sync R1 1800.0 1732.2``  the same with R1's clock when it sent the message (the
                       ``timecode`` start: a receiver measures the clocks' offset from it)
``show R1 S W P``      R1 runs the show whose scenario file, world file and motion parameters
                       have the SHA-256 digests (hexadecimal, 16 digits) S, W and P (``-``:
                       no world file): robots that run different shows refuse to start

Roles are the scenario's robot names: plain ASCII identifiers, a letter or ``_`` then
letters, digits, ``_``, ``.`` or ``-`` (the names the choreography language accepts for
robots). A time is a plain decimal number (ASCII digits, optional sign, fraction and
exponent) that is finite as a float. Anything else is rejected with a
:class:`SyncMessageError` that says what was expected, so a node can log it and go on:
:func:`parse_message` raises nothing else, whatever the text. Whether a well-formed time is a
plausible start is the start agreement's business (:func:`dancebots.sync.start.implausible`),
as it depends on the receiver's clock.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from dancebots.sync.hold import HoldMessage

__all__ = ["EchoMessage", "HoldMessageError", "ShowMessage", "StartProposal",
           "SyncMessageError", "format_hold", "format_message", "is_role", "parse_hold",
           "parse_message"]

_ROLE = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]*")
_SECONDS = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NONFINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
_DIGEST = re.compile(r"[0-9a-f]{16}|-")
_SHOWN = 80
"""Characters of a bad message quoted in its error (the rest is counted, not copied)."""


@dataclass(frozen=True, slots=True)
class EchoMessage:
    """A network-test message: ``origin`` asks; ``echoed_by`` is set on the echo."""

    origin: str
    echoed_by: str | None = None


@dataclass(frozen=True, slots=True)
class StartProposal:
    """``role`` proposes to start the show at ``start`` (s, the robots' common clock);
    ``sent``: its clock when it sent the proposal (s; None: not said)."""

    role: str
    start: float
    sent: float | None = None


@dataclass(frozen=True, slots=True)
class ShowMessage:
    """``role`` runs the show whose ``scenario``, ``world`` and ``parameters`` have these
    digests (16 hexadecimal digits of SHA-256; world ``-``: none)."""

    role: str
    scenario: str
    world: str
    parameters: str

    @property
    def digests(self) -> tuple[str, str, str]:
        return self.scenario, self.world, self.parameters


class SyncMessageError(ValueError):
    """A /sync message that is not one of the three forms; ``text`` is what was received,
    ``reason`` why it is refused."""

    def __init__(self, text: str, reason: str) -> None:
        super().__init__(f"bad /sync message {_shown(text)}: {reason}; expected 'test ROLE', "
                         "'test ROLE ECHOER', 'sync ROLE SECONDS [SENT]' or 'show ROLE S W P'")
        self.text = text
        self.reason = reason


def is_role(word: str) -> bool:
    """Is ``word`` a role name (a robot name of the choreography language)?"""
    return _ROLE.fullmatch(word) is not None


def parse_message(text: str) -> EchoMessage | StartProposal | ShowMessage:
    """The message a /sync text carries (see the module's docstring for the forms); raises
    :class:`SyncMessageError`, and nothing else, for any other text."""
    if not isinstance(text, str):
        raise SyncMessageError(repr(text), f"a {type(text).__name__} is not text")
    words = text.split()
    if not words:
        raise SyncMessageError(text, "it is empty")
    kind, rest = words[0], words[1:]
    if kind == "test":
        if len(rest) not in (1, 2):
            raise SyncMessageError(text, f"'test' takes 1 or 2 roles, not {len(rest)}")
        _check_roles(text, rest)
        return EchoMessage(rest[0], rest[1] if len(rest) == 2 else None)
    if kind == "sync":
        if len(rest) not in (2, 3):
            raise SyncMessageError(text, "'sync' takes a role, a time and optionally the "
                                   f"sender's clock, not {len(rest)} words")
        _check_roles(text, rest[:1])
        times = _finite_numbers(rest[1:], lambda why: SyncMessageError(text, why),
                                "a time in seconds", "a finite time")
        return StartProposal(rest[0], times[0], times[1] if len(times) == 2 else None)
    if kind == "show":
        if len(rest) != 4:
            raise SyncMessageError(text, "'show' takes a role and three digests, not "
                                   f"{len(rest)} words")
        _check_roles(text, rest[:1])
        for word in rest[1:]:
            if not _DIGEST.fullmatch(word):
                raise SyncMessageError(text, f"{_shown(word)} is not a digest (16 hexadecimal "
                                       "digits, or - for no file)")
        return ShowMessage(*rest)
    raise SyncMessageError(text, f"unknown kind {_shown(kind)}")


def format_message(message: EchoMessage | StartProposal | ShowMessage) -> str:
    """The /sync text of a message (inverse of :func:`parse_message`; times in full
    precision, so every robot holds the very same proposal)."""
    if isinstance(message, ShowMessage):
        return f"show {message.role} {message.scenario} {message.world} {message.parameters}"
    if isinstance(message, StartProposal):
        sent = f" {message.sent!r}" if message.sent is not None else ""
        return f"sync {message.role} {message.start!r}{sent}"
    if message.echoed_by is None:
        return f"test {message.origin}"
    return f"test {message.origin} {message.echoed_by}"


class HoldMessageError(ValueError):
    """A /hold message that is not ``hold ROLE STAMP SHOW_TIME HOLDS [X Y] [pace P]``;
    ``text`` is what was received, ``reason`` why it is refused."""

    def __init__(self, text: str, reason: str) -> None:
        super().__init__(f"bad /hold message {_shown(text)}: {reason}; expected 'hold ROLE "
                         "STAMP SHOW_TIME HOLDS [X Y] [pace P]' (HOLDS 0 or 1, 0 < P <= 1)")
        self.text = text
        self.reason = reason


def parse_hold(text: str) -> HoldMessage:
    """The :class:`~dancebots.sync.hold.HoldMessage` a /hold text carries (the formation's
    shared show clock, ``sync.hold``): ``hold ROLE STAMP SHOW_TIME HOLDS [X Y] [pace P]``,
    the sender's role, its clock when sending and its show time (s), whether it holds the
    show (0 or 1), where it stands in the show frame (m; absent: unknown) and the pace it can
    follow (above 0 and at most 1, the ``paced`` strategy; absent: 1). Raises
    :class:`HoldMessageError`, and nothing else, for any other text."""
    if not isinstance(text, str):
        raise HoldMessageError(repr(text), f"a {type(text).__name__} is not text")
    words = text.split()
    if not words or words[0] != "hold":
        raise HoldMessageError(text, "it does not start with 'hold'" if words
                               else "it is empty")
    rest = words[1:]
    pace = 1.0
    if len(rest) >= 2 and rest[-2] == "pace":
        pace = _finite_numbers(rest[-1:], lambda why: HoldMessageError(text, why), "a number",
                               "a finite number")[0]
        if not 0.0 < pace <= 1.0:  # (a robot that drives nothing holds the show: HOLDS)
            raise HoldMessageError(text, f"the pace must be above 0 and at most 1, not "
                                   f"{_shown(rest[-1])}")
        rest = rest[:-2]
    if len(rest) not in (4, 6):
        raise HoldMessageError(text, f"'hold' takes 4 or 6 words, not {len(rest)}")
    if not is_role(rest[0]):
        raise HoldMessageError(text, f"{_shown(rest[0])} is not a role name (a letter or _, "
                               "then letters, digits, _, . or -)")
    if rest[3] not in ("0", "1"):
        raise HoldMessageError(text, f"HOLDS must be 0 or 1, not {_shown(rest[3])}")
    numbers = _finite_numbers((rest[1], rest[2], *rest[4:]),
                              lambda why: HoldMessageError(text, why), "a number",
                              "a finite number")
    stamp, show_time, *position = numbers
    return HoldMessage(rest[0], stamp, show_time, rest[3] == "1",
                       (position[0], position[1]) if position else None, pace)


def _finite_numbers(words: Sequence[str], error: Callable[[str], ValueError], kind: str,
                    finite: str) -> list[float]:
    """The words as finite numbers; raises ``error(why)`` at the first that is not ``kind``
    (a plain decimal number) or not ``finite``."""
    values = []
    for word in words:
        value = _number(word)
        if value is None:
            raise error(f"{_shown(word)} is not {kind}")
        if not math.isfinite(value):
            raise error(f"{_shown(word)} is not {finite}")
        values.append(value)
    return values


def format_hold(message: HoldMessage) -> str:
    """The /hold text of a message (inverse of :func:`parse_hold`; times in full precision);
    ValueError for a message whose numbers are not finite."""
    numbers = (message.stamp, message.show_time, *(message.position or ()))
    if not all(math.isfinite(n) for n in numbers):
        raise ValueError(f"a hold message's times and position must be finite: {message}")
    if not 0.0 < message.pace <= 1.0:
        raise ValueError(f"a hold message's pace must be above 0 and at most 1: {message}")
    text = (f"hold {message.role} {message.stamp!r} {message.show_time!r} "
            f"{int(message.holds)}")
    if message.position is not None:
        text += f" {message.position[0]!r} {message.position[1]!r}"
    if message.pace != 1.0:  # (the ``together`` strategy's messages stay as they were)
        text += f" pace {message.pace!r}"
    return text


def _number(word: str) -> float | None:
    """``word`` as a float: a plain decimal number (then finite, or inf for a huge exponent),
    a spelled-out nan or infinity (not finite), or None for anything else."""
    if _NONFINITE.fullmatch(word) is not None:
        return math.nan
    return float(word) if _SECONDS.fullmatch(word) is not None else None


def _check_roles(text: str, roles: list[str]) -> None:
    for role in roles:
        if not is_role(role):
            raise SyncMessageError(text, f"{_shown(role)} is not a role name (a letter or _, "
                                   "then letters, digits, _, . or -)")


def _shown(text: str) -> str:
    """``text`` quoted, cut after :data:`_SHOWN` characters."""
    if len(text) <= _SHOWN:
        return repr(text)
    return f"{text[:_SHOWN]!r}... ({len(text)} characters)"
