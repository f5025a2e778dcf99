"""preview.mp4 (report/preview.py, ``run --music``): the run in real time with the music and
the robots' sounds mixed in, checked with ffprobe and by decoding its sound with ffmpeg."""

from __future__ import annotations

import json
import subprocess
import wave
from pathlib import Path

import numpy as np
import pytest

from dancebots.cli import main
from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.report.frames import ffmpeg_available
from dancebots.report.preview import PREVIEW_FPS, audio_streams, write_preview
from dancebots.report.sound import SAMPLE_RATE, espeak_available, render_events_wav
from dancebots.shows.formation import RobotEvent, SimConfig, simulate
from dancebots.sim import prepare_show

pytestmark = pytest.mark.skipif(not ffmpeg_available(),
                                reason="needs ffmpeg (scripts/dev.sh installs it)")
SHOW = "robots R1\nrow R1 0 0\nmove 1 0\n"


def write_wav(path: Path, samples: np.ndarray) -> None:
    with wave.open(str(path), "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(SAMPLE_RATE)
        handle.writeframes((np.clip(samples, -1, 1) * 32767).astype("<i2").tobytes())


def streams(path: Path) -> dict[str, object]:
    probe = subprocess.run(["ffprobe", "-v", "error", "-show_entries",
                            "stream=codec_type,codec_name:format=duration", "-of", "json",
                            str(path)], capture_output=True, text=True, check=True)
    return json.loads(probe.stdout)


def decoded_sound(path: Path) -> np.ndarray:
    """The preview's sound as mono samples at SAMPLE_RATE (ffmpeg decodes it)."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", str(path), "-f", "s16le", "-ac", "1",
                          "-ar", str(SAMPLE_RATE), "-"], capture_output=True, check=True).stdout
    return np.frombuffer(raw, dtype="<i2").astype(float) / 32767


def test_the_preview_has_the_show_in_real_time_with_the_music_and_a_beep_over_it(
        tmp_path: Path) -> None:
    _, plan, diagnostics = compile_scenario(SHOW, "t.dance")
    assert plan is not None, diagnostics
    arena, placement = prepare_show(place_show(plan, None))
    result = simulate(plan, arena, placement, SimConfig(lidar=None, settle=1.0))
    music = tmp_path / "music.wav"
    seconds = np.arange(int(30 * SAMPLE_RATE)) / SAMPLE_RATE  # longer than the show
    write_wav(music, 0.05 * np.sin(2 * np.pi * 220.0 * seconds))  # a quiet 220 Hz tone
    events = None
    if espeak_available():
        events = tmp_path / "events.wav"
        render_events_wav([RobotEvent(1.0, "R1", "beep", "")], float(result.times[-1]),
                          str(events))
    path = tmp_path / "preview.mp4"
    duration = write_preview(result, str(music), str(path), str(events) if events else None)
    info = streams(path)
    kinds = sorted((s["codec_type"], s["codec_name"]) for s in info["streams"])
    assert kinds == [("audio", "aac"), ("video", "h264")]
    frames = int(np.floor((result.times[-1] - result.times[0]) * PREVIEW_FPS + 1e-9)) + 1
    assert duration == pytest.approx(frames / PREVIEW_FPS)
    assert float(info["format"]["duration"]) == pytest.approx(duration, abs=0.15)
    assert not list(tmp_path.glob(".*"))  # the silent video is gone
    sound = decoded_sound(path)
    quiet = np.sqrt(np.mean(sound[int(0.3 * SAMPLE_RATE):int(0.8 * SAMPLE_RATE)] ** 2))
    assert 0.02 < quiet < 0.06  # the music alone: a 0.05 sine has an RMS of 0.035
    if events is not None:
        beep = np.sqrt(np.mean(sound[int(1.02 * SAMPLE_RATE):int(1.22 * SAMPLE_RATE)] ** 2))
        assert beep > 3 * quiet  # the beep at 1.0 s over the music


def test_run_with_music_writes_the_preview_and_refuses_what_has_no_sound(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    show = tmp_path / "one.dance"
    show.write_text(SHOW)
    music = tmp_path / "music.wav"
    write_wav(music, np.zeros(SAMPLE_RATE))
    out = tmp_path / "out"
    assert main(["run", str(show), "--no-animation", "--music", str(music),
                 "--out", str(out)]) == 0
    assert (out / "preview.mp4").read_bytes()[4:8] == b"ftyp"
    assert audio_streams(str(out / "preview.mp4")) == 1
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]
    capsys.readouterr()
    text = tmp_path / "notes.txt"
    text.write_text("not music\n")
    for bad, message in ((tmp_path / "missing.wav", "no such file"),
                         (text, "ffmpeg finds no sound in it")):
        assert main(["run", str(show), "--no-animation", "--music", str(bad),
                     "--out", str(tmp_path / "refused")]) == 2
        assert f"--music {bad}: {message}" in capsys.readouterr().err
    assert not (tmp_path / "refused").exists()


def test_the_music_the_tempo_names_goes_into_the_preview_and_a_missing_one_is_a_warning(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`tempo 120 music FILE` (FILE next to the scenario) is run's default --music; a file
    that is not there is a warning at the tempo line, and the run goes on without it."""
    write_wav(tmp_path / "song.wav", 0.1 * np.sin(np.arange(SAMPLE_RATE) * 0.05))
    show = tmp_path / "to_music.dance"
    show.write_text("robots R1\ntempo 120 music song.wav\nrow R1 0 0\nmove 1 0 by beat 9\n")
    out = tmp_path / "out"
    assert main(["run", str(show), "--no-animation", "--out", str(out)]) == 0
    assert audio_streams(str(out / "preview.mp4")) == 1
    capsys.readouterr()
    show.write_text("robots R1\ntempo 120 music gone.wav\nrow R1 0 0\nmove 1 0\n")
    assert main(["check", str(show)]) == 0
    err = capsys.readouterr().err
    assert (f"{show}:2:1: warning: the music file gone.wav is not there (looked next to the "
            f"scenario: {tmp_path / 'gone.wav'})") in err
    out = tmp_path / "without"
    assert main(["run", str(show), "--no-animation", "--out", str(out)]) == 0
    assert not (out / "preview.mp4").exists()
