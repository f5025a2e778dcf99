"""Draw a :class:`Plan`: the scenario path, every virtual leader, every robot's desired path,
and under it the show's timeline (each instruction when its leader runs it, beats, cues)."""

from __future__ import annotations

from typing import Any

import numpy as np

from dancebots.geometry import Pose, footprint_corners, points_to_world
from dancebots.plan.planner import Plan, instruction_timeline
from dancebots.report.drawing import draw_arena
from dancebots.world import DEFAULT_ROBOT_TYPE, World

__all__ = ["MAX_BEAT_LINES", "plot_plan", "plot_timeline"]

MAX_BEAT_LINES = 400
"""Most beat lines the timeline draws (a 1 h show at 600 beats per minute has 36,000 beats:
it gets a line every 256)."""


def plot_plan(plan: Plan, world: World | None = None, transform: Pose | None = None,
              ax: Any = None, period: float = 0.1) -> Any:
    """Plot the plan (in the world frame when ``transform`` is given); returns the figure.

    Scenario waypoints: dashed grey; virtual leaders: black; robots: one colour each, with
    their footprints at the start (solid) and at the end (dashed). Without ``ax`` the figure
    also has the show's timeline under the map (:func:`plot_timeline`).
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon as PolygonPatch

    if ax is None:
        fig, (ax, strip) = plt.subplots(2, 1, figsize=(8, 10), layout="constrained",
                                        height_ratios=(8, 2))
        plot_timeline(plan, strip)
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


def plot_timeline(plan: Plan, ax: Any) -> None:
    """The show's time axis on ``ax``: each instruction as a bar from its start to its end
    (``plan.planner.instruction_timeline``), a lane per formation, labelled with its line;
    with a tempo, a tick every beat and a line every fourth; each cue as a triangle at its
    time (green when met, red when missed), on the instruction's lane."""
    timeline = instruction_timeline(plan)
    tempo = plan.scenario.tempo
    end = max([plan.duration, *(entry.end for entry in timeline)], default=plan.duration)
    lanes = sorted({entry.formation for entry in timeline})
    lane = {formation: k for k, formation in enumerate(lanes)}
    colours = {"move": "tab:blue", "circle": "tab:orange", "wait": "0.7",
               "formation": "tab:purple"}
    for entry in timeline:
        y = lane[entry.formation]
        width = max(entry.end - entry.start, end * 0.002)
        ax.barh(y, width, left=entry.start, height=0.6, color=colours.get(entry.kind, "0.5"),
                edgecolor="white", linewidth=0.5)
        if entry.end - entry.start > end * 0.03:
            ax.text(entry.start + 0.5 * (entry.end - entry.start), y, str(entry.line),
                    ha="center", va="center", fontsize=6, color="white")
        if entry.cue_time is not None:
            ax.plot([entry.cue_time], [y + 0.45], marker="v", markersize=6, linestyle="none",
                    color="tab:red" if entry.cue_missed_by else "tab:green")
    if tempo is not None:
        period = 60.0 / tempo.bpm
        first = max(0, int(np.ceil((0.0 - tempo.first_beat) / period)))
        count = int((end - tempo.first_beat) / period) + 1
        # a line per beat, a darker one every 4; fewer on a long show (at most MAX_BEAT_LINES)
        every = 1
        while (count - first) / every > MAX_BEAT_LINES:
            every *= 4
        beats = np.arange(first, count)
        beats = beats[beats % every == 0]
        times = tempo.first_beat + beats * period
        bars = beats % (4 * every) == 0
        ax.vlines(times[~bars], 0, 1, transform=ax.get_xaxis_transform(), color="0.85",
                  linewidth=0.3, zorder=0)
        ax.vlines(times[bars], 0, 1, transform=ax.get_xaxis_transform(), color="0.4",
                  linewidth=0.6, zorder=0)
        lines = "a line per beat" if every == 1 else f"a line every {every} beats"
        ax.set_title(f"timeline: {tempo.bpm:g} beats per minute ({lines}, darker every "
                     f"{4 * every}), cues met (green) and missed (red)", fontsize="small")
    else:
        ax.set_title("timeline", fontsize="small")
    ax.set_xlim(0.0, end * 1.01 if end > 0 else 1.0)
    ax.set_ylim(-0.6, len(lanes) - 0.4 + 0.3)
    ax.set_yticks(range(len(lanes)), [f"formation {f}" for f in lanes], fontsize=6)
    ax.set_xlabel("show time [s]")
