"""Formation metrics of a simulated show (pure functions of a :class:`RunResult`).

Per robot: the error to its desired pose (the leader's pose composed with the robot's offset,
thesis ch. 4.2) and the deviation of its distance to the leader from the desired one (d_act -
d_req, eq. 4.4a, thesis fig. 7.5). Per row of each formation: the largest change of the
distance between neighbours from their desired spacing (thesis ch. 7.2.1: "the maximal change
in the distance between the robots ... around 16 cm for 2D and 18 cm for 3D").
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.shows.formation import STATUS, RunResult

__all__ = ["RobotMetrics", "RowMetrics", "RunMetrics", "run_metrics", "spacing_change"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class RobotMetrics:
    """One robot: RMS and max position error to its desired pose, m; RMS and max of
    |d_act - d_req|, m; while the show runs (0 <= t <= show duration). stops: how often a stop
    flag held it (thesis 5.2, each spoken once); stopped_time: s held; error: why it went
    into the error state, if it did; final_error: distance from its final slot (its desired
    pose at the end of the run) at the end of the run, m."""

    robot: str
    rms_error: float
    max_error: float
    rms_leader_distance_deviation: float
    max_leader_distance_deviation: float
    stops: int = 0
    stopped_time: float = 0.0
    error: str | None = None
    final_error: float = 0.0


@dataclass(frozen=True, slots=True)
class RowMetrics:
    """Neighbours in one row of one formation (scenario ``line``): their desired spacings (m)
    and the largest |distance - desired spacing| while they follow that formation, m."""

    line: int
    robots: tuple[str, ...]
    desired_spacings: tuple[float, ...]
    max_spacing_change: float


@dataclass(frozen=True, slots=True)
class RunMetrics:
    """Everything ``metrics.json`` holds."""

    scenario: str
    profile: str
    seed: int
    show_duration: float
    run_duration: float
    robots: tuple[RobotMetrics, ...]
    rows: tuple[RowMetrics, ...]
    collisions: int
    collision_events: tuple[dict[str, object], ...]
    min_clearance: float | None
    events: tuple[dict[str, object], ...] = ()

    @property
    def max_spacing_change(self) -> float | None:
        return max((r.max_spacing_change for r in self.rows), default=None)

    def to_json(self) -> dict[str, object]:
        def r3(value: float | None) -> float | None:
            return None if value is None or not math.isfinite(value) else round(value, 4)

        return {
            "scenario": self.scenario,
            "profile": self.profile,
            "seed": self.seed,
            "show_duration_s": r3(self.show_duration),
            "run_duration_s": r3(self.run_duration),
            "collisions": self.collisions,
            "collision_events": list(self.collision_events),
            "min_clearance_m": r3(self.min_clearance),
            "max_spacing_change_m": r3(self.max_spacing_change),
            "per_robot": {
                m.robot: {
                    "rms_error_m": r3(m.rms_error),
                    "max_error_m": r3(m.max_error),
                    "rms_leader_distance_deviation_m": r3(m.rms_leader_distance_deviation),
                    "max_leader_distance_deviation_m": r3(m.max_leader_distance_deviation),
                    "stops": m.stops,
                    "stopped_s": r3(m.stopped_time),
                    "error": m.error,
                    "final_error_m": r3(m.final_error),
                } for m in self.robots
            },
            "stops": sum(m.stops for m in self.robots),
            "events": list(self.events),
            "rows": [
                {"line": row.line, "robots": list(row.robots),
                 "desired_spacings_m": [r3(s) for s in row.desired_spacings],
                 "max_spacing_change_m": r3(row.max_spacing_change)}
                for row in self.rows
            ],
        }


def run_metrics(result: RunResult) -> RunMetrics:
    """Compute the metrics of a run."""
    plan = result.plan
    during = result.times <= plan.duration + 1e-9
    error = np.hypot(result.poses[..., 0] - result.desired[..., 0],
                     result.poses[..., 1] - result.desired[..., 1])[:, during]
    deviation = np.abs(result.leader_distance - result.required_distance)[:, during]
    final = np.hypot(result.poses[:, -1, 0] - result.desired[:, -1, 0],
                     result.poses[:, -1, 1] - result.desired[:, -1, 1])  # (R,)
    period = float(np.median(np.diff(result.times))) if len(result.times) > 1 else 0.0
    stopped = result.status == STATUS.index("stopped")
    robots = tuple(
        RobotMetrics(name, float(np.sqrt(np.mean(error[i] ** 2))), float(error[i].max()),
                     float(np.sqrt(np.mean(deviation[i] ** 2))), float(deviation[i].max()),
                     sum(1 for e in result.events if e.robot == name and e.kind == "speech"),
                     float(stopped[i].sum() * period),
                     next((e.text for e in result.events
                           if e.robot == name and e.kind == "error"), None),
                     float(final[i]))
        for i, name in enumerate(result.robots))
    return RunMetrics(
        plan.scenario.path, result.config.profile.name, result.config.seed, plan.duration,
        float(result.times[-1]), robots, tuple(_rows(result)), len(result.collisions),
        tuple({"t_s": c.time, "robot": c.robot, "with": c.other, "kind": c.kind,
               "x_m": round(c.x, 3), "y_m": round(c.y, 3)} for c in result.collisions),
        result.min_clearance,
        tuple({"t_s": e.time, "robot": e.robot, "kind": e.kind, "text": e.text}
              for e in result.events))


def spacing_change(first: FloatArray, second: FloatArray, spacing: float) -> float:
    """The largest change of the distance between two robots from ``spacing``, m; their
    positions first, second (T, 2 or 3) at the same times."""
    distance = np.hypot(first[:, 0] - second[:, 0], first[:, 1] - second[:, 1])
    return float(np.abs(distance - spacing).max())


def _rows(result: RunResult) -> list[RowMetrics]:
    """Rows are robots with the same longitudinal offset, ordered left to right."""
    index = {name: i for i, name in enumerate(result.robots)}
    rows: list[RowMetrics] = []
    seen: set[tuple[int, tuple[str, ...]]] = set()
    for formation in result.plan.formations:
        by_x: dict[float, list[str]] = {}
        for robot in formation.robots:
            by_x.setdefault(round(formation.offsets[robot][0], 6), []).append(robot)
        for members in by_x.values():
            if len(members) < 2:
                continue
            ordered = tuple(sorted(members, key=lambda r: -formation.offsets[r][1]))
            key = (formation.span.line, ordered)
            if key in seen:  # what remains of a split formation
                continue
            seen.add(key)
            spacings, changes = [], []
            for a, b in itertools.pairwise(ordered):
                i, j = index[a], index[b]
                spacing = abs(formation.offsets[a][1] - formation.offsets[b][1])
                active = (result.formation[i] == formation.index) & (
                    result.formation[j] == formation.index)
                if not active.any():
                    continue
                spacings.append(spacing)
                changes.append(spacing_change(result.poses[i, active],
                                              result.poses[j, active], spacing))
            if changes:
                rows.append(RowMetrics(formation.span.line, ordered, tuple(spacings),
                                       max(changes)))
    return rows
