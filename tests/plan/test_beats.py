"""The beats of a music file (plan/beats.py, ``dancebots beats``): a generated click track of
known tempo, its beats found within 50 ms; what is no sound gets a clear error."""

from __future__ import annotations

import json
import wave
from pathlib import Path

import numpy as np
import pytest

from dancebots.cli import main
from dancebots.plan.beats import track_beats

RATE = 22050


def click_track(bpm: float, seconds: float, first: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Samples (N,) with a short 1 kHz click on every beat, and the beat times (B,) s."""
    samples = np.zeros(int(seconds * RATE))
    n = np.arange(int(0.03 * RATE))
    click = np.sin(2 * np.pi * 1000.0 * n / RATE) * np.exp(-n / (0.005 * RATE))
    beats = np.arange(first, seconds - 0.2, 60.0 / bpm)
    for beat in beats:
        start = int(beat * RATE)
        samples[start:start + len(click)] += click
    return samples, beats


def test_the_beats_of_a_click_track_are_found_within_50_ms(tmp_path: Path,
                                                           capsys: pytest.CaptureFixture[str],
                                                           ) -> None:
    samples, beats = click_track(120.0, 12.0)
    track = track_beats(samples, RATE)
    assert abs(len(track.beats) - len(beats)) <= 1
    assert max(np.abs(beats[:, None] - track.beats[None, :]).min(axis=0)) <= 0.05
    assert 110.0 <= track.tempo <= 130.0  # librosa's global estimate: 117.5 here
    path = tmp_path / "clicks.wav"
    with wave.open(str(path), "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(RATE)
        handle.writeframes((samples * 32767 * 0.9).astype("<i2").tobytes())
    assert main(["beats", str(path), "--json"]) == 0
    said = json.loads(capsys.readouterr().out)
    found = np.array(said["beats_s"])
    assert max(np.abs(beats[:, None] - found[None, :]).min(axis=0)) <= 0.05
    assert main(["beats", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith(f"{path}: tempo ")
    assert lines[0].endswith(" beats (12.0 s)")
    assert len(lines) == 1 + len(found)


def test_what_is_no_sound_is_refused_clearly(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    text = tmp_path / "notes.txt"
    text.write_text("la la la\n")
    assert main(["beats", str(tmp_path / "missing.wav")]) == 2
    assert capsys.readouterr().err == (
        f"dancebots beats: error: {tmp_path / 'missing.wav'}: no such file\n")
    assert main(["beats", str(text)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"dancebots beats: error: {text}: no sound could be read from it (")
    assert err.endswith("); give a WAV, FLAC, OGG or MP3 file\n")
    with pytest.raises(ValueError, match="empty or not a number"):
        track_beats(np.array([0.0, np.nan]), RATE)
    with pytest.raises(ValueError, match="sample rate must be positive"):
        track_beats(np.zeros(10), 0)
