"""Animate a :class:`RunResult`: robots as oriented rectangles with trails (GIF or MP4)."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from typing import Any

import numpy as np

from dancebots.sim.simulator import RunResult

__all__ = ["animate_run", "ffmpeg_available"]


def ffmpeg_available() -> bool:
    return shutil.which("ffmpeg") is not None


def animate_run(result: RunResult, path: str, *, speedup: float = 4.0, fps: int = 15,
                trail: float = 8.0, progress: Callable[[int, int], None] | None = None) -> None:
    """Write an animation to ``path`` (.gif with Pillow, .mp4 with ffmpeg).

    speedup: show seconds per video second; trail: seconds of path drawn behind each robot.
    """
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter
    from matplotlib.patches import Polygon as PolygonPatch

    from dancebots.geometry import footprint_corners
    from dancebots.report.run_plots import robot_colours

    times = result.times
    frame_times = np.arange(times[0], times[-1] + 1e-9, speedup / fps)
    ticks = np.clip(np.searchsorted(times, frame_times), 0, len(times) - 1)
    period = float(times[1] - times[0]) if len(times) > 1 else 0.1
    trail_ticks = max(1, int(trail / period))
    fig, ax = plt.subplots(figsize=(6.4, 6.4), dpi=80, layout="constrained")
    room = result.arena.room
    ax.add_patch(PolygonPatch(room, closed=True, fill=False, edgecolor="black", linewidth=2))
    for obstacle in result.arena.obstacles:
        ax.add_patch(PolygonPatch(obstacle.polygon, closed=True, facecolor="0.35"))
    ax.set_xlim(room[:, 0].min() - 0.5, room[:, 0].max() + 0.5)
    ax.set_ylim(room[:, 1].min() - 0.5, room[:, 1].max() + 0.5)
    ax.set_aspect("equal")
    ax.grid(True, linewidth=0.3)
    colours = robot_colours(len(result.robots))
    bodies: list[Any] = []
    trails: list[Any] = []
    for i, robot in enumerate(result.robots):
        bodies.append(ax.add_patch(PolygonPatch(np.zeros((4, 2)), closed=True,
                                                facecolor=colours[i], alpha=0.7,
                                                edgecolor="black", label=robot)))
        trails.append(ax.plot([], [], color=colours[i], linewidth=1.2)[0])
    leader_dots = ax.plot([], [], "k+", markersize=8, label="virtual leader")[0]
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top")
    ax.legend(loc="upper right", fontsize="x-small")
    types = result.placement.types

    def draw(frame: int) -> list[Any]:
        k = int(ticks[frame])
        for i in range(len(result.robots)):
            x, y, theta = result.poses[i, k]
            bodies[i].set_xy(footprint_corners(np.array(x), np.array(y), np.array(theta),
                                               types[i].length, types[i].width))
            start = max(0, k - trail_ticks)
            trails[i].set_data(result.poses[i, start:k + 1, 0], result.poses[i, start:k + 1, 1])
        leader_dots.set_data(result.leader[:, k, 0], result.leader[:, k, 1])
        clock.set_text(f"t = {times[k]:5.1f} s")
        if progress is not None:
            progress(frame + 1, len(ticks))
        return [*bodies, *trails, leader_dots, clock]

    animation = FuncAnimation(fig, draw, frames=len(ticks), blit=False)
    writer: Any = FFMpegWriter(fps=fps) if path.endswith(".mp4") else PillowWriter(fps=fps)
    try:
        animation.save(path, writer=writer)
    finally:
        plt.close(fig)
