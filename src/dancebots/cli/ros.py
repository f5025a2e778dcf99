"""``dancebots ros``: run the ROS 1 nodes with roslaunch (a thin shell).

``dancebots ros formation SCENARIO --role R1`` runs one robot (formation.launch), on each
robot of a show; ``dancebots ros simulate SCENARIO`` runs the simulator bridge and every
robot's nodes on this machine under one master (started by roslaunch when none runs). Both
put the ``dancebots_ros`` package on ROS_PACKAGE_PATH and this Python first on PATH, so the
nodes run with this installation of dancebots.
"""

from __future__ import annotations

import argparse
import os
import shlex
import shutil
import socket
import sys
import tempfile
from pathlib import Path

from dancebots.cli.common import (
    EXIT_INVALID,
    EXIT_OK,
    PROFILES,
    add_follower_argument,
    add_hold_argument,
    add_show_arguments,
    add_stop_rule_argument,
    add_timing_argument,
    fail,
    print_diagnostics,
    profile_missing,
)

NAME = "ros"
HELP = "run the show through ROS 1 (real robots or the ROS simulation)"
DESCRIPTION = ("Run a show through ROS 1: `formation` on each real robot (one per robot, the "
               "same files everywhere), `simulate` for every robot's nodes and the simulator "
               "bridge on this machine.")
START_STRATEGIES = ("agreed", "thesis", "timecode")
"""``sync.start.START_STRATEGIES`` (a test keeps them equal); the first is the default."""

_INSTALL = ("roslaunch is not installed; install Debian's ROS 1 packages: apt-get install "
            "ros-core python3-rospy python3-roslaunch python3-tf2-ros python3-sensor-msgs "
            "python3-geometry-msgs python3-std-msgs")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="ros_command", metavar="WHAT", required=True)
    formation = sub.add_parser("formation", help="this robot's nodes (formation.launch)",
                               description="Run this robot's nodes (network test, formation "
                               "member, obstacle detection) with roslaunch.")
    add_show_arguments(formation, world_help="world file (the same on every robot)")
    formation.add_argument("--role", required=True,
                           help="this robot's name in the scenario, e.g. R1")
    formation.add_argument("--robot-name", default="", metavar="PREFIX",
                           help="topic/frame prefix when robots share one master")
    formation.add_argument("--start-strategy", choices=START_STRATEGIES, default="agreed",
                           help="agreed (default): one start every robot agrees on whatever "
                           "the network does; thesis: as thesis 4.2 wrote it; timecode: at "
                           "--start-at (docs/ros.md)")
    formation.add_argument("--start-at", type=start_time, metavar="TIME",
                           help="start the show at this wall-clock time, the same on every "
                           "robot (the timecode start, for shows set to music and lights): "
                           "ISO 8601 (2026-11-27T20:00:00, local time unless it names a zone "
                           "such as Z or +01:00), seconds since the epoch, or +S for S seconds "
                           "from now (on each robot: give every robot the same absolute time "
                           "instead); a robot whose clock is more than 0.1 s off the "
                           "formation's (the median of the robots' clocks; of two robots, each "
                           "other's) refuses to start and says why (docs/ros.md)")
    formation.add_argument("--no-lidar", action="store_true",
                           help="run without obstacle detection (no stops, no force field)")
    add_follower_argument(formation)
    add_timing_argument(formation)
    add_hold_argument(formation)
    add_stop_rule_argument(formation)
    formation.add_argument("--print-command", action="store_true",
                           help="print what would run (the roslaunch command) and exit")
    formation.set_defaults(subparser=formation)
    simulate = sub.add_parser("simulate", help="the simulator bridge and every robot's nodes "
                              "on this machine", description="Run every robot's nodes and the "
                              "simulator bridge on this machine under one ROS master.")
    add_show_arguments(simulate)
    simulate.add_argument("--profile", choices=PROFILES, default="ideal",
                          help="the simulated robots' dynamics: ideal, realistic or physics "
                          "(MuJoCo) (default: ideal)")
    simulate.add_argument("--no-lidar", action="store_true",
                          help="robots without LIDAR (no stops, no force field)")
    add_follower_argument(simulate)
    add_timing_argument(simulate)
    add_hold_argument(simulate)
    add_stop_rule_argument(simulate)
    simulate.add_argument("--record", default="", metavar="FILE",
                          help="write the run's poses, the commands the robots obeyed and "
                          "the contacts here: FILE.mcap as an MCAP log with ROS 1 types "
                          "(Foxglove opens it), else NumPy's .npz")
    simulate.add_argument("--print-command", "--print-launch", dest="print_command",
                          action="store_true", help="print what would run (the generated "
                          "launch file) and exit")
    simulate.set_defaults(subparser=simulate)


def _roslaunch() -> str | None:
    found = shutil.which("roslaunch")
    if found is None:
        fail(NAME, _INSTALL)
    return found


