"""``dancebots follow``: the queue show of the second seed (a thin shell).

Loads the world (the bundled obstacle course by default), runs ``sim.queue`` with the chosen
detector and controller, and writes metrics.json, queue.png, animation.gif (and .mp4 with
ffmpeg) and log.csv through a staging directory, like ``dancebots run``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from dancebots.cli import EXIT_INVALID, EXIT_OK, bundled, print_diagnostics
from dancebots.diagnostics import DiagnosticError, read_source_file
from dancebots.leader_follower.controllers import CONTROLLERS
from dancebots.leader_follower.detectors import DETECTORS
from dancebots.report.follow import (
    QueueMetrics,
    animate_queue,
    metrics_json,
    plot_queue,
    queue_metrics,
    write_queue_log,
)
from dancebots.run_command import _check_output, _progress, _short, write_staged
from dancebots.sim.kinematics import PROFILES
from dancebots.sim.queue import LEADERS, QueueConfig, QueueResult, simulate_queue
from dancebots.sim.setup import SetupError
from dancebots.world import load_world

__all__ = ["BUNDLED_WORLDS", "add_follow_parser", "run_follow"]

BUNDLED_WORLDS = {"course": "follow_course.toml", "crossing": "follow_crossing.toml"}
"""``--world`` names of the bundled queue worlds (src/dancebots/data/)."""


def add_follow_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    follow = commands.add_parser(
        "follow", help="a queue of robots each following the object in front of it with its "
        "LIDAR alone (second seed): metrics, plot, animation, log")
    follow.add_argument("--world", metavar="W", help="world file with a spectator named "
                        "'leader' whose path the queue follows, or a bundled world: 'course' "
                        "(the obstacle course, default) or 'crossing' (the course with a "
                        "person crossing the queue)")
    follow.add_argument("--robots", type=int, default=3, help="followers (default 3)")
    follow.add_argument("--leader", choices=LEADERS, default="person",
                        help="person: the world's 'leader' walks its path (default); robot: a "
                        "robot drives that path, timed as the person walks it")
    follow.add_argument("--detector", choices=DETECTORS, default="a1",
                        help="a1: DBSCAN clusters; a2: Kalman tracks, the seed's target rule; "
                        "a2-track: Kalman tracks, the target is its track (default a1)")
    follow.add_argument("--controller", choices=CONTROLLERS, default="pid",
                        help="pid: go-to-goal PID (B1); vo: velocity obstacles (B2)")
    follow.add_argument("--rvo", action="store_true", help="reciprocal velocity obstacles")
    follow.add_argument("--gains", choices=("first", "tuned"), default="first",
                        help="the pid controller's seed gains: first (Kp_u 1.2, Kp_w 0.5, "
                        "default) or tuned (Kp_u 0.6, Kp_w 0.1, Ki_w 0.01)")
    follow.add_argument("--standoff", type=float, default=0.5, metavar="M",
                        help="distance kept to the object in front, m (default 0.5)")
    follow.add_argument("--profile", choices=sorted(PROFILES), default="ideal")
    follow.add_argument("--seed", type=int, default=0)
    follow.add_argument("--out", metavar="DIR", help="output directory (default "
                        "out/follow-DETECTOR-CONTROLLER)")
    follow.add_argument("--no-animation", action="store_true")


def _fail(message: str) -> int:
    print(f"dancebots follow: error: {message}", file=sys.stderr)
    return EXIT_INVALID


def run_follow(args: argparse.Namespace) -> int:
    world_path = args.world or "course"
    if world_path in BUNDLED_WORLDS and not Path(world_path).exists():
        world_path = _short(bundled(BUNDLED_WORLDS[world_path]))
    try:
        world = load_world(world_path)
    except DiagnosticError as exc:
        text, _ = read_source_file(world_path)
        print_diagnostics(exc.diagnostics, {world_path: (text or "").splitlines()})
        return EXIT_INVALID
    if not 1 <= args.robots <= 20:
        return _fail(f"--robots {args.robots} is outside 1 to 20")
    if not 0.2 <= args.standoff <= 3.0:
        return _fail(f"--standoff {args.standoff} is outside 0.2 to 3 m")
    target = Path(args.out or f"out/follow-{args.detector}-{args.controller}")
    problem = _check_output(target)
    if problem:
        return _fail(problem)
    config = QueueConfig(robots=args.robots, detector=args.detector,
                         controller=args.controller, standoff=args.standoff,
                         profile=PROFILES[args.profile], seed=args.seed, reciprocal=args.rvo,
                         gains=args.gains, leader=args.leader)
    console = Console(stderr=True)
    started = time.perf_counter()
    try:
        with _progress(console, "simulating  (s)") as update:
            result = simulate_queue(world, config, update)
    except SetupError as exc:
        return _fail(str(exc))
    wall = time.perf_counter() - started
    metrics = queue_metrics(result)
    written = write_staged(target, lambda staging: _write(result, metrics, staging,
                                                          not args.no_animation, console))
    _summary(result, metrics, wall, target, written, world_path)
    return EXIT_OK


def _write(result: QueueResult, metrics: QueueMetrics, directory: Path,
           animation: bool, console: Console) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with open(directory / "log.csv", "w", encoding="utf-8") as handle:
        write_queue_log(result, handle)
    figure = plot_queue(result)
    figure.savefig(directory / "queue.png", dpi=110)
    plt.close(figure)
    written = ["log.csv", "queue.png"]
    if animation:
        from dancebots.report.animation import ffmpeg_available

        for kind in ["gif"] + (["mp4"] if ffmpeg_available() else []):
            with _progress(console, f"animation.{kind} (frames)") as update:
                animate_queue(result, str(directory / f"animation.{kind}"),
                              progress=lambda done, total: update(done + 1, total))
            written.append(f"animation.{kind}")
    (directory / "metrics.json").write_text(metrics_json(metrics), encoding="utf-8")
    return [*written, "metrics.json"]


def _summary(result: QueueResult, metrics: QueueMetrics, wall: float, target: Path,
             written: list[str], world: str) -> None:
    out = Console()
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
