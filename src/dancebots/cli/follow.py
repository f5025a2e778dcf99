"""``dancebots follow``: the queue show of the second seed (a thin shell).

Loads the world (the bundled obstacle course by default), runs ``shows.queue`` with the chosen
detector and controller, and writes metrics.json, queue.png, animation.gif (and .mp4 with
ffmpeg) and log.csv through the output writer, like ``dancebots run``. Exit 0 when the queue
ran clean, 1 when not (a contact, a broken queue).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from dancebots.cli.common import (
    PROFILES,
    ShowOutcome,
    bundled,
    in_range,
    print_verdict,
    profile_missing,
    progress,
    refuse,
    run_show_into,
    short_path,
)

if TYPE_CHECKING:
    from rich.console import Console

    from dancebots.report.queue_metrics import QueueMetrics
    from dancebots.report.verdict import Verdict
    from dancebots.shows.queue import QueueResult

__all__ = ["BUNDLED_WORLDS"]

NAME = "follow"
HELP = ("a queue of robots each following the object in front of it with its LIDAR alone "
        "(second seed): metrics, plot, animation, log")
DESCRIPTION = ("Simulate a queue of robots that each follow the object in front of them with "
               "their LIDAR alone (the workshop paper's leader-follower strategy). Exit 0 when "
               "the queue ran clean, 1 when a robot touched something or the queue broke, 2 "
               "on invalid input.")

BUNDLED_WORLDS = {"course": "follow_course.toml", "crossing": "follow_crossing.toml"}
"""``--world`` names of the bundled queue worlds (src/dancebots/data/)."""
DETECTORS = ("a1", "a2", "a2-track")
"""``leader_follower.detectors.DETECTORS`` (a test keeps them equal)."""
CONTROLLERS = ("pid", "vo")
"""``leader_follower.controllers.CONTROLLERS``."""
LEADERS = ("person", "robot")
"""``shows.queue.LEADERS``."""
OUTPUT_NAMES = ("show.html", "log.csv", "run.mcap", "queue.png", "animation.gif",
                "animation.mp4", "metrics.json")
"""Every file a queue run may write into its output directory (besides the manifest)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--world", metavar="W", help="world file with a spectator named "
                        "'leader' whose path the queue follows, or a bundled world: 'course' "
                        "(the obstacle course, default) or 'crossing' (the course with a "
                        "person crossing the queue)")
    parser.add_argument("--robots", type=in_range(1, 20, integer=True), default=3,
                        metavar="N", help="followers, 1 to 20 (default 3)")
    parser.add_argument("--leader", choices=LEADERS, default="person",
                        help="person: the world's 'leader' walks its path (default); robot: a "
                        "robot drives that path, timed as the person walks it")
    parser.add_argument("--detector", choices=DETECTORS, default="a1",
                        help="a1: DBSCAN clusters; a2: Kalman tracks, the seed's target rule; "
                        "a2-track: Kalman tracks, the target is its track (default a1)")
    parser.add_argument("--controller", choices=CONTROLLERS, default="pid",
                        help="pid: go-to-goal PID (B1); vo: velocity obstacles (B2)")
    parser.add_argument("--rvo", action="store_true", help="reciprocal velocity obstacles")
    parser.add_argument("--gains", choices=("first", "tuned"), default="first",
                        help="the pid controller's seed gains: first (Kp_u 1.2, Kp_w 0.5, "
                        "default) or tuned (Kp_u 0.6, Kp_w 0.1, Ki_w 0.01)")
    parser.add_argument("--standoff", type=in_range(0.2, 3.0), default=0.5, metavar="M",
                        help="distance kept to the object in front, 0.2 to 3 m (default 0.5)")
    parser.add_argument("--profile", choices=PROFILES, default="ideal",
                        help="ideal: commands act at once; realistic: inertia, lag and noise; "
                        "physics: the robots' bodies and wheels in MuJoCo (needs `pip install "
                        "'dancebots[physics]'`) (default: ideal)")
    parser.add_argument("--seed", type=in_range(0, 2**32 - 1, integer=True), default=0,
                        metavar="N", help="seed of the noise of the realistic profile (default 0)")
    parser.add_argument("--out", metavar="DIR", help="output directory (default "
                        "out/follow-DETECTOR-CONTROLLER); same rules as `dancebots run --out`")
    parser.add_argument("--no-animation", action="store_true", help="skip the GIF/MP4")
    parser.add_argument("--json", action="store_true",
                        help="print the summary and the verdict as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from dancebots.diagnostics import DiagnosticError, read_source_file, source_lines
    from dancebots.report.queue_metrics import queue_metrics
    from dancebots.report.verdict import queue_verdict
    from dancebots.shows.queue import QueueConfig, simulate_queue
    from dancebots.sim.kinematics import PROFILES as CORE_PROFILES
    from dancebots.sim.setup import SetupError
    from dancebots.world import load_world

    missing = profile_missing(args.profile)
    if missing is not None:
        return refuse(NAME, args.json, missing)
    world_path = args.world or "course"
    if world_path in BUNDLED_WORLDS and not Path(world_path).exists():
        world_path = short_path(bundled(BUNDLED_WORLDS[world_path]))
    try:
        world = load_world(world_path)
    except DiagnosticError as exc:
        if not Path(world_path).exists():
            bundled_names = ", ".join(BUNDLED_WORLDS)
            exc = DiagnosticError([replace(d, hint=f"{d.hint}; or name a bundled world: "
                                           f"{bundled_names}") for d in exc.diagnostics])
        text, _ = read_source_file(world_path)
        return refuse(NAME, args.json, diagnostics=exc.diagnostics,
                      sources={world_path: source_lines(text or "")})
    config = QueueConfig(robots=int(args.robots), detector=args.detector,
                         controller=args.controller, standoff=args.standoff,
                         profile=CORE_PROFILES[args.profile], seed=int(args.seed),
                         reciprocal=args.rvo, gains=args.gains, leader=args.leader)
    target = Path(args.out or f"out/follow-{args.detector}-{args.controller}")
    console = Console(stderr=True, soft_wrap=True)

    def simulate_and_write(staging: Path) -> ShowOutcome:
        started = time.perf_counter()
        with progress(console, "simulating  (s)") as update:
            result = simulate_queue(world, config, update)
        wall = time.perf_counter() - started
        metrics = queue_metrics(result)
        verdict = queue_verdict(metrics)
        written = _write(result, metrics, verdict, staging, not args.no_animation, console)
        return ShowOutcome(written, wall, verdict, metrics.to_json(), lambda: _summary(
            metrics, verdict, wall, target, written, world_path))

    try:
        return run_show_into(NAME, target, OUTPUT_NAMES, args.json, simulate_and_write)
    except SetupError as exc:  # the world cannot hold this queue (e.g. it has no leader)
        return refuse(NAME, args.json, str(exc))


def _write(result: QueueResult, metrics: QueueMetrics, verdict: Verdict, directory: Path,
           animation: bool, console: Console) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dancebots.report.mcap_log import write_queue_mcap
    from dancebots.report.queue_animation import animate_queue
    from dancebots.report.queue_log import write_queue_log
    from dancebots.report.queue_plots import plot_queue
    from dancebots.report.replay import write_queue_replay_html

    with open(directory / "log.csv", "w", encoding="utf-8") as handle:
        write_queue_log(result, handle)
    with progress(console, "run.mcap (ticks)") as update:
        write_queue_mcap(result, str(directory / "run.mcap"), update)
    figure = plot_queue(result)
    figure.savefig(directory / "queue.png", dpi=110)
    plt.close(figure)
    write_queue_replay_html(result, str(directory / "show.html"))
    written = ["show.html", "log.csv", "run.mcap", "queue.png"]
    if animation:
        from dancebots.report.frames import ffmpeg_available

        names = ["animation.gif"] + (["animation.mp4"] if ffmpeg_available() else [])
        with progress(console, f"{' and '.join(names)} (frames)") as update:
            animate_queue(result, [str(directory / name) for name in names], progress=update)
        written.extend(names)
    (directory / "metrics.json").write_text(json.dumps(
        {**metrics.to_json(), "verdict": verdict.to_json()}, indent=2) + "\n", encoding="utf-8")
    return [*written, "metrics.json"]


def _summary(metrics: QueueMetrics, verdict: Verdict, wall: float, target: Path,
             written: list[str], world: str) -> None:
    from rich.console import Console
    from rich.table import Table

    out = Console(soft_wrap=True, width=None if sys.stdout.isatty() else 120)
    table = Table(title=f"{world}: detector {metrics.detector}, controller "
                  f"{metrics.controller}, stand-off {metrics.standoff:g} m",
                  title_justify="left")
    for column in ("robot", "median error m", "max |error| m", "lost s", "kidnappings",
                   "kidnapped s", "collisions", "final gap m"):
        table.add_column(column, justify="left" if column == "robot" else "right")
    for f in metrics.followers:
        table.add_row(f.robot, f"{f.median_error:.3f}", f"{f.max_error:.3f}",
                      f"{f.lost_time:.1f}", str(f.kidnappings), f"{f.kidnapped_time:.1f}",
                      str(f.collisions), f"{f.final_gap:.2f}")
    out.print(table)
    out.print(f"simulated {metrics.duration:.1f} s in {wall:.2f} s; queue "
              + ("intact" if metrics.intact else "BROKEN"),
              style="green" if metrics.intact else "bold red", highlight=False)
    out.print(f"wrote {target}/: {', '.join(written)}", highlight=False)
    print_verdict(out, verdict, "queue")
