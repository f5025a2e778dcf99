"""Animate a :class:`RunResult`: robots as oriented rectangles with trails (GIF or MP4).

The room, obstacles and the leaders' paths are drawn once; each frame restores that
background and draws only the robots, their trails and the clock (matplotlib blitting), so a
frame costs milliseconds. GIFs are written with Pillow, MP4s by piping raw frames to ffmpeg.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.shows.formation import RunResult

__all__ = ["animate_run", "ffmpeg_available", "render_frames"]


def ffmpeg_available() -> bool:
    return shutil.which("ffmpeg") is not None


def render_frames(result: RunResult, *, speedup: float = 5.0, fps: int = 10,
                  trail: float = 8.0, size: float = 6.0, dpi: int = 80,
                  ) -> tuple[int, Iterator[NDArray[np.uint8]]]:
    """(frame count, iterator of RGB frames (H, W, 3)).

    speedup: show seconds per video second; trail: seconds of path behind each robot. When
    the result holds LIDAR scans, each robot's latest delivered scan is drawn as dots in its
    colour, where the things were when scanned (so the lag shows).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle
    from matplotlib.patches import Polygon as PolygonPatch

    from dancebots.geometry import footprint_corners
    from dancebots.report.run_plots import robot_colours
    from dancebots.shows.formation import STATUS

    times = result.times
    frame_times = np.arange(times[0], times[-1] + 1e-9, speedup / fps)
    ticks = np.clip(np.searchsorted(times, frame_times), 0, len(times) - 1)
    period = float(times[1] - times[0]) if len(times) > 1 else 0.1
    trail_ticks = max(1, int(trail / period))
    fig, ax = plt.subplots(figsize=(size, size), dpi=dpi, layout="constrained")
    room = result.arena.room
    ax.add_patch(PolygonPatch(room, closed=True, fill=False, edgecolor="black", linewidth=2))
    for obstacle in result.arena.obstacles:
        ax.add_patch(PolygonPatch(obstacle.polygon, closed=True, facecolor="0.35"))
    for i in range(len(result.robots)):
        ax.plot(result.leader[i, :, 0], result.leader[i, :, 1], color="0.75", linewidth=0.8,
                zorder=0)
    ax.set_xlim(room[:, 0].min() - 0.5, room[:, 0].max() + 0.5)
    ax.set_ylim(room[:, 1].min() - 0.5, room[:, 1].max() + 0.5)
    ax.set_aspect("equal")
    ax.grid(True, linewidth=0.3)
    ax.set_title(f"{result.plan.scenario.path} ({result.config.profile.name}, x{speedup:g})",
                 fontsize="small")
    colours = robot_colours(len(result.robots))
    bodies: list[Any] = []
    trails: list[Any] = []
    for i, robot in enumerate(result.robots):
        bodies.append(ax.add_patch(PolygonPatch(np.zeros((4, 2)), closed=True,
                                                facecolor=colours[i], alpha=0.8,
                                                edgecolor="black", label=robot,
                                                animated=True)))
        trails.append(ax.plot([], [], color=colours[i], linewidth=1.2, animated=True)[0])
    leader_dots = ax.plot([], [], "k+", markersize=8, label="virtual leader", animated=True)[0]
    people: list[Any] = [ax.add_patch(Circle((0.0, 0.0), radius, facecolor="purple", alpha=0.6,
                                  animated=True, label="spectator" if k == 0 else None))
              for k, radius in enumerate(result.spectator_radii.tolist())]
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", animated=True)
    scan_times = np.array([t for t, _ in result.lidar])
    hits: list[Any] = [ax.plot([], [], ".", color=colours[i], markersize=3.0, alpha=0.7,
                               animated=True)[0] for i in range(len(result.robots))] \
        if result.lidar else []
    ax.legend(handles=[*bodies, leader_dots, *people[:1]], loc="upper right",
              fontsize="x-small")
    canvas: Any = fig.canvas  # Agg: blitting and the RGBA buffer
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    types = result.placement.types

    def frames() -> Iterator[NDArray[np.uint8]]:
        try:
            for k in ticks.tolist():
                canvas.restore_region(background)
                for i in range(len(result.robots)):
                    x, y, theta = result.poses[i, k]
                    bodies[i].set_xy(footprint_corners(np.array(x), np.array(y),
                                                       np.array(theta), types[i].length,
                                                       types[i].width))
                    code = int(result.status[i, k])  # stopped: red outline; error: black
                    bodies[i].set_edgecolor(("black", "red", "black")[code])
                    bodies[i].set_linewidth((0.8, 2.5, 2.5)[code])
                    bodies[i].set_hatch("" if code == STATUS.index("ok") else "xx")
                    start = max(0, k - trail_ticks)
                    trails[i].set_data(result.poses[i, start:k + 1, 0],
                                       result.poses[i, start:k + 1, 1])
                    ax.draw_artist(trails[i])
                    ax.draw_artist(bodies[i])
                leader_dots.set_data(result.leader[:, k, 0], result.leader[:, k, 1])
                for person, (px, py) in zip(people, result.spectators[:, k].tolist(),
                                            strict=True):
                    person.set_center((px, py))
                    ax.draw_artist(person)
                clock.set_text(f"t = {times[k]:5.1f} s")
                if hits:  # the latest scan that has reached the robots: it lags
                    latest = int(np.searchsorted(scan_times, times[k] + 1e-9)) - 1
                    for i, dots in enumerate(hits):
                        if latest >= 0:
                            points = result.lidar[latest][1][i]
                            dots.set_data(points[:, 0], points[:, 1])
                        ax.draw_artist(dots)
                ax.draw_artist(leader_dots)
                ax.draw_artist(clock)
                canvas.blit(fig.bbox)
                yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
        finally:
            plt.close(fig)

    return len(ticks), frames()


def animate_run(result: RunResult, path: str, *, speedup: float = 5.0, fps: int = 10,
                progress: Callable[[int, int], None] | None = None) -> None:
    """Write the animation to ``path``: ``.mp4`` through ffmpeg, anything else as a GIF."""
    from PIL import Image

    count, frames = render_frames(result, speedup=speedup, fps=fps)

    def counted() -> Iterator[NDArray[np.uint8]]:
        for index, frame in enumerate(frames, start=1):
            yield frame
            if progress is not None:
                progress(index, count)

    if path.endswith(".mp4"):
        _write_mp4(counted(), path, fps)
        return
    images = [Image.fromarray(frame).quantize(colors=64) for frame in counted()]
    images[0].save(path, save_all=True, append_images=images[1:], duration=1000 // fps,
                   loop=0, optimize=False)


def _write_mp4(frames: Iterator[NDArray[np.uint8]], path: str, fps: int) -> None:
    first = next(frames)
    height, width = first.shape[:2]
    command = ["ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", str(fps), "-i", "-", "-vf",
               "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-f", "mp4", path]
    with subprocess.Popen(command, stdin=subprocess.PIPE) as process:
        assert process.stdin is not None
        process.stdin.write(first.tobytes())
        for frame in frames:
            process.stdin.write(frame.tobytes())
        process.stdin.close()
        if process.wait() != 0:
            raise OSError(f"ffmpeg failed to write {path}")
