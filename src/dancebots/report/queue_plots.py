"""The figure of a queue show (``shows.queue``): paths and gaps over time."""

from __future__ import annotations

from typing import Any

from dancebots.report.drawing import draw_arena
from dancebots.report.queue_metrics import surface_gaps
from dancebots.shows.queue import LEADER, QueueResult

__all__ = ["draw_room", "plot_queue"]


def plot_queue(result: QueueResult) -> Any:
    """Figure: the paths in the room (left) and each follower's gap to the object in front
    over time with the stand-off, lost and kidnapped times shaded (right)."""
    import matplotlib.pyplot as plt

    figure, (room_axes, gap_axes) = plt.subplots(1, 2, figsize=(13, 5),
                                                 gridspec_kw={"width_ratios": [1.4, 1]})
    draw_room(room_axes, result)
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


def draw_room(axes: Any, result: QueueResult) -> None:
    """Draw the room's walls and obstacles on ``axes`` and frame the room (0.2 m margin)."""
    draw_arena(axes, result.arena.room, result.arena.obstacles, margin=0.2)
