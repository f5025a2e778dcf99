"""What a spectator sees of a formation: the thesis's follower and timing against the additions.

Runs every thesis listing that forms a formation (6.1-6.3, 7.1-7.4), the bundled demo and the
bundled open-day show (in its hall) with each follower (``thesis``: eq. 4.4; ``tracking``:
Kanayama's law on the slot's motion) and each timing (``thesis``; ``feasible``: the leader
slows where a slot would move faster than 0.8 vmax), in the ideal and realistic profiles,
with and without LIDAR, and prints per run:

* ``head°``: the largest heading error against the slot's heading, deg (180: turned round);
* ``rev%``: the share of the show a robot drives against its slot's direction of motion;
* ``flips``: the most sign flips of one robot's commanded angular speed (chatter);
* ``slot rms`` / ``slot max``: the distance from the slot, m (over robots and ticks);
* ``spacing``: the largest change of the distance between two robots of one formation, m;
* ``final``: the largest final distance from the slot, m; ``contacts``: collisions.

Run: ``.venv/bin/python benchmarks/eval_formation.py [--quick]`` (``--quick``: 7.1 and 7.2
only, ideal profile).
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import numpy as np

from dancebots.check import CheckOptions
from dancebots.loading import load_show
from dancebots.plan.planner import TIMINGS, Timing
from dancebots.robot import FOLLOWERS, BrainOptions, Follower
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim import PROFILES, prepare_show
from dancebots.sim.lidar import LidarConfig

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "src" / "dancebots" / "data"
SHOWS = [(f"examples/thesis_{n}.dance", None) for n in ("6_1", "6_2", "6_3", "7_1", "7_2",
                                                         "7_3", "7_4")]
SHOWS += [(str(DATA / "demo.dance"), None), (str(DATA / "open_day.dance"),
                                            str(DATA / "open_day.toml"))]


def spectator_figures(result: RunResult) -> dict[str, float]:
    """The figures above from one run (world frame; ticks of the show only)."""
    during = result.times <= result.plan.duration
    poses, desired = result.poses[:, during], result.desired[:, during]
    heading = np.abs(np.angle(np.exp(1j * (poses[..., 2] - desired[..., 2]))))
    step = np.diff(desired[..., :2], axis=1)
    along = step[..., 0] * np.cos(desired[:, 1:, 2]) + step[..., 1] * np.sin(desired[:, 1:, 2])
    speed = result.velocities[:, during][:, 1:, 0]
    against = (np.abs(along) > 0.005) & (np.abs(speed) > 0.02) & (
        np.sign(speed) != np.sign(along))
    turn = result.commands[:, during, 1]
    signs = np.sign(np.where(np.abs(turn) > 0.05, turn, 0.0))
    flips = max(int(np.sum(signs[i, 1:] * signs[i, :-1] < 0)) for i in range(len(signs)))
    slot = np.hypot(*(poses[..., :2] - desired[..., :2]).transpose(2, 0, 1))
    spacing = 0.0
    for a, b in itertools.combinations(range(len(result.robots)), 2):
        same = result.formation[a, during] == result.formation[b, during]
        actual = np.hypot(*(poses[a, :, :2] - poses[b, :, :2]).T)
        wanted = np.hypot(*(desired[a, :, :2] - desired[b, :, :2]).T)
        if same.any():
            spacing = max(spacing, float(np.abs(actual - wanted)[same].max()))
    final = np.hypot(*(result.poses[:, -1, :2] - result.desired[:, -1, :2]).T)
    return {"head°": float(np.degrees(heading.max())), "rev%": 100.0 * float(against.mean()),
            "flips": flips, "slot rms": float(np.sqrt((slot ** 2).mean())),
            "slot max": float(slot.max()), "spacing": spacing, "final": float(final.max()),
            "contacts": len(result.collisions)}


def run(scenario: str, world: str | None, follower: Follower, timing: Timing, profile: str,
        lidar: bool) -> dict[str, float]:
    show = load_show(scenario, world, None, check=CheckOptions(), timing=timing)
    if show.plan is None or show.report is None or show.report.placement is None:
        raise SystemExit(f"{scenario}: does not load: {show.diagnostics}")
    arena, placement = prepare_show(show.report.placement)
    config = SimConfig(profile=PROFILES[profile], lidar=LidarConfig() if lidar else None,
                       brain=BrainOptions(follower=follower))
    return spectator_figures(simulate(show.plan, arena, placement, config))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="7.1 and 7.2, ideal profile")
    args = parser.parse_args()
    shows = SHOWS[3:5] if args.quick else SHOWS
    profiles = ("ideal",) if args.quick else ("ideal", "realistic")
    columns = ("head°", "rev%", "flips", "slot rms", "slot max", "spacing", "final",
               "contacts")
    print(f"{'show':<16} {'profile':<9} {'lidar':<5} {'follower':<8} {'timing':<8} "
          + " ".join(f"{c:>8}" for c in columns))
    for (scenario, world), profile, lidar in itertools.product(shows, profiles, (False, True)):
        for follower, timing in itertools.product(FOLLOWERS, TIMINGS):
            figures = run(scenario, world, follower, timing, profile, lidar)
            print(f"{Path(scenario).stem:<16} {profile:<9} {'on' if lidar else 'off':<5} "
                  f"{follower:<8} {timing:<8} " + " ".join(
                      f"{figures[c]:>8.0f}" if c in ("head°", "flips", "contacts")
                      else f"{figures[c]:>8.1f}" if c == "rev%" else f"{figures[c]:>8.3f}"
                      for c in columns), flush=True)


if __name__ == "__main__":
    main()
