"""Where ``check``'s simulation pass spends a 20-robot, 1,000-line show (issue 12's 5 s target).

Run: ``.venv/bin/python benchmarks/bench_check_ticks.py [--show FILE] [--stop-rule R]``
(default: ``bench_compile.big_scenario()``, the 1,000-instruction, 20-robot show, written to a
temporary directory). Runs ``dancebots check SHOW --simulation-limit 50000`` in this process
with timers around the brains' kernel (``robot_batch_jit.brains_tick``, main thread) and the
LIDAR's scans (``sim.stage.scan_clouds``, cast on the second thread for 8 robots or more),
and prints the wall time, the ticks, the kernel's and the rays' time per tick (mean and
median of the calls) and what is left for the rest (Python around the kernels, planning,
building the brains, the result). The compiled work, kernel plus rays, bounds what 2 cores
can do at this fidelity: at best half of it. The rays' time is their wall time on the second
thread, which the kernel's thread slows where the two cores share a physical one. One run:
the machine is shared, so compare ratios and repeat before quoting a figure.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_compile import big_scenario


def timed(calls: list[float], function: Callable[..., Any]) -> Callable[..., Any]:
    """``function`` that appends each call's wall time (s) to ``calls`` (lock-free: one
    list per thread's function)."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            calls.append(time.perf_counter() - start)

    return wrapper


def per_tick(calls: list[float], ticks: int) -> str:
    if not calls:
        return "none"
    return (f"{sum(calls):6.2f} s in {len(calls):,} calls: {sum(calls) / ticks * 1e6:6.0f} us a "
            f"tick (median call {statistics.median(calls) * 1e6:.0f} us)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--show", type=Path, help="choreography (default: the 1,000-line show)")
    parser.add_argument("--stop-rule", default=None, help="check's --stop-rule (default: its)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        show = args.show
        if show is None:
            show = Path(folder) / "big.dance"
            show.write_text(big_scenario())
        from dancebots import robot_batch_jit
        from dancebots.sim import stage

        kernel: list[float] = []
        rays: list[float] = []
        robot_batch_jit.brains_tick = timed(kernel, robot_batch_jit.brains_tick)
        stage.scan_clouds = timed(rays, stage.scan_clouds)  # type: ignore[assignment]
        command = ["dancebots", "check", str(show), "--simulation-limit", "50000"]
        if args.stop_rule:
            command += ["--stop-rule", args.stop_rule]
        cli = importlib.import_module("dancebots.cli.main")
        sys.argv = command
        start = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            try:
                cli.main()
            except SystemExit as stop:
                status = stop.code
            else:
                status = 0
        wall = time.perf_counter() - start
    ticks = len(kernel)
    if not ticks:
        print(f"check exited {status} without running the batched brains: nothing to time")
        raise SystemExit(1)
    compiled = sum(kernel) + sum(rays)
    print(f"check {show.name}: exit {status}, {wall:.2f} s wall in this process, "
          f"{ticks:,} ticks")
    print(f"  brains' kernel: {per_tick(kernel, ticks)}")
    print(f"  LIDAR rays:     {per_tick(rays, ticks)}")
    print(f"  the rest (Python around them, planning, brains, result): "
          f"{wall - sum(kernel):.2f} s on the main thread")
    print(f"  compiled work {compiled:.2f} s: on 2 cores at least {compiled / 2:.2f} s "
          f"at this fidelity, before any Python (target 5 s)")


if __name__ == "__main__":
    main()
