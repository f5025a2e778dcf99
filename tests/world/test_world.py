"""World files: the bundled ones load; every error has its exact message and position."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from dancebots.diagnostics import DiagnosticError
from dancebots.world import CROWD_KINDS, THESIS_ROOM_SIZE, load_world, parse_world


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


def test_every_error_of_bad_crowds_at_its_line(data: Path) -> None:
    path = data / "worlds" / "bad_crowds.toml"
    world, diagnostics = parse_world(path.read_text(), "bad_crowds.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [
        'bad_crowds.toml:4:1: error: \'kind\' must be "adult" or "child", not the string \'elder\'',
        "bad_crowds.toml:5:1: error: 'count' must be a whole number, not a decimal number",
        "bad_crowds.toml:6:1: error: 'speed' must be greater than 0",
        "bad_crowds.toml:7:1: error: 'seed' must be between 0 and 9223372036854775807",
        "bad_crowds.toml:8:1: error: 'area' of crowd 'class' must be a list of at least 3 [x, y] "
        "points",
        "bad_crowds.toml:9:1: error: unknown key 'mood' in a crowd",
        "bad_crowds.toml:12:1: error: 'count' must be between 1 and 1000",
        "bad_crowds.toml:13:1: error: 'radius' must be a finite number",
        "bad_crowds.toml:14:1: error: 'speed_sd' must be a number, not true/false",
        "bad_crowds.toml:15:1: error: 'height' must be greater than 0 and at most 5",
        "bad_crowds.toml:16:1: error: 'seed' must be a whole number, not a decimal number",
        "bad_crowds.toml:19:1: error: crowd 'crowd 3' has no 'count'",
        "bad_crowds.toml:19:1: error: crowd 'crowd 3' has no 'area'",
        "bad_crowds.toml:20:1: error: a crowd's 'name' must be a string",
    ]


@pytest.mark.parametrize(("text", "headline"), [
    ("[room\n", "w.toml:1:6: error: invalid TOML: expected ']' at the end of a table "
     "declaration"),
    ("[room]\nsize = 3\nsize = 4\n", "w.toml:3:9: error: invalid TOML: cannot overwrite a value"),
    ("[[robots]]\nname = \"R1\"\nx = 1\n", "w.toml:1:1: error: missing key 'y'"),
    ("[[robots]]\nname = \"R1\"\nx = 2\ny = 2\n[[robots]]\nname = \"R1\"\n",
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
            'path = [[1, 1], [5, 1, 2.5]]\n[[spectators]]\npath = [[2, 2]]\n')
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics
    child, other = world.spectators
    assert (child.name, child.radius, child.height, child.speed, child.loop, child.start) == (
        "child", 0.3, 1.7, 0.9, True, 2.0)
    assert child.waypoints.tolist() == [[1.0, 1.0], [5.0, 1.0]]
    assert child.pauses.tolist() == [0.0, 2.5]
    assert other.name == "spectator 2"


@pytest.mark.parametrize(("text", "headline"), [
    ("[[spectators]]\nname = \"a\"\n", "w.toml:1:1: error: spectator 'a' needs a 'path': a "
     "list of [x, y] or [x, y, pause_s] waypoints"),
    ("[[spectators]]\npath = [[0, 0, -1]]\n", "w.toml:2:1: error: the path of spectator "
     "'spectator 1' must hold coordinates within +-10000 m and pauses from 0 to 3600 s"),
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


HUGE = "1" + "0" * 400  # an integer TOML reads exactly and no float holds


@pytest.mark.parametrize(("text", "headline", "hint"), [
    (f"[room]\nsize = {HUGE}\n", "w.toml:2:1: error: 'size' must be between 1 and 10000",
     "is a digit too many?"),
    (f"[[robots]]\nname = 'A'\nx = -{HUGE}\ny = 0\n",
     "w.toml:3:1: error: 'x' must be between -10000 and 10000", "is a digit too many?"),
    ("[room]\nsize = 5e-324\n", "w.toml:2:1: error: 'size' must be between 1 and 10000",
     "see the range of each key in docs/worlds.md"),
    ("[room]\nsize = -0.0\n", "w.toml:2:1: error: 'size' must be greater than 0",
     "see the range of each key in docs/worlds.md"),
    ("[room]\nsize = nan\n", "w.toml:2:1: error: 'size' must be a finite number",
     "write a decimal number; nan and inf are not accepted"),
    ("[robot_types.SIM]\nmax_speed = 1e-300\n", "w.toml:2:1: error: 'max_speed' must be "
     "between 0.01 and 100", "see the range of each key in docs/worlds.md"),
    (f"[room]\npolygon = [[0, 0], [{HUGE}, 0], [1, 1]]\n", "w.toml:2:1: error: the points of "
     "the room must be finite numbers within +-10000 m", None),
    (f"[[obstacles]]\npolygon = [[0, 0], [1, 0], [1, {HUGE}]]\n", "w.toml:2:1: error: the "
     "points of obstacle 'obstacle 1' must be finite numbers within +-10000 m", None),
    (f"[[spectators]]\npath = [[1, 1], [2, {HUGE}]]\n", "w.toml:2:1: error: the path of "
     "spectator 'spectator 1' must hold coordinates within +-10000 m and pauses from 0 to "
     "3600 s", None),
    ("[[spectators]]\npath = [[1, 1], [2, 2, 1e308]]\n", "w.toml:2:1: error: the path of "
     "spectator 'spectator 1' must hold coordinates within +-10000 m and pauses from 0 to "
     "3600 s", None),
    ("[[spectators]]\nspeed = 1e-320\npath = [[1, 1], [2, 2]]\n", "w.toml:2:1: error: "
     "'speed' must be between 0.01 and 10", "see the range of each key in docs/worlds.md"),
    ("[[spectators]]\nspeed = 0.01\nloop = true\npath = [[1, 1], [200, 2]]\n",
     "w.toml:4:1: error: the walk of spectator 'spectator 1' lasts 39801 s, longer than 1 h",
     "shorten the path or the pauses, or raise the speed"),
])
def test_hostile_numbers_are_positioned_errors(text: str, headline: str,
                                               hint: str | None) -> None:
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [headline]
    assert diagnostics[0].hint == hint


@pytest.mark.parametrize("separator", ["\x85", "\u2028", "\u2029"])
def test_only_newlines_end_lines_of_a_world(separator: str) -> None:
    text = f'# a note{separator}with odd breaks\n[room]\nsize = 0\n'
    _, diagnostics = parse_world(text, "w.toml")
    assert [d.headline() for d in diagnostics] == [
        "w.toml:3:1: error: 'size' must be greater than 0"]


def test_every_error_of_an_impossible_world(data: Path) -> None:
    """Valid values that no show can run in: each problem at the key to change."""
    path = data / "worlds" / "impossible.toml"
    world, diagnostics = parse_world(path.read_text(), "impossible.toml")
    assert world is None
    assert [(d.headline(), d.hint) for d in diagnostics] == [
        ("impossible.toml:11:1: error: obstacle 'pillar' is defined twice",
         "give each obstacle its own name"),
        ("impossible.toml:12:1: error: obstacle 'pillar' is not inside the room",
         "move its corners inside the room, or make the room larger"),
        ("impossible.toml:16:1: error: robot 'R1' starts outside the room or against its wall",
         "its SIM footprint (1.2 x 0.6 m) must lie inside the room, clear of the walls: move "
         "x, y or turn it"),
        ("impossible.toml:26:1: error: robots 'R2' and 'R3' overlap at their start poses",
         "place them further apart: the simulator would hold both where they stand"),
        ("impossible.toml:32:1: error: robot 'R4' starts in or against obstacle 'pillar'",
         "move it off the obstacle: its footprint must not touch it"),
        ("impossible.toml:37:1: error: robot 'R5' starts where spectator 'child' stands",
         "move the robot or the spectator's first waypoint"),
        ("impossible.toml:45:1: error: spectator 'child' is defined twice",
         "give each spectator its own name"),
        ("impossible.toml:47:1: error: spectator 'child' starts outside the room",
         "its disc (radius 0.5 m) at the first waypoint must lie inside the room"),
        ("impossible.toml:52:1: error: the path of spectator 'parent' leaves the room",
         "its disc (radius 0.3 m) must stay inside the room along the whole path"),
        ("impossible.toml:56:1: error: the path of spectator 'visitor' crosses obstacle "
         "'pillar'", "route the path around the obstacle: the spectator's disc must not "
         "touch it"),
        ("impossible.toml:68:1: error: crowd 'visitors' is defined twice",
         "give each crowd its own name"),
        ("impossible.toml:73:1: error: crowd 'parent' has the name of a spectator",
         "contacts are reported by name: give the crowd and the spectator different names"),
        ("impossible.toml:78:1: error: spectator 'class 2' has the name of a member of crowd "
         "'class'", "the crowd's members are 'class 1' to 'class 5': rename the crowd or the "
         "spectator"),
        ("impossible.toml:81:1: error: the area of crowd 'class' is not inside the room",
         "move its corners inside the room, or make the room larger"),
        ("impossible.toml:85:1: error: crowd 'queue' has no room: 40 discs of radius 0.25 m "
         "cover 7.85 m², more than half of the 4 m² of its area free of obstacles",
         "enlarge the area or lower count"),
    ]


ROBOT = '[[robots]]\nname = "{}"\ntype = "{}"\nx = {}\ny = {}\nyaw_deg = {}\n'


@pytest.mark.parametrize(("robots", "problem"), [
    # SIM 1.2 x 0.6 m: x from 0.6 to 10.073 fits the 10.673 m room with yaw 0, but against
    # the wall is refused too (the simulator would count it a contact)
    ([("A", "SIM", 0.6001, 5, 0)], None),
    ([("A", "SIM", 0.6, 5, 0)], "robot 'A' starts outside the room or against its wall"),
    ([("A", "SIM", 0.5999, 5, 0)], "robot 'A' starts outside the room or against its wall"),
    ([("A", "SIM", 5, 10.673 - 0.3001, 0)], None),
    ([("A", "SIM", 5, 10.673 - 0.2999, 0)],
     "robot 'A' starts outside the room or against its wall"),
    # turned by 90 degrees it is 0.6 m wide along x
    ([("A", "SIM", 0.3001, 5, 90)], None),
    ([("A", "SIM", 0.3, 5, 90)], "robot 'A' starts outside the room or against its wall"),
    # side by side 0.6 m apart: touching is allowed, 0.1 mm of overlap is not
    ([("A", "SIM", 3, 3, 0), ("B", "SIM", 3, 3.6, 0)], None),
    ([("A", "SIM", 3, 3, 0), ("B", "SIM", 3, 3.5999, 0)],
     "robots 'A' and 'B' overlap at their start poses"),
    # nose to tail (the thesis's rows 1.2 m apart)
    ([("A", "SIM", 3, 3, 0), ("B", "SIM", 4.2, 3, 0)], None),
    ([("A", "SIM", 3, 3, 0), ("B", "HUSKY", 3.3, 3, 90)],
     "robots 'A' and 'B' overlap at their start poses"),
])
def test_start_poses_must_fit_the_room_and_each_other(
        robots: list[tuple[str, str, float, float, float]], problem: str | None) -> None:
    text = "".join(ROBOT.format(*robot) for robot in robots)
    world, diagnostics = parse_world(text, "w.toml")
    assert [d.message for d in diagnostics] == ([problem] if problem else [])
    assert (world is None) == (problem is not None)


@pytest.mark.parametrize(("spectator", "problem"), [
    # radius 0.3 m in a 10 m room: the centre may come to 0.3 m of a wall
    ("path = [[0.3, 2], [9.7, 2]]", None),
    ("path = [[0.29, 2], [9.7, 2]]", "spectator 'a' starts outside the room"),
    ("path = [[0.3, 2], [9.71, 2]]", "the path of spectator 'a' leaves the room"),
    ("path = [[11, 5]]", "spectator 'a' starts outside the room"),
    # the way back to the first waypoint of a loop counts: it cuts the pillar's corner
    ("path = [[3, 3], [3, 7], [7, 7]]", None),
    ("path = [[3, 3], [3, 7], [7, 7]]\nloop = true",
     "the path of spectator 'a' crosses obstacle 'pillar'"),
    ("path = [[4.2, 5.5]]", "the path of spectator 'a' crosses obstacle 'pillar'"),
])
def test_spectator_paths_must_stay_in_the_room_and_off_obstacles(spectator: str,
                                                                 problem: str | None) -> None:
    text = ('[room]\nsize = 10\n[[obstacles]]\nname = "pillar"\n'
            'polygon = [[4.5, 4.5], [5.5, 4.5], [5.5, 5.5], [4.5, 5.5]]\n'
            f'[[spectators]]\nname = "a"\n{spectator}\n')
    world, diagnostics = parse_world(text, "w.toml")
    assert [d.message for d in diagnostics] == ([problem] if problem else [])
    assert (world is None) == (problem is not None)
    assert all((d.line, d.col) == (8, 1) for d in diagnostics)  # at its 'path'


def test_the_bundled_and_example_worlds_are_possible(examples: Path, data: Path) -> None:
    bundled = Path(__file__).resolve().parent.parent / "src" / "dancebots" / "data"
    for path in [*bundled.glob("*.toml"), *(examples / "worlds").glob("*.toml"),
                 data / "worlds" / "two_robots.toml"]:
        load_world(str(path))


def test_a_positive_key_out_of_range_states_its_real_range() -> None:
    world, problems = parse_world("[room]\nsize = 10\nwall_height = 1e308\n", "w.toml")
    assert world is None
    assert [(d.line, d.message) for d in problems] == [
        (3, "'wall_height' must be greater than 0 and at most 100")]


# --- crowds ---------------------------------------------------------------------------------

AREA = "area = [[1, 1], [9, 1], [9, 9], [1, 9]]"


def crowd(*lines: str, count: int | None = 5, area: str | None = AREA) -> str:
    """A world of one [[crowds]] entry: header, count and area (lines 1 to 3 when given),
    then ``lines``."""
    body = [f"count = {count}"] if count is not None else []
    body += [area] if area is not None else []
    return "\n".join(["[[crowds]]", *body, *lines]) + "\n"


def test_the_crowds_of_a_world_file(data: Path) -> None:
    world = load_world(str(data / "worlds" / "crowds.toml"))
    adults, children = world.crowds
    adult = CROWD_KINDS["adult"]
    assert (adults.name, adults.count, adults.kind, adults.seed, adults.line) == (
        "crowd 1", 20, "adult", 0, 26)
    assert (adults.speed, adults.speed_sd, adults.radius, adults.height) == (
        adult.speed, adult.speed_sd, adult.radius, adult.height)
    assert adults.area.tolist() == [[4.0, 4.0], [10.0, 4.0], [10.0, 10.0], [4.0, 10.0]]
    assert adults.area.dtype == float
    assert (children.name, children.count, children.kind, children.seed, children.line) == (
        "school class", 12, "child", 42, 30)
    assert (children.speed, children.speed_sd, children.radius, children.height) == (
        1.5, 0.5, 0.2, 1.2)
    assert [s.name for s in world.spectators] == ["guide"]


@pytest.mark.parametrize("kind", sorted(CROWD_KINDS))
def test_a_crowd_takes_its_kinds_defaults(kind: str) -> None:
    world, diagnostics = parse_world(crowd(f'kind = "{kind}"'), "w.toml")
    assert world is not None, diagnostics
    [group] = world.crowds
    defaults = CROWD_KINDS[kind]
    assert (group.kind, group.speed, group.speed_sd, group.radius, group.height, group.seed) == (
        kind, defaults.speed, defaults.speed_sd, defaults.radius, defaults.height, 0)
    assert (group.name, group.count, group.line) == ("crowd 1", 5, 1)


def test_a_crowd_without_a_kind_is_adults() -> None:
    world, diagnostics = parse_world(crowd(), "w.toml")
    assert world is not None, diagnostics
    assert world.crowds[0].kind == "adult"
    assert world.crowds[0].radius == CROWD_KINDS["adult"].radius


@pytest.mark.parametrize("values", [
    # the ends of every range
    {"count": "1", "speed": "0.1", "speed_sd": "0", "radius": "0.01", "height": "1e-300",
     "seed": "0"},
    {"count": "1", "speed": "3.0", "speed_sd": "2.0", "radius": "1.0", "height": "5",
     "seed": str(2**63 - 1)},
    {"count": "20", "kind": '"child"', "speed": "2", "seed": "17", "name": '"kids"'},
])
def test_explicit_crowd_values(values: dict[str, str]) -> None:
    text = crowd(*(f"{key} = {value}" for key, value in values.items() if key != "count"),
                 count=int(values["count"]))
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics
    [group] = world.crowds
    for key, value in values.items():
        expected = value.strip('"') if value.startswith('"') else (
            int(value) if key in ("count", "seed") else float(value))
        assert getattr(group, key) == expected, key
    assert isinstance(group.count, int)
    assert isinstance(group.seed, int)


def test_a_thousand_pedestrians_in_a_large_area() -> None:
    text = crowd("radius = 0.1", count=1000, area="area = [[0, 0], [10, 0], [10, 10], [0, 10]]")
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics
    assert world.crowds[0].count == 1000


def test_a_multi_line_area_keeps_the_positions_of_the_keys_after_it() -> None:
    text = "[[crowds]]\narea = [\n  [1, 1],\n  [9, 1],\n  [9, 9],\n]\ncount = 0\n"
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [
        "w.toml:7:1: error: 'count' must be between 1 and 1000"]


WHOLE = "write it without a decimal point; nan and inf are not accepted"
RANGES = "see the range of each key in docs/worlds.md"
FINITE = "write a decimal number; nan and inf are not accepted"
DIGITS = "is a digit too many?"


@pytest.mark.parametrize(("text", "headline", "hint"), [
    # the table itself
    ("crowds = 3\n", "w.toml:1:1: error: 'crowds' must be an array of tables: [[crowds]]",
     None),
    ("crowds = [1]\n", "w.toml:1:1: error: each crowd must be a table: [[crowds]]", None),
    (crowd(count=None), "w.toml:1:1: error: crowd 'crowd 1' has no 'count'",
     "add count = N: how many pedestrians walk (1 to 1000)"),
    (crowd(area=None), "w.toml:1:1: error: crowd 'crowd 1' has no 'area'",
     "add area = [[x, y], ...] with the corners, in order, of where the crowd walks"),
    (crowd("colour = 'red'"), "w.toml:4:1: error: unknown key 'colour' in a crowd",
     "a crowd has name, count, area, kind, speed, speed_sd, radius, height, seed"),
    (crowd("name = 3"), "w.toml:4:1: error: a crowd's 'name' must be a string", None),
    (crowd('kind = "elder"'), "w.toml:4:1: error: 'kind' must be \"adult\" or \"child\", not "
     "the string 'elder'", "the crowd kinds are adult child"),
    (crowd("kind = 1"), "w.toml:4:1: error: 'kind' must be \"adult\" or \"child\", not that "
     "value", "the crowd kinds are adult child"),
    (crowd('kind = "Adult"'), "w.toml:4:1: error: 'kind' must be \"adult\" or \"child\", not "
     "the string 'Adult'", "the crowd kinds are adult child"),
    # count: a whole number from 1 to 1000
    (crowd(count=0), "w.toml:2:1: error: 'count' must be between 1 and 1000", RANGES),
    (crowd(count=-1), "w.toml:2:1: error: 'count' must be between 1 and 1000", RANGES),
    (crowd(count=1001), "w.toml:2:1: error: 'count' must be between 1 and 1000", RANGES),
    (crowd(count=10000), "w.toml:2:1: error: 'count' must be between 1 and 1000", DIGITS),
    (crowd(count=10**400), "w.toml:2:1: error: 'count' must be between 1 and 1000", DIGITS),
    (crowd("count = 5.0", count=None), "w.toml:3:1: error: 'count' must be a whole number, "
     "not a decimal number", WHOLE),
    (crowd("count = nan", count=None), "w.toml:3:1: error: 'count' must be a whole number, "
     "not a decimal number", WHOLE),
    (crowd("count = 1e308", count=None), "w.toml:3:1: error: 'count' must be a whole number, "
     "not a decimal number", WHOLE),
    (crowd("count = true", count=None), "w.toml:3:1: error: 'count' must be a whole number, "
     "not true/false", WHOLE),
    (crowd("count = '5'", count=None), "w.toml:3:1: error: 'count' must be a whole number, "
     "not the string '5'", WHOLE),
    (crowd("count = {n = 5}", count=None), "w.toml:3:1: error: 'count' must be a whole "
     "number, not a table", WHOLE),
    # seed: a whole number from 0 to 2**63 - 1
    (crowd("seed = -1"), "w.toml:4:1: error: 'seed' must be between 0 and "
     "9223372036854775807", RANGES),
    (crowd(f"seed = {2**63}"), "w.toml:4:1: error: 'seed' must be between 0 and "
     "9223372036854775807", RANGES),
    (crowd(f"seed = {10**400}"), "w.toml:4:1: error: 'seed' must be between 0 and "
     "9223372036854775807", DIGITS),
    (crowd("seed = 1.5"), "w.toml:4:1: error: 'seed' must be a whole number, not a decimal "
     "number", WHOLE),
    (crowd("seed = inf"), "w.toml:4:1: error: 'seed' must be a whole number, not a decimal "
     "number", WHOLE),
    (crowd("seed = false"), "w.toml:4:1: error: 'seed' must be a whole number, not "
     "true/false", WHOLE),
    # speed: 0.1 to 3 m/s
    (crowd("speed = 0"), "w.toml:4:1: error: 'speed' must be greater than 0", RANGES),
    (crowd("speed = -1"), "w.toml:4:1: error: 'speed' must be greater than 0", RANGES),
    (crowd("speed = 1e-300"), "w.toml:4:1: error: 'speed' must be between 0.1 and 3", RANGES),
    (crowd("speed = 3.01"), "w.toml:4:1: error: 'speed' must be between 0.1 and 3", RANGES),
    (crowd("speed = 1e308"), "w.toml:4:1: error: 'speed' must be between 0.1 and 3", RANGES),
    (crowd(f"speed = {10**400}"), "w.toml:4:1: error: 'speed' must be between 0.1 and 3",
     DIGITS),
    (crowd("speed = nan"), "w.toml:4:1: error: 'speed' must be a finite number", FINITE),
    (crowd("speed = -inf"), "w.toml:4:1: error: 'speed' must be a finite number", FINITE),
    (crowd("speed = 'x'"), "w.toml:4:1: error: 'speed' must be a number, not the string 'x'",
     None),
    # speed_sd: 0 to 2 m/s
    (crowd("speed_sd = -1"), "w.toml:4:1: error: 'speed_sd' must be between 0 and 2", RANGES),
    (crowd("speed_sd = 2.5"), "w.toml:4:1: error: 'speed_sd' must be between 0 and 2",
     RANGES),
    (crowd("speed_sd = inf"), "w.toml:4:1: error: 'speed_sd' must be a finite number", FINITE),
    (crowd("speed_sd = true"), "w.toml:4:1: error: 'speed_sd' must be a number, not "
     "true/false", None),
    # radius: 0.01 to 1 m
    (crowd("radius = 0"), "w.toml:4:1: error: 'radius' must be greater than 0", RANGES),
    (crowd("radius = 1e-300"), "w.toml:4:1: error: 'radius' must be between 0.01 and 1",
     RANGES),
    (crowd("radius = 1.5"), "w.toml:4:1: error: 'radius' must be between 0.01 and 1", RANGES),
    (crowd("radius = nan"), "w.toml:4:1: error: 'radius' must be a finite number", FINITE),
    (crowd("radius = [1]"), "w.toml:4:1: error: 'radius' must be a number, not a list", None),
    # height: more than 0, at most 5 m
    (crowd("height = 0"), "w.toml:4:1: error: 'height' must be greater than 0", RANGES),
    (crowd("height = 5.5"), "w.toml:4:1: error: 'height' must be greater than 0 and at most 5",
     RANGES),
    (crowd("height = 1e308"), "w.toml:4:1: error: 'height' must be greater than 0 and at "
     "most 5", RANGES),
    (crowd("height = inf"), "w.toml:4:1: error: 'height' must be a finite number", FINITE),
    # area: a simple polygon inside the room
    (crowd(area="area = [[1, 1], [2, 2]]"), "w.toml:3:1: error: 'area' of crowd 'crowd 1' "
     "must be a list of at least 3 [x, y] points", "e.g. area = [[0, 0], [1, 0], [1, 1]]"),
    (crowd(area="area = 'hall'"), "w.toml:3:1: error: 'area' of crowd 'crowd 1' must be a "
     "list of at least 3 [x, y] points", "e.g. area = [[0, 0], [1, 0], [1, 1]]"),
    (crowd(area="area = [[0, 0], [1, 1], [1, 0], [0, 1]]"), "w.toml:3:1: error: the polygon "
     "of crowd 'crowd 1' is not simple (its edges cross or it has no area)",
     "list the corners in order around the outline"),
    (crowd(area=f"area = [[1, 1], [9, 1], [9, {10**400}]]"), "w.toml:3:1: error: the points "
     "of crowd 'crowd 1' must be finite numbers within +-10000 m", None),
    (crowd(area="area = [[1, 1], [9, 1], [9, nan]]"), "w.toml:3:1: error: the points of crowd "
     "'crowd 1' must be finite numbers within +-10000 m", None),
    (crowd(area="area = [[1, 1], [11, 1], [11, 9], [1, 9]]"), "w.toml:3:1: error: the area "
     "of crowd 'crowd 1' is not inside the room",
     "move its corners inside the room, or make the room larger"),
    (crowd(area="area = [[-1, -1], [-5, -1], [-5, -5]]"), "w.toml:3:1: error: the area of "
     "crowd 'crowd 1' is not inside the room",
     "move its corners inside the room, or make the room larger"),
    # room for the crowd: the discs may cover half of the area less the obstacles
    (crowd(count=1000), "w.toml:2:1: error: crowd 'crowd 1' has no room: 1000 discs of radius "
     "0.25 m cover 196 m², more than half of the 64 m² of its area free of obstacles",
     "enlarge the area or lower count"),
    (crowd("radius = 1", count=11), "w.toml:2:1: error: crowd 'crowd 1' has no room: 11 discs "
     "of radius 1 m cover 34.6 m², more than half of the 64 m² of its area free of obstacles",
     "enlarge the area or lower count"),
    # names: one per crowd, none a spectator's or a crowd member's
    # the second crowd's default name, at its header
    (crowd('name = "crowd 2"') + crowd(), "w.toml:5:1: error: crowd 'crowd 2' is defined "
     "twice", "give each crowd its own name"),
    (crowd('name = "a"') + crowd('name = "a"'), "w.toml:8:1: error: crowd 'a' is defined "
     "twice", "give each crowd its own name"),
    ('[[spectators]]\nname = "fans"\npath = [[0.5, 0.5]]\n' + crowd('name = "fans"'),
     "w.toml:7:1: error: crowd 'fans' has the name of a spectator",
     "contacts are reported by name: give the crowd and the spectator different names"),
    ('[[spectators]]\npath = [[0.5, 0.5]]\n[[crowds]]\nname = "spectator 1"\ncount = 1\n'
     + AREA + "\n", "w.toml:4:1: error: crowd 'spectator 1' has the name of a spectator",
     "contacts are reported by name: give the crowd and the spectator different names"),
    ('[[spectators]]\nname = "crowd 1 5"\npath = [[0.5, 0.5]]\n' + crowd(),
     "w.toml:4:1: error: spectator 'crowd 1 5' has the name of a member of crowd 'crowd 1'",
     "the crowd's members are 'crowd 1 1' to 'crowd 1 5': rename the crowd or the spectator"),
    # the top level knows [[crowds]]
    ("[[crowd]]\n", "w.toml:1:1: error: unknown key 'crowd'", "the top-level tables are "
     "[room], [[obstacles]], [[robots]], [[spectators]], [[crowds]] and [robot_types.NAME]"),
    # an integer Python will not read: an error at its line, not a traceback
    (crowd("seed = 1" + "0" * 5000), "w.toml:4:1: error: invalid TOML: an integer of more "
     "than 4300 digits", DIGITS),
])
def test_crowd_errors(text: str, headline: str, hint: str | None) -> None:
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert [(d.headline(), d.hint) for d in diagnostics] == [(headline, hint)]


@pytest.mark.parametrize(("name", "problem"), [
    ("crowd 1 6", None),  # the crowd has 5 members
    ("crowd 1 05", None),
    ("crowd 1 0", None),
    ("crowd 1", "crowd 'crowd 1' has the name of a spectator"),
    ("crowd 1 1", "spectator 'crowd 1 1' has the name of a member of crowd 'crowd 1'"),
])
def test_crowd_member_names(name: str, problem: str | None) -> None:
    text = f'[[spectators]]\nname = "{name}"\npath = [[0.5, 0.5]]\n' + crowd()
    world, diagnostics = parse_world(text, "w.toml")
    assert [d.message for d in diagnostics] == ([problem] if problem else [])
    assert (world is None) == (problem is not None)


@pytest.mark.parametrize(("count", "pillar", "problem"), [
    # area 2 x 2.5 = 5 m²; discs of radius 0.25 m, 0.196 m² each
    (12, False, None),  # 2.36 m² of 5: under half
    (13, False, "crowd 'crowd 1' has no room: 13 discs of radius 0.25 m cover 2.55 m², more "
     "than half of the 5 m² of its area free of obstacles"),
    # a 1 m² pillar inside the area leaves 4 m²
    (10, True, None),
    (11, True, "crowd 'crowd 1' has no room: 11 discs of radius 0.25 m cover 2.16 m², more "
     "than half of the 4 m² of its area free of obstacles"),
])
def test_a_crowd_needs_room_free_of_obstacles(count: int, pillar: bool,
                                               problem: str | None) -> None:
    obstacle = ('[[obstacles]]\npolygon = [[2, 2], [3, 2], [3, 3], [2, 3]]\n' if pillar
                else "")
    text = obstacle + crowd(count=count, area="area = [[1.5, 1.5], [3.5, 1.5], [3.5, 4], "
                                              "[1.5, 4]]")
    world, diagnostics = parse_world(text, "w.toml")
    assert [d.message for d in diagnostics] == ([problem] if problem else [])
    assert (world is None) == (problem is not None)


def test_an_obstacle_outside_the_area_leaves_it_free() -> None:
    text = ('[[obstacles]]\npolygon = [[9.5, 9.5], [10, 9.5], [10, 10]]\n'
            + crowd(count=12, area="area = [[1.5, 1.5], [3.5, 1.5], [3.5, 4], [1.5, 4]]"))
    world, diagnostics = parse_world(text, "w.toml")
    assert world is not None, diagnostics


def test_every_crowd_error_in_one_pass() -> None:
    text = crowd("speed = 0", "seed = 1.5", 'kind = "teen"', count=0)
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [
        "w.toml:2:1: error: 'count' must be between 1 and 1000",
        "w.toml:4:1: error: 'speed' must be greater than 0",
        "w.toml:5:1: error: 'seed' must be a whole number, not a decimal number",
        "w.toml:6:1: error: 'kind' must be \"adult\" or \"child\", not the string 'teen'",
    ]
