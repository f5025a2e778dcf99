"""The simulated LIDAR of thesis ch. 7.1: point clouds for every robot in one vectorised pass.

Rays are cast in 2D against the walls, the obstacles, the other robots and the spectators;
the third dimension is added as the thesis does: each hit is repeated every 10 cm up to the
height of what was hit (robots and obstacles 1 m, walls their height, spectators theirs).
For a ray that hits something nearer than the wall, the lower half of the wall is hidden and
its upper half is still seen. A hit nearer than ``min_range`` cannot be measured; the sensor
reports it at ``min_range`` (as a scanner's too-near code: something is there), so that a
person standing in a robot's footprint is seen in it rather than not at all; nothing beyond
``max_range``. Clouds are in the sensor's ``base_link`` frame
(x forward, y left, z up; the sensor sits on the robot's centre) and carry the time of the
scan; the simulator delivers them ``latency`` seconds later.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import accumulate

import numpy as np
from numpy.typing import NDArray

from dancebots.perception.cloud import PointCloud
from dancebots.sim.kernels import kernel
from dancebots.sim.raycast import (
    ray_directions,
    rays_to_convex_walls,
    rays_to_discs,
    rays_to_segments,
    rays_to_segments_culled,
)

__all__ = ["LidarConfig", "LidarScene", "PointCloud", "scan_clouds", "scan_ranges"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class LidarConfig:
    """rays per scan (256 in the thesis's simulator, 1024 on the real sensor); ranges in m
    (5 m: the obstacle detection uses 2 m around the robot, the force field 1.5 m);
    latency and period in s (the real LIDAR lags about 300 ms and scans at 10 Hz);
    height_step: spacing of the points repeated in height, m; robot_height in m; compiled:
    cast with the numba-compiled loops (else the vectorised NumPy kernels; same results)."""

    rays: int = 256
    min_range: float = 0.3
    max_range: float = 5.0
    latency: float = 0.3
    period: float = 0.1
    height_step: float = 0.1
    robot_height: float = 1.0
    compiled: bool = True

    def angles(self) -> FloatArray:
        """Ray angles (N,) in rad relative to the robot's heading, from -pi, evenly spaced
        (a copy: the scans use one array per ray count, :func:`_ray_angles`)."""
        return _ray_angles(self.rays).copy()


@lru_cache(maxsize=16)
def _ray_turns(rays: int) -> FloatArray:
    """The cosines and sines (2, N) of :meth:`LidarConfig.angles` of ``rays`` rays
    (``raycast_jit.ray_turns``; imports numba)."""
    turns: FloatArray = kernel("sim.raycast_jit").ray_turns(_ray_angles(rays))
    return turns


@lru_cache(maxsize=16)
def _ray_angles(rays: int) -> FloatArray:
    """:meth:`LidarConfig.angles` of ``rays`` rays, computed once and shared by the scans of
    this module, which only read it (a LIDAR scans every tick; numba kernels take the array,
    so it stays writeable: a read-only one is another type to compile)."""
    result: FloatArray = -np.pi + np.arange(rays, dtype=np.float64) * (2.0 * np.pi / rays)
    return result


def _segments(polygon: FloatArray) -> FloatArray:
    return np.stack([polygon, np.concatenate([polygon[1:], polygon[:1]])], axis=1)


def _distance_to_segments(points: FloatArray, segments: FloatArray) -> FloatArray:
    """(P, S) distance of each point (P, 2) to each segment (S, 2, 2)."""
    start = segments[:, 0]
    edge = segments[:, 1] - start
    length2 = np.maximum((edge**2).sum(axis=1), 1e-12)
    rel = points[:, None, :] - start[None]
    u = np.clip((rel * edge).sum(axis=2) / length2, 0.0, 1.0)
    closest = start[None] + u[..., None] * edge[None]
    result: FloatArray = np.hypot(*(points[:, None, :] - closest).transpose(2, 0, 1))
    return result


@dataclass(frozen=True, slots=True, eq=False)
class LidarScene:
    """What the LIDARs see that does not move, prepared once per show.

    walls (W, 2, 2): the room's edges; convex_room: the room (W, 2) counter-clockwise when it
    is convex, else None; wall_height in m; obstacle_segments (S, 2, 2): the obstacles' edges,
    counter-clockwise per outline, with their heights (S,) in m.
    """

    room: FloatArray
    walls: FloatArray
    convex_room: FloatArray | None
    wall_height: float
    obstacle_segments: FloatArray
    obstacle_heights: FloatArray

    @classmethod
    def build(cls, room: FloatArray, wall_height: float,
              obstacles: list[tuple[FloatArray, float]]) -> LidarScene:
        """The scene of a room polygon (W, 2) and (polygon (K, 2), height) obstacles."""
        outlines = [_segments(_counter_clockwise(polygon)) for polygon, _ in obstacles]
        segments = np.concatenate(outlines) if outlines else np.zeros((0, 2, 2))
        heights = np.concatenate([np.full(len(s), h) for s, (_, h) in zip(
            outlines, obstacles, strict=True)]) if outlines else np.zeros(0)
        return cls(room, _segments(room), _counter_clockwise(room) if _is_convex(room) else None,
                   float(wall_height), segments, heights)


def scan_clouds(config: LidarConfig, stamp: float, poses: FloatArray, corners: FloatArray,
                scene: LidarScene, discs: FloatArray, disc_heights: FloatArray,
                ) -> list[PointCloud]:
    """One scan of every robot.

    poses (R, 3) world; corners (R, 4, 2) robot footprints; scene: walls and obstacles;
    discs (C, 3) spectators (x, y, radius) with heights (C,).
    Returns one :class:`PointCloud` per robot.
    """
    count = len(poses)
    angles = _ray_angles(config.rays)  # (shared, read here only)
    origins = poses[:, :2]
    headings = poses[:, 2]
    if len(discs) == 0:
        discs, disc_heights = np.zeros((0, 3)), np.zeros(0)
    if config.compiled:
        raycast = kernel("sim.raycast_jit")  # (imports numba)
        solid, solid_height, wall = raycast.cast_scene(
            origins, headings, angles, corners, config.robot_height, scene.obstacle_segments,
            scene.obstacle_heights, discs, np.asarray(disc_heights, dtype=float), scene.walls,
            config.max_range)
        # columns of points, robot by robot: the hit itself (below the wall), the wall's
        # upper half behind it, or the whole wall when nothing stands before it
        columns, counts = raycast.build_columns(solid, solid_height, wall,
                                                _ray_turns(config.rays), config.min_range,
                                                config.max_range, scene.wall_height)
        ends = list(accumulate(counts.tolist()))  # (slices: np.split costs 2 us a robot)
        return [PointCloud(stamp, columns[start:end], config.height_step)
                for start, end in zip([0, *ends[:-1]], ends, strict=True)]
    # robots' edges and obstacles' edges: culled by angular span and range
    segments = np.concatenate([_segments_of(corners), scene.obstacle_segments])  # (4R + S,)
    heights = np.concatenate([np.full(4 * count, config.robot_height), scene.obstacle_heights])
    owner = np.concatenate([np.repeat(np.arange(count), 4),
                            np.full(len(scene.obstacle_segments), -1)])
    solid, solid_height, wall = _cast_numpy(config, origins, headings, angles, segments,
                                            owner, heights, scene, discs, disc_heights)
    wall_height = scene.wall_height
    in_range = solid <= config.max_range
    blocked = solid < wall
    solid = np.maximum(solid, config.min_range)  # too near to measure: at min_range
    wall_seen = wall <= config.max_range
    distances = np.stack([solid, wall], axis=1)  # (R, 2, N)
    tops = np.stack([solid_height, np.full_like(wall, wall_height)], axis=1)
    bottoms = np.stack([np.zeros_like(wall), np.where(blocked, 0.5 * wall_height, 0.0)], axis=1)
    kept = np.stack([in_range & blocked, wall_seen], axis=1)
    sensor, ray, kind = np.nonzero(np.swapaxes(kept, 1, 2))  # by robot, ray, then kind
    distance = distances[sensor, kind, ray]
    columns = np.stack([distance * np.cos(angles[ray]), distance * np.sin(angles[ray]),
                        bottoms[sensor, kind, ray], tops[sensor, kind, ray]], axis=1)
    splits = np.cumsum(np.bincount(sensor, minlength=count))[:-1]
    return [PointCloud(stamp, part, config.height_step) for part in np.split(columns, splits)]


def scan_ranges(config: LidarConfig, poses: FloatArray, corners: FloatArray,
                scene: LidarScene, discs: FloatArray, disc_heights: FloatArray) -> FloatArray:
    """A planar scan (a 2D LIDAR such as a TurtleBot's, at the height of everything): per
    robot and ray the range to the nearest robot edge, obstacle, spectator or wall, m;
    inf where that is nearer than ``min_range`` or beyond ``max_range`` (an invalid
    reading). poses (R, 3), corners (R, 4, 2), discs (C, 3). Returns (R, N), rays at
    ``config.angles()`` from the robot's heading."""
    cast_scene = kernel("sim.raycast_jit").cast_scene  # (imports numba)
    if len(discs) == 0:
        discs, disc_heights = np.zeros((0, 3)), np.zeros(0)
    solid, _, wall = cast_scene(poses[:, :2], poses[:, 2], _ray_angles(config.rays), corners,
                                config.robot_height, scene.obstacle_segments,
                                scene.obstacle_heights, discs,
                                np.asarray(disc_heights, dtype=float),
                                scene.walls, config.max_range)
    ranges = np.minimum(solid, wall)
    result: FloatArray = np.where((ranges >= config.min_range) & (ranges <= config.max_range),
                                  ranges, np.inf)
    return result


def _segments_of(corners: FloatArray) -> FloatArray:
    """The 4 edges (4R, 2, 2) of R footprints (R, 4, 2), robot by robot."""
    following = np.concatenate([corners[:, 1:], corners[:, :1]], axis=1)
    result: FloatArray = np.stack([corners, following], axis=2).reshape(-1, 2, 2)
    return result


def _counter_clockwise(polygon: FloatArray) -> FloatArray:
    """The polygon (K, 2) with its corners in counter-clockwise order (shoelace sign)."""
    x, y = polygon[:, 0], polygon[:, 1]
    area2 = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    return polygon if area2 > 0 else polygon[::-1].copy()


def _is_convex(polygon: FloatArray) -> bool:
    """Do all the polygon's turns (K, 2) go the same way?"""
    edge = np.roll(polygon, -1, axis=0) - polygon
    following = np.roll(edge, -1, axis=0)
    turn = edge[:, 0] * following[:, 1] - edge[:, 1] * following[:, 0]
    return bool(np.all(turn >= 0) or np.all(turn <= 0))


def _cast_numpy(config: LidarConfig, origins: FloatArray, headings: FloatArray,
                angles: FloatArray, segments: FloatArray, owner: NDArray[np.int64],
                heights: FloatArray, scene: LidarScene, discs: FloatArray,
                disc_heights: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The vectorised NumPy caster (the reference the compiled one is tested against)."""
    count = len(origins)
    # a ray's first hit on a closed counter-clockwise outline is on an edge facing the sensor:
    # edges facing away (back faces) are skipped
    edge = segments[:, 1] - segments[:, 0]
    to_edge = segments[None, :, 0, :] - origins[:, None, :]  # (R, S, 2)
    facing = to_edge[..., 0] * edge[:, 1] - to_edge[..., 1] * edge[:, 0] < 0.0
    visible = facing & (owner[None, :] != np.arange(count)[:, None]) & (
        _distance_to_segments(origins, segments) <= config.max_range)
    solid, which = rays_to_segments_culled(origins, headings, angles, segments, visible)
    solid_height = np.where(which >= 0, heights[np.maximum(which, 0)], 0.0)
    directions = ray_directions(headings, angles)
    if len(discs):
        people, who = rays_to_discs(origins, directions, discs)
        nearer = people < solid
        solid = np.where(nearer, people, solid)
        solid_height = np.where(nearer, disc_heights[np.maximum(who, 0)], solid_height)
    if scene.convex_room is not None:
        wall = rays_to_convex_walls(origins, directions, scene.convex_room)
    else:
        wall, _ = rays_to_segments(origins, directions, scene.walls)

    return solid, solid_height, wall
