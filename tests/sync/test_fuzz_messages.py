"""Fuzzing the /sync message parser: any text is a message or a SyncMessageError."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.sync import messages
from dancebots.sync.messages import (
    EchoMessage,
    StartProposal,
    SyncMessageError,
    format_message,
    parse_message,
)

WORDS = ["test", "sync", "R1", "R2", "_a.b-c", "1R", "R 1", "", "é", "\x00", "1732.25",
         "5e-324", "1e308", "1e309", "1" + "0" * 400, "nan", "-inf", "Infinity", "-0", "+.5",
         "1e", "0x10", "1_000", "١٢", "\u2028", "\x85", "sync\x0cR1"]


def parse_or_refuse(text: str) -> EchoMessage | StartProposal | None:
    refused: SyncMessageError | None = None
    try:
        return parse_message(text)
    except SyncMessageError as exc:
        refused = exc
    assert refused.reason
    assert len(str(refused)) < 400 + 2 * messages._SHOWN  # a long message is quoted short
    return None


@settings(max_examples=400, deadline=None)
@given(st.lists(st.sampled_from(WORDS), max_size=5), st.sampled_from([" ", "  ", "\t", "\n"]))
def test_word_streams_parse_or_are_refused(words: list[str], sep: str) -> None:
    message = parse_or_refuse(sep.join(words))
    if isinstance(message, StartProposal):
        assert math.isfinite(message.start)
        assert parse_message(format_message(message)) == message


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=200))
def test_random_text_parses_or_is_refused(text: str) -> None:
    parse_or_refuse(text)


@settings(max_examples=200, deadline=None)
@given(st.from_regex(r"[A-Za-z_][A-Za-z0-9_.-]{0,10}", fullmatch=True),
       st.floats(allow_nan=False, allow_infinity=False))
def test_every_finite_proposal_round_trips(role: str, start: float) -> None:
    message = StartProposal(role, start)
    assert parse_message(format_message(message)) == message
