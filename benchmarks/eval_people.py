"""Shows among people (issue 13): the figures of its targets, measured.

Run: ``.venv/bin/python benchmarks/eval_people.py [--runs N] [--skip-speedup]
[--stop-rule predicted|fixed|closing|ssm] [--hold paced|together|alone]`` (the
certification's stop rule, default predicted, and hold strategy, default paced: the project's
defaults)

Prints:
1. ``dancebots certify`` of the bundled open-day show among a random crowd
   (``data/open_day_crowd.toml``, realistic profile) over N seeds on 2 local processes:
   contacts of a moving robot with a person (target 0 over 1,000 seeds), contacts with a
   robot standing still, the smallest robot-person gap, the time robots were held, how far
   the formation drifted while one waited (target: 0.10 m), runs per minute and the
   projected time of 1,000 runs (target: under 10 minutes on this machine's 2 cores);
2. the same N seeds on 1 process: the speed-up of 2 processes (skipped with
   ``--skip-speedup``);
3. the default ideal run of the open-day show (scripted visitors): how far any robot was from
   its place while one was held (target 0.10 m).

Each certification is a real ``dancebots certify`` process; the machine is shared, so compare
the ratio, not single times.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path


def certify(runs: int, jobs: int, out: Path, stop_rule: str,
            hold: str = "together") -> dict[str, object]:
    done = subprocess.run([sys.executable, "-m", "dancebots.cli", "certify", "--runs",
                           str(runs), "--jobs", str(jobs), "--out", str(out), "--json",
                           "--stop-rule", stop_rule, "--hold", hold],
                          capture_output=True, text=True, check=False)
    if done.returncode not in (0, 1):
        raise SystemExit(f"certify failed ({done.returncode}):\n{done.stderr[-2000:]}")
    result: dict[str, object] = json.loads(done.stdout)["metrics"]
    return result


def default_run(out: Path) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-m", "dancebots.cli", "run", "--no-animation",
                           "--out", str(out), "--json"], capture_output=True, text=True,
                          check=False)
    result: dict[str, object] = json.loads(done.stdout)["metrics"]
    return result


def _without_walls(cert: dict[str, object]) -> list[dict[str, object]]:
    """The per-run lines without their wall times (which differ from run to run)."""
    runs = cert["per_run"]
    assert isinstance(runs, list)
    return [{k: v for k, v in r.items() if k != "wall"} for r in runs]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--skip-speedup", action="store_true")
    parser.add_argument("--stop-rule", choices=("predicted", "fixed", "closing", "ssm"),
                        default="predicted")
    parser.add_argument("--hold", choices=("paced", "together", "alone"), default="paced")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        two = certify(args.runs, 2, Path(scratch) / "two", args.stop_rule, args.hold)
        gap, held, apart = two["min_person_gap_m"], two["held_robot_s"], two[
            "held_place_error_m"]
        assert isinstance(gap, dict)
        assert isinstance(held, dict)
        assert isinstance(apart, dict)
        wall2 = float(two["wall_s"])  # type: ignore[arg-type]
        print(f"certify, bundled open-day show among a crowd, realistic, {args.runs} seeds, "
              f"stop rule {args.stop_rule}, hold {args.hold}, 2 processes:")
        print(f"  contacts of a moving robot with a person: {two['contacts_moving']} "
              f"(runs with one: {two['runs_with_contacts_moving']}); with a robot standing "
              f"still: {two['contacts_standing']}; robots with robots/walls: "
              f"{two['robot_contacts']}")
        print(f"  smallest robot-person gap per run, m: min {gap['min']}, 5 % {gap['p5']}, "
              f"median {gap['median']}")
        print(f"  robots held, robot-s per run: median {held['median']}, max {held['max']}")
        print(f"  farthest from its place while one was held, m: median {apart['median']}, "
              f"max {apart['max']}  (target 0.10)")
        print(f"  shows that did not finish (waited beyond the run's limit): "
              f"{two['runs_unfinished']}; runs not clean: {two['runs_not_clean']}")
        print(f"  wall {wall2:.1f} s: {60 * args.runs / wall2:.1f} runs/min; 1,000 runs "
              f"projected {1000 * wall2 / args.runs / 60:.1f} min (target < 10)")
        if not args.skip_speedup:
            one = certify(args.runs, 1, Path(scratch) / "one", args.stop_rule, args.hold)
            wall1 = float(one["wall_s"])  # type: ignore[arg-type]
            same = _without_walls(one) == _without_walls(two)
            print(f"  1 process: {wall1:.1f} s; speed-up of 2 processes {wall1 / wall2:.2f}x; "
                  f"same per-run results: {same}")
        metrics = default_run(Path(scratch) / "default")
        print("default ideal run of the open-day show (scripted visitors): farthest from its "
              f"place while a robot was held {metrics['held_place_error_m']} m (target 0.10), "
              f"stops {metrics['stops']}, smallest gap to a person "
              f"{metrics['min_person_gap_m']} m")


if __name__ == "__main__":
    main()
