"""The metrics of a queue show (``shows.queue``), pure.

Distances: a follower's *gap* is the free distance from its centre to the surface of the
object in front (the leader's disc, or the rear of the robot ahead, taken as half its
length), so that the stand-off the controllers keep (to the centroid of what they see)
compares with it directly; the distance error is gap - stand-off.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.shows.queue import QueueResult

__all__ = ["INTACT_GAP", "FollowerMetrics", "QueueMetrics", "queue_metrics", "surface_gaps"]

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
    """A queue run: its detector and controller, stand-off, m; duration, s; the followers,
    front to back."""

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
