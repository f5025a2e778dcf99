"""Results of a queue show (``sim.queue``): metrics, plots, animation and log.

Distances: a follower's *gap* is the free distance from its centre to the surface of the
object in front (the leader's disc, or the rear of the robot ahead, taken as half its
length), so that the stand-off the controllers keep (to the centroid of what they see)
compares with it directly; the distance error is gap - stand-off.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TextIO

import numpy as np
from numpy.typing import NDArray

from dancebots.shows.queue import LEADER, QueueResult

__all__ = ["FollowerMetrics", "QueueMetrics", "animate_queue", "plot_queue",
           "queue_metrics", "surface_gaps", "write_queue_log"]

FloatArray = NDArray[np.float64]
INTACT_GAP = 1.5
"""m: a follower whose final gap to the object in front is larger has lost the queue."""


def surface_gaps(result: QueueResult) -> FloatArray:
    """(R, T) free distance from each follower's centre to the object in front, m."""
    extent = np.array([result.leader_extent]
                      + [0.5 * result.config.robot_type.length] * (len(result.robots) - 1))
    gaps: FloatArray = result.gap - extent[:, None]
    return gaps


@dataclass(frozen=True, slots=True)
class FollowerMetrics:
    """One follower: distance error (gap - stand-off) median, RMS and largest |.|, m; time
    without a target, s; kidnappings (episodes in which its target was another object)
    and their time, s; contacts; final gap, m; whether it still follows at the end."""

    robot: str
    median_error: float
    rms_error: float
    max_error: float
    lost_time: float
    kidnappings: int
    kidnapped_time: float
    collisions: int
    final_gap: float
    intact: bool


@dataclass(frozen=True, slots=True)
class QueueMetrics:
    detector: str
    controller: str
    standoff: float
    duration: float
    followers: tuple[FollowerMetrics, ...]

    @property
    def intact(self) -> bool:
        """Did every follower keep the queue to the end?"""
        return all(f.intact for f in self.followers)

    def to_json(self) -> dict[str, Any]:
        def r3(value: float) -> float:
            return round(value, 3)

        return {"detector": self.detector, "controller": self.controller,
                "standoff_m": self.standoff, "duration_s": r3(self.duration),
                "queue_intact": self.intact,
                "followers": [{
                    "robot": f.robot, "median_distance_error_m": r3(f.median_error),
                    "rms_distance_error_m": r3(f.rms_error),
                    "max_abs_distance_error_m": r3(f.max_error),
                    "lost_target_s": r3(f.lost_time), "kidnappings": f.kidnappings,
                    "kidnapped_s": r3(f.kidnapped_time), "collisions": f.collisions,
                    "final_gap_m": r3(f.final_gap), "intact": f.intact}
                    for f in self.followers]}


def queue_metrics(result: QueueResult) -> QueueMetrics:
    """The metrics of a queue run (pure)."""
    dt = float(np.median(np.diff(result.times))) if len(result.times) > 1 else 0.0
    gaps = surface_gaps(result)
    errors = gaps - result.config.standoff
    kidnapped_all, lost = result.kidnapped, result.lost
    followers = []
    for i, robot in enumerate(result.robots):
        error = errors[i]
        kidnapped = kidnapped_all[i]
        episodes = int(np.count_nonzero(kidnapped[1:] & ~kidnapped[:-1]) + int(kidnapped[0]))
        final = float(gaps[i, -1])
        followers.append(FollowerMetrics(
            robot, float(np.median(error)), float(np.sqrt(np.mean(error**2))),
            float(np.abs(error).max()), float(lost[i].sum() * dt), episodes,
            float(kidnapped.sum() * dt),
            sum(1 for c in result.collisions if c.robot == robot), final, final <= INTACT_GAP))
    return QueueMetrics(result.config.detector, result.config.controller,
                        result.config.standoff, float(result.times[-1]), tuple(followers))


def plot_queue(result: QueueResult) -> Any:
    """Figure: the paths in the room (left) and each follower's gap to the object in front
    over time with the stand-off, lost and kidnapped times shaded (right)."""
    import matplotlib.pyplot as plt

    figure, (room_axes, gap_axes) = plt.subplots(1, 2, figsize=(13, 5),
                                                 gridspec_kw={"width_ratios": [1.4, 1]})
    _draw_room(room_axes, result)
    colours = plt.get_cmap("tab10")
    room_axes.plot(*result.leader.T, ls="--", color="0.3", lw=1.2,
                   label=f"leader ({result.config.leader})")
    for k, name in enumerate(result.spectator_names):
        if name != LEADER:
            room_axes.plot(*result.spectators[k].T, ls="--", color="tab:red", lw=1.2,
                           label=name)
    for i, robot in enumerate(result.robots):
        room_axes.plot(*result.poses[i, :, :2].T, color=colours(i), lw=1.5, label=robot)
        room_axes.plot(*result.poses[i, -1, :2], "o", color=colours(i))
    room_axes.set_aspect("equal")
    room_axes.legend(loc="upper left", fontsize=8)
    room_axes.set_title(f"queue: detector {result.config.detector}, controller "
                        f"{result.config.controller}")
    gaps = surface_gaps(result)
    lost, kidnapped = result.lost, result.kidnapped
    for i, robot in enumerate(result.robots):
        gap_axes.plot(result.times, gaps[i], color=colours(i), label=robot)
        for mask, colour in ((lost[i], "0.85"), (kidnapped[i], "tab:red")):
            gap_axes.fill_between(result.times, 0, 1, where=mask, color=colour, alpha=0.25,
                                  transform=gap_axes.get_xaxis_transform(), lw=0)
    gap_axes.axhline(result.config.standoff, color="k", ls=":", label="stand-off")
    gap_axes.set_xlabel("time [s]")
    gap_axes.set_ylabel("gap to the object in front [m]")
    gap_axes.set_title("gaps (grey: target lost, red: kidnapped)")
    gap_axes.legend(fontsize=8)
    figure.tight_layout()
    return figure


