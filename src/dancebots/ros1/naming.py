"""Topic, frame and parameter names of one robot, and its type from the host name.

On a real robot (thesis ch. 3) every robot has its own ROS master and the names are global:
``/points_filtered``, ``/nav/cmd_vel``, frames ``map`` and ``base_link``, parameters
``/length`` and ``/width``. When several robots share one master (the simulator, the
multi-host test) the optional robot name prefixes all of them: ``/R1/points_filtered``,
``R1/map``. ``/sync`` is shared by the formation in both cases.
"""

from __future__ import annotations

from dataclasses import dataclass

from dancebots.world import BUILTIN_ROBOT_TYPES, RobotType

__all__ = ["HOLD_TOPIC", "HOST_ROBOT_TYPES", "SYNC_TOPIC", "RobotNames", "robot_type_for_host"]

SYNC_TOPIC = "/sync"
HOLD_TOPIC = "/hold"
"""The formation's shared show clock (``sync.hold``): every formation_member's hold messages
(std_msgs/String, ``sync.messages.format_hold``), read by every other one."""
HOST_ROBOT_TYPES = {"ctu-robot": "TRADR", "husky-robot": "HUSKY"}
"""Thesis ch. 3: the host names of the real robots; any other host is the simulator's."""


@dataclass(frozen=True, slots=True)
class RobotNames:
    """The names of robot ``prefix`` ("" on a robot of its own)."""

    prefix: str = ""

    def topic(self, name: str) -> str:
        """``/name`` or ``/prefix/name``."""
        return f"/{self.prefix}/{name}" if self.prefix else f"/{name}"

    def frame(self, name: str) -> str:
        """TF frame ``name`` or ``prefix/name`` (tf2 frame ids have no leading slash)."""
        return f"{self.prefix}/{name}" if self.prefix else name

    def param(self, name: str) -> str:
        """Parameter ``/name`` or ``/prefix/name``."""
        return self.topic(name)


def robot_type_for_host(hostname: str) -> RobotType:
    """The robot type a host runs on (thesis ch. 3): ctu-robot is a TRADR, husky-robot a
    HUSKY, anything else the simulator's robot (1.2 x 0.6 m)."""
    return BUILTIN_ROBOT_TYPES[HOST_ROBOT_TYPES.get(hostname, "SIM")]
