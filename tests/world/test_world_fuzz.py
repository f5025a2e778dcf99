"""Fuzzing the world-file reader: any text gives a World or diagnostics, never an exception."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.diagnostics import source_lines
from dancebots.world import parse_world

HEADERS = ["[room]", "[[obstacles]]", "[[robots]]", "[robot_types.HUSKY]", "[robot_types.X]",
           "[[spectators]]",
           "[room.inner]", "[[room]]", "[walls]"]
KEYS = ["size", "polygon", "wall_height", "name", "type", "x", "y", "yaw", "yaw_deg", "height",
        "length", "width", "max_speed", "max_angular_speed", "colour", "path", "loop", "start",
        "radius"]
VALUES = ["1", "-1", "0", "1e400", "nan", "inf", "-inf", '"R1"', '"HUSKY"', '"ROOMBA"', "true",
          "[[0, 0], [1, 0], [1, 1]]", "[[0, 0], [1, 1], [1, 0], [0, 1]]", "[[0, 0]]", "[]",
          "[1, 2]", "{a = 1}", '"', "[[0, 0], [1e9, 0], [0, 1]]", "10.673", "3.5",
          "[[1, 1], [2, 2, 3.0]]", "[[1, 1, -1]]", "false"]
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
