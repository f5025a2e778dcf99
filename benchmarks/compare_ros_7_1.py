"""Scenario 7.1 through ROS against the pure simulation (the figures of docs/ros.md).

Run: ``.venv/bin/python benchmarks/compare_ros_7_1.py`` (needs Debian's ROS 1 packages;
starts its own master through roslaunch unless ROS_MASTER_URI names a running one; takes
about a minute, the show runs in real time). Prints the largest change of the distance
between the two robots (row spacing 1.2 m) in both runs, and how far apart their final
positions are.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.plan.planner import PlanParameters
from dancebots.report.metrics import spacing_change
from dancebots.robot import BrainOptions
from dancebots.shows.formation import SimConfig, simulate
from dancebots.sim import prepare_show

SCENARIO = Path(__file__).parents[1] / "examples" / "thesis_7_1.dance"
SPACING = 1.2


def main() -> None:
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    # the ROS nodes' defaults: the path follower on the feasible timing
    _, plan, diagnostics = compile_scenario(SCENARIO.read_text(), str(SCENARIO),
                                            PlanParameters(timing="feasible"))
    assert plan is not None, diagnostics
    pure = simulate(plan, *prepare_show(place_show(plan, None, places="path")),
                    SimConfig(brain=BrainOptions(follower="path")))
    with tempfile.TemporaryDirectory() as folder:
        record = Path(folder) / "record.npz"
        subprocess.run([str(Path(sys.executable).parent / "dancebots"), "ros", "simulate",
                        str(SCENARIO), "--record", str(record)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        ros = np.load(record)
        poses, contacts = ros["poses"], len(ros["contacts"])
    print(f"row-distance change: ROS {spacing_change(poses[0], poses[1], SPACING):.3f} m, "
          f"pure simulation {spacing_change(pure.poses[0], pure.poses[1], SPACING):.3f} m")
    gaps = np.hypot(*(poses[:, -1, :2] - pure.poses[:, -1, :2]).T)
    print("final positions apart: " + ", ".join(
        f"{robot} {gap * 100:.1f} cm" for robot, gap in zip(plan.robots, gaps, strict=True))
          + f"; contacts through ROS: {contacts}")


if __name__ == "__main__":
    main()
