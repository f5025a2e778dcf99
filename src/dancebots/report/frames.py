"""The reports' one frame engine: blitted matplotlib frames, written as a GIF or an MP4.

A show's animation sets its figure up once (room, obstacles, paths: the background) and gives
an update function that moves its artists to one sample and returns them in drawing order.
The engine draws the background once; each frame then restores it, draws only the returned
artists and copies the RGB buffer (matplotlib blitting), so a frame costs milliseconds instead
of a full redraw. Each frame is rendered once and goes to every file asked for
(:func:`write_animation`): GIFs with Pillow, every frame mapped without dithering onto one
palette of 64 colours taken from the first frame and the drawings' accent colours (a median
cut per frame took 3 of the open-day animation's 4 s), MP4s by piping raw frames to ffmpeg.
``animation.animate_run`` (formations) and ``queue_animation.animate_queue`` (queues)
are the two users; both draw their robots with ``RobotMarks`` (footprint, heading, name).
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ACCENT_COLOURS", "GIF_COLOURS", "Clock", "RobotMarks", "blit_frames",
           "ffmpeg_available", "frame_ticks", "gif_palette", "write_animation", "write_frames"]

RGBFrame = NDArray[np.uint8]
"""(H, W, 3) one frame, RGB, H x W the figure's size in pixels."""
GIF_COLOURS = 64
"""Palette size of a GIF (one palette for all its frames)."""
ACCENT_COLOURS = ("red", "black", "purple", "0.3", "0.75", "tab:blue", "tab:orange",
                  "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:gray",
                  "tab:olive", "tab:cyan")
"""Colours a later frame may show that the first need not (a held robot's red outline, an
error's black, people, scans, the robots' colours): the GIF palette holds them too."""


class Clock:
    """A line of text that changes every frame (the show time), above the axes' top right
    corner, in the title's row (so the layout keeps room for it: give the axes a title).

    Drawn as glyph outlines of a monospace font, set up once: matplotlib's ``Text`` lays its
    string out and rasterises it at every draw, which costs milliseconds per frame; this
    costs a tenth of a millisecond. Only ``CHARACTERS`` can be shown.
    """

    CHARACTERS = "0123456789.:-+ tsm=/"

    def __init__(self, axes: Any, *, fontsize: float = 9.0, pad: float = 6.0,
                 zorder: float = 5.0) -> None:
        from matplotlib.collections import PathCollection
        from matplotlib.font_manager import FontProperties
        from matplotlib.path import Path
        from matplotlib.textpath import TextPath, text_to_path
        from matplotlib.transforms import Affine2D, ScaledTranslation

        font = FontProperties(family="monospace", size=fontsize)
        self._glyphs = {c: TextPath((0.0, 0.0), c, prop=font) if c.strip()
                        else Path(np.zeros((1, 2))) for c in self.CHARACTERS}
        width, _, _ = text_to_path.get_text_width_height_descent("0" * 10, font, ismath=False)
        self._advance = width / 10  # points, the same for every character
        self._pad = pad  # points from the axes' top to the baseline (axes.titlepad)
        in_points = Affine2D().scale(axes.figure.dpi / 72.0)
        corner = ScaledTranslation(1.0, 1.0, axes.transAxes)  # the axes' top right, pixels
        self.artist: Any = PathCollection([], offsets=np.zeros((0, 2)), transform=in_points,
                                          offset_transform=in_points + corner,
                                          facecolors="black", edgecolors="none",
                                          zorder=zorder)
        self.artist.set_in_layout(False)
        axes.add_artist(self.artist)
        self.artist.set_clip_on(False)

    def set_text(self, text: str) -> Any:
        """Show ``text`` (right-aligned at the axes' right edge); returns the artist."""
        count = len(text)
        self.artist.set_paths([self._glyphs[c] for c in text])
        self.artist.set_offsets(np.stack([(np.arange(count) - count) * self._advance,
                                          np.full(count, self._pad)], axis=1))
        return self.artist


