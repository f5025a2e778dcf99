"""Speakers and the WAV of a run's speech and beeps."""

from __future__ import annotations

import io
import wave
from pathlib import Path

import numpy as np
import pytest

from dancebots.report.sound import TextSpeaker, espeak_available, render_events_wav
from dancebots.safety import STOP_SENTENCE
from dancebots.shows.formation import RobotEvent


def test_text_speaker() -> None:
    out = io.StringIO()
    speaker = TextSpeaker(out, "R1 ")
    speaker.say(STOP_SENTENCE)
    speaker.beep()
    assert out.getvalue() == f"R1 says: {STOP_SENTENCE}\nR1 beep\n"


def loudness(samples: np.ndarray, rate: int, start: float, end: float) -> float:
    return float(np.abs(samples[int(start * rate):int(end * rate)]).max(initial=0))


def test_wav_has_speech_and_beeps_at_their_times(tmp_path: Path) -> None:
    """scripts/dev.sh installs espeak-ng, so this runs in CI."""
    if not espeak_available():
        pytest.skip("espeak-ng is not installed (scripts/dev.sh installs it)")
    events = [RobotEvent(1.0, "R1", "speech", STOP_SENTENCE), RobotEvent(6.0, "R1", "beep", ""),
              RobotEvent(7.0, "R1", "resume", "the way is clear")]
    target = tmp_path / "sound.wav"
    assert render_events_wav(events, 8.0, str(target)) == 2
    with wave.open(str(target)) as handle:
        rate = handle.getframerate()
        assert (handle.getnchannels(), handle.getsampwidth()) == (1, 2)
        samples = np.frombuffer(handle.readframes(handle.getnframes()), dtype="<i2")
    assert len(samples) == 8 * rate
    assert loudness(samples, rate, 0.0, 0.99) == 0  # silence before the speech
    assert loudness(samples, rate, 1.0, 3.0) > 3000  # the sentence
    assert loudness(samples, rate, 5.0, 5.99) == 0
    assert loudness(samples, rate, 6.0, 6.25) > 10000  # the beep
    assert loudness(samples, rate, 6.3, 8.0) == 0  # "resume" makes no sound
