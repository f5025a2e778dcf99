"""World files: the bundled ones load; every error has its exact message and position."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from dancebots.diagnostics import DiagnosticError
from dancebots.world import THESIS_ROOM_SIZE, load_world, parse_world


def test_thesis_room(examples: Path) -> None:
    world = load_world(str(examples / "worlds" / "thesis_room.toml"))
    assert world.room.max() == THESIS_ROOM_SIZE
    assert world.wall_height == 2.0
    assert world.obstacles == ()


def test_robots_types_and_poses(data: Path) -> None:
    world = load_world(str(data / "worlds" / "two_robots.toml"))
    r1, r2 = world.robots
    assert (r1.name, r1.type.name, r1.type.length, r1.type.max_speed) == ("R1", "HUSKY", 0.99, 1.0)
    assert (r2.type.name, r2.type.width, r2.type.max_speed) == ("TRADR", 0.60, 0.5)
    assert (r1.start.x, r1.start.y, r1.start.theta) == (1.5, 3.6, 0.0)
    assert world.obstacles[0].name == "pillar"
    assert world.obstacles[0].line == 5


def test_defaults_and_custom_types() -> None:
    text = ('[robot_types.MARV]\nlength = 0.8\n[[robots]]\nname = "A"\ntype = "MARV"\n'
            'x = 1\ny = 2\nyaw_deg = 90\n')
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics
    robot = world.robots[0]
    assert (robot.type.length, robot.type.width, robot.type.max_speed) == (0.8, 0.6, 0.5)
    assert robot.start.theta == pytest.approx(math.pi / 2)
    assert world.room.max() == THESIS_ROOM_SIZE


def test_every_error_of_a_bad_world_at_its_line(data: Path) -> None:
    path = data / "worlds" / "bad.toml"
    world, diagnostics = parse_world(path.read_text(), "bad.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [
        "bad.toml:2:1: error: 'size' must be greater than 0",
        "bad.toml:3:1: error: unknown key 'colour' in [room]",
        "bad.toml:7:1: error: the polygon of obstacle 'bow tie' is not simple (its edges cross "
        "or it has no area)",
        "bad.toml:10:1: error: 'polygon' of obstacle 'obstacle 2' must be a list of at least 3 "
        "[x, y] points",
        "bad.toml:14:1: error: unknown robot type 'ROOMBA'",
        "bad.toml:19:1: error: 'x' must be a number, not the string 'one'",
        "bad.toml:20:1: error: 'y' must be a finite number",
        "bad.toml:23:1: error: 'max_speed' must be greater than 0",
    ]


@pytest.mark.parametrize(("text", "headline"), [
    ("[room\n", "w.toml:1:6: error: invalid TOML: expected ']' at the end of a table "
     "declaration"),
    ("[room]\nsize = 3\nsize = 4\n", "w.toml:3:9: error: invalid TOML: cannot overwrite a value"),
    ("[[robots]]\nname = \"R1\"\nx = 1\n", "w.toml:1:1: error: missing key 'y'"),
    ("[[robots]]\nname = \"R1\"\nx = 0\ny = 0\n[[robots]]\nname = \"R1\"\n",
     "w.toml:6:1: error: robot 'R1' is defined twice"),
    ("room = 3\n", "w.toml:1:1: error: 'room' must be a table: [room]"),
    ("[room]\nsize = 1e400\n", "w.toml:2:1: error: 'size' must be a finite number"),
    ("[room]\npolygon = [[0, 0], [4, 0], [4, 4]]\nsize = 3\n",
     "w.toml:3:1: error: give either 'size' or 'polygon' for the room, not both"),
    ("[[robots]]\nname = \"A\"\nx = 0\ny = 0\nyaw = 1\nyaw_deg = 3\n",
     "w.toml:6:1: error: give either 'yaw' (rad) or 'yaw_deg', not both"),
    ("[walls]\n", "w.toml:1:1: error: unknown key 'walls'"),
])
def test_world_error_messages(text: str, headline: str) -> None:
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert diagnostics[0].headline() == headline


def test_load_world_raises_with_diagnostics(tmp_path: Path) -> None:
    with pytest.raises(DiagnosticError) as caught:
        load_world(str(tmp_path))
    assert caught.value.diagnostics[0].message == "is a directory, not a file"
    with pytest.raises(DiagnosticError) as caught:
        load_world(str(tmp_path / "missing.toml"))
    assert caught.value.diagnostics[0].message == "no such file"


def test_spectators() -> None:
    text = ('[[spectators]]\nname = "child"\nspeed = 0.9\nstart = 2\nloop = true\n'
            'path = [[0, 0], [4, 0, 2.5]]\n[[spectators]]\npath = [[1, 1]]\n')
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics
    child, other = world.spectators
    assert (child.name, child.radius, child.height, child.speed, child.loop, child.start) == (
        "child", 0.3, 1.7, 0.9, True, 2.0)
    assert child.waypoints.tolist() == [[0.0, 0.0], [4.0, 0.0]]
    assert child.pauses.tolist() == [0.0, 2.5]
    assert other.name == "spectator 2"


@pytest.mark.parametrize(("text", "headline"), [
    ("[[spectators]]\nname = \"a\"\n", "w.toml:1:1: error: spectator 'a' needs a 'path': a "
     "list of [x, y] or [x, y, pause_s] waypoints"),
    ("[[spectators]]\npath = [[0, 0, -1]]\n", "w.toml:2:1: error: the path of spectator "
     "'spectator 1' must hold finite coordinates and pauses >= 0"),
    ("[[spectators]]\npath = [[0, 0]]\nspeed = 0\n", "w.toml:3:1: error: 'speed' must be "
     "greater than 0"),
    ("[[spectators]]\npath = [[0, 0]]\nloop = 1\n", "w.toml:3:1: error: 'loop' must be true "
     "or false"),
])
def test_spectator_errors(text: str, headline: str) -> None:
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert diagnostics[0].headline() == headline


def test_slowest_speed_is_the_default_vmax(data: Path) -> None:
    world = load_world(str(data / "worlds" / "two_robots.toml"))
    assert world.slowest_speed() == 0.5  # the TRADR; the HUSKY drives 1.0 m/s
    empty, _ = parse_world("", "w.toml")
    assert empty is not None
    assert empty.slowest_speed() is None
