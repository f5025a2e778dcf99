"""World files: TOML (read with the standard library's ``tomllib``) to a :class:`World`.

``docs/worlds.md`` is the format's reference. Lengths in m, angles in rad (``yaw``) or
degrees (``yaw_deg``), speeds in m/s and rad/s. The room's and obstacles' coordinates are in
the *world frame*. Every problem is a :class:`Diagnostic` with the file, line and column of
the offending key.
"""

from __future__ import annotations

import bisect
import math
import re
import tomllib
from collections.abc import Mapping
from typing import Any, cast

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import (
    Diagnostic,
    DiagnosticError,
    Severity,
    read_source_file,
    source_lines,
)
from dancebots.geometry import Pose
from dancebots.world.model import (
    BUILTIN_ROBOT_TYPES,
    CROWD_KINDS,
    DEFAULT_ROBOT_TYPE,
    THESIS_ROOM_SIZE,
    Crowd,
    CrowdKind,
    Obstacle,
    RobotType,
    Spectator,
    World,
    WorldRobot,
    spectator_route,
    square_room,
    start_conflicts,
)

__all__ = ["MISSING_WORLD_HINT", "load_world", "parse_world"]

MAX_COORDINATE = 10_000.0
"""Largest accepted coordinate, m (room, obstacles, robots, spectator paths)."""
MIN_ROOM_SIZE = 1.0
"""Smallest accepted side of a square room, m."""
MIN_ROBOT_VALUE = 0.01
"""Smallest accepted robot length and width (m), speeds (m/s, rad/s) and spectator radius (m)."""
MIN_SPECTATOR_SPEED = 0.01
"""Slowest accepted walking speed of a spectator, m/s."""
MAX_WALK = 3600.0
"""Longest accepted spectator walk (start delay, walking and pauses; one round of a loop), s."""
MAX_CROWD = 1000
"""Most pedestrians accepted in one crowd."""
MAX_SEED = 2**63 - 1
"""Largest accepted crowd seed."""
CROWD_FILL = 0.5
"""Most of a crowd's free area (its area less the obstacles) its discs may cover."""


MISSING_WORLD_HINT = ("check the path; docs/worlds.md describes world files, and "
                      "examples/worlds/ holds some")


def load_world(path: str) -> World:
    """Read and validate a world file; raises :class:`DiagnosticError` with every problem."""
    text, diagnostics = read_source_file(path, MISSING_WORLD_HINT)
    if text is None:
        raise DiagnosticError(diagnostics)
    world, diagnostics = parse_world(text, path)
    if world is None:
        raise DiagnosticError(diagnostics)
    return world


