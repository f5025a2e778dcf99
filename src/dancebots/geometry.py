"""Poses, transforms and angle helpers (REP 103: x forward, y left, angles CCW).

All functions are pure. Scalar helpers take and return floats; the vectorised helpers take
NumPy arrays whose shapes are given in their docstrings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Pose",
    "compose_points",
    "compose_poses",
    "footprint_corners",
    "frame_turns",
    "integrate_unicycle",
    "points_in_frames",
    "points_to_local",
    "points_to_world",
    "wrap_angle",
    "wrap_angles",
]

FloatArray = NDArray[np.float64]


def wrap_angle(angle: float) -> float:
    """Wrap an angle in rad to (-pi, pi]: the package's one convention (:func:`wrap_angles`
    is the same, vectorised)."""
    wrapped = math.remainder(angle, math.tau)
    return math.pi if wrapped == -math.pi else wrapped


def wrap_angles(angles: FloatArray) -> FloatArray:
    """Vectorised :func:`wrap_angle`; any shape, rad -> (-pi, pi]."""
    wrapped = np.remainder(angles + np.pi, 2.0 * np.pi) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


@dataclass(frozen=True, slots=True)
class Pose:
    """A planar pose: position (x, y) in m and heading theta in rad, in a named frame."""

    x: float
    y: float
    theta: float

    def compose(self, other: Pose) -> Pose:
        """This pose followed by ``other`` expressed in this pose's frame (``self ⊕ other``)."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            wrap_angle(self.theta + other.theta),
        )

    def inverse(self) -> Pose:
        """The pose ``p`` with ``self.compose(p)`` the identity."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose(-c * self.x - s * self.y, s * self.x - c * self.y, wrap_angle(-self.theta))

    def to_local(self, x: float, y: float) -> tuple[float, float]:
        """Express the world point (x, y) in this pose's frame."""
        dx, dy = x - self.x, y - self.y
        c, s = math.cos(self.theta), math.sin(self.theta)
        return c * dx + s * dy, -s * dx + c * dy

    def to_world(self, x: float, y: float) -> tuple[float, float]:
        """Express the point (x, y) of this pose's frame in the parent frame."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return self.x + c * x - s * y, self.y + s * x + c * y


def frame_turns(frames: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The cosines and sines (...,) of frames' (..., 3) headings: what :func:`compose_poses`
    and :func:`compose_points` compute first, for a caller that composes with the same frames
    every tick."""
    return np.cos(frames[..., 2]), np.sin(frames[..., 2])


def compose_poses(frames: FloatArray, poses: FloatArray,
                  turns: tuple[FloatArray, FloatArray] | None = None) -> FloatArray:
    """``frames ⊕ poses`` vectorised (:meth:`Pose.compose`): poses (..., 3) given in frames
    (..., 3) (x, y, theta; the shapes broadcast), expressed in the frames' parent; theta
    wrapped to (-pi, pi]. ``turns``: the frames' :func:`frame_turns`, if known."""
    c, s = frame_turns(frames) if turns is None else turns
    shape = (np.shape(frames) if np.shape(frames) == np.shape(poses)  # (the usual case)
             else np.broadcast_shapes(np.shape(frames), np.shape(poses)))
    result = np.empty(shape)
    result[..., 0] = frames[..., 0] + c * poses[..., 0] - s * poses[..., 1]
    result[..., 1] = frames[..., 1] + s * poses[..., 0] + c * poses[..., 1]
    result[..., 2] = wrap_angles(frames[..., 2] + poses[..., 2])
    return result


def compose_points(frames: FloatArray, points: FloatArray,
                   turns: tuple[FloatArray, FloatArray] | None = None) -> FloatArray:
    """``frames ⊕ points`` vectorised: points (..., 2) (x, y), each given in its frame
    (..., 3) (x, y, theta; the shapes broadcast over ...), expressed in the frames' parent.
    Returns (..., 2). The positions of :func:`compose_poses`, without a heading; ``turns``
    the frames' :func:`frame_turns`, if known."""
    c, s = frame_turns(frames) if turns is None else turns
    shape = (np.shape(frames)[:-1] if np.shape(frames)[:-1] == np.shape(points)[:-1]
             else np.broadcast_shapes(np.shape(frames)[:-1], np.shape(points)[:-1]))
    result = np.empty((*shape, 2))
    result[..., 0] = frames[..., 0] + c * points[..., 0] - s * points[..., 1]
    result[..., 1] = frames[..., 1] + s * points[..., 0] + c * points[..., 1]
    return result


