"""How often a robot parking on a final slot near it reverses its turn when its centre moves
a little as it turns on the spot (a skid-steer robot's does): the chatter a spectator sees.

Run: ``.venv/bin/python benchmarks/eval_parking_noise.py [--starts N] [--seed S] [--sigma M]``

Draws the starts of ``benchmarks/eval_parking.py`` (within ``approach_distance`` of a final
slot at the origin, turned beyond ``approach_heading``) and drives an ideal unicycle by
``tracking_step`` at 10 Hz for 30 s from each, twice: as the brain does (the settling flag,
``settling_on_slot``, carried from tick to tick: a robot that came within
``settle_distance`` goes on settling until it is beyond ``face_distance``) and without the
flag (the law of fe88e33, stateless). At every tick it turns on the spot its centre moves by
a seeded normal step of ``sigma`` m (default 2 mm) in x and in y. Prints, for each, how
many runs reverse their turn (the commanded turn rate changes sign while the robot is more
than 30 deg from its heading) once or more and twice or more, the most reversals of a run,
the distances (cm) from the slot where they happen (the most common first), where the runs
end (m: median, 95th percentile, largest; how many beyond ``settle_distance``) and the
latest time a run came to stand still (s). One reversal is the parking's own (it turns to
face the slot, drives onto it, turns to the heading); more are chatter. On 2026-12-07
(default seed and sigma): without the flag 125 of 400 runs reversed, 45 of them twice or
more, 5 the most, nearly all at 5-6 cm (``settle_distance``: a robot that drove onto its
slot reaches it still far off its heading, and a centimetre out ``turn_then_drive_step``
faces the slot again); with it 104 reversed, 3 twice or more, 3 the most, ending as near
(median 4.0 cm against 3.9, 30 beyond ``settle_distance`` against 27).
"""

from __future__ import annotations

import argparse
import collections
import math

import numpy as np

from dancebots.control.tracking import TrackingParams, settling_on_slot, tracking_step
from dancebots.geometry import wrap_angle
from eval_parking import SLOT, TICK, draw_starts

SECONDS = 30.0
OFF = math.radians(30.0)  # rad: reversals count while the robot is farther off its heading


def noisy_parking(params: TrackingParams, start: tuple[float, float, float], sigma: float,
                  seed: int, settling_flag: bool = True) -> tuple[list[float], float, float]:
    """(the distances (m) from the slot of each reversal, the distance at the end (m), the
    time it last came to stand still (s; inf: it never did)) of a unicycle parked from
    ``start`` with its centre moved by N(0, sigma) m in x and y at each tick it turned on
    the spot (``numpy.random.default_rng(seed)``), the settling flag carried as the brain
    does where ``settling_flag`` (else never set)."""
    rng = np.random.default_rng(seed)
    x, y, theta = start
    reversals: list[float] = []
    last = 0.0
    still_from = 0.0
    settling = False
    for tick in range(round(SECONDS / TICK)):
        linear, angular = tracking_step(params, (x, y, theta), SLOT, settling=settling)
        if settling_flag:
            settling = settling_on_slot(params, (x, y, theta), SLOT, settling)
        if angular != 0.0 and abs(wrap_angle(theta)) > OFF:
            sign = math.copysign(1.0, angular)
            if last != 0.0 and sign != last:
                reversals.append(math.hypot(x, y))
            last = sign
        if linear != 0.0 or angular != 0.0:
            still_from = math.inf
        elif math.isinf(still_from):
            still_from = tick * TICK
        if abs(angular) > 1e-12:  # an arc, integrated exactly, or a turn on the spot
            radius = linear / angular
            x += radius * (math.sin(theta + angular * TICK) - math.sin(theta))
            y -= radius * (math.cos(theta + angular * TICK) - math.cos(theta))
        else:
            x += linear * math.cos(theta) * TICK
            y += linear * math.sin(theta) * TICK
        theta += angular * TICK
        if linear == 0.0 and angular != 0.0:
            x += rng.normal(0.0, sigma)
            y += rng.normal(0.0, sigma)
    return reversals, math.hypot(x, y), still_from


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--starts", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--sigma", type=float, default=0.002,
                        help="m: the centre's step at each tick on the spot (default 0.002)")
    args = parser.parse_args(argv)
    if args.starts < 1 or not (math.isfinite(args.sigma) and args.sigma >= 0.0):
        parser.error("--starts must be 1 or more and --sigma a finite length of 0 m or more")
    params = TrackingParams()
    starts = draw_starts(params, args.starts, args.seed)
    print(f"{args.starts} starts within {params.approach_distance} m of a final slot, turned "
          f"beyond {math.degrees(params.approach_heading):g} deg (seed {args.seed}), the centre "
          f"moved {1000 * args.sigma:g} mm a tick on the spot")
    for label, flag in (("with the settling flag (the brain's law)", True),
                        ("without it (stateless, fe88e33)", False)):
        runs = [noisy_parking(params, start, args.sigma, args.seed * 100_003 + k, flag)
                for k, start in enumerate(starts)]
        counts = np.array([len(reversals) for reversals, _, _ in runs])
        ends = np.array([end for _, end, _ in runs])
        still = max(still_from for _, _, still_from in runs)
        where = collections.Counter(round(100 * d) for reversals, _, _ in runs
                                    for d in reversals)
        print(f"{label}:")
        print(f"  runs that reverse their turn: {int(np.sum(counts >= 1))}, twice or more: "
              f"{int(np.sum(counts >= 2))}, the most in a run: {int(counts.max())}")
        print("  where, cm from the slot (reversals): "
              + (", ".join(f"{cm}: {n}" for cm, n in where.most_common(6)) or "none"))
        d50, d95, dmax = np.percentile(ends, [50, 95, 100])
        beyond = int(np.sum(ends > params.settle_distance + 1e-3))
        print(f"  end m: median {d50:.3f}, 95 % {d95:.3f}, max {dmax:.3f}; beyond "
              f"settle_distance {beyond}; the latest to stand still: "
              + ("never" if math.isinf(still) else f"{still:.1f} s"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