class RobotMarks:
    """Robots drawn for a frame: footprint, heading mark and name, moved by ``move``.

    Four collections on ``axes`` (which must have an equal aspect, so that a heading in the
    room is the same angle on screen), one item per robot: the footprints (rectangles
    length x width m, filled with the robot's colour), a line from each centre to the middle
    of its front edge, an arrowhead just beyond that edge and the robot's name beside its
    circumscribed circle, up and to the right. The arrowhead and the names are sized in
    points, so they stay legible however small the room makes the robots; a robot driving
    backwards shows its arrowhead on the side away from its motion. Collections draw all the
    robots in one call each, which keeps frames fast with many robots.
    """

    def __init__(self, axes: Any, names: Sequence[str], lengths: NDArray[np.float64],
                 widths: NDArray[np.float64], colours: Sequence[Any], *,
                 fontsize: float = 7.0, alpha: float = 0.85, zorder: float = 3.0) -> None:
        from matplotlib.collections import LineCollection, PathCollection, PolyCollection
        from matplotlib.colors import to_rgba
        from matplotlib.font_manager import FontProperties
        from matplotlib.textpath import TextPath
        from matplotlib.transforms import Affine2D

        count = len(names)
        self._lengths = np.asarray(lengths, dtype=float)
        self._widths = np.asarray(widths, dtype=float)
        self._reach = np.hypot(self._lengths, self._widths) / 2 / np.sqrt(2.0)  # (R,) x and y
        in_points = Affine2D().scale(axes.figure.dpi / 72.0)  # sizes in points, on screen
        # the arrowhead in points, pointing along +x from the middle of the front edge
        self._arrow = np.array([[0.0, 0.45], [0.95, 0.0], [0.0, -0.45]]) * fontsize
        self.bodies: Any = PolyCollection([], closed=True,
                                          facecolors=[to_rgba(c, alpha) for c in colours],
                                          edgecolors="black", linewidths=0.8, zorder=zorder)
        self.headings: Any = LineCollection([], colors="black", linewidths=1.0, zorder=zorder)
        self.arrows: Any = PolyCollection([], closed=True, offsets=np.zeros((count, 2)),
                                          offset_transform=axes.transData,
                                          transform=in_points, facecolors="black",
                                          edgecolors="none", zorder=zorder)
        gap = 0.15 * fontsize  # between the circumscribed circle and the name
        font = FontProperties(size=fontsize, weight="bold")
        self.labels = tuple(names)
        self.names: Any = PathCollection(
            [TextPath((gap, gap), name, prop=font) for name in names],
            offsets=np.zeros((count, 2)), offset_transform=axes.transData,
            transform=in_points, facecolors="0.1", edgecolors="none", zorder=zorder,
            label="robot names")
        for collection in self.artists:
            collection.set_in_layout(False)
            axes.add_collection(collection, autolim=False)

    @property
    def artists(self) -> list[Any]:
        """The robots' collections, in drawing order."""
        return [self.bodies, self.headings, self.arrows, self.names]

    def move(self, poses: NDArray[np.float64]) -> list[Any]:
        """Put the robots at poses (R, 3) (x, y m, heading rad) and return ``artists``."""
        from dancebots.geometry import footprint_corners

        x, y, theta = poses[:, 0], poses[:, 1], poses[:, 2]
        cos, sin = np.cos(theta), np.sin(theta)
        centre = poses[:, :2]
        front = centre + (self._lengths / 2)[:, None] * np.stack([cos, sin], axis=1)
        self.bodies.set_verts(footprint_corners(x, y, theta, self._lengths, self._widths))
        self.headings.set_segments(np.stack([centre, front], axis=1))
        rotation = np.stack([np.stack([cos, sin], axis=1), np.stack([-sin, cos], axis=1)],
                            axis=1)  # (R, 2, 2): row vectors times it turn by theta
        self.arrows.set_verts(self._arrow @ rotation)
        self.arrows.set_offsets(front)
        self.names.set_offsets(centre + self._reach[:, None])
        return self.artists


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
    """:func:`write_animation` to one file."""
    return write_animation(frames, [path], fps=fps, count=count, progress=progress)


