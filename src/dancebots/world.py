"""World files: the room, polygon obstacles and the robots with their types and start poses.

A world file is TOML (read with the standard library's ``tomllib``); ``docs/worlds.md`` is its
reference. Lengths in m, angles in rad (``yaw``) or degrees (``yaw_deg``), speeds in m/s and
rad/s. The room's and obstacles' coordinates are in the *world frame*. Every problem is a
:class:`Diagnostic` with the file, line and column of the offending key.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, DiagnosticError, Severity, read_source_file
from dancebots.geometry import Pose

__all__ = [
    "BUILTIN_ROBOT_TYPES",
    "DEFAULT_ROBOT_TYPE",
    "THESIS_ROOM_SIZE",
    "Obstacle",
    "RobotType",
    "Spectator",
    "World",
    "WorldRobot",
    "load_world",
    "parse_world",
]

THESIS_ROOM_SIZE = 10.673
"""Side of the thesis simulator's square room, m (thesis ch. 7.1)."""
MAX_COORDINATE = 10_000.0


@dataclass(frozen=True, slots=True)
class RobotType:
    """A kind of robot: rectangular footprint (length along x, width along y, m) and limits."""

    name: str
    length: float
    width: float
    max_speed: float
    max_angular_speed: float


BUILTIN_ROBOT_TYPES: Mapping[str, RobotType] = {
    # thesis ch. 2: HUSKY 99 x 67 cm, 1 m/s; TRADR 73 x 60 cm, 0.5 m/s; both > 180 deg/s.
    "HUSKY": RobotType("HUSKY", 0.99, 0.67, 1.0, math.pi),
    "TRADR": RobotType("TRADR", 0.73, 0.60, 0.5, math.pi),
    # thesis ch. 3: the 2D simulator's robot is 1.2 x 0.6 m.
    "SIM": RobotType("SIM", 1.2, 0.6, 0.5, math.pi),
    # the second seed's queues: TurtleBot3 Burger, 138 x 178 mm, 0.22 m/s, 2.84 rad/s.
    "TURTLEBOT3": RobotType("TURTLEBOT3", 0.138, 0.178, 0.22, 2.84),
}
DEFAULT_ROBOT_TYPE = BUILTIN_ROBOT_TYPES["SIM"]


@dataclass(frozen=True, slots=True, eq=False)
class Obstacle:
    """A polygon obstacle; ``polygon`` (N, 2) in m, world frame; ``height`` in m."""

    name: str
    polygon: NDArray[np.float64]
    height: float
    line: int


@dataclass(frozen=True, slots=True)
class WorldRobot:
    """A robot of the world: its role, type and start pose in the world frame."""

    name: str
    type: RobotType
    start: Pose
    line: int


@dataclass(frozen=True, slots=True, eq=False)
class Spectator:
    """A visitor: a disc of ``radius`` m and ``height`` m walking ``waypoints`` (K, 2) (world
    frame, m) at ``speed`` m/s, standing ``pauses`` (K,) s at each waypoint, starting after
    ``start`` s; with ``loop`` it walks back to the first waypoint and around again."""

    name: str
    radius: float
    height: float
    speed: float
    waypoints: NDArray[np.float64]
    pauses: NDArray[np.float64]
    loop: bool
    start: float
    line: int


@dataclass(frozen=True, slots=True, eq=False)
class World:
    """The room (polygon (N, 2), world frame), its wall height, obstacles, robots and
    spectators."""

    path: str
    room: NDArray[np.float64]
    wall_height: float
    obstacles: tuple[Obstacle, ...]
    robots: tuple[WorldRobot, ...]
    spectators: tuple[Spectator, ...] = ()

    def robot(self, name: str) -> WorldRobot | None:
        return next((r for r in self.robots if r.name == name), None)

    def slowest_speed(self) -> float | None:
        """The smallest max speed of the world's robots, m/s: the default vmax (thesis 4.1:
        the user gives the speed of the slowest robot); None without robots."""
        return min((r.type.max_speed for r in self.robots), default=None)


def square_room(size: float) -> NDArray[np.float64]:
    """The square room [0, size] x [0, size] as a counter-clockwise polygon (4, 2)."""
    return np.array([[0.0, 0.0], [size, 0.0], [size, size], [0.0, size]])


def load_world(path: str) -> World:
    """Read and validate a world file; raises :class:`DiagnosticError` with every problem."""
    text, diagnostics = read_source_file(path)
    if text is None:
        raise DiagnosticError(diagnostics)
    world, diagnostics = parse_world(text, path)
    if world is None:
        raise DiagnosticError(diagnostics)
    return world


