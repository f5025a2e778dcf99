"""Vectorised 2D ray casting: rays against line segments and discs (thesis ch. 7.1 LIDAR).

Pure functions over NumPy arrays; no loop over rays, segments or robots. Shapes:
R sensors, N rays per sensor, S segments, C discs. Distances in m; ``inf`` where nothing
is hit.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["ray_directions", "rays_to_convex_walls", "rays_to_discs", "rays_to_segments",
           "rays_to_segments_culled"]

FloatArray = NDArray[np.float64]


def _trig(values: FloatArray) -> tuple[FloatArray, FloatArray]:
    """cos and sin (shape of ``values``) from libm (``math``), as the compiled caster takes
    them (NumPy's own cos may round the last bit otherwise), so that both cast alike."""
    flat = values.ravel().tolist()
    return (np.array([math.cos(v) for v in flat]).reshape(values.shape),
            np.array([math.sin(v) for v in flat]).reshape(values.shape))


def ray_directions(headings: FloatArray, angles: FloatArray) -> FloatArray:
    """Unit directions (R, N, 2) of rays at ``angles`` (N,) rad relative to ``headings`` (R,):
    each angle's unit vector turned by the heading (the compiled caster's arithmetic)."""
    ch, sh = _trig(headings)
    ca, sa = _trig(angles)
    return np.stack([ch[:, None] * ca[None, :] - sh[:, None] * sa[None, :],
                     sh[:, None] * ca[None, :] + ch[:, None] * sa[None, :]], axis=-1)


def rays_to_segments(origins: FloatArray, directions: FloatArray, segments: FloatArray,
                     ignore: NDArray[np.bool_] | None = None) -> tuple[FloatArray, NDArray[
                         np.int64]]:
    """Nearest hit of each ray on the segments.

    origins (R, 2), directions (R, N, 2) unit vectors, segments (S, 2, 2) as (start, end),
    ignore (R, S): segments a sensor does not see (its own robot). Returns distances (R, N)
    (inf: no hit) and the index (R, N) of the segment hit (-1: none).

    Solves o + t d = p + u e for t >= 0, 0 <= u <= 1 with cross products; rays parallel to a
    segment never hit it.
    """
    count, rays = directions.shape[:2]
    if len(segments) == 0:
        return np.full((count, rays), np.inf), np.full((count, rays), -1, dtype=np.int64)
    start = segments[:, 0]  # (S, 2)
    edge = segments[:, 1] - start  # (S, 2)
    offset = start[None, :, :] - origins[:, None, :]  # (R, S, 2)
    dx, dy = directions[..., 0][..., None], directions[..., 1][..., None]  # (R, N, 1)
    denominator = dx * edge[:, 1] - dy * edge[:, 0]  # (R, N, S): d x e
    offset_cross_edge = offset[..., 0] * edge[:, 1] - offset[..., 1] * edge[:, 0]  # (R, S)
    offset_cross_dir = (offset[:, None, :, 0] * dy - offset[:, None, :, 1] * dx)  # (R, N, S)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = offset_cross_edge[:, None, :] / denominator
        u = offset_cross_dir / denominator
    valid = (np.abs(denominator) > 1e-12) & (t >= 0.0) & (u >= 0.0) & (u <= 1.0)
    if ignore is not None:
        valid &= ~ignore[:, None, :]
    t = np.where(valid, t, np.inf)
    nearest = np.argmin(t, axis=2)
    distance = np.take_along_axis(t, nearest[..., None], axis=2)[..., 0]
    return distance, np.where(np.isfinite(distance), nearest, -1)


def rays_to_discs(origins: FloatArray, directions: FloatArray,
                  discs: FloatArray) -> tuple[FloatArray, NDArray[np.int64]]:
    """Nearest hit of each ray on the discs (C, 3) = (x, y, radius).

    Returns distances (R, N) (inf: no hit) and the disc index (R, N) (-1: none). A sensor
    inside a disc does not see that disc.
    """
    count, rays = directions.shape[:2]
    if len(discs) == 0:
        return np.full((count, rays), np.inf), np.full((count, rays), -1, dtype=np.int64)
    relative = origins[:, None, :] - discs[None, :, :2]  # (R, C, 2): o - c
    b = (directions[:, :, None, 0] * relative[:, None, :, 0]
         + directions[:, :, None, 1] * relative[:, None, :, 1])  # (R, N, C): d . (o - c)
    c = (relative**2).sum(axis=2) - discs[:, 2] ** 2  # (R, C)
    discriminant = b * b - c[:, None, :]
    with np.errstate(invalid="ignore"):
        t = -b - np.sqrt(discriminant)
    valid = (discriminant >= 0.0) & (t >= 0.0) & (c[:, None, :] > 0.0)
    t = np.where(valid, t, np.inf)
    nearest = np.argmin(t, axis=2)
    distance = np.take_along_axis(t, nearest[..., None], axis=2)[..., 0]
    return distance, np.where(np.isfinite(distance), nearest, -1)


def rays_to_segments_culled(origins: FloatArray, headings: FloatArray, angles: FloatArray,
                            segments: FloatArray, visible: NDArray[np.bool_],
                            ) -> tuple[FloatArray, NDArray[np.int64]]:
    """Like :func:`rays_to_segments` for evenly spaced rays, testing each segment only
    against the rays inside its angular span, as the sensor sees it.

    origins (R, 2), headings (R,), angles (N,) evenly spaced over the full circle from
    angles[0], segments (S, 2, 2), visible (R, S): the pairs to consider (range-culled, own
    robot excluded). The work grows with the total angular span of the visible segments,
    not with R * N * S. Returns distances (R, N) and segment indices (R, N) (-1: none).
    """
    count, rays = len(origins), len(angles)
    distance = np.full((count, rays), np.inf)
    which = np.full((count, rays), -1, dtype=np.int64)
    sensor, segment = np.nonzero(visible)
    if sensor.size == 0:
        return distance, which
    step = 2.0 * np.pi / rays
    relative = segments[segment] - origins[sensor][:, None, :]  # (P, 2 ends, 2)
    ends = np.arctan2(relative[..., 1], relative[..., 0]) - headings[sensor][:, None] - angles[0]
    first = np.remainder(ends[:, 0], 2.0 * np.pi)
    span = np.remainder(ends[:, 1] - ends[:, 0], 2.0 * np.pi)
    backwards = span > np.pi  # the short way round goes from the second end to the first
    first = np.where(backwards, np.remainder(ends[:, 1], 2.0 * np.pi), first)
    span = np.where(backwards, 2.0 * np.pi - span, span)
    start = np.floor(first / step).astype(np.int64)
    size = np.floor((first + span) / step).astype(np.int64) - start + 2
    pair = np.repeat(np.arange(sensor.size), size)
    offsets = np.arange(pair.size) - np.repeat(np.cumsum(size) - size, size)
    ray = np.remainder(start[pair] + offsets, rays)
    owner = sensor[pair]
    ch, sh = _trig(headings)
    ca, sa = _trig(angles)
    dx = ch[owner] * ca[ray] - sh[owner] * sa[ray]  # as ``ray_directions``
    dy = sh[owner] * ca[ray] + ch[owner] * sa[ray]
    seg = segment[pair]
    edge = segments[seg, 1] - segments[seg, 0]
    offset = segments[seg, 0] - origins[owner]
    denominator = dx * edge[:, 1] - dy * edge[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (offset[:, 0] * edge[:, 1] - offset[:, 1] * edge[:, 0]) / denominator
        u = (offset[:, 0] * dy - offset[:, 1] * dx) / denominator
    valid = (np.abs(denominator) > 1e-12) & (t >= 0.0) & (u >= 0.0) & (u <= 1.0)
    owner, ray, seg, t = owner[valid], ray[valid], seg[valid], t[valid]
    np.minimum.at(distance, (owner, ray), t)
    nearest = t == distance[owner, ray]
    which[owner[nearest], ray[nearest]] = seg[nearest]
    return distance, which


def rays_to_convex_walls(origins: FloatArray, directions: FloatArray,
                         polygon: FloatArray) -> FloatArray:
    """Distance (R, N) at which rays from inside a convex counter-clockwise polygon (W, 2)
    leave it: for each edge with outward normal n, t = n.(p - o) / n.d over the edges the ray
    moves towards (n.d > 0), and the smallest such t. The same as :func:`rays_to_segments`
    against the polygon's edges for sensors inside it, with a fraction of the operations."""
    edge = np.roll(polygon, -1, axis=0) - polygon  # (W, 2)
    normal = np.stack([edge[:, 1], -edge[:, 0]], axis=1)  # outward for counter-clockwise
    reach = ((polygon[None, :, :] - origins[:, None, :]) * normal[None]).sum(axis=2)  # (R, W)
    towards = directions @ normal.T  # (R, N, W)
    t = np.divide(reach[:, None, :], towards, out=np.full_like(towards, np.inf),
                  where=towards > 1e-12)
    result: FloatArray = t.min(axis=2)
    return result
