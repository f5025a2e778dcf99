"""Synthetic planar scans with known answers: legs (small discs), robots and walls
(segments), cast with the simulator's NumPy reference kernels, plus optional noise."""

from __future__ import annotations

import numpy as np

from dancebots.leader_follower.scan import Scan
from dancebots.sim.raycast import ray_directions, rays_to_discs, rays_to_segments

BEAMS = 360
ANGLES = -np.pi + np.arange(BEAMS) * (2 * np.pi / BEAMS)


def legs(x: float, y: float, apart: float = 0.2, radius: float = 0.06) -> list[tuple]:
    """A person's two legs side by side (across the line of sight from the origin)."""
    return [(x, y - 0.5 * apart, radius), (x, y + 0.5 * apart, radius)]


def box(x: float, y: float, length: float = 0.14, width: float = 0.18) -> list[tuple]:
    """The four edges of an axis-aligned robot footprint centred at (x, y)."""
    corners = np.array([[x + length / 2, y + width / 2], [x - length / 2, y + width / 2],
                        [x - length / 2, y - width / 2], [x + length / 2, y - width / 2]])
    return [(tuple(corners[k]), tuple(corners[(k + 1) % 4])) for k in range(4)]


def make_scan(discs: list[tuple] = (), segments: list[tuple] = (), *,
              pose: tuple[float, float, float] = (0.0, 0.0, 0.0), stamp: float = 0.0,
              max_range: float = 3.5, noise: float = 0.0, seed: int = 0) -> Scan:
    """The scan a robot at ``pose`` (world = odometry frame) takes of world-frame discs
    (x, y, r) and segments ((x0, y0), (x1, y1))."""
    origin = np.array([pose[:2]])
    directions = ray_directions(np.array([pose[2]]), ANGLES)
    ranges = np.full(BEAMS, np.inf)
    if discs:
        hit, _ = rays_to_discs(origin, directions, np.array(discs, dtype=float))
        ranges = np.minimum(ranges, hit[0])
    if segments:
        hit, _ = rays_to_segments(origin, directions, np.array(segments, dtype=float))
        ranges = np.minimum(ranges, hit[0])
    if noise:
        ranges = ranges + np.random.default_rng(seed).normal(0.0, noise, BEAMS)
    ranges = np.where((ranges > 0.12) & (ranges <= max_range), ranges, np.inf)
    return Scan(stamp, ranges, ANGLES.copy(), pose)