class _Locator:
    """Finds the line and column of a key in the TOML text (tomllib gives no positions)."""

    def __init__(self, text: str) -> None:
        self.lines = text.splitlines()
        self.headers: list[tuple[int, str]] = []
        for number, line in enumerate(self.lines, start=1):
            match = re.match(r"\s*(\[\[?)\s*([^\]]+?)\s*\]", line)
            if match:
                self.headers.append((number, match.group(2).replace(" ", "")))

    def table(self, name: str, occurrence: int = 0) -> int:
        found = [n for n, header in self.headers if header == name]
        return found[occurrence] if occurrence < len(found) else 1

    def key(self, table: str | None, key: str, occurrence: int = 0) -> tuple[int, int]:
        start = self.table(table, occurrence) if table else 1
        if not table and self.headers:
            end = self.headers[0][0]
        else:
            later = [n for n, _ in self.headers if n > start]
            end = later[0] if later else len(self.lines) + 1
        pattern = re.compile(rf"\s*\"?{re.escape(key)}\"?\s*=")
        for number in range(start, min(end, len(self.lines) + 1)):
            line = self.lines[number - 1]
            if pattern.match(line):
                return number, len(line) - len(line.lstrip()) + 1
        return start, 1


def parse_world(text: str, path: str = "<world>") -> tuple[World | None, list[Diagnostic]]:
    """Parse world-file text; returns (world or None when there is an error, diagnostics)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        match = re.search(r"\(at line (\d+), column (\d+)\)", message)
        line, col = (int(match.group(1)), int(match.group(2))) if match else (
            max(1, len(text.splitlines())), 1)
        message = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)", "", message)
        return None, [Diagnostic(path, line, col, Severity.ERROR,
                                 f"invalid TOML: {message[:1].lower()}{message[1:]}",
                                 "see docs/worlds.md for the world-file format")]
    return _World(path, text, data).build()


class _World:
    def __init__(self, path: str, text: str, data: dict[str, Any]) -> None:
        self.path = path
        self.data = data
        self.where = _Locator(text)
        self.diagnostics: list[Diagnostic] = []

    def error(self, position: tuple[int, int], message: str, hint: str | None = None) -> None:
        self.diagnostics.append(Diagnostic(self.path, position[0], position[1], Severity.ERROR,
                                           message, hint))

    def number(self, table: Mapping[str, Any], key: str, where: tuple[str | None, int], *,
               default: float | None = None, low: float = -MAX_COORDINATE,
               high: float = MAX_COORDINATE, positive: bool = False) -> float | None:
        position = self.where.key(where[0], key, where[1])
        if key not in table:
            if default is None:
                line = self.where.table(where[0], where[1]) if where[0] else 1
                self.error((line, 1), f"missing key '{key}'", "see docs/worlds.md")
            return default
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.error(position, f"'{key}' must be a number, not {_describe(value)}")
            return None
        value = float(value)
        if not math.isfinite(value):
            self.error(position, f"'{key}' must be a finite number")
            return None
        if positive and value <= 0:
            self.error(position, f"'{key}' must be greater than 0")
            return None
        if not low <= value <= high:
            self.error(position, f"'{key}' must be between {low:g} and {high:g}")
            return None
        return value

    def polygon(self, value: Any, key: str, position: tuple[int, int],
                what: str) -> NDArray[np.float64] | None:
        ok = isinstance(value, list) and len(value) >= 3 and all(
            isinstance(p, list) and len(p) == 2 and all(
                isinstance(c, int | float) and not isinstance(c, bool) for c in p) for p in value)
        if not ok:
            self.error(position, f"'{key}' of {what} must be a list of at least 3 [x, y] "
                       "points", "e.g. polygon = [[0, 0], [1, 0], [1, 1]]")
            return None
        points = np.array(value, dtype=float)
        if not np.all(np.isfinite(points)) or np.any(np.abs(points) > MAX_COORDINATE):
            self.error(position, f"the points of {what} must be finite numbers within "
                       f"+-{MAX_COORDINATE:g} m")
            return None
        shape = shapely.Polygon(points)
        if not shape.is_valid or shape.area <= 0.0:
            self.error(position, f"the polygon of {what} is not simple (its edges cross or it "
                       "has no area)", "list the corners in order around the outline")
            return None
        return points

    def build(self) -> tuple[World | None, list[Diagnostic]]:
        known = {"room", "obstacles", "robots", "robot_types", "spectators"}
        for key in self.data:
            if key not in known:
                self.error(self.where.key(None, key) if not isinstance(self.data[key], dict)
                           else (self.where.table(key), 1),
                           f"unknown key '{key}'", "the top-level tables are [room], "
                           "[[obstacles]], [[robots]], [[spectators]] and [robot_types.NAME]")
        room, wall_height = self.room()
        types = self.robot_types()
        obstacles = self.obstacles()
        robots = self.robots(types)
        spectators = self.spectators()
        if self.diagnostics or room is None:
            return None, sorted(self.diagnostics, key=lambda d: (d.line, d.col))
        return World(self.path, room, wall_height, tuple(obstacles), tuple(robots),
                     tuple(spectators)), []

    def room(self) -> tuple[NDArray[np.float64] | None, float]:
        table = self.data.get("room", {})
        if not isinstance(table, dict):
            self.error(self.where.key(None, "room"), "'room' must be a table: [room]")
            return None, 2.0
        for key in table:
            if key not in ("size", "polygon", "wall_height"):
                self.error(self.where.key("room", key), f"unknown key '{key}' in [room]",
                           "[room] takes size, polygon or wall_height")
        wall = self.number(table, "wall_height", ("room", 0), default=2.0, positive=True,
                           high=100.0)
        if "polygon" in table:
            if "size" in table:
                self.error(self.where.key("room", "size"), "give either 'size' or 'polygon' "
                           "for the room, not both")
            return self.polygon(table["polygon"], "polygon", self.where.key("room", "polygon"),
                                "the room"), wall or 2.0
        size = self.number(table, "size", ("room", 0), default=THESIS_ROOM_SIZE, positive=True)
        return (square_room(size) if size else None), wall or 2.0

    def robot_types(self) -> dict[str, RobotType]:
        types = dict(BUILTIN_ROBOT_TYPES)
        table = self.data.get("robot_types", {})
        if not isinstance(table, dict):
            self.error(self.where.key(None, "robot_types"), "'robot_types' must be a table")
            return types
        for name, spec in table.items():
            header = f"robot_types.{name}"
            if not isinstance(spec, dict):
                self.error(self.where.key("robot_types", name), f"robot type '{name}' must be "
                           "a table", f"write [robot_types.{name}] with length, width, ...")
                continue
            base = types.get(name, DEFAULT_ROBOT_TYPE)
            for key in spec:
                if key not in ("length", "width", "max_speed", "max_angular_speed"):
                    self.error(self.where.key(header, key), f"unknown key '{key}' in robot type "
                               f"'{name}'", "a robot type has length, width, max_speed and "
                               "max_angular_speed")
            values = {key: self.number(spec, key, (header, 0), default=getattr(base, key),
                                       positive=True, high=100.0)
                      for key in ("length", "width", "max_speed", "max_angular_speed")}
            length, width = values["length"], values["width"]
            speed, turn = values["max_speed"], values["max_angular_speed"]
            if length and width and speed and turn:
                types[name] = RobotType(name, length, width, speed, turn)
        return types

    def obstacles(self) -> list[Obstacle]:
        entries = self.data.get("obstacles", [])
        if not isinstance(entries, list):
            self.error(self.where.key(None, "obstacles"), "'obstacles' must be an array of "
                       "tables: [[obstacles]]")
            return []
        result = []
        for index, entry in enumerate(entries):
            line = self.where.table("obstacles", index)
            if not isinstance(entry, dict):
                self.error((line, 1), "each obstacle must be a table: [[obstacles]]")
                continue
            for key in entry:
                if key not in ("name", "polygon", "height"):
                    self.error(self.where.key("obstacles", key, index),
                               f"unknown key '{key}' in an obstacle",
                               "an obstacle has name, polygon and height")
            name = entry.get("name", f"obstacle {index + 1}")
            if not isinstance(name, str):
                self.error(self.where.key("obstacles", "name", index),
                           "an obstacle's 'name' must be a string")
                name = f"obstacle {index + 1}"
            height = self.number(entry, "height", ("obstacles", index), default=1.0,
                                 positive=True, high=100.0)
            if "polygon" not in entry:
                self.error((line, 1), f"obstacle '{name}' has no 'polygon'",
                           "add polygon = [[x, y], ...] with its corners in order")
                continue
            polygon = self.polygon(entry["polygon"], "polygon",
                                   self.where.key("obstacles", "polygon", index),
                                   f"obstacle '{name}'")
            if polygon is not None and height is not None:
                result.append(Obstacle(name, polygon, height, line))
        return result

    def robots(self, types: Mapping[str, RobotType]) -> list[WorldRobot]:
        entries = self.data.get("robots", [])
        if not isinstance(entries, list):
            self.error(self.where.key(None, "robots"), "'robots' must be an array of tables: "
                       "[[robots]]")
            return []
        result: list[WorldRobot] = []
        for index, entry in enumerate(entries):
            line = self.where.table("robots", index)
            if not isinstance(entry, dict):
                self.error((line, 1), "each robot must be a table: [[robots]]")
                continue
            for key in entry:
                if key not in ("name", "type", "x", "y", "yaw", "yaw_deg"):
                    self.error(self.where.key("robots", key, index),
                               f"unknown key '{key}' in a robot",
                               "a robot has name, type, x, y and yaw or yaw_deg")
            name = entry.get("name")
            if not isinstance(name, str) or not name:
                self.error(self.where.key("robots", "name", index) if "name" in entry
                           else (line, 1), "each robot needs a 'name' (its role in the "
                           "scenario)", 'e.g. name = "R1"')
                continue
            if any(r.name == name for r in result):
                self.error(self.where.key("robots", "name", index),
                           f"robot '{name}' is defined twice")
                continue
            type_name = entry.get("type", DEFAULT_ROBOT_TYPE.name)
            if not isinstance(type_name, str) or type_name not in types:
                self.error(self.where.key("robots", "type", index),
                           f"unknown robot type {type_name!r}",
                           f"the robot types are {' '.join(sorted(types))}")
                continue
            where = ("robots", index)
            x = self.number(entry, "x", where)
            y = self.number(entry, "y", where)
            if "yaw" in entry and "yaw_deg" in entry:
                self.error(self.where.key("robots", "yaw_deg", index),
                           "give either 'yaw' (rad) or 'yaw_deg', not both")
                continue
            if "yaw_deg" in entry:
                degrees = self.number(entry, "yaw_deg", where, low=-3600.0, high=3600.0)
                yaw = None if degrees is None else math.radians(degrees)
            else:
                yaw = self.number(entry, "yaw", where, default=0.0, low=-100.0, high=100.0)
            if x is None or y is None or yaw is None:
                continue
            result.append(WorldRobot(name, types[type_name], Pose(x, y, yaw), line))
        return result


    def spectators(self) -> list[Spectator]:
        entries = self.data.get("spectators", [])
        if not isinstance(entries, list):
            self.error(self.where.key(None, "spectators"), "'spectators' must be an array of "
                       "tables: [[spectators]]")
            return []
        result = []
        allowed = ("name", "radius", "height", "speed", "path", "loop", "start")
        for index, entry in enumerate(entries):
            line = self.where.table("spectators", index)
            if not isinstance(entry, dict):
                self.error((line, 1), "each spectator must be a table: [[spectators]]")
                continue
            for key in entry:
                if key not in allowed:
                    self.error(self.where.key("spectators", key, index),
                               f"unknown key '{key}' in a spectator",
                               "a spectator has " + ", ".join(allowed))
            name = entry.get("name", f"spectator {index + 1}")
            if not isinstance(name, str):
                self.error(self.where.key("spectators", "name", index),
                           "a spectator's 'name' must be a string")
                continue
            where = ("spectators", index)
            radius = self.number(entry, "radius", where, default=0.3, positive=True, high=5.0)
            height = self.number(entry, "height", where, default=1.7, positive=True, high=5.0)
            speed = self.number(entry, "speed", where, default=1.0, positive=True, high=10.0)
            start = self.number(entry, "start", where, default=0.0, low=0.0, high=1e6)
            loop = entry.get("loop", False)
            if not isinstance(loop, bool):
                self.error(self.where.key("spectators", "loop", index),
                           "'loop' must be true or false")
                continue
            path = entry.get("path")
            position = self.where.key("spectators", "path", index) if "path" in entry else (
                line, 1)
            points = path if isinstance(path, list) else None
            ok = points is not None and len(points) >= 1 and all(
                isinstance(p, list) and len(p) in (2, 3) and all(
                    isinstance(c, int | float) and not isinstance(c, bool) for c in p)
                for p in points)
            if not ok or points is None:
                self.error(position, f"spectator '{name}' needs a 'path': a list of [x, y] or "
                           "[x, y, pause_s] waypoints", 'e.g. path = [[1, 1], [5, 1, 3.0]]')
                continue
            table = np.array([[*p, 0.0] if len(p) == 2 else p for p in points], dtype=float)
            if not np.all(np.isfinite(table)) or np.any(np.abs(table[:, :2]) > MAX_COORDINATE) \
                    or np.any(table[:, 2] < 0):
                self.error(position, f"the path of spectator '{name}' must hold finite "
                           "coordinates and pauses >= 0")
                continue
            if radius is None or height is None or speed is None or start is None:
                continue
            result.append(Spectator(name, radius, height, speed, table[:, :2].copy(),
                                    table[:, 2].copy(), loop, start, line))
        return result


def _describe(value: object) -> str:
    if isinstance(value, str):
        return f"the string {value[:20]!r}"
    return {list: "a list", dict: "a table", bool: "true/false"}.get(type(value), "that value")
