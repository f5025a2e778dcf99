"""Scenario -> Plan: formation offsets, the virtual leader's motion (thesis eq. 4.1-4.3, 6.1)."""

from dancebots.plan.formation import DEFAULT_LEAD, formation_offsets
from dancebots.plan.leader import arc_angular_speed, arc_command, leader_speed, waypoint_command
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
    "Plan",
    "PlanParameters",
    "PlannedFormation",
    "arc_angular_speed",
    "arc_command",
    "build_plan",
    "desired_pose",
    "formation_offsets",
    "leader_speed",
    "virtual_leader_pose",
    "waypoint_command",
]
