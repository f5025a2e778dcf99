"""The run log: every sample of a run as a CSV table in long format (docs/run-outputs.md).

One row per robot per control tick; ``pandas.read_csv("log.csv")`` reads it.
"""

from __future__ import annotations

import csv
from typing import TextIO

from dancebots.shows.formation import RunResult

__all__ = ["LOG_COLUMNS", "write_log"]

LOG_COLUMNS = (
    "t", "robot", "x", "y", "theta", "v", "w", "v_cmd", "w_cmd", "x_des", "y_des", "theta_des",
    "x_vl", "y_vl", "theta_vl", "d_vl", "d_req", "formation",
)
"""Column names; units s, m, rad, m/s, rad/s; poses in the world frame (docs/run-outputs.md).
In the physics profiles one more: ``w_wheels``, the yaw rate the wheels would give without
slip, rad/s."""


def write_log(result: RunResult, handle: TextIO) -> None:
    """Write the run's samples as CSV to an open text file."""
    writer = csv.writer(handle, lineterminator="\n")
    wheels = result.wheel_rates
    writer.writerow(LOG_COLUMNS if wheels is None else (*LOG_COLUMNS, "w_wheels"))
    distance = result.leader_distance
    for k, t in enumerate(result.times.tolist()):
        for i, robot in enumerate(result.robots):
            pose, velocity = result.poses[i, k], result.velocities[i, k]
            command, desired, leader = (result.commands[i, k], result.desired[i, k],
                                        result.leader[i, k])
            row = [
                f"{t:.2f}", robot, *(f"{v:.4f}" for v in pose), *(f"{v:.4f}" for v in velocity),
                *(f"{v:.4f}" for v in command), *(f"{v:.4f}" for v in desired),
                *(f"{v:.4f}" for v in leader), f"{distance[i, k]:.4f}",
                f"{result.required_distance[i, k]:.4f}", int(result.formation[i, k]),
            ]
            if wheels is not None:
                row.append(f"{wheels[i, k]:.4f}")
            writer.writerow(row)
