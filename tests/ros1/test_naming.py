"""Names of a robot's topics, frames and parameters; robot types from host names."""

from __future__ import annotations

from dancebots.ros1 import RobotNames, robot_type_for_host
from dancebots.world import BUILTIN_ROBOT_TYPES


def test_a_robot_of_its_own_uses_the_thesis_names() -> None:
    names = RobotNames()
    assert names.topic("points_filtered") == "/points_filtered"
    assert names.topic("nav/cmd_vel") == "/nav/cmd_vel"
    assert names.frame("base_link") == "base_link"
    assert names.param("length") == "/length"


def test_robots_sharing_a_master_prefix_everything() -> None:
    names = RobotNames("R1")
    assert names.topic("points_filtered") == "/R1/points_filtered"
    assert names.frame("map") == "R1/map"
    assert names.param("width") == "/R1/width"


def test_host_names_select_the_robot_type() -> None:
    assert robot_type_for_host("ctu-robot") == BUILTIN_ROBOT_TYPES["TRADR"]
    assert robot_type_for_host("husky-robot") == BUILTIN_ROBOT_TYPES["HUSKY"]
    assert robot_type_for_host("laptop") == BUILTIN_ROBOT_TYPES["SIM"]
