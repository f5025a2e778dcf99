"""``dancebots beats``: the tempo and the beat times of a music file (for cues on its beats)."""

from __future__ import annotations

import argparse
import json

from dancebots.cli.common import EXIT_OK, fail

NAME = "beats"
HELP = "print the tempo and the beat times of a music file"
DESCRIPTION = ("Track the beats of a music file (WAV, FLAC, OGG, MP3: what libsndfile or "
               "ffmpeg reads) with librosa's beat tracker and print the tempo and every "
               "beat's time from the start of the music, to place a show's moves on them. "
               "The first run on a machine compiles librosa's kernels (about 25 s).")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("music", metavar="FILE", help="the music file")
    parser.add_argument("--json", action="store_true",
                        help='print {"tempo_bpm": ..., "beats_s": [...]} as JSON')


RATE = 22050
"""Hz: the music is resampled to this, mono, before its beats are tracked."""


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    if not Path(args.music).is_file():
        return fail(NAME, f"{args.music}: no such file")
    try:
        import librosa
    except ImportError:
        return fail(NAME, "beat tracking needs librosa: pip install 'dancebots[music]' "
                    "(scripts/dev.sh installs it)")
    import warnings

    from dancebots.plan.beats import track_beats

    try:
        with warnings.catch_warnings():  # librosa's fallback notices: the error below says it
            warnings.simplefilter("ignore")
            samples, rate = librosa.load(args.music, sr=RATE, mono=True)
    except Exception as exc:  # any decoder's failure: one clear error
        return fail(NAME, f"{args.music}: no sound could be read from it ({type(exc).__name__}"
                    f"); give a WAV, FLAC, OGG or MP3 file")
    try:
        track = track_beats(samples, int(rate))
    except ValueError as exc:
        return fail(NAME, f"{args.music}: {exc}")
    if args.json:
        print(json.dumps(track.to_json()))
        return EXIT_OK
    print(f"{args.music}: tempo {track.tempo:.1f} bpm, {len(track.beats)} beats "
          f"({len(samples) / rate:.1f} s)")
    for number, time in enumerate(track.beats.tolist(), start=1):
        print(f"beat {number:4d}  {time:8.3f} s")
    return EXIT_OK
