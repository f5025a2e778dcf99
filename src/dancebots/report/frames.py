"""The reports' one frame engine: blitted matplotlib frames, written as a GIF or an MP4.

A show's animation sets its figure up once (room, obstacles, paths: the background) and gives
an update function that moves its artists to one sample and returns them in drawing order.
The engine draws the background once; each frame then restores it, draws only the returned
artists and copies the RGB buffer (matplotlib blitting), so a frame costs milliseconds instead
of a full redraw. GIFs are written with Pillow (64 colours), MP4s by piping raw frames to
ffmpeg. ``animation.animate_run`` (formations) and ``queue_animation.animate_queue`` (queues)
are the two users.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["GIF_COLOURS", "blit_frames", "ffmpeg_available", "frame_ticks", "write_frames"]

RGBFrame = NDArray[np.uint8]
"""(H, W, 3) one frame, RGB, H x W the figure's size in pixels."""
GIF_COLOURS = 64
"""Palette size of a GIF frame."""


def ffmpeg_available() -> bool:
    """Can MP4s be written (is ``ffmpeg`` on the PATH)?"""
    return shutil.which("ffmpeg") is not None


def frame_ticks(times: NDArray[np.float64], speedup: float, fps: int) -> NDArray[np.intp]:
    """(F,) the sample each frame shows: one frame per ``speedup / fps`` show seconds from
    ``times[0]`` to ``times[-1]`` (times (T,) s, increasing), each the first sample at or
    after its frame time, so F = floor((times[-1] - times[0]) * fps / speedup) + 1 and the
    video plays ``speedup`` show seconds per second."""
    frame_times = np.arange(times[0], times[-1] + 1e-9, speedup / fps)
    ticks: NDArray[np.intp] = np.clip(np.searchsorted(times, frame_times), 0, len(times) - 1)
    return ticks


def blit_frames(figure: Any, update: Callable[[int], Sequence[Any]],
                keys: Sequence[int]) -> Iterator[RGBFrame]:
    """RGB frames (H, W, 3) uint8 of ``figure`` (H x W its size in pixels), one per key.

    ``update(key)`` moves the animated artists to ``key`` (a sample index) and returns them
    in drawing order, the same artists every time; the engine marks them animated before it
    draws the background, so they are never part of it. The figure belongs to the engine:
    it is closed when the frames are exhausted (or the iterator is closed).
    """
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas: Any = figure.canvas
    if not isinstance(canvas, FigureCanvasAgg):  # blitting and the RGBA buffer need Agg
        canvas = FigureCanvasAgg(figure)
    try:
        if not keys:
            return
        for artist in update(keys[0]):
            artist.set_animated(True)
        canvas.draw()
        background = canvas.copy_from_bbox(figure.bbox)
        for key in keys:
            canvas.restore_region(background)
            for artist in update(key):
                figure.draw_artist(artist)
            canvas.blit(figure.bbox)
            yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
    finally:
        plt.close(figure)


def write_frames(frames: Iterable[RGBFrame], path: str, *, fps: int, count: int,
                 progress: Callable[[int, int], None] | None = None) -> int:
    """Write RGB frames (H, W, 3) uint8 to ``path``: ``.mp4`` through ffmpeg (H.264,
    yuv420p, padded to even sizes), anything else as a looping GIF (``GIF_COLOURS`` colours,
    1000 // fps ms per frame). ``progress(done, count)`` after each frame, done from 1;
    ``count`` is the expected number of frames, for the progress only. Returns the number of
    frames written; raises ValueError when there is none, OSError when ffmpeg fails."""

    def counted() -> Iterator[RGBFrame]:
        done = 0
        for done, frame in enumerate(frames, start=1):
            yield frame
            if progress is not None:
                progress(done, count)
        if done == 0:
            raise ValueError(f"no frames to write to {path}")

    if path.endswith(".mp4"):
        return _write_mp4(counted(), path, fps)
    from PIL import Image

    images = [Image.fromarray(frame).quantize(colors=GIF_COLOURS) for frame in counted()]
    images[0].save(path, save_all=True, append_images=images[1:], duration=1000 // fps,
                   loop=0, optimize=False)
    return len(images)


def _write_mp4(frames: Iterator[RGBFrame], path: str, fps: int) -> int:
    first = next(frames)
    height, width = first.shape[:2]
    command = ["ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", str(fps), "-i", "-", "-vf",
               "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-f", "mp4", path]
    written = 1
    with subprocess.Popen(command, stdin=subprocess.PIPE) as process:
        assert process.stdin is not None
        process.stdin.write(first.tobytes())
        for frame in frames:
            process.stdin.write(frame.tobytes())
            written += 1
        process.stdin.close()
        if process.wait() != 0:
            raise OSError(f"ffmpeg failed to write {path}")
    return written
