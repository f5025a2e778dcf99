"""Draw a :class:`Plan`: the scenario path, every virtual leader, every robot's desired path."""

from __future__ import annotations

from typing import Any

import numpy as np

from dancebots.geometry import Pose, footprint_corners, points_to_world
from dancebots.plan.planner import Plan
from dancebots.report.drawing import draw_arena
from dancebots.world import DEFAULT_ROBOT_TYPE, World

__all__ = ["plot_plan"]


def plot_plan(plan: Plan, world: World | None = None, transform: Pose | None = None,
              ax: Any = None, period: float = 0.1) -> Any:
    """Plot the plan (in the world frame when ``transform`` is given); returns the figure.

    Scenario waypoints: dashed grey; virtual leaders: black; robots: one colour each, with
    their footprints at the start (solid) and at the end (dashed).
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon as PolygonPatch

    if ax is None:
        fig, ax = plt.subplots(figsize=(8, 8), layout="constrained")
    else:
        fig = ax.figure
    place = transform or Pose(0.0, 0.0, 0.0)

    def to_world(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        points = points_to_world(xy[:, :2], place)
        return points[:, 0], points[:, 1]

    if world is not None:
        draw_arena(ax, world.room, world.obstacles, label="room")
    times = np.arange(0.0, plan.duration + period, period)
    for k, formation in enumerate(plan.formations):
        if len(formation.waypoints) > 1:
            ax.plot(*to_world(formation.waypoints[:, :2]), "--", color="0.6", linewidth=1.0,
                    label="scenario path" if k == 0 else None)
        leader_times = times[(times >= formation.start) & (times <= formation.end)]
        if len(leader_times) > 1:
            leader = formation.leader.poses_at(leader_times)
            ax.plot(*to_world(leader[:, :2]), color="black", linewidth=1.2,
                    label="virtual leader" if k == 0 else None)
    colours = plt.get_cmap("tab10" if len(plan.robots) <= 10 else "tab20")
    types = {r.name: r.type for r in world.robots} if world is not None else {}
    for i, robot in enumerate(plan.robots):
        colour = colours(i % colours.N)
        poses = plan.desired_poses(robot, times)
        xs, ys = to_world(poses[:, :2])
        ax.plot(xs, ys, color=colour, linewidth=1.5, label=robot)
        kind = types.get(robot, DEFAULT_ROBOT_TYPE)
        for index, style in ((0, "-"), (-1, "--")):
            corners = footprint_corners(xs[index:][:1], ys[index:][:1],
                                        poses[index:, 2][:1] + place.theta, kind.length,
                                        kind.width)[0]
            ax.add_patch(PolygonPatch(corners, closed=True, fill=False, edgecolor=colour,
                                      linestyle=style))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{plan.scenario.path}: {plan.duration:.1f} s")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig
