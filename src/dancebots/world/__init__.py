"""World files and the world they describe (:mod:`~dancebots.world.model`)."""

from dancebots.world.model import (
    BUILTIN_ROBOT_TYPES,
    CONTACT_MARGIN,
    DEFAULT_ROBOT_TYPE,
    MISSING_WORLD_HINT,
    THESIS_ROOM_SIZE,
    Obstacle,
    RobotType,
    Spectator,
    StartConflict,
    World,
    WorldRobot,
    load_world,
    parse_world,
    spectator_route,
    square_room,
    start_conflicts,
)

__all__ = [
    "BUILTIN_ROBOT_TYPES",
    "CONTACT_MARGIN",
    "DEFAULT_ROBOT_TYPE",
    "MISSING_WORLD_HINT",
    "THESIS_ROOM_SIZE",
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
