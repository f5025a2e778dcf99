"""The log of a queue show (``shows.queue``): every sample as CSV."""

from __future__ import annotations

import csv
import math
from typing import TextIO

from dancebots.report.queue_metrics import surface_gaps
from dancebots.shows.queue import QueueResult

__all__ = ["LOG_COLUMNS", "write_queue_log"]

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
