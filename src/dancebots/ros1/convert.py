"""Conversions between ROS messages and the core's arrays (needs the ROS message packages).

Clouds travel as sensor_msgs/PointCloud2 with float32 x, y, z fields in ``base_link``;
commands as geometry_msgs/Twist (linear.x, angular.z: thesis ch. 2); planar poses as
geometry_msgs/TransformStamped for TF.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from geometry_msgs.msg import TransformStamped
from numpy.typing import NDArray
from sensor_msgs.msg import PointCloud2, PointField

from dancebots.perception.cloud import PointCloud
from dancebots.perception.obstacles import DetectorParams

__all__ = ["MalformedCloudError", "cloud_message", "cloud_points", "obstacle_cloud",
           "transform_message"]

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


class MalformedCloudError(ValueError):
    """A PointCloud2 whose layout cannot be read (no float32 x, y, z fields, sizes that do not
    fit its data, ...). A node treats it as a scan that did not arrive."""


def cloud_points(message: Any) -> FloatArray:
    """The (M, 3) float64 x, y, z of a PointCloud2 whose x, y, z fields are float32 (any
    other fields and padding are skipped; points with a NaN or infinite coordinate are
    dropped). Raises :class:`MalformedCloudError`, and nothing else, when the fields, sizes and
    data do not describe such a cloud."""
    try:
        fields = list(message.fields)
        offsets = {f.name: f.offset for f in fields if f.datatype == PointField.FLOAT32}
        width, height = int(message.width), int(message.height)
        point_step, row_step = int(message.point_step), int(message.row_step)
        data = bytes(message.data)
        big_endian = bool(message.is_bigendian)
    except (AttributeError, TypeError, ValueError, OverflowError) as exc:
        raise MalformedCloudError(f"the cloud is not a PointCloud2 ({exc})") from None
    if not {"x", "y", "z"} <= offsets.keys():
        raise MalformedCloudError("the cloud has no float32 x, y and z fields")
    xyz = [offsets["x"], offsets["y"], offsets["z"]]
    if width < 0 or height < 0 or min(xyz) < 0 or point_step < max(xyz) + 4:
        raise MalformedCloudError(f"the cloud's fields at bytes {xyz} do not fit its points of "
                             f"{point_step} bytes ({width} x {height} points)")
    if width == 0 or height == 0:
        return np.zeros((0, 3))
    if height > 1 and row_step < width * point_step:
        raise MalformedCloudError(f"rows of {row_step} bytes cannot hold {width} points of "
                             f"{point_step} bytes")
    stride = row_step if height > 1 else width * point_step
    needed = stride * (height - 1) + width * point_step
    if len(data) < needed:
        raise MalformedCloudError(f"{width} x {height} points of {point_step} bytes need {needed} "
                             f"bytes of data, the cloud has {len(data)}")
    layout = np.dtype({"names": ["x", "y", "z"], "formats": [">f4" if big_endian else "<f4"] * 3,
                       "offsets": xyz, "itemsize": point_step})
    raw = np.ndarray((height, width), dtype=layout, buffer=data, strides=(stride, point_step))
    points = np.stack([raw["x"].ravel(), raw["y"].ravel(), raw["z"].ravel()],
                      axis=1).astype(np.float64)
    result: FloatArray = points[np.isfinite(points).all(axis=1)]
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


def transform_message(stamp: Any, parent: str, child: str,
                      pose: tuple[float, float, float] | list[float]) -> Any:
    """A TransformStamped at ``stamp`` (rospy.Time): the planar ``pose`` (x, y m, theta rad)
    of frame ``child`` in frame ``parent``."""
    transform = TransformStamped()
    transform.header.stamp = stamp
    transform.header.frame_id = parent
    transform.child_frame_id = child
    transform.transform.translation.x, transform.transform.translation.y = pose[0], pose[1]
    transform.transform.rotation.z = math.sin(0.5 * pose[2])
    transform.transform.rotation.w = math.cos(0.5 * pose[2])
    return transform
