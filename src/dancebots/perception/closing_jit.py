"""The ``closing`` stop rule's kernels (``perception.closing``) compiled with numba: the
strangers' points of a cloud and their gaps per bearing sector, for every robot at every
cloud. Same results as the NumPy reference (the tests hold them equal). A module of its own:
only runs with the ``closing`` rule compile it (``sim.kernels.kernel_modules``)."""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit
from numpy.typing import NDArray

from dancebots.jit_cache import drop_stale
from dancebots.perception import fast
from dancebots.perception.fast import _kept, far_from_all, to_local

__all__ = ["sector_gaps_moved", "stranger_points_columns"]


@njit(cache=True)
def stranger_points_columns(columns: NDArray[np.float64], height_step: float, crop_half: float,
                            z_min: float, z_max: float, seen_from: NDArray[np.float64],
                            mates: NDArray[np.float64], mate_radius: float,
                            ) -> NDArray[np.float64]:
    """The obstacle points (N, 2) of a cloud stored as columns (K, 4) (``base_link`` at
    ``seen_from``) that are more than ``mate_radius`` m from every centre of ``mates`` (M, 2),
    in the parent frame of ``seen_from`` (the robot's own map frame), as are ``mates``: the
    columns left out as by :func:`perceive_columns_split`, then the crop and height filter.
    NumPy: ``RobotBrain._stranger_points`` with ``SensingConfig.compiled`` off."""
    c, s = math.cos(seen_from[2]), math.sin(seen_from[2])
    kept = _kept(columns[far_from_all(columns, to_local(mates, seen_from), mate_radius)],
                 height_step, crop_half, z_min, z_max)
    world = np.empty_like(kept)
    for i in range(kept.shape[0]):  # as geometry.points_to_world
        world[i, 0] = seen_from[0] + c * kept[i, 0] - s * kept[i, 1]
        world[i, 1] = seen_from[1] + s * kept[i, 0] + c * kept[i, 1]
    return world


@njit(cache=True)
def sector_gaps_moved(points: NDArray[np.float64], pose: NDArray[np.float64], length: float,
                      width: float, sectors: int) -> NDArray[np.float64]:
    """``perception.closing.sector_gaps`` of points (N, 2) given in the parent frame of
    ``pose`` (the robot's own map frame), taken to ``base_link`` at ``pose``: (S,) the
    smallest gap (m) to the footprint per bearing sector, inf where none."""
    gaps = np.full(sectors, np.inf)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    half_l, half_w = 0.5 * length, 0.5 * width
    for i in range(points.shape[0]):
        dx, dy = points[i, 0] - pose[0], points[i, 1] - pose[1]
        x = c * dx + s * dy
        y = -s * dx + c * dy
        if not (abs(x) < math.inf and abs(y) < math.inf):  # not a number: no point
            continue
        gap = math.hypot(max(abs(x) - half_l, 0.0), max(abs(y) - half_w, 0.0))
        sector = min(int((math.atan2(y, x) + math.pi) / (2.0 * math.pi) * sectors),
                     sectors - 1)
        if gap < gaps[sector]:
            gaps[sector] = gap
    return gaps


drop_stale(sys.modules[__name__], (fast,))  # its kernels call perception.fast's
