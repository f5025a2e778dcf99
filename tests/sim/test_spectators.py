"""How long a spectator's walk lasts, consistent with where it is."""

from __future__ import annotations

import pytest

from dancebots.sim.spectators import spectator_position, walk_duration
from dancebots.world import parse_world


def spectator(extra: str = ""):  # type: ignore[no-untyped-def]
    world, diagnostics = parse_world(
        "[room]\nsize = 10.0\n[[spectators]]\nname = \"p\"\nspeed = 1.0\nstart = 1.0\n"
        f"path = [[1.0, 1.0], [4.0, 1.0, 2.0], [4.0, 5.0]]\n{extra}", "w.toml")
    assert world is not None, diagnostics
    return world.spectators[0]


def test_walk_duration_is_start_legs_and_pauses() -> None:
    walker = spectator()
    assert walk_duration(walker) == pytest.approx(1.0 + 3.0 + 2.0 + 4.0)
    assert spectator_position(walker, walk_duration(walker) - 0.5) == pytest.approx((4.0, 4.5))
    assert spectator_position(walker, walk_duration(walker)) == pytest.approx((4.0, 5.0))


def test_a_loop_lasts_one_round_back_to_the_start() -> None:
    walker = spectator("loop = true\n")
    assert walk_duration(walker) == pytest.approx(1.0 + 3.0 + 2.0 + 4.0 + 5.0)
    assert spectator_position(walker, walk_duration(walker) - 1e-9) == pytest.approx(
        (1.0, 1.0), abs=1e-6)


def test_spectator_walks_its_path_with_pauses_and_loops() -> None:
    world, _ = parse_world("[[spectators]]\nspeed = 1\nstart = 1\nloop = true\n"
                           "path = [[1, 1], [5, 1, 2], [5, 4]]\n", "w.toml")
    assert world is not None
    visitor = world.spectators[0]
    # stands until 1 s; then 4 m east (4 s), a 2 s pause, 3 m north (3 s) and 5 m back to the
    # start (5 s): a 14 s loop; positions relative to the first waypoint (1, 1)
    expected = {0.0: (0, 0), 1.0: (0, 0), 3.0: (2, 0), 6.0: (4, 0), 7.5: (4, 0.5),
                9.0: (4, 2), 11.0: (3.2, 2.4), 13.5: (1.2, 0.9), 15.0: (0, 0), 17.0: (2, 0)}
    for walked, (x, y) in expected.items():
        assert spectator_position(visitor, walked) == pytest.approx((x + 1, y + 1)), walked