def points_to_world(points: FloatArray, pose: tuple[float, float, float] | Pose) -> FloatArray:
    """Points (M, 2) given in the frame of ``pose`` (x, y, theta), expressed in its parent
    frame (:meth:`Pose.to_world`, vectorised). Returns (M, 2)."""
    x, y, theta = (pose.x, pose.y, pose.theta) if isinstance(pose, Pose) else pose
    c, s = math.cos(theta), math.sin(theta)
    result: FloatArray = np.column_stack([x + c * points[:, 0] - s * points[:, 1],
                                          y + s * points[:, 0] + c * points[:, 1]])
    return result


def points_to_local(points: FloatArray, pose: tuple[float, float, float] | Pose) -> FloatArray:
    """Points (M, 2) given in the parent frame of ``pose`` (x, y, theta), expressed in the
    frame of ``pose`` (:meth:`Pose.to_local`, vectorised; the inverse of
    :func:`points_to_world`). Returns (M, 2)."""
    x, y, theta = (pose.x, pose.y, pose.theta) if isinstance(pose, Pose) else pose
    c, s = math.cos(theta), math.sin(theta)
    dx, dy = points[:, 0] - x, points[:, 1] - y
    result: FloatArray = np.column_stack([c * dx + s * dy, -s * dx + c * dy])
    return result


def points_in_frames(points: FloatArray, frames: FloatArray) -> FloatArray:
    """Points (..., 2) given in the frames' parent, each expressed in its frame (..., 3)
    (x, y, theta); the shapes broadcast, e.g. points (1, C, 2) and frames (R, 1, 3) give every
    point in every frame, (R, C, 2) (:meth:`Pose.to_local`, vectorised over frames)."""
    c, s = np.cos(frames[..., 2]), np.sin(frames[..., 2])
    dx, dy = points[..., 0] - frames[..., 0], points[..., 1] - frames[..., 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


def integrate_unicycle(
    x: FloatArray, y: FloatArray, theta: FloatArray, v: FloatArray, w: FloatArray, dt: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Exact unicycle motion for constant (v, w) over dt; all arrays broadcast together.

    Straight line for w == 0, circular arc of radius v / w otherwise. Units m, rad, m/s, rad/s, s.
    Returns (x, y, theta) with theta not wrapped (callers wrap when they need to).
    """
    dtheta = w * dt
    # sin(a + d) - sin(a) = 2 cos(a + d/2) sin(d/2); the sinc form is exact and stable for w -> 0.
    half = 0.5 * dtheta
    chord = v * dt * np.sinc(half / np.pi)  # v dt sin(half) / half
    mid = theta + half
    return x + chord * np.cos(mid), y + chord * np.sin(mid), theta + dtheta


def footprint_corners(
    x: FloatArray, y: FloatArray, theta: FloatArray, length: float | FloatArray,
    width: float | FloatArray,
) -> FloatArray:
    """Corners of rectangular footprints centred on (x, y) with heading theta.

    x, y, theta have one shape S; length (along the heading) and width (across it), in m, are
    scalars or arrays of shape S. Returns shape S + (4, 2), corners counter-clockwise starting
    at the front left.
    """
    c, s = np.cos(theta), np.sin(theta)
    half_l, half_w = 0.5 * np.asarray(length, dtype=float), 0.5 * np.asarray(width, dtype=float)
    along_x, along_y = c * half_l, s * half_l  # half the length along the heading
    across_x, across_y = -s * half_w, c * half_w  # half the width to the left
    shape = np.broadcast_shapes(np.shape(x), np.shape(along_x), np.shape(across_x))
    result = np.empty((*shape, 4, 2))
    result[..., 0, 0] = x + along_x + across_x  # front left
    result[..., 0, 1] = y + along_y + across_y
    result[..., 1, 0] = x - along_x + across_x  # rear left
    result[..., 1, 1] = y - along_y + across_y
    result[..., 2, 0] = x - along_x - across_x  # rear right
    result[..., 2, 1] = y - along_y - across_y
    result[..., 3, 0] = x + along_x - across_x  # front right
    result[..., 3, 1] = y + along_y - across_y
    return result
