"""Launching the ROS 1 nodes: where the ``dancebots_ros`` package is, the environment in
which roslaunch finds it and runs this installation's Python, and the generated launch file
of a ROS simulation. Pure text and paths: importing this module does not import rospy.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from xml.sax.saxutils import quoteattr

__all__ = ["PACKAGE_DIR", "START_ALLOWANCE", "ros_environment", "simulation_launch"]

PACKAGE_DIR = Path(__file__).parent / "package"
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


def simulation_launch(scenario: str, robots: tuple[str, ...], world: str = "",
                      vmax: float = 0.0, profile: str = "ideal", lidar: bool = True,
                      record: str = "", stop_after: float = 0.0,
                      types: tuple[tuple[float, float, float], ...] = (),
                      follower: str = "thesis", timing: str = "thesis",
                      hold: str = "", stop_rule: str = "", show_end: float = 0.0,
                      settle: float = 20.0) -> str:
    """The launch file of a ROS simulation: the bridge, and formation.launch per robot with
    its name as prefix; types: per robot (length, width, max speed) of the simulated robot;
    follower, timing, hold and stop_rule: the strategies (``--follower``, ``--timing``,
    ``--hold``, ``--stop-rule``; a hold or stop rule of "" lets the node choose); stop_after:
    s after which the bridge ends the run; show_end: the show time (s) from which it ends it
    once every robot says on /hold that its show time is there and it holds nothing, and
    every robot stands, or ``settle`` s of show time later (0: at stop_after only)."""
    def attr(value: object) -> str:
        return quoteattr(str(value))

    lines = ["<launch>",
             '  <node pkg="dancebots_ros" type="sim_bridge" name="sim_bridge" output="screen" '
             'required="true">',
             f"    <param name=\"scenario\" value={attr(scenario)}/>",
             f"    <param name=\"world\" value={attr(world)}/>",
             f"    <param name=\"vmax\" value={attr(vmax)}/>",
             f"    <param name=\"profile\" value={attr(profile)}/>",
             f"    <param name=\"timing\" value={attr(timing)}/>",
             f"    <param name=\"lidar\" value={attr(str(lidar).lower())}/>",
             f"    <param name=\"record\" value={attr(record)}/>",
             f"    <param name=\"stop_after\" value={attr(stop_after)}/>",
             f"    <param name=\"show_end\" value={attr(show_end)}/>",
             f"    <param name=\"settle\" value={attr(settle)}/>",
             "  </node>"]
    for i, robot in enumerate(robots):
        lines.append('  <include file="$(find dancebots_ros)/launch/formation.launch">')
        for key, value in (("scenario", scenario), ("role", robot), ("world", world),
                           ("vmax", vmax), ("robot_name", robot),
                           ("lidar", str(lidar).lower()), ("follower", follower),
                           ("timing", timing), ("hold", hold), ("stop_rule", stop_rule)):
            lines.append(f"    <arg name=\"{key}\" value={attr(value)}/>")
        if types:  # the simulated robot's size and speed, not this host's
            for key, value in zip(("length", "width", "max_speed"), types[i], strict=True):
                lines.append(f"    <arg name=\"{key}\" value={attr(value)}/>")
        lines.append("  </include>")
    lines.append("</launch>")
    return "\n".join(lines) + "\n"