def _draw_room(axes: Any, result: QueueResult) -> None:
    from matplotlib.patches import Polygon

    room = result.arena.room
    axes.add_patch(Polygon(room, closed=True, fill=False, color="k", lw=1.5))
    for obstacle in result.arena.obstacles:
        axes.add_patch(Polygon(obstacle.polygon, closed=True, color="0.6"))
    low, high = room.min(axis=0), room.max(axis=0)
    axes.set_xlim(low[0] - 0.2, high[0] + 0.2)
    axes.set_ylim(low[1] - 0.2, high[1] + 0.2)


def animate_queue(result: QueueResult, path: str, *, speedup: float = 5.0,
                  fps: int = 10, progress: Callable[[int, int], None] | None = None) -> int:
    """Write the run as a GIF, or an MP4 when ``path`` ends in .mp4 (needs ffmpeg), at
    ``speedup`` x real time; ``progress(frame, frames)`` after each frame. Returns the
    number of frames."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter
    from matplotlib.patches import Circle, Polygon

    from dancebots.geometry import footprint_corners

    figure, axes = plt.subplots(figsize=(9, 5))
    _draw_room(axes, result)
    axes.set_aspect("equal")
    axes.set_title(f"queue of {len(result.robots)} ({', '.join(result.robots)}, front to back)"
                   f": detector {result.config.detector}, controller "
                   f"{result.config.controller}; x: targets")
    colours = plt.get_cmap("tab10")
    kind = result.config.robot_type
    bodies = [Polygon(np.zeros((4, 2)), closed=True, color=colours(i))
              for i in range(len(result.robots))]
    for body in bodies:
        axes.add_patch(body)
    people = [Circle((0, 0), r, color="0.3" if n == LEADER else "tab:red", alpha=0.7)
              for n, r in zip(result.spectator_names, result.spectator_radii.tolist(),
                              strict=True)]
    for person in people:
        axes.add_patch(person)
    leader_mark = axes.scatter([], [], marker="s", color="0.3", s=40,
                               label="leader robot") if result.config.leader == "robot" \
        else None
    targets = axes.scatter([], [], marker="x", color="k", s=30, label="targets")
    clock = axes.text(0.01, 0.97, "", transform=axes.transAxes, va="top")
    step = max(1, round(speedup / fps / max(float(np.median(np.diff(result.times))), 1e-9)))
    frames = list(range(0, len(result.times), step))

    def draw(k: int) -> list[Any]:
        for i, body in enumerate(bodies):
            x, y, theta = result.poses[i, k]
            body.set_xy(footprint_corners(np.array(x), np.array(y), np.array(theta),
                                          kind.length, kind.width))
        for person, position in zip(people, result.spectators[:, k], strict=True):
            person.set_center(tuple(position))
        seen = result.targets[:, k]
        targets.set_offsets(seen[~np.isnan(seen[:, 0])].reshape(-1, 2))
        clock.set_text(f"t = {result.times[k]:.1f} s")
        if leader_mark is not None:
            leader_mark.set_offsets(result.leader[k:k + 1])
            return [*bodies, *people, targets, clock, leader_mark]
        return [*bodies, *people, targets, clock]

    animation = FuncAnimation(figure, draw, frames=frames, blit=True)
    writer = FFMpegWriter(fps=fps) if path.endswith(".mp4") else PillowWriter(fps=fps)
    animation.save(path, writer=writer, progress_callback=progress)
    plt.close(figure)
    return len(frames)


LOG_COLUMNS = ("t", "robot", "x", "y", "theta", "u_cmd", "w_cmd", "x_target", "y_target",
               "x_ahead", "y_ahead", "gap", "lost", "kidnapped")
"""The queue log's columns; units s, m, rad, m/s, rad/s; world frame."""


def write_queue_log(result: QueueResult, handle: TextIO) -> None:
    """Every sample as CSV, one row per follower per tick (``pandas.read_csv`` reads it)."""
    writer = csv.writer(handle, lineterminator="\n")
    writer.writerow(LOG_COLUMNS)
    gaps, lost, kidnapped = surface_gaps(result), result.lost, result.kidnapped
    for k, t in enumerate(result.times.tolist()):
        for i, robot in enumerate(result.robots):
            target = result.targets[i, k]
            writer.writerow([
                f"{t:.2f}", robot, *(f"{v:.4f}" for v in result.poses[i, k]),
                *(f"{v:.4f}" for v in result.commands[i, k]),
                *("" if math.isnan(v) else f"{v:.4f}" for v in target),
                *(f"{v:.4f}" for v in result.ahead[i, k]), f"{gaps[i, k]:.4f}",
                int(lost[i, k]), int(kidnapped[i, k])])
