"""What a spectator sees of a formation: the thesis's follower and timing against the additions.

Runs every thesis listing that forms a formation (6.1-6.3, 7.1-7.4; 7.4 also with the thesis's
robots, a HUSKY and a TRADR: ``thesis_7_4+HT``), the bundled demo and the
bundled open-day show (in its hall) with each follower (``thesis``: eq. 4.4; ``tracking``:
Kanayama's law on the rigid slot's motion; ``path``, the default: the same law on the place
on the leader's path) and each timing (``thesis``; ``feasible``, the default: the leader
slows where a slot or place would move faster than 0.8 vmax), in the ideal and realistic profiles,
with and without LIDAR (the thesis follower with the thesis's independent leaders, ``--hold
alone``; the others with the formation's shared clock, ``paced``, the default), and prints
per run:

* ``head°``: the largest heading error against the slot's heading, deg (180: turned round);
* ``rev%``: the share of the time a slot moves that a robot drives against it (at least
  5 cm in one go: ``report.metrics.REVERSE_DISTANCE_MIN``);
* ``rev cm``: the longest way a robot drove against its slot's direction in one go, cm
  (``max_reverse_distance_m``: shorter and slower ones too, e.g. a robot braking while its
  reference turns round);
* ``rev sum``: all such ways of all robots together, cm (``reverse_distance_m``);
* ``flips``: sign flips of the commanded angular speeds (chatter);
* ``slot rms`` / ``slot max``: the distance from the slot, m (over robots and ticks);
* ``spacing``: the largest change of the distance between two robots of one formation, m;
* ``final``: the largest final distance from the slot, m; ``contacts``: collisions;
* ``clean``: 1 when the run's verdict is clean.

The figures are ``metrics.json``'s (``report.metrics``, docs/run-outputs.md).

Run: ``.venv/bin/python benchmarks/eval_formation.py [--quick]`` (``--quick``: 7.1 and 7.2
only, ideal profile).
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

from dancebots.check import CheckOptions
from dancebots.loading import load_show
from dancebots.plan.planner import TIMINGS, Timing
from dancebots.report.metrics import run_metrics
from dancebots.report.verdict import FINAL_SLOT_TOLERANCE, run_verdict
from dancebots.robot import FOLLOWERS, BrainOptions, Follower
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim import PROFILES, prepare_show
from dancebots.sim.lidar import LidarConfig

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "src" / "dancebots" / "data"
SHOWS: list[tuple[str, str | None]] = [
    (f"examples/thesis_{n}.dance", None) for n in ("6_1", "6_2", "6_3", "7_1", "7_2", "7_3",
                                                    "7_4")]
SHOWS += [("examples/thesis_7_4.dance", "examples/worlds/thesis_7_4_husky_tradr.toml"),
          (str(DATA / "demo.dance"), None), (str(DATA / "open_day.dance"),
                                            str(DATA / "open_day.toml"))]


def spectator_figures(result: RunResult) -> dict[str, float]:
    """The figures above, as ``metrics.json`` has them (``report.metrics.run_metrics``)."""
    metrics = run_metrics(result)
    return {"head°": metrics.max_heading_error, "rev%": 100.0 * metrics.reverse_fraction,
            "rev cm": 100.0 * metrics.max_reverse_distance,
            "rev sum": 100.0 * metrics.reverse_distance,
            "flips": metrics.angular_sign_flips, "slot rms": metrics.rms_slot_error,
            "slot max": metrics.max_slot_error, "spacing": metrics.max_formation_error or 0.0,
            "final": metrics.max_final_error, "contacts": metrics.collisions,
            "clean": float(run_verdict(metrics, FINAL_SLOT_TOLERANCE).clean)}


def run(scenario: str, world: str | None, follower: Follower, timing: Timing, profile: str,
        lidar: bool) -> dict[str, float]:
    show = load_show(scenario, world, None, check=CheckOptions(), timing=timing)
    if show.plan is None or show.report is None or show.report.placement is None:
        raise SystemExit(f"{scenario}: does not load: {show.diagnostics}")
    arena, placement = prepare_show(show.report.placement)
    config = SimConfig(profile=PROFILES[profile], lidar=LidarConfig() if lidar else None,
                       brain=BrainOptions(follower=follower),
                       hold=None)  # together; alone for the thesis follower
    return spectator_figures(simulate(show.plan, arena, placement, config))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="7.1 and 7.2, ideal profile")
    args = parser.parse_args()
    shows = SHOWS[3:5] if args.quick else SHOWS
    profiles = ("ideal",) if args.quick else ("ideal", "realistic")
    columns = ("head°", "rev%", "rev cm", "rev sum", "flips", "slot rms", "slot max",
               "spacing", "final",
               "contacts", "clean")
    print(f"{'show':<16} {'profile':<9} {'lidar':<5} {'follower':<8} {'timing':<8} "
          + " ".join(f"{c:>8}" for c in columns))
    for (scenario, world), profile, lidar in itertools.product(shows, profiles, (False, True)):
        for follower, timing in itertools.product(FOLLOWERS, TIMINGS):
            figures = run(scenario, world, follower, timing, profile, lidar)
            name = Path(scenario).stem + ("+HT" if world and "husky" in world else "")
            print(f"{name:<16} {profile:<9} {'on' if lidar else 'off':<5} "
                  f"{follower:<8} {timing:<8} " + " ".join(
                      f"{figures[c]:>8.0f}" if c in ("head°", "flips", "contacts", "clean")
                      else f"{figures[c]:>8.1f}" if c in ("rev%", "rev cm", "rev sum")
                      else f"{figures[c]:>8.3f}"
                      for c in columns), flush=True)


if __name__ == "__main__":
    main()
