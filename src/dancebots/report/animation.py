"""Animate a :class:`RunResult`: robots as oriented rectangles with trails (GIF or MP4).

The room, obstacles and the leaders' paths are the background; each frame moves the robots,
their trails, the spectators, the LIDAR dots and the clock, drawn by the reports' frame
engine (``report.frames``: blitting, GIF with Pillow, MP4 through ffmpeg).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.report.frames import blit_frames, ffmpeg_available, frame_ticks, write_frames
from dancebots.shows.formation import RunResult

__all__ = ["animate_run", "ffmpeg_available", "render_frames"]
# ffmpeg_available is the engine's, also importable here with animate_run (cli/run.py)


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
    ticks = frame_ticks(times, speedup, fps)
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
    types = result.placement.types

    def update(k: int) -> list[Any]:
        """Move every animated artist to tick k; they are drawn in the returned order."""
        drawn: list[Any] = []
        for i in range(len(result.robots)):
            x, y, theta = result.poses[i, k]
            bodies[i].set_xy(footprint_corners(np.array(x), np.array(y), np.array(theta),
                                               types[i].length, types[i].width))
            code = int(result.status[i, k])  # stopped: red outline; error: black
            bodies[i].set_edgecolor(("black", "red", "black")[code])
            bodies[i].set_linewidth((0.8, 2.5, 2.5)[code])
            bodies[i].set_hatch("" if code == STATUS.index("ok") else "xx")
            start = max(0, k - trail_ticks)
            trails[i].set_data(result.poses[i, start:k + 1, 0], result.poses[i, start:k + 1, 1])
            drawn += [trails[i], bodies[i]]
        leader_dots.set_data(result.leader[:, k, 0], result.leader[:, k, 1])
        for person, (px, py) in zip(people, result.spectators[:, k].tolist(), strict=True):
            person.set_center((px, py))
        clock.set_text(f"t = {times[k]:5.1f} s")
        if hits:  # the latest scan that has reached the robots: it lags
            latest = int(np.searchsorted(scan_times, times[k] + 1e-9)) - 1
            if latest >= 0:
                for i, dots in enumerate(hits):
                    points = result.lidar[latest][1][i]
                    dots.set_data(points[:, 0], points[:, 1])
        return [*drawn, *people, *hits, leader_dots, clock]

    return len(ticks), blit_frames(fig, update, ticks.tolist())


def animate_run(result: RunResult, path: str, *, speedup: float = 5.0, fps: int = 10,
                progress: Callable[[int, int], None] | None = None) -> None:
    """Write the animation to ``path``: ``.mp4`` through ffmpeg, anything else as a GIF;
    ``progress(frame, frames)`` after each frame, from 1."""
    count, frames = render_frames(result, speedup=speedup, fps=fps)
    write_frames(frames, path, fps=fps, count=count, progress=progress)
