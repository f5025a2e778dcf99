"""Voicing the robots' events: speakers for live use and a WAV of a whole run.

A :class:`Speaker` says sentences and beeps. :class:`TextSpeaker` writes them as lines of
text; :class:`EspeakSpeaker` speaks through the ``espeak-ng`` program (Debian package
``espeak-ng``). :func:`render_events_wav` puts a run's speech and beeps on the show's time
line in one WAV file (mono, 16 bit): speech synthesised once per sentence with espeak-ng,
beeps as short 880 Hz tones.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
import wave
from collections.abc import Iterable
from pathlib import Path
from typing import Protocol, TextIO

import numpy as np
from numpy.typing import NDArray

from dancebots.shows.formation import RobotEvent

__all__ = ["EspeakSpeaker", "Speaker", "TextSpeaker", "espeak_available",
           "render_events_wav"]

SAMPLE_RATE = 22050
BEEP_HZ = 880.0
BEEP_SECONDS = 0.25


class Speaker(Protocol):
    def say(self, text: str) -> None: ...

    def beep(self) -> None: ...


class TextSpeaker:
    """Writes what a robot would say, one line per event, to a text stream."""

    def __init__(self, stream: TextIO, prefix: str = "") -> None:
        self.stream = stream
        self.prefix = prefix

    def say(self, text: str) -> None:
        self.stream.write(f"{self.prefix}says: {text}\n")

    def beep(self) -> None:
        self.stream.write(f"{self.prefix}beep\n")


def espeak_available() -> bool:
    return shutil.which("espeak-ng") is not None


class EspeakSpeaker:
    """Speaks through espeak-ng without waiting for it; beeps with a short tone."""

    def say(self, text: str) -> None:
        subprocess.Popen(["espeak-ng", text], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)

    def beep(self) -> None:
        subprocess.Popen(["espeak-ng", "beep"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)


def _speech(text: str) -> NDArray[np.float64]:
    """Samples (N,) in [-1, 1] at SAMPLE_RATE of espeak-ng saying ``text``."""
    with tempfile.TemporaryDirectory() as folder:
        target = Path(folder) / "speech.wav"
        subprocess.run(["espeak-ng", "-w", str(target), text], check=True,
                       capture_output=True)
        with wave.open(str(target)) as handle:
            rate, width = handle.getframerate(), handle.getsampwidth()
            frames = handle.readframes(handle.getnframes())
    if width != 2:
        raise OSError(f"espeak-ng wrote {8 * width}-bit audio; 16-bit expected")
    samples = np.frombuffer(frames, dtype="<i2").astype(np.float64) / 32768.0
    if rate != SAMPLE_RATE:  # resample linearly to the output rate
        times = np.arange(int(len(samples) * SAMPLE_RATE / rate)) / SAMPLE_RATE
        samples = np.interp(times, np.arange(len(samples)) / rate, samples)
    return samples


def _beep() -> NDArray[np.float64]:
    t = np.arange(int(BEEP_SECONDS * SAMPLE_RATE)) / SAMPLE_RATE
    envelope = np.minimum(1.0, np.minimum(t, BEEP_SECONDS - t) / 0.01)  # 10 ms ramps
    result: NDArray[np.float64] = 0.5 * np.sin(2 * np.pi * BEEP_HZ * t) * envelope
    return result


def render_events_wav(events: Iterable[RobotEvent], duration: float, path: str) -> int:
    """Write the speech and beeps of ``events`` at their show times into a WAV of
    ``duration`` s (longer if the last sentence needs it). Returns the number of sounds."""
    if not espeak_available():
        raise OSError("espeak-ng is not installed (Debian package espeak-ng; "
                      "scripts/dev.sh installs it)")
    clips: dict[str, NDArray[np.float64]] = {}
    placed: list[tuple[int, NDArray[np.float64]]] = []
    for event in events:
        if event.kind == "speech":
            clip = clips.setdefault(event.text, _speech(event.text))
        elif event.kind == "beep":
            clip = clips.setdefault("\0beep", _beep())
        else:
            continue
        placed.append((round(max(event.time, 0.0) * SAMPLE_RATE), clip))
    length = max([int(duration * SAMPLE_RATE)] + [start + len(c) for start, c in placed])
    track = np.zeros(length)
    for start, clip in placed:
        track[start:start + len(clip)] += clip
    pcm = (np.clip(track, -1.0, 1.0) * 32767).astype("<i2")
    with wave.open(path, "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(SAMPLE_RATE)
        handle.writeframes(pcm.tobytes())
    return len(placed)
