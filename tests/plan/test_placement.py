"""place_show: the plan placed in its world, sampled once for the check and the simulator."""

from __future__ import annotations

import numpy as np
import pytest

from dancebots.check import check_show
from dancebots.plan.placement import place_show, sample_show
from dancebots.plan.planner import Plan
from dancebots.sim.setup import prepare_show
from dancebots.world import DEFAULT_ROBOT_TYPE, parse_world
from tests_support import plan_of

SHOW = "robots A B\nrow A,B 0 1.2\nmove 2 0\ncircle 1.5 90 0.2\n"


def test_samples_cover_the_show_and_its_first_slots() -> None:
    """Every 0.1 s from 0 to the end, and the first slots are the row's: A at (-0.5, 0.6)
    and B at (-0.5, -0.6), the leader 0.5 m ahead of the row (docs/language.md)."""
    plan = plan_of(SHOW)
    samples = sample_show(plan, 0.1)
    assert samples.period == 0.1
    assert samples.times[0] == 0.0
    assert samples.times[-1] == plan.duration
    assert np.diff(samples.times).max() <= 0.1 + 1e-9
    assert samples.poses.shape == (2, len(samples.times), 3)
    np.testing.assert_allclose(samples.first_slots, [[-0.5, 0.6, 0.0], [-0.5, -0.6, 0.0]],
                               atol=1e-12)
    assert samples.diagnostics == ()


def test_check_and_setup_sample_the_plan_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """One placement feeds the check and the simulator's setup: the plan's desired poses are
    computed once per robot, for the samples (the first slots are their first column)."""
    plan = plan_of(SHOW)
    calls: list[int] = []
    original = Plan.desired_poses

    def counted(self: Plan, robot: str, times: np.ndarray) -> np.ndarray:
        calls.append(len(times))
        return original(self, robot, times)

    monkeypatch.setattr(Plan, "desired_poses", counted)
    show = place_show(plan)
    report = check_show(show)
    _arena, placement = prepare_show(show)
    assert report.placement is show
    assert not show.errors
    assert calls == [len(show.samples.times), len(show.samples.times)]
    assert placement.types == show.types
    assert np.array_equal(placement.starts, show.starts)


def test_the_open_arena_is_the_footprints_plus_two_metres_on_whole_metres() -> None:
    """One robot of the default type driving straight along x from its
    first slot to its last: the room spans its footprint at both ends, plus 2 m, rounded
    outwards to whole metres."""
    plan = plan_of("robots A\nrow A 0 0\nmove 2 0\n")
    kind = DEFAULT_ROBOT_TYPE
    first, last = (plan.desired_poses("A", np.array([t]))[0] for t in (0.0, plan.duration))
    assert first[1] == last[1] == 0.0
    assert first[2] == last[2] == 0.0
    arena, _ = prepare_show(place_show(plan))
    low = np.floor([first[0] - kind.length / 2 - 2.0, -kind.width / 2 - 2.0])
    high = np.ceil([last[0] + kind.length / 2 + 2.0, kind.width / 2 + 2.0])
    assert arena.room.tolist() == [[low[0], low[1]], [high[0], low[1]], [high[0], high[1]],
                                   [low[0], high[1]]]


def test_a_world_without_robots_centres_the_show() -> None:
    """A straight show from x0 to x1 on y = 0, in a 20 m room without [[robots]]: the show
    frame is shifted by (10 - (x0 + x1) / 2, 10) and not turned."""
    plan = plan_of("robots A\nrow A 0 0\nmove 2 0\n")
    x0, x1 = (float(plan.desired_poses("A", np.array([t]))[0, 0]) for t in (0.0, plan.duration))
    world, _ = parse_world("[room]\nsize = 20\n", "hall.toml")
    assert world is not None
    show = place_show(plan, world)
    assert show.transform is not None
    assert (show.transform.x, show.transform.y, show.transform.theta) == pytest.approx(
        (10.0 - 0.5 * (x0 + x1), 10.0, 0.0), abs=1e-12)


def test_a_world_that_places_some_robots_is_an_error_and_no_placement() -> None:
    world, _ = parse_world('[room]\nsize = 20\n[[robots]]\nname = "A"\nx = 5\ny = 5\n',
                           "hall.toml")
    assert world is not None
    show = place_show(plan_of(SHOW), world)
    assert show.transform is None
    assert show.starts is None
    assert [d.message for d in show.errors] == [
        "the world places A but not B (hall.toml:3)"]
