"""What a simulated show predicts, as diagnostics at the scenario's lines (check's second pass).

``check`` first judges the rigid desired poses (fast); then it runs the show in the ideal
profile and reports here what a spectator would see go wrong, at the line of the instruction
the robot's formation was executing: contacts, robots driving against their slot's direction,
robots far from their slot for a while, robots that leave their formation, and robots that do
not reach their final slot or heading. Pure: a :class:`~dancebots.shows.formation.RunResult`
in, diagnostics out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, Severity
from dancebots.plan.placement import instruction_position, true_runs
from dancebots.report.metrics import (
    against_desired,
    heading_errors,
    moving_over_to_place,
    off_formation,
    samples_per_tick,
)
from dancebots.report.verdict import FINAL_HEADING_TOLERANCE, FINAL_SLOT_TOLERANCE
from dancebots.shows.formation import RunResult

__all__ = ["FindingLimits", "simulated_findings"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class FindingLimits:
    """What counts as a finding.

    slot_distance: a robot further than this from its place (``RunResult.reference``),
    m, ... for at least min_duration s (also the shortest run of driving against the
    slot's direction that is reported); final_distance (m) and final_heading (deg): at
    the end of the run (the verdict's tolerances); per_kind: at most this many findings of
    one kind (the rest are counted in the last one).
    """

    slot_distance: float = 0.5
    min_duration: float = 1.0
    final_distance: float = FINAL_SLOT_TOLERANCE
    final_heading: float = FINAL_HEADING_TOLERANCE
    per_kind: int = 10


def simulated_findings(result: RunResult, what_ran: str,
                       limits: FindingLimits = FindingLimits()) -> list[Diagnostic]:
    """Warnings for what went wrong in ``result``, in time order within each kind, each at the
    line of the instruction active for that robot then. ``what_ran`` names the simulation in
    the messages (e.g. "ideal profile, thesis follower")."""
    plan = result.plan
    path = plan.scenario.path
    findings: list[Diagnostic] = []

    def at(robot: int, tick: int) -> tuple[int, int]:
        formation = plan.formations[int(result.formation[robot, tick])]
        time = float(result.show_time[robot, tick])  # the plan's time the robot was at
        if time >= formation.end and formation.timings:  # after the show: its last instruction
            return formation.timings[-1].span.line, formation.timings[-1].span.col
        return instruction_position(formation, time)

    def add(kind: list[Diagnostic], robot: int, tick: int, message: str, hint: str) -> None:
        line, col = at(robot, tick)
        kind.append(Diagnostic(path, line, col, Severity.WARNING,
                               f"simulated ({what_ran}): {message}", hint))

    contacts: list[Diagnostic] = []
    index = {name: i for i, name in enumerate(result.robots)}
    for event in result.collisions:
        tick = min(int(np.searchsorted(result.times, event.time)), len(result.times) - 1)
        other = {"robot": event.other, "wall": "the wall"}.get(
            event.kind, f"{event.kind} '{event.other}'")
        add(contacts, index[event.robot], tick,
            f"{event.robot} touches {other} at t = {event.time:.1f} s",
            "their paths cross or come too close here: move the formations apart, let one "
            "wait, or slow the show (--vmax)" if event.kind == "robot"
            else "steer the formation clear of it, or let the robots see it (LIDAR)")
    reversing: list[Diagnostic] = []
    off_slot: list[Diagnostic] = []
    during = result.during_show
    step = float(np.median(np.diff(result.times))) if len(result.times) > 1 else 0.0
    shortest = max(1, round(limits.min_duration / step)) if step > 0 else 1
    for i, name in enumerate(result.robots):
        speed = np.where(during, result.velocities[i, :, 0], 0.0)  # as run_metrics
        against = during & against_desired(speed, result.reference[i, :, 3],
                                           tick=samples_per_tick(result),
                                           sample_period=step or None)
        for a, b in true_runs(against):
            if b - a >= shortest:
                add(reversing, i, a, f"{name} drives against its slot's direction from t = "
                    f"{result.times[a]:.1f} s to {result.times[b - 1]:.1f} s",
                    "it drives backwards where its slot moves forwards (or the other way): "
                    "the thesis follower turns round after sharp corners and stops (the "
                    "path and tracking followers do not); give the corners more room or "
                    "slow the show (--vmax)")
        # from where its follower should be (``RunResult.reference``): its rigid slot for
        # tracking, its place on the leader's path for thesis and path
        distance = np.hypot(result.poses[i, :, 0] - result.reference[i, :, 0],
                            result.poses[i, :, 1] - result.reference[i, :, 1])
        moving_over = moving_over_to_place(result, i, distance, limits.min_duration)
        for a, b in true_runs(during & ~moving_over & (distance > limits.slot_distance)):
            if b - a >= shortest:
                add(off_slot, i, a, f"{name} is more than {limits.slot_distance:g} m from its "
                    f"place from t = {result.times[a]:.1f} s to {result.times[b - 1]:.1f} s "
                    f"(up to {distance[a:b].max():.2f} m)",
                    "it cannot keep up or was held: slow the show (--vmax) or give the "
                    "formation more room (a robot close behind another is slowed by its "
                    "LIDAR)")
    outside: list[Diagnostic] = []
    for i, name in enumerate(result.robots):
        distance, out, _ = off_formation(result, i, limits.min_duration)  # (T,) each
        for a, b in true_runs(out):
            if (b - a) * step < limits.min_duration - 1e-9:  # the verdict's rule
                continue
            add(outside, i, a, f"{name} leaves its formation from t = {result.times[a]:.1f} s "
                f"to {result.times[b - 1]:.1f} s (up to {distance[a:b].max():.2f} m from "
                "where the formation puts it, more than the formation is deep plus a robot "
                "length)", "it waits behind the robots ahead where the leader turns too "
                "tightly for the formation (check's note at the turn gives a circle that "
                "keeps the shape), it was held while the others drove on, or it cannot keep "
                "up: widen the turn, or slow the show (--vmax)")
    final: list[Diagnostic] = []
    last = len(result.times) - 1
    for i, name in enumerate(result.robots):
        slot = result.final_slot[i]  # at the plan's end, even if the run ended before it
        gap = float(np.hypot(*(result.poses[i, last, :2] - slot[:2])))
        turn = float(np.degrees(heading_errors(result.poses[i, last, 2], slot[2])))
        if gap > limits.final_distance:
            add(final, i, last, f"{name} ends {gap:.2f} m from its final slot",
                "it did not reach its place in the last formation: see the findings before "
                "this one for why")
        if turn > limits.final_heading:
            add(final, i, last, f"{name} ends facing {turn:.0f} deg away from its final "
                "heading", "it did not reach its place either: see the findings before this "
                "one for why" if gap > limits.final_distance else "it reached its place but "
                "turned round on the way, or could not turn there (see the findings before "
                "this one)")
    for kind in (contacts, reversing, off_slot, outside, final):
        if len(kind) > limits.per_kind:
            more = len(kind) - limits.per_kind + 1
            kind[limits.per_kind - 1:] = [Diagnostic(
                path, kind[limits.per_kind - 1].line, kind[limits.per_kind - 1].col,
                Severity.WARNING, f"simulated ({what_ran}): ... and {more} more like the "
                "ones above", None)]
        findings.extend(kind)
    return findings
