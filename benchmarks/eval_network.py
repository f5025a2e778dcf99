"""The experiment both seeds imply: formation error against network trouble.

The thesis argues that a virtual leader computed on every robot needs no communication while
moving (only the start agreement, and here the formation's shared show clock), so it is
robust to network trouble, where a leader-follower formation that shares poses is not; the
paper's LIDAR-only queue needs no network at all. Three robots in a column 1.8 m apart drive
3 m, stop 2 s, a quarter circle of 4 m radius, 2 m, stop 2 s, a right-angle corner and 2 m
(stops and a corner: where a pose that is late or lost misleads), ideal profile, LIDAR on,
the ``tracking`` follower (rigid slots, so that both formations are measured against the
same geometry):

* ``virtual leader``: every robot follows its slot of the plan's virtual leader; the
  messages of the shared show clock go over the lossy transport; a clock offset shifts a
  robot's show time;
* ``shared pose`` (``SimConfig.formation_control``): robot 1 follows its slot, robots 2
  and 3 their slots relative to robot 1's pose as broadcast at 10 Hz over the same
  transport, extrapolated by the velocity sent over the message's age on their clocks;
* ``LIDAR queue``: the paper's queue (A2 with tracking, VO) on its static course: no
  network, so its figures do not move along the axes (its formation error: the followers'
  median distance error to the object ahead).

One axis at a time: message delay 0-0.9 s (the shared clock's heartbeat times out at 1 s),
loss 0-30 %, clock offset 0-200 ms between the first and the last robot. Delay and loss are
injected in-process (the kernel here has no netem). Prints a table; ``--figure F.png``
draws the curves. ``benchmarks/reproduce.py`` puts both into docs/results.md.

Run: ``.venv/bin/python benchmarks/eval_network.py [--figure F.png]``.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from dancebots.cli.common import bundled
from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.plan.planner import PlanParameters
from dancebots.report.metrics import run_metrics
from dancebots.report.queue_metrics import queue_metrics
from dancebots.robot import BrainOptions
from dancebots.shows.formation import SimConfig, simulate
from dancebots.shows.queue import QueueConfig, simulate_queue
from dancebots.sim import prepare_show
from dancebots.world import load_world

COURSE = ("robots R1 R2 R3\ncolumn R1;R2;R3 1.8 0\nmove 3 0\nwait 2\ncircle 4 90 0.08\n"
          "move 2 0\nwait 2\nmove 3 -90\nmove 2 0\n")
AXES = {"delay s": (0.0, 0.25, 0.5, 0.75, 0.9), "loss": (0.0, 0.1, 0.2, 0.3),
        "clock offset s": (0.0, 0.05, 0.1, 0.2)}
STRATEGIES = ("virtual leader", "shared pose")


@dataclass(frozen=True)
class Point:
    """One run: RMS and largest formation error (m), contacts, show length (s)."""

    rms: float
    largest: float
    contacts: int
    length: float


def formation_run(strategy: str, delay: float, loss: float, offset: float) -> Point:
    _, plan, diagnostics = compile_scenario(COURSE, "network.dance",
                                            PlanParameters(timing="feasible"))
    assert plan is not None, diagnostics
    arena, placement = prepare_show(place_show(plan, None))
    config = SimConfig(brain=BrainOptions(follower="tracking"), hold_delay=delay,
                       hold_loss=loss, clock_offsets=(offset / 2, 0.0, -offset / 2),
                       formation_control="shared-pose" if strategy == "shared pose"
                       else "virtual-leader")
    result = simulate(plan, arena, placement, config)
    metrics = run_metrics(result)
    return Point(metrics.rms_formation_error or 0.0, metrics.max_formation_error or 0.0,
                 metrics.collisions, float(result.times[-1]))


def queue_point() -> tuple[float, int]:
    """The LIDAR queue on the paper's static course: the followers' median distance error
    (m, the largest of the three) and its kidnappings (none without a crossing person)."""
    metrics = queue_metrics(simulate_queue(load_world(bundled("follow_course.toml")),
                                           QueueConfig(detector="a2-track", controller="vo")))
    return (max(f.median_error for f in metrics.followers),
            sum(f.kidnappings for f in metrics.followers))


def sweep() -> tuple[dict[tuple[str, str, float], Point], tuple[float, int]]:
    """Every strategy along every axis (the others at 0), and the queue's figures."""
    points = {}
    for axis, values in AXES.items():
        for value in values:
            delay = value if axis == "delay s" else 0.0
            loss = value if axis == "loss" else 0.0
            offset = value if axis == "clock offset s" else 0.0
            for strategy in STRATEGIES:
                points[strategy, axis, value] = formation_run(strategy, delay, loss, offset)
    return points, queue_point()


def table_rows(points: dict[tuple[str, str, float], Point],
               queue: tuple[float, int]) -> list[tuple[str, ...]]:
    rows = []
    for axis, values in AXES.items():
        for value in values:
            row = [axis, f"{value:g}"]
            for strategy in STRATEGIES:
                point = points[strategy, axis, value]
                row += [f"{100 * point.rms:.1f} / {100 * point.largest:.1f}",
                        str(point.contacts), f"{point.length:.0f}"]
            row += [f"{100 * queue[0]:.1f}", str(queue[1])]
            rows.append(tuple(row))
    return rows


HEADER = ("axis", "value", "virtual leader: error rms / max cm", "contacts", "show s",
          "shared pose: error rms / max cm", "contacts", "show s",
          "LIDAR queue: median error cm", "kidnappings")


def figure(points: dict[tuple[str, str, float], Point], queue: tuple[float, int]) -> Any:
    """The RMS formation error along each axis, one panel per axis."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(AXES), figsize=(11, 3.4), layout="constrained",
                             sharey=True)
    for ax, (axis, values) in zip(axes, AXES.items(), strict=True):
        for strategy, colour in zip(STRATEGIES, ("tab:blue", "tab:orange"), strict=True):
            ax.plot(values, [100 * points[strategy, axis, v].rms for v in values], "o-",
                    color=colour, label=strategy)
        ax.plot(values, [100 * queue[0]] * len(values), "--", color="tab:green",
                label="LIDAR queue (median)")
        ax.set_xlabel(axis)
        ax.grid(True, linewidth=0.3)
    axes[0].set_ylabel("formation error, cm")
    axes[0].legend(fontsize="small")
    return fig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--figure", type=Path, help="also draw the curves to this PNG")
    args = parser.parse_args()
    points, queue = sweep()
    print(" | ".join(HEADER))
    for row in table_rows(points, queue):
        print(" | ".join(row))
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        figure(points, queue).savefig(args.figure, dpi=80)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
