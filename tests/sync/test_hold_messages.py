"""The /hold messages of the formation's shared show clock (sync/messages.py): exact errors,
round trips, and any text is a message or a HoldMessageError (hypothesis, hostile numbers)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.sync import messages
from dancebots.sync.hold import HoldMessage
from dancebots.sync.messages import HoldMessageError, format_hold, parse_hold

EXPECTED = ("; expected 'hold ROLE STAMP SHOW_TIME HOLDS [X Y] [pace P]' (HOLDS 0 or 1, "
            "0 < P <= 1)")


def test_a_hold_message_with_and_without_a_position() -> None:
    assert parse_hold("hold R1 1732.25 12.5 1 0.5 -1e-3") == HoldMessage(
        "R1", 1732.25, 12.5, True, (0.5, -0.001))
    assert parse_hold("hold R_2 0 0 0") == HoldMessage("R_2", 0.0, 0.0, False, None)


def test_a_paced_hold_message_says_its_pace() -> None:
    assert parse_hold("hold R1 3 2 0 pace 0.25") == HoldMessage("R1", 3.0, 2.0, False, None,
                                                                  0.25)
    message = HoldMessage("R1", 3.0, 2.0, False, (1.0, 2.0), 0.5)
    assert format_hold(message) == "hold R1 3.0 2.0 0 1.0 2.0 pace 0.5"
    assert parse_hold(format_hold(message)) == message
    # a full pace is not written: the ``together`` strategy's messages are as before
    assert format_hold(HoldMessage("R1", 3.0, 2.0, True)) == "hold R1 3.0 2.0 1"


@pytest.mark.parametrize(("text", "reason"), [
    ("", "it is empty"),
    ("sync R1 1", "it does not start with 'hold'"),
    ("hold R1 1 2", "'hold' takes 4 or 6 words, not 3"),
    ("hold R1 1 2 0 5", "'hold' takes 4 or 6 words, not 5"),
    ("hold 1R 1 2 0", "'1R' is not a role name (a letter or _, then letters, digits, _, . or "
                      "-)"),
    ("hold R1 1 2 yes", "HOLDS must be 0 or 1, not 'yes'"),
    ("hold R1 nan 2 0", "'nan' is not a finite number"),
    ("hold R1 1 -inf 0", "'-inf' is not a finite number"),
    ("hold R1 1e400 2 1", "'1e400' is not a finite number"),
    ("hold R1 1 2 1 0x10 3", "'0x10' is not a number"),
    ("hold R1 1 2 0 pace 1.5", "the pace must be above 0 and at most 1, not '1.5'"),
    ("hold R1 1 2 0 pace -0.1", "the pace must be above 0 and at most 1, not '-0.1'"),
    ("hold R1 1 2 0 pace 0", "the pace must be above 0 and at most 1, not '0'"),
    ("hold R1 1 2 0 pace -0", "the pace must be above 0 and at most 1, not '-0'"),
    ("hold R1 1 2 0 pace nan", "'nan' is not a finite number"),
    ("hold R1 1 2 0 pace", "'hold' takes 4 or 6 words, not 5"),
    ("hold R1 1 2 pace 0.5", "'hold' takes 4 or 6 words, not 3"),
])
def test_bad_hold_messages_say_what_is_wrong(text: str, reason: str) -> None:
    with pytest.raises(HoldMessageError) as caught:
        parse_hold(text)
    assert caught.value.reason == reason
    assert str(caught.value) == f"bad /hold message {text!r}: {reason}{EXPECTED}"


def test_a_message_that_cannot_be_sent_is_refused() -> None:
    with pytest.raises(ValueError, match="must be finite"):
        format_hold(HoldMessage("R1", math.nan, 1.0, False))
    for pace in (2.0, 0.0):
        with pytest.raises(ValueError, match="pace must be above 0 and at most 1"):
            format_hold(HoldMessage("R1", 1.0, 1.0, False, None, pace))


WORDS = ["hold", "pace", "0.5", "R1", "R2", "_a.b-c", "1R", "", "é", "\x00", "1732.25",
         "5e-324", "1e308", "1e309", "1" + "0" * 400, "nan", "-inf", "0", "1", "-0", "+.5",
         "1e", "0x10", "١٢", "\u2028"]


def parse_or_refuse(text: str) -> HoldMessage | None:
    refused: HoldMessageError | None = None
    try:
        return parse_hold(text)
    except HoldMessageError as exc:
        refused = exc
    assert refused.reason
    assert len(str(refused)) < 400 + 2 * messages._SHOWN  # a long message is quoted short
    return None


@settings(max_examples=400, deadline=None)
@given(st.lists(st.sampled_from(WORDS), max_size=7), st.sampled_from([" ", "\t", "\n"]))
def test_word_streams_parse_or_are_refused(words: list[str], sep: str) -> None:
    message = parse_or_refuse(sep.join(words))
    if message is not None:
        assert math.isfinite(message.stamp)
        assert math.isfinite(message.show_time)
        assert parse_hold(format_hold(message)) == message


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=200))
def test_random_text_parses_or_is_refused(text: str) -> None:
    parse_or_refuse(text)


finite = st.floats(allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(st.from_regex(r"[A-Za-z_][A-Za-z0-9_.-]{0,10}", fullmatch=True), finite, finite,
       st.booleans(), st.none() | st.tuples(finite, finite),
       st.floats(0.0, 1.0, exclude_min=True))
def test_every_finite_message_round_trips(role: str, stamp: float, show_time: float,
                                          holds: bool, position: tuple[float, float] | None,
                                          pace: float) -> None:
    message = HoldMessage(role, stamp, show_time, holds, position, pace)
    assert parse_hold(format_hold(message)) == message