class _Locator:
    """Finds the line and column of a key in the TOML text (tomllib gives no positions)."""

    def __init__(self, text: str) -> None:
        self.lines = source_lines(text)
        self.headers: list[tuple[int, str]] = []
        # a table header: keys (bare or quoted, dotted) in brackets, alone on its line, so
        # that the rows of an array written over several lines ("  [1, 1],") are not one
        part = r"""(?:[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*')"""
        table = re.compile(rf"\s*(\[\[?)\s*({part}(?:\s*\.\s*{part})*)\s*\]\]?\s*(?:#.*)?$")
        for number, line in enumerate(self.lines, start=1):
            match = table.match(line)
            if match:
                self.headers.append((number, match.group(2).replace(" ", "")))
        # indexes, so that finding a key costs the length of its table, not of the file
        self.header_lines = [n for n, _ in self.headers]
        self.by_name: dict[str, list[int]] = {}
        for number, header in self.headers:
            self.by_name.setdefault(header, []).append(number)

    def table(self, name: str, occurrence: int = 0) -> int:
        found = self.by_name.get(name, [])
        return found[occurrence] if occurrence < len(found) else 1

    def key(self, table: str | None, key: str, occurrence: int = 0) -> tuple[int, int]:
        start = self.table(table, occurrence) if table else 1
        if not table and self.headers:
            end = self.headers[0][0]
        else:
            later = bisect.bisect_right(self.header_lines, start)
            end = self.header_lines[later] if later < len(self.header_lines) else (
                len(self.lines) + 1)
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
            max(1, len(source_lines(text))), 1)
        message = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)", "", message)
        return None, [Diagnostic(path, line, col, Severity.ERROR,
                                 f"invalid TOML: {message[:1].lower()}{message[1:]}",
                                 "see docs/worlds.md for the world-file format")]
    except ValueError:
        # tomllib reads integers with int(), which refuses more than 4300 digits
        # (sys.int_info.str_digits_check_threshold) with a ValueError of its own
        lines = source_lines(text)
        line = next((n for n, t in enumerate(lines, start=1)
                     if re.search(r"\d(?:_?\d){4300}", t)), 1)
        return None, [Diagnostic(path, line, 1, Severity.ERROR,
                                 "invalid TOML: an integer of more than 4300 digits",
                                 "is a digit too many?")]
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
        value = _float(value)
        if value is None:
            bounds = (f"greater than 0 and at most {high:g}" if positive and low <= 0 else
                      f"between {low:g} and {high:g}")
            self.error(position, f"'{key}' must be {bounds}", "is a digit too many?")
            return None
        ranges = "see the range of each key in docs/worlds.md"
        if not math.isfinite(value):
            self.error(position, f"'{key}' must be a finite number",
                       "write a decimal number; nan and inf are not accepted")
            return None
        if positive and value <= 0:
            self.error(position, f"'{key}' must be greater than 0", ranges)
            return None
        if not low <= value <= high:
            bounds = (f"greater than 0 and at most {high:g}" if positive and low <= 0 else
                      f"between {low:g} and {high:g}")
            self.error(position, f"'{key}' must be {bounds}", ranges)
            return None
        return value

    def polygon(self, value: Any, key: str, position: tuple[int, int],
                what: str) -> NDArray[np.float64] | None:
        ok = isinstance(value, list) and len(value) >= 3 and all(
            isinstance(p, list) and len(p) == 2 and all(
                isinstance(c, int | float) and not isinstance(c, bool) for c in p) for p in value)
        if not ok:
            self.error(position, f"'{key}' of {what} must be a list of at least 3 [x, y] "
                       "points", f"e.g. {key} = [[0, 0], [1, 0], [1, 1]]")
            return None
        points = _float_array(value)
        if points is None or not np.all(np.isfinite(points)) \
                or np.any(np.abs(points) > MAX_COORDINATE):
            self.error(position, f"the points of {what} must be finite numbers within "
                       f"+-{MAX_COORDINATE:g} m")
            return None
        shape = shapely.Polygon(points)
        if not shape.is_valid or shape.area <= 0.0:
            self.error(position, f"the polygon of {what} is not simple (its edges cross or it "
                       "has no area)", "list the corners in order around the outline")
            return None
        return points

    def integer(self, table: Mapping[str, Any], key: str, where: tuple[str, int], *,
                default: int | None, low: int, high: int) -> int | None:
        """A whole number from ``low`` to ``high``; None (and an error at the key) otherwise,
        or when it is missing without a default."""
        if key not in table:
            return default
        position = self.where.key(where[0], key, where[1])
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, int):
            what = "a decimal number" if isinstance(value, float) else _describe(value)
            self.error(position, f"'{key}' must be a whole number, not {what}",
                       "write it without a decimal point; nan and inf are not accepted")
            return None
        if not low <= value <= high:
            digits = value > high and len(str(value)) > len(str(high))
            self.error(position, f"'{key}' must be between {low} and {high}",
                       "is a digit too many?" if digits else
                       "see the range of each key in docs/worlds.md")
            return None
        return value

    def build(self) -> tuple[World | None, list[Diagnostic]]:
        known = {"room", "obstacles", "robots", "robot_types", "spectators", "crowds"}
        for key in self.data:
            if key not in known:
                self.error(self.where.key(None, key) if not isinstance(self.data[key], dict)
                           else (self.where.table(key), 1),
                           f"unknown key '{key}'", "the top-level tables are [room], "
                           "[[obstacles]], [[robots]], [[spectators]], [[crowds]] and "
                           "[robot_types.NAME]")
        room, wall_height = self.room()
        types = self.robot_types()
        obstacles = self.obstacles()
        robots = self.robots(types)
        spectators = self.spectators()
        crowds = self.crowds()
        if room is not None:
            self.layout(room, obstacles, robots, spectators)
            self.crowd_layout(shapely.Polygon(room), obstacles, spectators, crowds)
        if self.diagnostics or room is None:
            return None, sorted(self.diagnostics, key=lambda d: (d.line, d.col))
        return World(self.path, room, wall_height, tuple(obstacles), tuple(robots),
                     tuple(spectators), tuple(crowds)), []

    def at(self, table: str, line: int, key: str) -> tuple[int, int]:
        """The position of ``key`` in the [[table]] entry whose header is on ``line``."""
        lines = [n for n, header in self.where.headers if header == table]
        return self.where.key(table, key, lines.index(line) if line in lines else 0)

    def layout(self, room: NDArray[np.float64], obstacles: list[Obstacle],
               robots: list[WorldRobot], spectators: list[Spectator]) -> None:
        """What makes a world impossible although every value is valid: things outside the
        room, robots that start on each other, an obstacle or a visitor, duplicate names."""
        for kind, table, things in (("obstacle", "obstacles", obstacles),
                                    ("spectator", "spectators", spectators)):
            seen: set[str] = set()
            for thing in things:
                if thing.name in seen:
                    self.error(self.at(table, thing.line, "name"),
                               f"{kind} '{thing.name}' is defined twice",
                               f"give each {kind} its own name")
                seen.add(thing.name)
        shape = shapely.Polygon(room)
        for obstacle in obstacles:
            if not shape.covers(shapely.Polygon(obstacle.polygon)):
                self.error(self.at("obstacles", obstacle.line, "polygon"),
                           f"obstacle '{obstacle.name}' is not inside the room",
                           "move its corners inside the room, or make the room larger")
        self.spectator_layout(shape, obstacles, spectators)
        starts = np.array([[r.start.x, r.start.y, r.start.theta] for r in robots])
        for conflict in start_conflicts([r.type for r in robots], starts, room, obstacles,
                                        spectators):
            robot = robots[conflict.robot]
            where = self.at("robots", robot.line, "x")
            if conflict.kind == "room":
                self.error(where, f"robot '{robot.name}' starts outside the room or against "
                           "its wall", f"its {robot.type.name} footprint ({robot.type.length:g} "
                           f"x {robot.type.width:g} m) must lie inside the room, clear of the "
                           "walls: move x, y or turn it")
            elif conflict.kind == "robot":
                other = robots[conflict.other]
                self.error(self.at("robots", other.line, "x"), f"robots '{robot.name}' and "
                           f"'{other.name}' overlap at their start poses",
                           "place them further apart: the simulator would hold both where "
                           "they stand")
            elif conflict.kind == "obstacle":
                self.error(where, f"robot '{robot.name}' starts in or against obstacle "
                           f"'{obstacles[conflict.other].name}'",
                           "move it off the obstacle: its footprint must not touch it")
            else:
                self.error(where, f"robot '{robot.name}' starts where spectator "
                           f"'{spectators[conflict.other].name}' stands",
                           "move the robot or the spectator's first waypoint")

    def spectator_layout(self, room: shapely.Polygon, obstacles: list[Obstacle],
                         spectators: list[Spectator]) -> None:
        """Each spectator's disc must stay in the room and off the obstacles along its walk."""
        for spectator in spectators:
            where = self.at("spectators", spectator.line, "path")
            start = shapely.Point(spectator.waypoints[0])
            route = spectator_route(spectator)
            radius = spectator.radius
            if not room.contains(start) or room.exterior.distance(start) < radius:
                self.error(where, f"spectator '{spectator.name}' starts outside the room",
                           f"its disc (radius {radius:g} m) at the first waypoint must lie "
                           "inside the room")
            elif not room.contains(route) or room.exterior.distance(route) < radius:
                self.error(where, f"the path of spectator '{spectator.name}' leaves the room",
                           f"its disc (radius {radius:g} m) must stay inside the room along "
                           "the whole path")
            for obstacle in obstacles:
                if shapely.Polygon(obstacle.polygon).distance(route) < radius:
                    self.error(where, f"the path of spectator '{spectator.name}' crosses "
                               f"obstacle '{obstacle.name}'", "route the path around the "
                               "obstacle: the spectator's disc must not touch it")

    def crowd_layout(self, room: shapely.Polygon, obstacles: list[Obstacle],
                     spectators: list[Spectator], crowds: list[Crowd]) -> None:
        """Each crowd's name must be its own (contacts are reported by name: a crowd's
        members are "NAME 1" to "NAME count"), its area inside the room, and room enough in
        the area less the obstacles for its discs."""
        seen: set[str] = set()
        spectator_names = {s.name for s in spectators}
        blocked = shapely.union_all([shapely.Polygon(o.polygon) for o in obstacles])
        for crowd in crowds:
            name = self.at("crowds", crowd.line, "name")
            if crowd.name in seen:
                self.error(name, f"crowd '{crowd.name}' is defined twice",
                           "give each crowd its own name")
            seen.add(crowd.name)
            if crowd.name in spectator_names:
                self.error(name, f"crowd '{crowd.name}' has the name of a spectator",
                           "contacts are reported by name: give the crowd and the spectator "
                           "different names")
            prefix = crowd.name + " "
            members = sorted(s for s in spectator_names if s.startswith(prefix)
                             and _member(s[len(prefix):], crowd.count))
            if members:
                self.error(name, f"spectator '{members[0]}' has the name of a member of crowd "
                           f"'{crowd.name}'", f"the crowd's members are '{prefix}1' to "
                           f"'{prefix}{crowd.count}': rename the crowd or the spectator")
            area = shapely.Polygon(crowd.area)
            if not room.covers(area):
                self.error(self.at("crowds", crowd.line, "area"), f"the area of crowd "
                           f"'{crowd.name}' is not inside the room",
                           "move its corners inside the room, or make the room larger")
                continue
            free = float(area.difference(blocked).area) if obstacles else float(area.area)
            taken = crowd.count * math.pi * crowd.radius**2
            if taken > CROWD_FILL * free:
                self.error(self.at("crowds", crowd.line, "count"), f"crowd '{crowd.name}' "
                           f"has no room: {crowd.count} discs of radius {crowd.radius:g} m "
                           f"cover {taken:.3g} m², more than half of the {free:.3g} m² of its "
                           "area free of obstacles", "enlarge the area or lower count")

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
        size = self.number(table, "size", ("room", 0), default=THESIS_ROOM_SIZE, positive=True,
                           low=MIN_ROOM_SIZE)
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
                                       positive=True, low=MIN_ROBOT_VALUE, high=100.0)
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
            radius = self.number(entry, "radius", where, default=0.3, positive=True,
                                 low=MIN_ROBOT_VALUE, high=5.0)
            height = self.number(entry, "height", where, default=1.7, positive=True, high=5.0)
            speed = self.number(entry, "speed", where, default=1.0, positive=True,
                                low=MIN_SPECTATOR_SPEED, high=10.0)
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
            table = _float_array([[*p, 0.0] if len(p) == 2 else p for p in points])
            if table is None or not np.all(np.isfinite(table)) \
                    or np.any(np.abs(table[:, :2]) > MAX_COORDINATE) \
                    or np.any(table[:, 2] < 0) or np.any(table[:, 2] > MAX_WALK):
                self.error(position, f"the path of spectator '{name}' must hold coordinates "
                           f"within +-{MAX_COORDINATE:g} m and pauses from 0 to "
                           f"{MAX_WALK:g} s")
                continue
            if radius is None or height is None or speed is None or start is None:
                continue
            walk = _walk_duration(table, speed, loop, start)
            if walk > MAX_WALK:
                self.error(position, f"the walk of spectator '{name}' lasts {walk:.0f} s, "
                           f"longer than {MAX_WALK / 3600:g} h",
                           "shorten the path or the pauses, or raise the speed")
                continue
            result.append(Spectator(name, radius, height, speed, table[:, :2].copy(),
                                    table[:, 2].copy(), loop, start, line))
        return result

    def crowds(self) -> list[Crowd]:
        entries = self.data.get("crowds", [])
        if not isinstance(entries, list):
            self.error(self.where.key(None, "crowds"), "'crowds' must be an array of tables: "
                       "[[crowds]]")
            return []
        result = []
        allowed = ("name", "count", "area", "kind", "speed", "speed_sd", "radius", "height",
                   "seed")
        kinds = " or ".join(f'"{kind}"' for kind in CROWD_KINDS)
        for index, entry in enumerate(entries):
            line = self.where.table("crowds", index)
            if not isinstance(entry, dict):
                self.error((line, 1), "each crowd must be a table: [[crowds]]")
                continue
            for key in entry:
                if key not in allowed:
                    self.error(self.where.key("crowds", key, index),
                               f"unknown key '{key}' in a crowd",
                               "a crowd has " + ", ".join(allowed))
            name = entry.get("name", f"crowd {index + 1}")
            if not isinstance(name, str):
                self.error(self.where.key("crowds", "name", index),
                           "a crowd's 'name' must be a string")
                name = f"crowd {index + 1}"
            where = ("crowds", index)
            kind = entry.get("kind", "adult")
            if not isinstance(kind, str) or kind not in CROWD_KINDS:
                self.error(self.where.key("crowds", "kind", index),
                           f"'kind' must be {kinds}, not {_describe(kind)}",
                           f"the crowd kinds are {' '.join(CROWD_KINDS)}")
                kind = None
            base = CROWD_KINDS[kind or "adult"]
            speed = self.number(entry, "speed", where, default=base.speed, positive=True,
                                low=0.1, high=3.0)
            speed_sd = self.number(entry, "speed_sd", where, default=base.speed_sd, low=0.0,
                                   high=2.0)
            radius = self.number(entry, "radius", where, default=base.radius, positive=True,
                                 low=MIN_ROBOT_VALUE, high=1.0)
            height = self.number(entry, "height", where, default=base.height, positive=True,
                                 high=5.0)
            seed = self.integer(entry, "seed", where, default=0, low=0, high=MAX_SEED)
            count = self.integer(entry, "count", where, default=None, low=1, high=MAX_CROWD)
            if "count" not in entry:
                self.error((line, 1), f"crowd '{name}' has no 'count'",
                           f"add count = N: how many pedestrians walk (1 to {MAX_CROWD})")
            if "area" not in entry:
                self.error((line, 1), f"crowd '{name}' has no 'area'",
                           "add area = [[x, y], ...] with the corners, in order, of where "
                           "the crowd walks")
                continue
            area = self.polygon(entry["area"], "area", self.where.key("crowds", "area", index),
                                f"crowd '{name}'")
            if area is None or kind is None or count is None or seed is None or speed is None \
                    or speed_sd is None or radius is None or height is None:
                continue
            result.append(Crowd(name, count, area, cast(CrowdKind, kind), speed, speed_sd,
                                radius, height, seed, line))
        return result


