"""Perception: LIDAR clouds -> obstacle points and stop flags (thesis ch. 5.2)."""

from dancebots.perception.cloud import PointCloud
from dancebots.perception.obstacles import (
    DetectorParams,
    StopFlags,
    compensate_motion,
    obstacle_points,
    obstacle_points_from_columns,
    stop_flags,
)

__all__ = [
    "DetectorParams",
    "PointCloud",
    "StopFlags",
    "compensate_motion",
    "obstacle_points",
    "obstacle_points_from_columns",
    "stop_flags",
]
