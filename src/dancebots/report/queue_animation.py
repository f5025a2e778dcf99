"""Animate a :class:`QueueResult`: the followers as oriented rectangles, the leader and the
other people as discs, each follower's target as a cross (GIF or MP4).

The room and its obstacles are the background; the frames are drawn by the reports' frame
engine (``report.frames``: blitting, GIF with Pillow, MP4 through ffmpeg).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.report.frames import blit_frames, frame_ticks, write_frames
from dancebots.report.queue_plots import draw_room
from dancebots.shows.queue import LEADER, QueueResult

__all__ = ["animate_queue", "render_queue_frames"]


def render_queue_frames(result: QueueResult, *, speedup: float = 5.0, fps: int = 10,
                        ) -> tuple[int, Iterator[NDArray[np.uint8]]]:
    """(frame count, iterator of RGB frames (H, W, 3): a 9 x 5 in figure, 900 x 500 pixels
    at matplotlib's default 100 dpi), one frame per ``speedup / fps`` show seconds
    (speedup: show seconds per video second)."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Polygon

    from dancebots.geometry import footprint_corners

    figure, axes = plt.subplots(figsize=(9, 5))
    draw_room(axes, result)
    axes.set_aspect("equal")
    axes.set_title(f"queue of {len(result.robots)} ({', '.join(result.robots)}, front to back)"
                   f": detector {result.config.detector}, controller "
                   f"{result.config.controller}; x: targets")
    colours = plt.get_cmap("tab10")
    kind = result.config.robot_type
    bodies = [Polygon(np.zeros((4, 2)), closed=True, color=colours(i))
              for i in range(len(result.robots))]
    people = [Circle((0, 0), r, color="0.3" if n == LEADER else "tab:red", alpha=0.7)
              for n, r in zip(result.spectator_names, result.spectator_radii.tolist(),
                              strict=True)]
    for patch in [*bodies, *people]:
        axes.add_patch(patch)
    leader_mark = [axes.scatter([], [], marker="s", color="0.3", s=40, label="leader robot")] \
        if result.config.leader == "robot" else []
    targets = axes.scatter([], [], marker="x", color="k", s=30, label="targets")
    clock = axes.text(0.01, 0.97, "", transform=axes.transAxes, va="top")

    def update(k: int) -> list[Any]:
        """Move every animated artist to tick k; they are drawn in the returned order."""
        for i, body in enumerate(bodies):
            x, y, theta = result.poses[i, k]
            body.set_xy(footprint_corners(np.array(x), np.array(y), np.array(theta),
                                          kind.length, kind.width))
        for person, position in zip(people, result.spectators[:, k], strict=True):
            person.set_center(tuple(position))
        for mark in leader_mark:
            mark.set_offsets(result.leader[k:k + 1])
        seen = result.targets[:, k]
        targets.set_offsets(seen[~np.isnan(seen[:, 0])].reshape(-1, 2))
        clock.set_text(f"t = {result.times[k]:.1f} s")
        return [*bodies, *people, *leader_mark, targets, clock]

    ticks = frame_ticks(result.times, speedup, fps)
    return len(ticks), blit_frames(figure, update, ticks.tolist())


def animate_queue(result: QueueResult, path: str, *, speedup: float = 5.0,
                  fps: int = 10, progress: Callable[[int, int], None] | None = None) -> int:
    """Write the run as a GIF, or an MP4 when ``path`` ends in .mp4 (needs ffmpeg), at
    ``speedup`` x real time; ``progress(frame, frames)`` after each frame, from 1. Returns
    the number of frames."""
    count, frames = render_queue_frames(result, speedup=speedup, fps=fps)
    return write_frames(frames, path, fps=fps, count=count, progress=progress)
