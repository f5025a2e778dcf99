"""The beats of a piece of music, for placing a show's moves on them (issue 15): librosa's
beat tracker (dynamic programming over an onset envelope, Ellis 2007) on the samples.

Pure: samples in, :class:`BeatTrack` out; reading a file is the shell's (``cli/beats.py``).
librosa compiles its numba kernels on its first call on a machine (about 25 s here), then
tracks 12 s of audio in about 3 s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["BeatTrack", "track_beats"]


@dataclass(frozen=True, slots=True)
class BeatTrack:
    """The tempo (beats per minute, librosa's global estimate) and the beat times (B,) in s
    from the start of the music."""

    tempo: float
    beats: NDArray[np.float64]

    def to_json(self) -> dict[str, object]:
        return {"tempo_bpm": self.tempo, "beats_s": self.beats.tolist()}


def track_beats(samples: NDArray[np.float64], rate: int) -> BeatTrack:
    """The beats of mono ``samples`` (N,) at ``rate`` Hz (librosa.beat.beat_track)."""
    import librosa  # imports numba; only where beats are tracked

    if rate <= 0:
        raise ValueError(f"the sample rate must be positive, not {rate}")
    if len(samples) == 0 or not np.isfinite(samples).all():
        raise ValueError("the sound is empty or not a number")
    tempo, beats = librosa.beat.beat_track(y=np.asarray(samples, dtype=np.float32), sr=rate,
                                           units="time")
    return BeatTrack(float(np.atleast_1d(tempo)[0]), np.asarray(beats, dtype=np.float64))
