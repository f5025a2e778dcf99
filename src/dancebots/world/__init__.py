"""World files and the world they describe: :mod:`~dancebots.world.model` (the room,
obstacles, spectators, robots and their types, the start-pose rules) and
:mod:`~dancebots.world.loader` (the TOML reader with its diagnostics)."""

from dancebots.world.loader import MISSING_WORLD_HINT, load_world, parse_world
from dancebots.world.model import (
    BUILTIN_ROBOT_TYPES,
    CONTACT_MARGIN,
    CROWD_KINDS,
    DEFAULT_ROBOT_TYPE,
    THESIS_ROOM_SIZE,
    Crowd,
    CrowdKind,
    Obstacle,
    RobotType,
    Spectator,
    StartConflict,
    World,
    WorldRobot,
    spectator_route,
    square_room,
    start_conflicts,
)

__all__ = [
    "BUILTIN_ROBOT_TYPES",
    "CONTACT_MARGIN",
    "CROWD_KINDS",
    "DEFAULT_ROBOT_TYPE",
    "MISSING_WORLD_HINT",
    "THESIS_ROOM_SIZE",
    "Crowd",
    "CrowdKind",
    "Obstacle",
    "RobotType",
    "Spectator",
    "StartConflict",
    "World",
    "WorldRobot",
    "load_world",
    "parse_world",
    "spectator_route",
    "square_room",
    "start_conflicts",
]
