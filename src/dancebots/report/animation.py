"""Animate a :class:`RunResult`: robots as oriented rectangles with a heading mark, their
name and trails (GIF or MP4).

The room, obstacles, the leaders' paths (broken at ``newVL`` jumps) and the legend (below
the room) are the background; each frame moves the robots, their trails, the spectators,
the LIDAR dots and the clock, drawn by the reports' frame engine (``report.frames``:
blitting, GIF with Pillow, MP4 through ffmpeg).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.report.drawing import draw_arena
from dancebots.report.frames import blit_frames, frame_ticks, write_animation
from dancebots.shows.formation import RunResult

__all__ = ["animate_run", "render_frames"]


def render_frames(result: RunResult, *, speedup: float = 5.0, fps: int = 10,
                  trail: float = 8.0, size: float = 6.0, dpi: int = 120,
                  ) -> tuple[int, Iterator[NDArray[np.uint8]]]:
    """(frame count, iterator of RGB frames (H, W, 3), a size x size in figure at dpi).

    speedup: show seconds per video second; trail: seconds of path behind each robot. Robots
    are drawn with a heading mark and their name (``frames.RobotMarks``); the virtual
    leaders' paths break where a new leader takes over; the legend sits below the room and
    the clock above it, next to the scenario's file name. When the result holds LIDAR scans,
    each robot's latest delivered scan is drawn as dots in its colour, where the things were
    when scanned (so the lag shows).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from dancebots.geometry import footprint_corners
    from dancebots.report.frames import Clock, RobotMarks
    from dancebots.report.run_plots import broken_at_changes, robot_colours
    from dancebots.shows.formation import STATUS

    times = result.times
    ticks = frame_ticks(times, speedup, fps)
    period = float(times[1] - times[0]) if len(times) > 1 else 0.1
    trail_ticks = max(1, int(trail / period))
    fig, ax = plt.subplots(figsize=(size, size), dpi=dpi, layout="constrained")
    draw_arena(ax, result.arena.room, result.arena.obstacles, margin=0.5)
    for i in range(len(result.robots)):
        leader = broken_at_changes(result.leader[i, :, :2], result.formation[i])
        ax.plot(leader[:, 0], leader[:, 1], color="0.75", linewidth=0.8, zorder=0)
    ax.set_aspect("equal")
    ax.grid(True, linewidth=0.3)
    ax.tick_params(labelsize="small")
    ax.set_title(f"{Path(result.plan.scenario.path).name} ({result.config.profile.name}, "
                 f"x{speedup:g})", fontsize="small", loc="left")
    clock = Clock(ax)  # in the title's row: never clipped, never over the room
    colours = robot_colours(len(result.robots))
    types = result.placement.types
    trails: Any = ax.add_collection(LineCollection([], colors=colours, linewidths=1.2),
                                    autolim=False)
    lengths = np.array([kind.length for kind in types])
    widths = np.array([kind.width for kind in types])
    robots = RobotMarks(ax, result.robots, lengths, widths, colours)
    held: Any = ax.add_collection(PolyCollection([], closed=True, facecolors="none",
                                                 hatch="xx", zorder=3),
                                  autolim=False)  # over a robot stopped or in error
    leader_dots = ax.plot([], [], "k+", markersize=8)[0]
    circle = np.exp(1j * np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False))
    disc = np.stack([circle.real, circle.imag], axis=1)  # (32, 2) the unit circle
    radii = result.spectator_radii[:, None, None]
    people: Any = ax.add_collection(PolyCollection([], closed=True, facecolors="purple",
                                                   alpha=0.6, edgecolors="none"),
                                    autolim=False)
    scan_times = np.array([t for t, _ in result.lidar])
    hits: list[Any] = [ax.plot([], [], ".", color=colours[i], markersize=3.0, alpha=0.7)[0]
                       for i in range(len(result.robots))] if result.lidar else []
    legend: list[Any] = [Line2D([], [], color="k", marker="+", linestyle="none",
                                markersize=8, label="virtual leader")]
    for code, colour in ((STATUS.index("stopped"), "red"), (STATUS.index("error"), "black")):
        if np.any(result.status == code):  # the states this show has
            legend.append(Patch(facecolor="none", edgecolor=colour, linewidth=1.5,
                                hatch="xx", label=STATUS[code]))
    if len(radii):
        legend.append(Patch(facecolor="purple", alpha=0.6, label="spectator"))
    if hits:
        legend.append(Line2D([], [], color="0.3", marker=".", linestyle="none",
                             label="LIDAR scan"))
    ax.legend(handles=legend, loc="upper center", bbox_to_anchor=(0.5, 0.0),
              borderaxespad=2.6, ncols=len(legend), fontsize="x-small", frameon=False,
              handlelength=1.5, columnspacing=1.2)  # below the tick labels
    poses = result.poses  # (R, T, 3)
    edge_colours = np.array([(0.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0)])
    edge_widths = np.array([0.8, 2.5, 2.5])  # per status code: ok, stopped, error
    ok = STATUS.index("ok")

    def update(k: int) -> list[Any]:
        """Move every animated artist to tick k; they are drawn in the returned order."""
        start = max(0, k - trail_ticks)
        trails.set_segments(poses[:, start:k + 1, :2])
        robots.move(poses[:, k])
        codes = result.status[:, k].astype(int)  # stopped: red outline; error: black
        robots.bodies.set_edgecolor(edge_colours[codes])
        robots.bodies.set_linewidth(edge_widths[codes])
        stopped = codes != ok
        held.set_verts(footprint_corners(poses[stopped, k, 0], poses[stopped, k, 1],
                                         poses[stopped, k, 2], lengths[stopped],
                                         widths[stopped]))
        held.set_edgecolor(edge_colours[codes[stopped]])
        leader_dots.set_data(result.leader[:, k, 0], result.leader[:, k, 1])
        people.set_verts(result.spectators[:, k, None, :] + radii * disc)
        if hits:  # the latest scan that has reached the robots: it lags
            latest = int(np.searchsorted(scan_times, times[k] + 1e-9)) - 1
            if latest >= 0:
                for i, dots in enumerate(hits):
                    points = result.lidar[latest][1][i]
                    dots.set_data(points[:, 0], points[:, 1])
        return [trails, robots.bodies, held, robots.headings, robots.arrows, people, *hits,
                leader_dots, robots.names, clock.set_text(f"t = {times[k]:5.1f} s")]

    return len(ticks), blit_frames(fig, update, ticks.tolist())


def animate_run(result: RunResult, path: str | Sequence[str], *, speedup: float = 5.0,
                fps: int = 10, progress: Callable[[int, int], None] | None = None) -> None:
    """Write the animation to ``path`` (or to each of several paths, every frame rendered
    once): ``.mp4`` through ffmpeg, anything else as a GIF; ``progress(frame, frames)`` after
    each frame, from 1."""
    count, frames = render_frames(result, speedup=speedup, fps=fps)
    write_animation(frames, [path] if isinstance(path, str) else path, fps=fps, count=count,
                    progress=progress)
