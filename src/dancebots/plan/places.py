"""Where each robot should be on its leader's path (thesis ch. 4.1: a robot drives the
leader's path shifted sideways by its lateral offset oy, its along offset ox behind).

``path_places`` is the path follower's reference (``control.tracking.path_references``) and
what the ``feasible`` timing's ordered departures check (``planner.build_plan``). Show frame,
times in s of show time.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import compose_points, compose_poses

if TYPE_CHECKING:
    from dancebots.plan.planner import Plan

__all__ = ["path_places"]

FloatArray = NDArray[np.float64]


def path_places(plan: Plan, robot: str, times: FloatArray,
                ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Where ``robot``'s place on its leader's path is at show times ``times`` (T,) s,
    ascending, show frame: positions (T, 2) m, the path's heading there (T,) rad (unwrapped)
    and the place's signed speed along it (T,) m/s. The leader's pose where the leader was
    ``-ox`` m of path earlier, shifted by (0, oy); before the leader has driven that far, on
    the straight line behind its first pose; once it stands after its last instruction, the
    rigid slot (its final pose composed with (ox, oy)). Speed: the leader's v times
    (1 - kappa oy), kappa the path's curvature at the place."""
    times = np.asarray(times, dtype=float)
    count = len(times)
    points = np.empty((count, 2))
    heading = np.empty(count)
    speed = np.zeros(count)
    which = plan.formation_indices(robot, times)
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(which)) + 1, [count]]).tolist()
    for a, b in itertools.pairwise(bounds):
        if a == b:
            continue
        formation = plan.formations[int(which[a])]
        leader = formation.leader
        ox, oy = formation.offsets[robot]
        now = times[a:b]
        step_length = leader.commands[:-1, 0] * np.diff(leader.times)
        driven = np.concatenate([[0.0], np.cumsum(step_length)])  # (N,) path length, m
        k = np.clip(np.searchsorted(leader.times, now, side="right") - 1, 0,
                    len(leader.times) - 1)
        v_now = leader.commands[k, 0]
        target = driven[k] + v_now * np.maximum(now - leader.times[k], 0.0) + min(ox, 0.0)
        j = np.clip(np.searchsorted(driven, target, side="right") - 1, 0,
                    max(len(driven) - 2, 0))
        v_then = leader.commands[j, 0]
        moved = v_then > 0.0
        back = np.where(moved, (target - driven[j]) / np.where(moved, v_then, 1.0), 0.0)
        then = leader.poses_at(leader.times[j] + np.maximum(back, 0.0))
        behind = target < 0.0  # before the leader has driven -ox: behind its first pose
        first = np.broadcast_to(leader.poses[0], (b - a, 3))
        then[behind] = compose_poses(first[behind], np.column_stack(
            [target[behind], np.zeros(int(behind.sum())), np.zeros(int(behind.sum()))]))
        curvature = np.where(moved & ~behind, leader.commands[j, 1] / np.where(
            moved, v_then, 1.0), 0.0)
        place = compose_points(then, np.column_stack([np.zeros(b - a), np.full(b - a, oy)]))
        done = now >= leader.times[-1]  # the leader stands at its end: the rigid slot
        place[done] = compose_points(leader.poses[-1], np.array([ox, oy]))
        then[done] = leader.poses[-1]
        points[a:b] = place
        heading[a:b] = then[:, 2]
        speed[a:b] = np.where(done, 0.0, v_now * (1.0 - curvature * oy))
    return points, np.unwrap(heading), speed


