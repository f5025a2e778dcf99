"""Animate a :class:`QueueResult`: the followers as oriented rectangles with a heading mark
and their name, the leader and the other people as discs, each follower's target as a
cross (GIF or MP4).

The room, its obstacles and the legend (below the room) are the background; the frames are
drawn by the reports' frame engine (``report.frames``: blitting, GIF with Pillow, MP4
through ffmpeg).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.report.frames import blit_frames, frame_ticks, write_animation
from dancebots.report.queue_plots import draw_room
from dancebots.shows.queue import LEADER, QueueResult

__all__ = ["animate_queue", "render_queue_frames"]


def render_queue_frames(result: QueueResult, *, speedup: float = 5.0, fps: int = 10,
                        ) -> tuple[int, Iterator[NDArray[np.uint8]]]:
    """(frame count, iterator of RGB frames (H, W, 3): a 9 x 5 in figure, 900 x 500 pixels
    at matplotlib's default 100 dpi), one frame per ``speedup / fps`` show seconds
    (speedup: show seconds per video second). The followers are drawn with a heading mark
    and their name (``frames.RobotMarks``), the legend sits below the room and the clock
    above it."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D

    from dancebots.report.frames import Clock, RobotMarks

    figure, axes = plt.subplots(figsize=(9, 5), layout="constrained")
    draw_room(axes, result)
    axes.set_aspect("equal")
    axes.set_title(f"queue of {len(result.robots)} ({', '.join(result.robots)}, front to back)"
                   f": detector {result.config.detector}, controller "
                   f"{result.config.controller}", loc="left", fontsize="medium")
    clock = Clock(axes, fontsize=10.0)  # in the title's row: never clipped, never in the room
    palette = plt.get_cmap("tab10")
    colours = [palette(i % palette.N) for i in range(len(result.robots))]
    kind = result.config.robot_type
    count = len(result.robots)
    robots = RobotMarks(axes, result.robots, np.full(count, kind.length),
                        np.full(count, kind.width), colours, alpha=1.0)
    leads = np.array([n == LEADER for n in result.spectator_names], dtype=bool)
    circle = np.exp(1j * np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False))
    disc = np.stack([circle.real, circle.imag], axis=1)  # (32, 2) the unit circle
    radii = result.spectator_radii[:, None, None]
    people: Any = axes.add_collection(PolyCollection(
        [], closed=True, facecolors=["0.3" if lead else "tab:red" for lead in leads],
        alpha=0.7, edgecolors="none"), autolim=False)
    leader_mark = [axes.scatter([], [], marker="s", color="0.3", s=40)] \
        if result.config.leader == "robot" else []
    targets = axes.scatter([], [], marker="x", color="k", s=30)
    legend = [Line2D([], [], color="k", marker="x", linestyle="none", label="targets")]
    if leader_mark:
        legend.append(Line2D([], [], color="0.3", marker="s", linestyle="none",
                             label="leader robot"))
    if leads.any():
        legend.append(Line2D([], [], color="0.3", alpha=0.7, marker="o", markersize=9,
                             linestyle="none", label="leader"))
    if not leads.all():
        legend.append(Line2D([], [], color="tab:red", alpha=0.7, marker="o", markersize=9,
                             linestyle="none", label="other people"))
    figure.legend(handles=legend, loc="outside lower center", ncols=len(legend),
                  fontsize="small", frameon=False)

    def update(k: int) -> list[Any]:
        """Move every animated artist to tick k; they are drawn in the returned order."""
        robots.move(result.poses[:, k])
        people.set_verts(result.spectators[:, k, None, :] + radii * disc)
        for mark in leader_mark:
            mark.set_offsets(result.leader[k:k + 1])
        seen = result.targets[:, k]
        targets.set_offsets(seen[~np.isnan(seen[:, 0])].reshape(-1, 2))
        return [robots.bodies, robots.headings, robots.arrows, people, *leader_mark, targets,
                robots.names, clock.set_text(f"t = {result.times[k]:5.1f} s")]

    ticks = frame_ticks(result.times, speedup, fps)
    return len(ticks), blit_frames(figure, update, ticks.tolist())


def animate_queue(result: QueueResult, path: str | Sequence[str], *, speedup: float = 5.0,
                  fps: int = 10, progress: Callable[[int, int], None] | None = None) -> int:
    """Write the run as a GIF, or an MP4 when ``path`` ends in .mp4 (needs ffmpeg), or to
    each of several paths with every frame rendered once, at ``speedup`` x real time;
    ``progress(frame, frames)`` after each frame, from 1. Returns the number of frames."""
    count, frames = render_queue_frames(result, speedup=speedup, fps=fps)
    return write_animation(frames, [path] if isinstance(path, str) else path, fps=fps,
                           count=count, progress=progress)
