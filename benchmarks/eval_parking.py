"""How robots park on a final slot near them while turned away from its heading: the turn they
make and where they end, for ``TrackingParams.handover_turn`` values and the posture law it
replaced there.

Run: ``.venv/bin/python benchmarks/eval_parking.py [--starts N] [--seed S]``

Draws N starts (seeded) within ``approach_distance`` of a final slot at the origin facing +x
(0.07 m to ``approach_distance`` away, in any direction) with the robot's heading more than
``approach_heading`` from the slot's, and drives an ideal unicycle by ``tracking_step`` at
10 Hz for 25 s from each (the settling flag carried as the brain does). Prints, per law:
the distance from the slot at the end (m: median, 95th percentile, largest; how many end
beyond ``settle_distance``), the largest heading error at the end (deg), and the turn
beyond the start's heading error (summed |dtheta| minus |heading error at the start|, deg:
median, 95th percentile, largest: a robot that only turns to the heading scores 0, one that
swings out and back twice the swing). "posture law" is
``parking_step`` (Aicardi et al. 1995; reverse where the slot is behind the robot) where
``turn_then_drive_step`` now drives, the law before 2026-11-29.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from dancebots.control.tracking import (
    SlotReference,
    TrackingParams,
    parking_step,
    settling_on_slot,
    tracking_step,
)
from dancebots.geometry import Pose, wrap_angle

SLOT = SlotReference((0.0, 0.0, 0.0), 0.0, 0.0, final=True)
TICK = 0.1  # s
SECONDS = 25.0
SEED_135_R4 = (0.108, -0.101, 1.872)  # m, m, rad: 0.15 m from its slot, 107 deg off


def posture_law_step(params: TrackingParams, pose: tuple[float, float, float],
                     reference: SlotReference, settling: bool = False) -> tuple[float, float]:
    """``tracking_step`` with the posture law where it now turns and drives (the law before)."""
    ex, ey = Pose(*pose).to_local(reference.pose[0], reference.pose[1])
    heading_error = wrap_angle(reference.pose[2] - pose[2])
    distance = math.hypot(ex, ey)
    if (params.settle_distance < distance <= params.approach_distance
            and math.cos(heading_error) <= math.cos(params.approach_heading)):
        linear, angular = parking_step(params, distance, math.atan2(ey, ex), heading_error,
                                       ex < 0.0)
        scale = 1.0
        if abs(linear) > params.max_linear:
            scale = params.max_linear / abs(linear)
        if abs(angular) * scale > params.max_angular:
            scale = params.max_angular / abs(angular)
        return linear * scale, angular * scale
    return tracking_step(params, pose, reference, settling=settling)


def drive(step, params: TrackingParams, start: tuple[float, float, float],  # type: ignore[no-untyped-def]
          ) -> tuple[float, float, float]:
    """(distance m, |heading error| rad at the end, turn rad summed) of an ideal unicycle
    (the settling flag carried as the brain does, ``settling_on_slot``)."""
    x, y, theta = start
    turned = 0.0
    settling = False
    for _ in range(round(SECONDS / TICK)):
        linear, angular = step(params, (x, y, theta), SLOT, settling=settling)
        settling = settling_on_slot(params, (x, y, theta), SLOT, settling)
        x += linear * math.cos(theta) * TICK
        y += linear * math.sin(theta) * TICK
        theta += angular * TICK
        turned += abs(angular) * TICK
    return math.hypot(x, y), abs(wrap_angle(theta)), turned


def draw_starts(params: TrackingParams, count: int, seed: int) -> list[tuple[float, float, float]]:
    """``count`` poses (x, y, heading) within approach_distance, turned beyond approach_heading."""
    rng = np.random.default_rng(seed)
    starts: list[tuple[float, float, float]] = []
    while len(starts) < count:
        radius = rng.uniform(0.07, params.approach_distance)
        angle, heading = rng.uniform(-math.pi, math.pi, size=2)
        if abs(heading) > params.approach_heading:
            starts.append((radius * math.cos(angle), radius * math.sin(angle), heading))
    return starts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--starts", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    base = TrackingParams()
    starts = draw_starts(base, args.starts, args.seed)
    laws = [("posture law (before)", posture_law_step, base)]
    for turn in (0.0, math.pi / 4, math.pi / 2, math.pi, math.inf):
        name = "handover_turn " + ("inf" if math.isinf(turn) else f"{math.degrees(turn):g} deg")
        if math.isclose(turn, base.handover_turn):
            name += " (default)"
        laws.append((name, tracking_step, TrackingParams(handover_turn=turn)))
    print(f"{args.starts} starts within {base.approach_distance} m of a final slot, turned "
          f"beyond {math.degrees(base.approach_heading):g} deg from its heading (seed {args.seed})")
    print(f"{'law':32s} {'end m: median':>14s} {'p95':>6s} {'max':>6s} {'> settle':>9s} "
          f"{'heading max':>12s} {'extra turn deg: median':>23s} {'p95':>5s} {'max':>5s}")
    for name, step, params in laws:
        ends = np.array([drive(step, params, start) for start in starts])
        extra = np.degrees(ends[:, 2] - np.abs([start[2] for start in starts]))
        d50, d95, dmax = np.percentile(ends[:, 0], [50, 95, 100])
        t50, t95, tmax = np.percentile(extra, [50, 95, 100])
        beyond = int(np.sum(ends[:, 0] > params.settle_distance + 1e-3))
        print(f"{name:32s} {d50:14.3f} {d95:6.3f} {dmax:6.3f} {beyond:9d} "
              f"{math.degrees(ends[:, 1].max()):12.1f} {t50:23.0f} {t95:5.0f} {tmax:5.0f}")
    # dense crowd seed 135's R4 at the show's end, in its final slot's frame (docs/control.md)
    for name, step in (("posture law (before)", posture_law_step), ("now", tracking_step)):
        distance, error, turned = drive(step, base, SEED_135_R4)
        print(f"dense seed 135's R4 from {SEED_135_R4}, {name}: turned "
              f"{math.degrees(turned):.0f} deg, ends {100 * distance:.1f} cm from the slot, "
              f"{math.degrees(error):.1f} deg off")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
