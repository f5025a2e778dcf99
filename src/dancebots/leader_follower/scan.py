"""Planar scans and the objects detectors report, in the robot's odometry frame.

Frames: a scan's ranges are measured along rays at ``angles`` from the robot's heading
(``base_link``); detectors report positions and velocities in the odometry frame (``odom``),
so that a person standing still keeps its position while the robot moves (the second seed's
tracker worked in the robot frame, where standing people appear to move).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import Pose, points_to_world

__all__ = ["Detection", "Scan", "TrackedObject", "to_odom", "to_robot"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True, eq=False)
class Scan:
    """One planar LIDAR scan: ``ranges`` (N,) m (inf: no reading) along ``angles`` (N,) rad
    from the heading, taken at ``stamp`` s when the robot stood at ``pose`` (x, y, theta) in
    its odometry frame."""

    stamp: float
    ranges: FloatArray
    angles: FloatArray
    pose: tuple[float, float, float]

    def points(self, field_of_view: float = 2.0 * math.pi) -> tuple[FloatArray, FloatArray]:
        """The valid readings within +-field_of_view/2 of the heading: (M, 2) points in
        ``base_link`` and their angles (M,)."""
        keep = np.isfinite(self.ranges) & (np.abs(self.angles) <= 0.5 * field_of_view + 1e-9)
        ranges, angles = self.ranges[keep], self.angles[keep]
        return np.column_stack([ranges * np.cos(angles), ranges * np.sin(angles)]), angles


@dataclass(frozen=True, slots=True)
class TrackedObject:
    """An object in the odometry frame: position (x, y) m, velocity (vx, vy) m/s, radius m;
    ``track`` its track number (-1 for detectors without tracks)."""

    position: tuple[float, float]
    velocity: tuple[float, float] = (0.0, 0.0)
    radius: float = 0.1
    track: int = -1


@dataclass(frozen=True, slots=True)
class Detection:
    """What a detector reports for one scan: the object to follow (None: lost) and every
    object it saw (for collision avoidance), all in the odometry frame."""

    target: TrackedObject | None
    objects: tuple[TrackedObject, ...] = ()


def to_odom(points: FloatArray, pose: tuple[float, float, float]) -> FloatArray:
    """Points (M, 2) in ``base_link`` at ``pose`` -> (M, 2) in the odometry frame."""
    return points_to_world(points, pose)


def to_robot(point: tuple[float, float], pose: tuple[float, float, float]) -> tuple[float, float]:
    """A point (x, y) of the odometry frame in ``base_link`` at ``pose``."""
    return Pose(*pose).to_local(*point)