def write_animation(frames: Iterable[RGBFrame], paths: Sequence[str], *, fps: int,
                    count: int, progress: Callable[[int, int], None] | None = None) -> int:
    """Write RGB frames (H, W, 3) uint8 to every one of ``paths``, each frame rendered once:
    ``.mp4`` through ffmpeg (H.264, yuv420p, padded to even sizes), anything else as a
    looping GIF (one palette of ``GIF_COLOURS`` colours, :func:`gif_palette`, no dithering;
    1000 // fps ms per frame). ``progress(done, count)`` after each frame, done from 1;
    ``count`` is the expected number of frames, for the progress only. Returns the number of
    frames written; raises ValueError when there is none or no path, OSError when ffmpeg
    fails (no ffmpeg is left running)."""
    if not paths:
        raise ValueError("no file to write the frames to")
    from PIL import Image

    videos: list[tuple[str, subprocess.Popen[bytes]]] = []
    gifs: list[str] = [path for path in paths if not path.endswith(".mp4")]
    images: list[Any] = []
    palette: Any = None
    done = 0
    try:
        for done, frame in enumerate(frames, start=1):
            if done == 1:
                videos = [(path, _ffmpeg(path, frame.shape, fps)) for path in paths
                          if path.endswith(".mp4")]
                palette = gif_palette(frame) if gifs else None
            for _, process in videos:
                assert process.stdin is not None
                process.stdin.write(frame.tobytes())
            if gifs:
                images.append(Image.fromarray(frame).quantize(
                    palette=palette, dither=Image.Dither.NONE))
            if progress is not None:
                progress(done, count)
        if done == 0:
            raise ValueError(f"no frames to write to {', '.join(paths)}")
        for path, process in videos:
            assert process.stdin is not None
            process.stdin.close()
            if process.wait() != 0:
                raise OSError(f"ffmpeg failed to write {path}")
    finally:
        for _, process in videos:  # on an error: no ffmpeg left behind, no pipe left open
            if process.poll() is None:
                process.kill()
                process.wait()
            if process.stdin is not None and not process.stdin.closed:
                process.stdin.close()
    for path in gifs:
        images[0].save(path, save_all=True, append_images=images[1:], duration=1000 // fps,
                       loop=0, optimize=False)
    return done


def gif_palette(frame: RGBFrame) -> Any:
    """A Pillow palette image of ``GIF_COLOURS`` colours (median cut) for every frame of a
    GIF: from ``frame`` (the first: the room, the robots, the legend) with a band of
    :data:`ACCENT_COLOURS` below it, so that what appears later finds its colour."""
    from matplotlib.colors import to_rgb
    from PIL import Image

    accents = (np.array([to_rgb(c) for c in ACCENT_COLOURS]) * 255.0).round().astype(np.uint8)
    width = frame.shape[1]
    row = accents[np.arange(width) * len(accents) // width]  # (W, 3): each accent a stretch
    sample = np.concatenate([frame, np.repeat(row[None], 8, axis=0)], axis=0)
    return Image.fromarray(sample).quantize(colors=GIF_COLOURS)


def _ffmpeg(path: str, shape: tuple[int, ...], fps: int) -> subprocess.Popen[bytes]:
    """An ffmpeg process that encodes raw RGB frames of ``shape`` (H, W, 3) from its stdin
    to the MP4 at ``path``."""
    height, width = shape[:2]
    command = ["ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", str(fps), "-i", "-", "-vf",
               "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset", "veryfast",
               "-pix_fmt", "yuv420p", "-f", "mp4", path]
    return subprocess.Popen(command, stdin=subprocess.PIPE)
