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
