"""place_show: the plan placed in its world, sampled once for the check and the simulator."""

from __future__ import annotations

import numpy as np
import pytest

from dancebots.check import check_show
from dancebots.plan.placement import place_show, sample_show
from dancebots.plan.planner import Plan
from dancebots.sim.setup import prepare_show
from dancebots.world import parse_world
from tests_support import plan_of

SHOW = "robots A B\nrow A,B 0 1.2\nmove 2 0\ncircle 1.5 90 0.2\n"


def test_samples_are_the_plans_desired_poses() -> None:
    plan = plan_of(SHOW)
    samples = sample_show(plan, 0.1)
    assert samples.period == 0.1
    assert samples.times[0] == 0.0
    assert samples.times[-1] == plan.duration
    assert samples.poses.shape == (2, len(samples.times), 3)
    for i, robot in enumerate(plan.robots):
        assert np.array_equal(samples.poses[i], plan.desired_poses(robot, samples.times))
        assert np.array_equal(samples.first_slots[i], plan.desired_poses(robot, np.zeros(1))[0])
    assert samples.diagnostics == ()


def test_check_and_setup_sample_the_plan_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """One placement feeds the check and the simulator's setup: the plan's desired poses are
    computed once per robot for the samples and once for the first slots, and no more."""
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
    assert sorted(calls) == [1, 1, len(show.samples.times), len(show.samples.times)]
    assert placement.types == show.types
    assert np.array_equal(placement.starts, show.starts)


def test_open_arena_holds_every_footprint_with_its_margin() -> None:
    show = place_show(plan_of(SHOW))
    low, high = show.footprint_extent()
    arena, _ = prepare_show(show)
    assert np.all(arena.room.min(axis=0) <= low - 2.0)
    assert np.all(arena.room.max(axis=0) >= high + 2.0)
    assert np.all(arena.room == np.round(arena.room))  # corners on whole metres


def test_a_world_without_robots_centres_the_show() -> None:
    world, _ = parse_world("[room]\nsize = 20\n", "hall.toml")
    assert world is not None
    show = place_show(plan_of(SHOW), world)
    assert show.transform is not None
    assert show.transform.theta == 0.0
    points = show.samples.poses[..., :2] + [show.transform.x, show.transform.y]
    centre = 0.5 * (points.min(axis=(0, 1)) + points.max(axis=(0, 1)))
    assert centre == pytest.approx([10.0, 10.0])


def test_a_world_that_places_some_robots_is_an_error_and_no_placement() -> None:
    world, _ = parse_world('[room]\nsize = 20\n[[robots]]\nname = "A"\nx = 5\ny = 5\n',
                           "hall.toml")
    assert world is not None
    show = place_show(plan_of(SHOW), world)
    assert show.transform is None
    assert show.starts is None
    assert [d.message for d in show.errors] == [
        "the world places A but not B (hall.toml:3)"]
