"""Time to parse, plan and check a 1,000-instruction, 20-robot choreography (target < 1 s),
and crowds of 1,000 robots (target: check under 1 s).

Run: ``.venv/bin/python benchmarks/bench_compile.py [--repeat N] [--write FILE]``
(``--write``: also save the 1,000-instruction choreography, e.g. to time ``dancebots check
FILE --simulation-limit 50000``, which simulates it). Prints the median and the
spread of N runs of each stage (one core, wall clock: the machine is shared, so compare
medians and ratios, not single runs).
"""

from __future__ import annotations

import argparse
import statistics
import time

from dancebots.check import check_plan
from dancebots.plan import build_plan
from dancebots.scenario import parse_scenario


def big_scenario(instructions: int = 1000, robots: int = 20) -> str:
    """20 robots in a 4 x 5 grid that splits into two halves and joins again, repeatedly,
    with gentle moves and circles: every construct of the language, deterministic."""
    names = [f"R{i + 1}" for i in range(robots)]
    left = [n for i, n in enumerate(names) if i % 5 < 2]
    right = [n for n in names if n not in left]
    rows = [names[r * 5:(r + 1) * 5] for r in range(4)]
    grid = "square " + ";".join(",".join(row) for row in rows) + " 2 1.5"
    half_l = "square " + ";".join(",".join(n for n in row if n in left) for row in rows)
    half_r = "square " + ";".join(",".join(n for n in row if n in right) for row in rows)
    lines = ["robots " + " ".join(names), "groups", "left " + " ".join(left),
             "right " + " ".join(right), "start", grid]
    body = 1
    cycle = 0
    while body < instructions:
        block = [f"move {2 + cycle % 3} {(-1) ** cycle}", "circle 15 10 0.02",
                 half_l + " 2 1.5", half_r + " 2 1.5", "newVL",
                 "move 1 2 left", "move 1 -2 right", "move 1 -2 left", "move 1 2 right",
                 grid, "newVL"]
        lines.extend(block)
        body += len(block)
        cycle += 1
    return "\n".join(lines) + "\n"


def crowd_scenario(robots: int = 1000, split: bool = False) -> str:
    """``robots`` robots side by side in one row that moves 2 m; with ``split``, the left half
    then forms a row of its own that turns away from the rest: robot pairs of different
    formations, compared at every sample."""
    names = [f"R{i + 1}" for i in range(robots)]
    half = names[: robots // 2]
    lines = ["robots " + " ".join(names), "groups", "left " + " ".join(half), "start",
             "row " + ",".join(names) + " 0 1.2", "move 2 0"]
    if split:
        lines += ["row " + ",".join(half) + " 0 1.2", "newVL", "move 20 10 left"]
    return "\n".join(lines) + "\n"


def bench_crowds(repeat: int) -> None:
    """Median check time of the 1,000-robot crowds (the robot-pair checks' worst cases)."""
    for split in (False, True):
        text = crowd_scenario(1000, split)
        scenario, diagnostics = parse_scenario(text, "crowd.dance")
        assert scenario is not None, diagnostics[:3]
        plan, diagnostics = build_plan(scenario)
        assert plan is not None, diagnostics[:3]
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            report = check_plan(plan)
            times.append(time.perf_counter() - t0)
        label = "1,000 robots, split in two" if split else "1,000 robots in one row"
        median = statistics.median(times)
        print(f"{label}: show {plan.duration:.0f} s, {len(report.diagnostics)} warnings, check "
              f"median {median * 1000:.1f} ms (min {min(times) * 1000:.1f}, max "
              f"{max(times) * 1000:.1f}) -> {'meets' if median < 1.0 else 'MISSES'} < 1 s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--write", metavar="FILE", help="also write the choreography to FILE "
                        "(refused if FILE exists)")
    args = parser.parse_args()
    text = big_scenario()
    if args.write:
        with open(args.write, "x", encoding="utf-8") as out:  # never overwrites a file
            out.write(text)
    stages: dict[str, list[float]] = {"parse": [], "plan": [], "check": [], "total": []}
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        scenario, diagnostics = parse_scenario(text, "bench.dance")
        t1 = time.perf_counter()
        assert scenario is not None, diagnostics[:3]
        plan, diagnostics = build_plan(scenario)
        t2 = time.perf_counter()
        assert plan is not None, diagnostics[:3]
        report = check_plan(plan)
        t3 = time.perf_counter()
        for name, value in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t3 - t0), strict=True):
            stages[name].append(value)
    count = sum(1 for line in text.splitlines()[5:] if line.strip())
    print(f"scenario: {count} instruction lines, {len(scenario.robots)} robots, "
          f"{len(plan.formations)} formations, show {plan.duration:.0f} s, "
          f"{len(report.diagnostics)} warnings")
    for name, values in stages.items():
        print(f"{name:>6}: median {statistics.median(values) * 1000:8.1f} ms   "
              f"min {min(values) * 1000:8.1f} ms   max {max(values) * 1000:8.1f} ms")
    verdict = "meets" if statistics.median(stages["total"]) < 1.0 else "MISSES"
    print(f"target: check and plan under 1 s on one core -> {verdict} it")
    bench_crowds(args.repeat)


if __name__ == "__main__":
    main()
