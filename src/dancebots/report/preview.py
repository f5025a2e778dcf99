"""``preview.mp4``: a run in real time with its sound, as the audience would see and hear it
(``dancebots run --music FILE``; issue 15).

The run's animation (``animation.render_frames``) at 1x speed, encoded once (H.264 through
ffmpeg), then muxed with an audio track: the music from the show's start (any file ffmpeg
reads: WAV, MP3, OGG, FLAC ...) and, where given, the robots' speech and beeps at their times
(``sound.render_events_wav``) mixed over it without normalisation (ffmpeg's ``amix``); the
result lasts as long as the video. The silent video is a temporary file next to the result,
removed again.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

from dancebots.report.animation import render_frames
from dancebots.report.frames import write_animation
from dancebots.shows.formation import RunResult

__all__ = ["PREVIEW_FPS", "audio_streams", "write_preview"]

PREVIEW_FPS = 10
"""Frames per second of the preview (the brains' own rate: every tick is a frame)."""


def audio_streams(path: str) -> int:
    """How many audio streams ffprobe finds in the file at ``path`` (0: none, or no media
    ffmpeg can read); OSError without ffprobe."""
    if shutil.which("ffprobe") is None:
        raise OSError("ffprobe is not installed (Debian package ffmpeg; scripts/dev.sh "
                      "installs it)")
    probe = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "stream=codec_type",
                            "-of", "json", path], capture_output=True, text=True, check=False)
    if probe.returncode != 0:
        return 0
    streams = json.loads(probe.stdout or "{}").get("streams", [])
    return sum(1 for stream in streams if stream.get("codec_type") == "audio")


def write_preview(result: RunResult, music: str, path: str, events_wav: str | None = None,
                  progress: Callable[[int, int], None] | None = None) -> float:
    """Write the real-time preview of ``result`` to ``path`` (module docstring): the
    ``music`` file's sound from show time 0, with ``events_wav`` (the robots' speech and
    beeps, a WAV from show time 0) mixed over it. ``progress(frame, frames)`` while the
    frames are drawn. Returns the preview's duration, s; OSError when ffmpeg fails."""
    count, frames = render_frames(result, speedup=1.0, fps=PREVIEW_FPS)
    target = Path(path)
    silent = target.with_name(f".{target.name}.video.mp4")
    duration = count / PREVIEW_FPS
    try:
        write_animation(frames, [str(silent)], fps=PREVIEW_FPS, count=count,
                        progress=progress)
        inputs = ["-i", str(silent), "-i", music, *(["-i", events_wav] if events_wav else [])]
        mix = ("[1:a][2:a]amix=inputs=2:duration=longest:normalize=0[sound]" if events_wav
               else "[1:a]anull[sound]")
        command = ["ffmpeg", "-y", "-loglevel", "error", *inputs, "-filter_complex", mix,
                   "-map", "0:v", "-map", "[sound]", "-c:v", "copy", "-c:a", "aac",
                   "-t", f"{duration:.3f}", str(target)]
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise OSError(f"ffmpeg could not write {path}: {done.stderr.strip()[-500:]}")
    finally:
        silent.unlink(missing_ok=True)  # written here, removed here
    return duration