def _member(number: str, count: int) -> bool:
    """Whether ``number`` is how a crowd of ``count`` numbers one of its members (1 to
    count, written without a sign or leading zeros)."""
    return number.isascii() and number.isdigit() and not number.startswith("0") \
        and len(number) <= len(str(count)) and int(number) <= count


def _float(value: int | float) -> float | None:
    """``value`` as a float; None for an integer beyond the float range (e.g. 10**400)."""
    try:
        return float(value)
    except OverflowError:
        return None


def _float_array(value: Any) -> NDArray[np.float64] | None:
    """A list of equally long lists of numbers as a float array; None when a number is an
    integer beyond the float range."""
    try:
        return np.array(value, dtype=float)
    except OverflowError:
        return None


def _walk_duration(table: NDArray[np.float64], speed: float, loop: bool, start: float) -> float:
    """A spectator's start delay, walking time at ``speed`` (m/s) and pauses, s (one round for
    a loop): the closed form of ``sim.spectators.walk_duration``, checked at load time."""
    points = np.vstack([table[:, :2], table[:1, :2]]) if loop else table[:, :2]
    legs = float(np.hypot(*np.diff(points, axis=0).T).sum()) if len(points) > 1 else 0.0
    pauses = float(table[1:, 2].sum()) + (float(table[0, 2]) if loop else 0.0)
    return start + legs / speed + pauses


def _describe(value: object) -> str:
    if isinstance(value, str):
        return f"the string {value[:20]!r}"
    return {list: "a list", dict: "a table", bool: "true/false"}.get(type(value), "that value")
