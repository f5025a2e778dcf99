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
from xml.sax.saxutils import quoteattr

from dancebots.cli import compile_files, print_diagnostics
from dancebots.diagnostics import has_errors
from dancebots.sim.setup import SetupError, prepare_show

__all__ = ["PACKAGE_DIR", "add_ros_parser", "ros_environment", "run_ros", "simulation_launch"]

PACKAGE_DIR = Path(__file__).parent / "ros1" / "package"
"""The folder that holds the ROS package ``dancebots_ros`` (for ROS_PACKAGE_PATH)."""
START_ALLOWANCE = 30.0
"""s the simulation allows for starting the nodes, the network test and the 4 s start delay."""


def ros_environment(base: dict[str, str] | None = None) -> dict[str, str]:
    """The environment in which roslaunch finds ``dancebots_ros`` and its nodes run this
    Python (with rospy from Debian's packages beside it)."""
    env = dict(os.environ if base is None else base)
    paths = [str(PACKAGE_DIR), *filter(None, env.get("ROS_PACKAGE_PATH", "").split(":"))]
    env["ROS_PACKAGE_PATH"] = ":".join(dict.fromkeys(paths))
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def add_ros_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    ros = commands.add_parser("ros", help="run the show through ROS 1 (real robots or the "
                              "ROS simulation)")
    sub = ros.add_subparsers(dest="ros_command", metavar="WHAT", required=True)
    formation = sub.add_parser("formation", help="this robot's nodes (formation.launch)")
    formation.add_argument("scenario", metavar="SCENARIO")
    formation.add_argument("--role", required=True, help="this robot's name in the scenario")
    formation.add_argument("--world", default="", help="world file (the same on every robot)")
    formation.add_argument("--vmax", type=float, default=0.0, help="vmax, m/s (the same on "
                           "every robot; default: from the world, else 0.5)")
    formation.add_argument("--robot-name", default="", help="topic/frame prefix when robots "
                           "share one master")
    formation.add_argument("--start-strategy", choices=("agreed", "thesis"), default="agreed")
    formation.add_argument("--no-lidar", action="store_true")
    formation.add_argument("--print-command", action="store_true",
                           help="print the roslaunch command and exit")
    simulate = sub.add_parser("simulate", help="the simulator bridge and every robot's nodes "
                              "on this machine")
    simulate.add_argument("scenario", metavar="SCENARIO")
    simulate.add_argument("--world", default="")
    simulate.add_argument("--vmax", type=float, default=0.0)
    simulate.add_argument("--profile", choices=("ideal", "realistic"), default="ideal")
    simulate.add_argument("--no-lidar", action="store_true")
    simulate.add_argument("--record", default="", metavar="FILE.npz",
                          help="write the run's poses and commands here")
    simulate.add_argument("--print-launch", action="store_true",
                          help="print the generated launch file and exit")


def simulation_launch(scenario: str, robots: tuple[str, ...], world: str = "",
                      vmax: float = 0.0, profile: str = "ideal", lidar: bool = True,
                      record: str = "", stop_after: float = 0.0,
                      types: tuple[tuple[float, float, float], ...] = ()) -> str:
    """The launch file of a ROS simulation: the bridge, and formation.launch per robot with
    its name as prefix; types: per robot (length, width, max speed) of the simulated robot."""
    def attr(value: object) -> str:
        return quoteattr(str(value))

    lines = ["<launch>",
             '  <node pkg="dancebots_ros" type="sim_bridge" name="sim_bridge" output="screen" '
             'required="true">',
             f"    <param name=\"scenario\" value={attr(scenario)}/>",
             f"    <param name=\"world\" value={attr(world)}/>",
             f"    <param name=\"vmax\" value={attr(vmax)}/>",
             f"    <param name=\"profile\" value={attr(profile)}/>",
             f"    <param name=\"lidar\" value={attr(str(lidar).lower())}/>",
             f"    <param name=\"record\" value={attr(record)}/>",
             f"    <param name=\"stop_after\" value={attr(stop_after)}/>",
             "  </node>"]
    for i, robot in enumerate(robots):
        lines.append('  <include file="$(find dancebots_ros)/launch/formation.launch">')
        for key, value in (("scenario", scenario), ("role", robot), ("world", world),
                           ("vmax", vmax), ("robot_name", robot),
                           ("lidar", str(lidar).lower())):
            lines.append(f"    <arg name=\"{key}\" value={attr(value)}/>")
        if types:  # the simulated robot's size and speed, not this host's
            for key, value in zip(("length", "width", "max_speed"), types[i], strict=True):
                lines.append(f"    <arg name=\"{key}\" value={attr(value)}/>")
        lines.append("  </include>")
    lines.append("</launch>")
    return "\n".join(lines) + "\n"


def _roslaunch() -> str | None:
    found = shutil.which("roslaunch")
    if found is None:
        print("dancebots ros: roslaunch is not installed; install Debian's ROS 1 packages: "
              "apt-get install ros-core python3-rospy python3-roslaunch python3-tf2-ros "
              "python3-sensor-msgs python3-geometry-msgs python3-std-msgs", file=sys.stderr)
    return found


def run_ros(args: argparse.Namespace) -> int:
    sources: dict[str, list[str]] = {}
    plan, world, diagnostics = compile_files(argparse.Namespace(
        scenario=args.scenario, world=args.world or None, vmax=args.vmax or None), sources)
    if plan is None or has_errors(diagnostics):
        print_diagnostics(diagnostics, sources)
        return 2
    scenario = str(Path(args.scenario).resolve())
    world_file = str(Path(args.world).resolve()) if args.world else ""
    if args.ros_command == "formation":
        if args.role not in plan.robots:
            print(f"dancebots ros: --role {args.role!r} is not one of the scenario's robots "
                  f"({', '.join(plan.robots)})", file=sys.stderr)
            return 2
        roslaunch = "roslaunch" if args.print_command else _roslaunch()
        if roslaunch is None:
            return 2
        command = [roslaunch, "dancebots_ros", "formation.launch", f"scenario:={scenario}",
                   f"role:={args.role}", f"world:={world_file}", f"vmax:={args.vmax}",
                   f"robot_name:={args.robot_name}", f"start_strategy:={args.start_strategy}",
                   f"lidar:={str(not args.no_lidar).lower()}",
                   # bash does not export HOSTNAME: pass the host's name when it is unset
                   f"hostname:={os.environ.get('HOSTNAME') or socket.gethostname()}"]
        if args.print_command:
            print(shlex.join(command))
            return 0
        os.execve(roslaunch, command, ros_environment())
    try:
        _, placement = prepare_show(plan, world)
    except SetupError as exc:
        print(f"dancebots ros: {exc}", file=sys.stderr)
        return 2
    text = simulation_launch(
        scenario, plan.robots, world_file, args.vmax, args.profile, not args.no_lidar,
        str(Path(args.record).resolve()) if args.record else "",
        plan.duration + START_ALLOWANCE,
        tuple((t.length, t.width, t.max_speed) for t in placement.types))
    if args.print_launch:
        print(text, end="")
        return 0
    roslaunch = _roslaunch()
    if roslaunch is None:
        return 2
    folder = Path(tempfile.mkdtemp(prefix="dancebots-ros-"))
    launch = folder / "simulation.launch"
    launch.write_text(text)
    os.execve(roslaunch, [roslaunch, str(launch)], ros_environment())
    return 0  # not reached
