"""Point clouds as the robots receive them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["PointCloud"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True, eq=False)
class PointCloud:
    """A scan taken at ``stamp`` (s of show time), in ``base_link`` (m).

    Stored as ``columns`` (K, 4): x, y, z_low, z_high of each hit, whose points are repeated
    every ``height_step`` from z_low to z_high; :meth:`points` expands them to the (M, 3)
    cloud a ROS node publishes. Consumers that only need what stands between two heights read
    the columns directly (see ``perception.obstacles``), which is what keeps 100 robots fast.
    """

    stamp: float
    columns: FloatArray
    height_step: float = 0.1

    def points(self) -> FloatArray:
        """The cloud (M, 3): every column's points, z = z_low, z_low + step, ..., <= z_high."""
        low, high = self.columns[:, 2], self.columns[:, 3]
        levels = np.floor((high - low) / self.height_step + 1e-9).astype(np.int64) + 1
        column = np.repeat(np.arange(len(self.columns)), levels)
        level = np.arange(column.size) - np.repeat(np.cumsum(levels) - levels, levels)
        z = low[column] + level * self.height_step
        result: FloatArray = np.stack([self.columns[column, 0], self.columns[column, 1], z],
                                      axis=1)
        return result
