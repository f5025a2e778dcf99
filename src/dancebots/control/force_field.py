"""The virtual force field (thesis ch. 1, 5.2; the F of eq. 4.4b): obstacles push back.

Every obstacle point within ``radius`` of the robot's footprint adds a small force pointing
from the footprint to away from the point, growing as the point comes nearer; the sum is the
force F in ``base_link`` that eq. 4.4b turns into steering.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["repulsive_force"]


def repulsive_force(points: NDArray[np.float64], length: float, width: float,
                    radius: float = 1.0, gain: float = 0.02) -> tuple[float, float]:
    """Force (Fx, Fy) from obstacle points (M, 2) in ``base_link`` on a robot of the given
    footprint (m). Each point at distance d < radius from the footprint contributes
    gain * (1 - d / radius)^2 along the direction from the point to the footprint."""
    if len(points) == 0:
        return 0.0, 0.0
    half = np.array([0.5 * length, 0.5 * width])
    nearest = np.clip(points, -half, half)  # closest footprint point to each obstacle point
    away = nearest - points
    distance = np.hypot(away[:, 0], away[:, 1])
    near = (distance < radius) & (distance > 1e-9)
    if not near.any():
        return 0.0, 0.0
    weight = gain * (1.0 - distance[near] / radius) ** 2
    force = (away[near] / distance[near, None] * weight[:, None]).sum(axis=0)
    return float(force[0]), float(force[1])
