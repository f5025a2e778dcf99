"""Figures of a simulated show, thin layers over a :class:`RunResult`.

``plot_speeds_and_distances`` is thesis fig. 7.5 (commanded speeds and the distance to the
virtual leader over time); ``plot_trajectories`` is fig. 7.6 (robot paths with the virtual
leader's path, the desired paths, the room and obstacles).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.report.drawing import draw_arena
from dancebots.shows.formation import RunResult

__all__ = ["broken_at_changes", "plot_speeds_and_distances", "plot_trajectories",
           "robot_colours"]


def robot_colours(count: int) -> list[Any]:
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("tab10" if count <= 10 else "tab20")
    return [cmap(i % cmap.N) for i in range(count)]


def broken_at_changes(points: NDArray[np.float64], formation: NDArray[np.integer[Any]],
                      ) -> NDArray[np.float64]:
    """(T + B, D) the points (T, D) of a path with a row of NaN inserted before each of the
    B samples where formation (T,) (the plan formation followed, ``RunResult.formation[i]``)
    changes: there a new virtual leader may take over (``newVL``) and the leader and the
    desired path jump, so a line drawn through the points breaks instead of joining the
    jump."""
    changes = np.flatnonzero(np.diff(formation)) + 1
    broken: NDArray[np.float64] = np.insert(np.asarray(points, dtype=float), changes, np.nan,
                                            axis=0)
    return broken


def plot_speeds_and_distances(result: RunResult) -> Any:
    """Commanded linear and angular speeds and the distance to the leader (solid) against
    the desired one (dashed) over show time, one colour per robot (thesis fig. 7.5). Shaded:
    a robot held by a stop flag (light) or in the error state (dark)."""
    import matplotlib.pyplot as plt

    fig, (linear, angular, distance) = plt.subplots(3, 1, figsize=(10, 9), sharex=True,
                                                    layout="constrained")
    colours = robot_colours(len(result.robots))
    for i, robot in enumerate(result.robots):
        linear.plot(result.times, result.commands[i, :, 0], color=colours[i], label=robot)
        angular.plot(result.times, result.commands[i, :, 1], color=colours[i])
        distance.plot(result.times, result.leader_distance[i], color=colours[i])
        distance.plot(result.times, result.required_distance[i], "--", color=colours[i],
                      linewidth=0.8)
    for event in result.collisions:
        for axis in (linear, angular, distance):
            axis.axvline(event.time, color="red", linewidth=0.8, alpha=0.6)
    from dancebots.shows.formation import STATUS

    for i in range(len(result.robots)):  # shade the times a robot is held or in error
        for code, shade in ((STATUS.index("stopped"), 0.12), (STATUS.index("error"), 0.3)):
            held = np.concatenate([[False], result.status[i] == code, [False]])
            edges = np.flatnonzero(np.diff(held.astype(np.int8)))
            for a, b in zip(edges[::2], edges[1::2], strict=True):
                linear.axvspan(result.times[a], result.times[b - 1], color=colours[i],
                               alpha=shade, linewidth=0)
    linear.set_ylabel("linear [m/s]")
    angular.set_ylabel("angular [rad/s]")
    distance.set_ylabel("distance to leader [m]\n(dashed: desired)")
    distance.set_xlabel("show time [s]")
    for axis in (linear, angular, distance):
        axis.grid(True, linewidth=0.3)
        axis.axvline(result.plan.duration, color="0.5", linewidth=0.8, linestyle=":")
    linear.legend(loc="upper right", fontsize="small", ncol=min(6, len(result.robots)))
    linear.set_title(f"{result.plan.scenario.path}: commanded speeds and distance to the "
                     f"virtual leader ({result.config.profile.name})")
    return fig


def plot_trajectories(result: RunResult) -> Any:
    """Robot paths (solid), where their followers should have them (dashed: the rigid slots
    for ``tracking``, the places on the leaders' paths otherwise), the virtual leaders (black), the
    room and obstacles, footprints at start and end, spectators' walks (dotted), stops
    (orange rings) and collisions (red crosses) (fig. 7.6)."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon as PolygonPatch

    from dancebots.geometry import footprint_corners

    fig, ax = plt.subplots(figsize=(9, 9), layout="constrained")
    arena = result.arena
    draw_arena(ax, arena.room, arena.obstacles)
    colours = robot_colours(len(result.robots))
    for i, robot in enumerate(result.robots):  # leader and desired paths break at newVL jumps
        leader = broken_at_changes(result.leader[i, :, :2], result.formation[i])
        ax.plot(leader[:, 0], leader[:, 1], color="black", linewidth=0.8,
                label="virtual leader" if i == 0 else None)
        # dashed: where its follower should have it (``RunResult.reference``: the rigid slot
        # for tracking, the place on the leader's path for path and thesis)
        desired = broken_at_changes(result.reference[i, :, :2], result.formation[i])
        ax.plot(desired[:, 0], desired[:, 1], "--", color=colours[i], linewidth=0.8)
        ax.plot(result.poses[i, :, 0], result.poses[i, :, 1], color=colours[i], linewidth=1.6,
                label=robot)
        kind = result.placement.types[i]
        for k, style in ((0, "-"), (-1, ":")):
            pose = result.poses[i, k]
            corners = footprint_corners(np.array(pose[0]), np.array(pose[1]), np.array(pose[2]),
                                        kind.length, kind.width)
            ax.add_patch(PolygonPatch(corners, closed=True, fill=False, edgecolor=colours[i],
                                      linestyle=style))
    for k in range(len(result.spectators)):
        ax.plot(result.spectators[k, :, 0], result.spectators[k, :, 1], ":", color="purple",
                linewidth=1.0, label="spectators" if k == 0 else None)
    stops = [(e.robot, e.time) for e in result.events if e.kind == "speech"]
    if stops:
        index = {name: i for i, name in enumerate(result.robots)}
        at = np.array([result.poses[index[r], int(np.searchsorted(result.times, t)), :2]
                       for r, t in stops])
        ax.plot(at[:, 0], at[:, 1], "o", markerfacecolor="none", markeredgecolor="orange",
                markersize=9, label="stop")
    if result.collisions:
        ax.plot([c.x for c in result.collisions], [c.y for c in result.collisions], "x",
                color="red", markersize=10, markeredgewidth=2, label="collision")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(f"{result.plan.scenario.path}: trajectories ({result.config.profile.name}, "
                 f"{result.config.brain.follower} follower; dashed: its places)")
    return fig
