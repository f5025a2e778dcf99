"""Scenario -> Plan: formation offsets, the virtual leader's motion (thesis eq. 4.1-4.3, 6.1),
and the plan placed in its world (``PlacedShow``)."""

from dancebots.plan.compile import compile_scenario
from dancebots.plan.formation import DEFAULT_LEAD, formation_offsets
from dancebots.plan.leader import arc_angular_speed, arc_command, leader_speed, waypoint_command
from dancebots.plan.placement import PlacedShow, ShowSamples, place_show, robot_types
from dancebots.plan.planner import (
    InstructionTiming,
    LeaderTrajectory,
    Plan,
    PlannedFormation,
    PlanParameters,
    build_plan,
    desired_pose,
    virtual_leader_pose,
)

__all__ = [
    "DEFAULT_LEAD",
    "InstructionTiming",
    "LeaderTrajectory",
    "PlacedShow",
    "Plan",
    "PlanParameters",
    "PlannedFormation",
    "ShowSamples",
    "arc_angular_speed",
    "arc_command",
    "build_plan",
    "compile_scenario",
    "desired_pose",
    "formation_offsets",
    "leader_speed",
    "place_show",
    "robot_types",
    "virtual_leader_pose",
    "waypoint_command",
]