def run(args: argparse.Namespace) -> int:
    from dancebots.loading import load_show
    from dancebots.plan.placement import place_show
    from dancebots.ros1.launching import START_ALLOWANCE, ros_environment, simulation_launch
    from dancebots.shows.formation import SimConfig, settle_from
    from dancebots.sim.setup import SetupError, prepare_show
    from dancebots.sync.hold import default_hold_strategy

    show = load_show(args.scenario, args.world, args.vmax, timing=args.timing)
    if show.plan is None or not show.valid:
        print_diagnostics(show.diagnostics, show.sources)
        return EXIT_INVALID
    plan = show.plan
    vmax = args.vmax or 0.0
    scenario = str(Path(args.scenario).resolve())
    world_file = str(Path(args.world).resolve()) if args.world else ""
    if args.ros_command == "formation":
        if args.role not in plan.robots:
            args.subparser.error(f"--role {args.role!r} is not one of the scenario's robots "
                                 f"({', '.join(plan.robots)})")
        roslaunch = "roslaunch" if args.print_command else _roslaunch()
        if roslaunch is None:
            return EXIT_INVALID
        strategy = "timecode" if args.start_at is not None else args.start_strategy
        if strategy == "timecode" and args.start_at is None:
            args.subparser.error("--start-strategy timecode needs --start-at TIME")
        timecode = [f"start_at:={args.start_at!r}"] if args.start_at is not None else []
        command = [roslaunch, "dancebots_ros", "formation.launch", f"scenario:={scenario}",
                   f"role:={args.role}", f"world:={world_file}", f"vmax:={vmax}",
                   f"robot_name:={args.robot_name}", f"start_strategy:={strategy}", *timecode,
                   f"lidar:={str(not args.no_lidar).lower()}", f"follower:={args.follower}",
                   f"timing:={args.timing}", f"hold:={args.hold or ''}",
                   f"stop_rule:={args.stop_rule or ''}",
                   # bash does not export HOSTNAME: pass the host's name when it is unset
                   f"hostname:={os.environ.get('HOSTNAME') or socket.gethostname()}"]
        if args.print_command:
            print(shlex.join(command))
            return EXIT_OK
        os.execve(roslaunch, command, ros_environment())
    missing = profile_missing(args.profile)
    if missing is not None:
        return fail(NAME, missing)
    try:
        _, placement = prepare_show(place_show(plan, show.world))
    except SetupError as exc:
        return fail(NAME, str(exc))
    # the bridge ends the run once the formation's clocks reach the show's end and every
    # robot stands (``~show_end``), or at the run's limit: as ``dancebots run``, the show's
    # end, its settling, and for a formation that waits together the longest wait
    show_end = settle_from(plan, args.follower)
    waits = (args.hold or default_hold_strategy(args.follower)) != "alone"
    limits = SimConfig()
    text = simulation_launch(
        scenario, plan.robots, world_file, vmax, args.profile, not args.no_lidar,
        str(Path(args.record).resolve()) if args.record else "",
        show_end + START_ALLOWANCE + limits.settle + (limits.max_pause if waits else 0.0),
        tuple((t.length, t.width, t.max_speed) for t in placement.types),
        args.follower, args.timing, args.hold or "", args.stop_rule or "",
        show_end if waits else 0.0, limits.settle)
    if args.print_command:
        print(text, end="")
        return EXIT_OK
    roslaunch = _roslaunch()
    if roslaunch is None:
        return EXIT_INVALID
    # roslaunch reads the launch XML from its standard input ("-"): an unnamed temporary
    # file that is gone with the last process holding it, so a run leaves no file behind
    with tempfile.TemporaryFile() as launch:
        launch.write(text.encode())
        launch.seek(0)
        os.dup2(launch.fileno(), 0)
    sys.stdout.flush()
    os.execve(roslaunch, [roslaunch, "-"], ros_environment())
    return EXIT_OK  # not reached


def start_time(text: str, now: float | None = None) -> float:
    """``--start-at``: a wall-clock time as seconds since the epoch, from ISO 8601 (local
    time unless it names a zone), seconds since the epoch, or ``+S`` (S seconds after
    ``now``, default the clock now). Raises ``argparse.ArgumentTypeError`` saying what is
    accepted."""
    import datetime
    import math
    import time as clock

    hint = ("give an ISO 8601 time (2026-11-27T20:00:00, 20:00 today is 2026-11-27T20:00), "
            "seconds since the epoch (1795810800) or +SECONDS from now (+30)")
    value: float | None = None
    try:
        if text.startswith("+"):
            value = (clock.time() if now is None else now) + float(text[1:])
        elif text.replace(".", "", 1).isdigit():
            value = float(text)
        else:
            value = datetime.datetime.fromisoformat(text).timestamp()
    except (ValueError, OverflowError, OSError):
        value = None
    if value is None or not math.isfinite(value) or value <= 0.0:
        raise argparse.ArgumentTypeError(f"{text!r} is not a time: {hint}")
    return value
