"""Fuzzing the world-file reader: any text gives a World or diagnostics, never an exception."""

from __future__ import annotations

import tomllib

from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.diagnostics import source_lines
from dancebots.world import parse_world

HEADERS = ["[room]", "[[obstacles]]", "[[robots]]", "[robot_types.HUSKY]", "[robot_types.X]",
           "[[spectators]]", "[[crowds]]",
           "[room.inner]", "[[room]]", "[walls]"]
KEYS = ["size", "polygon", "wall_height", "name", "type", "x", "y", "yaw", "yaw_deg", "height",
        "length", "width", "max_speed", "max_angular_speed", "colour", "path", "loop", "start",
        "radius", "count", "area", "kind", "speed", "speed_sd", "seed"]
VALUES = ["1", "-1", "0", "1e400", "nan", "inf", "-inf", '"R1"', '"HUSKY"', '"ROOMBA"', "true",
          "[[0, 0], [1, 0], [1, 1]]", "[[0, 0], [1, 1], [1, 0], [0, 1]]", "[[0, 0]]", "[]",
          "[1, 2]", "{a = 1}", '"', "[[0, 0], [1e9, 0], [0, 1]]", "10.673", "3.5",
          "[[1, 1], [2, 2, 3.0]]", "[[1, 1, -1]]", "false", '"adult"', '"child"', "5",
          "[[1, 1], [9, 1], [9, 9], [1, 9]]"]
HOSTILE = ["5e-324", "-5e-324", "1e-300", "1e-320", "-0.0", "-0", "1" + "0" * 400,
           "-1" + "0" * 400, "1e308", "0.01", "10000", "10000.0001",
           "[[0, 0], [1" + "0" * 400 + ", 0], [1, 1]]", "[[1, 1], [2, 2, 1e308]]",
           "[[1, 1], [2, 1" + "0" * 400 + "]]", "[[0, 0], [5e-324, 0], [0, 5e-324]]"]

line = st.one_of(
    st.sampled_from(HEADERS),
    st.builds(lambda k, v: f"{k} = {v}", st.sampled_from(KEYS),
              st.sampled_from(VALUES + HOSTILE)),
)


@settings(max_examples=400, deadline=None)
@given(st.lists(line, max_size=15))
def test_random_world_files_give_only_diagnostics(lines: list[str]) -> None:
    text = "\n".join(lines)
    world, diagnostics = parse_world(text, "fuzz.toml")
    assert (world is None) == bool(diagnostics)
    for d in diagnostics:
        assert d.is_error
        assert 1 <= d.line <= max(1, len(lines))
        assert d.col >= 1


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=300))
def test_random_text_world_files(text: str) -> None:
    world, diagnostics = parse_world(text, "fuzz.toml")
    assert (world is None) == bool(diagnostics)
    for d in diagnostics:
        assert 1 <= d.line <= max(1, len(source_lines(text)))
        assert d.col >= 1


# --- crowds: hostile numbers in each numeric key -------------------------------------------

CROWD_NUMBERS = ["count", "speed", "speed_sd", "radius", "height", "seed"]
HOSTILE_NUMBERS = ["0", "-0.0", "1e-300", "5e-324", "1e308", "nan", "inf", "-inf", "-1",
                   "1" + "0" * 400, "-1" + "0" * 400, "1" + "0" * 5000, "true", '"x"',
                   "{a = 1}", "[1, 2]", "2.5", "3", "1000", "1001", str(2**63 - 1),
                   str(2**63)]
CROWD_BASE = ['name = "visitors"', "count = 5", "area = [[1, 1], [9, 1], [9, 9], [1, 9]]"]


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(st.sampled_from(CROWD_NUMBERS), st.sampled_from(HOSTILE_NUMBERS),
                       max_size=len(CROWD_NUMBERS)),
       st.sampled_from(["", 'kind = "adult"', 'kind = "child"']))
def test_hostile_numbers_in_a_crowd(values: dict[str, str], kind: str) -> None:
    """Each numeric key of a crowd given a hostile value: a valid World holding those values,
    or diagnostics, each at the line of a key that was given one; never an exception."""
    base = [line for line in CROWD_BASE if line.split(" = ")[0] not in values]
    given_lines = [f"{key} = {value}" for key, value in values.items()]
    lines = ["[[crowds]]", *base, *([kind] if kind else []), *given_lines]
    world, diagnostics = parse_world("\n".join(lines) + "\n", "fuzz.toml")
    assert (world is None) == bool(diagnostics)
    at = {lines.index(line) + 1 for line in given_lines}
    for d in diagnostics:
        assert d.is_error
        assert d.line in at, d.headline()
        assert d.col == 1, d.headline()
    if world is not None:
        [crowd] = world.crowds
        for key, value in values.items():
            expected = tomllib.loads(f"v = {value}")["v"]
            assert getattr(crowd, key) == expected, key
            assert type(getattr(crowd, key)) is (int if key in ("count", "seed") else float)
