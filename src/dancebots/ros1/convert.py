"""Conversions between ROS messages and the core's arrays (needs the ROS message packages).

Clouds travel as sensor_msgs/PointCloud2 with float32 x, y, z fields in ``base_link``;
commands as geometry_msgs/Twist (linear.x, angular.z: thesis ch. 2).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from sensor_msgs.msg import PointCloud2, PointField

from dancebots.perception.cloud import PointCloud
from dancebots.perception.obstacles import DetectorParams

__all__ = ["cloud_message", "cloud_points", "obstacle_cloud"]

FloatArray = NDArray[np.float64]
_XYZ = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4")])


def cloud_message(points: FloatArray, header: Any) -> Any:
    """A PointCloud2 of ``points`` (M, 3) m with ``header`` (stamp and frame)."""
    data = np.empty(len(points), dtype=_XYZ)
    data["x"], data["y"], data["z"] = points[:, 0], points[:, 1], points[:, 2]
    return PointCloud2(
        header=header, height=1, width=len(points),
        fields=[PointField(name, 4 * k, PointField.FLOAT32, 1)
                for k, name in enumerate("xyz")],
        is_bigendian=False, point_step=12, row_step=12 * len(points), data=data.tobytes(),
        is_dense=True)


def cloud_points(message: Any) -> FloatArray:
    """The (M, 3) float64 x, y, z of a PointCloud2 whose x, y, z fields are float32 (any
    other fields and padding are skipped; points with a NaN coordinate are dropped)."""
    offsets = {f.name: f.offset for f in message.fields if f.datatype == PointField.FLOAT32}
    if not {"x", "y", "z"} <= offsets.keys():
        raise ValueError("the cloud has no float32 x, y and z fields")
    count = message.width * message.height
    layout = np.dtype({"names": ["x", "y", "z"], "formats": ["<f4" if not message.is_bigendian
                                                              else ">f4"] * 3,
                       "offsets": [offsets["x"], offsets["y"], offsets["z"]],
                       "itemsize": message.point_step})
    raw = np.frombuffer(bytes(message.data), dtype=layout, count=count)
    points = np.stack([raw["x"], raw["y"], raw["z"]], axis=1).astype(np.float64)
    result: FloatArray = points[~np.isnan(points).any(axis=1)]
    return result


def obstacle_cloud(stamp: float, points: FloatArray,
                   detection: DetectorParams | None = None) -> PointCloud:
    """The ``/obstacles`` output of obstacle_detection (points (M, 2 or 3) already cropped,
    height-filtered and flattened, thesis 5.2) as the cloud a RobotBrain reads: one column
    per point at the middle of the kept height band, so the brain's own filter keeps them
    all. ``stamp`` in the brain's show time, s."""
    detection = detection or DetectorParams()
    middle = 0.5 * (detection.z_min + detection.z_max)
    columns = np.column_stack([points[:, 0], points[:, 1], np.full(len(points), middle),
                               np.full(len(points), middle)]) if len(points) else np.zeros(
        (0, 4))
    return PointCloud(stamp, columns)
