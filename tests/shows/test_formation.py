"""The formation show: deterministic, the 10 Hz rule, no passing through, the thesis scenarios."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.geometry import footprint_corners
from dancebots.plan.placement import place_show
from dancebots.shows.formation import RunResult, SimConfig, simulate, smallest_gap
from dancebots.sim import IDEAL, REALISTIC, Profile, prepare_show
from dancebots.sim.collision import rectangles_overlap
from tests_support import plan_of


def run(text: str, config: SimConfig | None = None) -> RunResult:
    """Simulate without LIDAR unless the config says otherwise (the follower's own tests)."""
    plan = plan_of(text)
    arena, placement = prepare_show(place_show(plan, None))
    return simulate(plan, arena, placement, config or SimConfig(lidar=None))


def no_overlaps(result: RunResult) -> bool:
    lengths = np.array([t.length for t in result.placement.types])
    widths = np.array([t.width for t in result.placement.types])
    for k in range(len(result.times)):
        poses = result.poses[:, k]
        corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], lengths,
                                    widths)
        for i, j in itertools.combinations(range(len(result.robots)), 2):
            if rectangles_overlap(corners[i:i + 1], corners[j:j + 1])[0]:
                return False
    return True


@pytest.mark.parametrize("name", ["thesis_7_1.dance", "thesis_7_2.dance"])
@pytest.mark.parametrize("profile", [IDEAL, REALISTIC], ids=lambda p: p.name)
@pytest.mark.parametrize("lidar", [True, False], ids=["lidar", "no-lidar"])
def test_thesis_scenarios_run_without_collision(examples: Path, name: str,
                                                profile: Profile, lidar: bool) -> None:
    config = SimConfig(profile=profile) if lidar else SimConfig(profile=profile, lidar=None)
    result = run((examples / name).read_text(), config)
    assert result.collisions == ()
    assert result.times[-1] >= result.plan.duration
    assert no_overlaps(result)
    # every robot ends near its final desired pose
    final_error = np.hypot(*(result.poses[:, -1, :2] - result.desired[:, -1, :2]).T)
    assert np.all(final_error < 0.25), final_error


def test_scenario_7_1_keeps_the_row_like_the_thesis(examples: Path) -> None:
    """Thesis 7.2.1: the distance between the two robots changes by about 16 cm (2D)."""
    result = run((examples / "thesis_7_1.dance").read_text(), SimConfig(lidar=None))
    distance = np.hypot(*(result.poses[0, :, :2] - result.poses[1, :, :2]).T)
    assert 0.05 < np.abs(distance - 1.2).max() < 0.25


def test_same_seed_same_run_other_seed_other_run(examples: Path) -> None:
    text = (examples / "thesis_7_3.dance").read_text()
    first = run(text, SimConfig(profile=REALISTIC, seed=3))
    second = run(text, SimConfig(profile=REALISTIC, seed=3))
    other = run(text, SimConfig(profile=REALISTIC, seed=4))
    assert first.events == second.events
    assert np.array_equal(first.poses, second.poses)
    assert not np.array_equal(first.poses, other.poses)


def test_robots_start_on_their_slots_and_follow(examples: Path) -> None:
    result = run((examples / "thesis_7_3.dance").read_text())
    assert np.allclose(result.poses[:, 0], result.desired[:, 0])
    during = result.times <= result.plan.duration
    error = np.hypot(*(result.poses[:, during, :2] - result.desired[:, during, :2])
                     .transpose(2, 0, 1))
    assert error.max() < 0.6


def test_robot_stops_when_commands_come_too_rarely() -> None:
    """Commands every 0.3 s: each one acts for the steps starting 0 s and 0.1 s after it and
    is stale (older than 0.1 s) for the third, so by t = 0.3 s the robot has driven 0.2 s at
    0.35 m/s = 0.07 m, against 0.105 m when stale commands were still obeyed."""
    text = "robots R1\nrow R1 0 0\nmove 3 0\n"
    strict = run(text, SimConfig(control_period=0.3, lidar=None))
    lenient = run(text, SimConfig(control_period=0.3, command_timeout=1.0, lidar=None))
    assert strict.times[1] == pytest.approx(0.3)
    assert strict.poses[0, 1, 0] - strict.poses[0, 0, 0] == pytest.approx(0.07)
    assert lenient.poses[0, 1, 0] - lenient.poses[0, 0, 0] == pytest.approx(0.105)


def test_crossing_robots_are_stopped_and_counted() -> None:
    text = ("robots R1 R2\ngroups\na R1\nb R2\nstart\nrow R1,R2 0 3\nrow R1 0 0\nrow R2 0 0\n"
            "newVL\nmove 3 -60 a\nmove 3 60 b\n")
    result = run(text)
    assert len(result.collisions) >= 1
    event = result.collisions[0]
    assert {event.robot, event.other} == {"R1", "R2"}
    assert event.kind == "robot"
    assert no_overlaps(result)  # never passed through


def test_open_arena_holds_the_show(examples: Path) -> None:
    plan = plan_of((examples / "thesis_6_3.dance").read_text())
    arena, placement = prepare_show(place_show(plan, None))
    everything = np.concatenate([plan.desired_poses(r, np.arange(0, plan.duration, 0.5))[:, :2]
                                 for r in plan.robots])
    assert np.all(everything.min(axis=0) > arena.room.min(axis=0) + 1.0)
    assert np.all(everything.max(axis=0) < arena.room.max(axis=0) - 1.0)
    assert placement.starts.shape == (4, 3)



@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), robots=st.integers(2, 5))
def test_smallest_gap_equals_every_pair_at_every_near_tick(seed: int, robots: int) -> None:
    """The pruned search (nearest pairs first, only ticks whose bound beats the best so far)
    answers exactly what measuring every pair at every tick within a metre of touching
    does."""
    import shapely

    rng = np.random.default_rng(seed)
    poses = np.concatenate([rng.uniform(-3.0, 3.0, (robots, 30, 2)),
                            rng.uniform(-np.pi, np.pi, (robots, 30, 1))], axis=2)
    lengths, widths = rng.uniform(0.3, 1.2, robots), rng.uniform(0.3, 0.7, robots)
    reach = 0.5 * np.hypot(lengths, widths)
    expected = np.inf
    for i, j in itertools.combinations(range(robots), 2):
        centre = np.hypot(*(poses[i, :, :2] - poses[j, :, :2]).T)
        near = centre < reach[i] + reach[j] + 1.0
        if near.any():
            gaps = shapely.distance(
                shapely.polygons(footprint_corners(*poses[i, near].T, lengths[i], widths[i])),
                shapely.polygons(footprint_corners(*poses[j, near].T, lengths[j], widths[j])))
            expected = min(expected, float(gaps.min()))
    assert smallest_gap(poses, lengths, widths) == expected


def test_smallest_gap_of_no_ticks_or_poses_that_are_not_numbers() -> None:
    """No ticks: no pair ever comes near (inf), as for robots far apart; a robot whose poses
    are not numbers is never near anything."""
    sizes = np.array([1.2, 1.2]), np.array([0.6, 0.6])
    assert smallest_gap(np.zeros((2, 0, 3)), *sizes) == math.inf
    poses = np.zeros((2, 3, 3))
    poses[1, :, 0] = np.nan
    assert smallest_gap(poses, *sizes) == math.inf
    poses[1, 2, 0] = 2.0  # one tick with a number: 0.8 m apart
    assert smallest_gap(poses, *sizes) == pytest.approx(0.8)


@pytest.mark.parametrize("name", ["thesis_7_1", "thesis_7_4"])
def test_the_numpy_references_simulate_the_same_show(examples: Path, name: str) -> None:
    """SimConfig(compiled=False) runs the LIDAR, the perception and the collision tests on
    their NumPy references (check does, for a short show): the same run, poses to the last
    bit and commands to rounding (the compiled and NumPy kernels round in other places),
    here with the turn guard busy (7.4's robots side by side) and without."""
    from dancebots.check import CheckOptions
    from dancebots.loading import load_show
    from dancebots.robot import BrainOptions

    show = load_show(str(examples / f"{name}.dance"), None, None, check=CheckOptions(),
                     timing="feasible")
    assert show.report is not None
    assert show.report.placement is not None
    arena, placement = prepare_show(show.report.placement)
    config = SimConfig(brain=BrainOptions(follower="path"))
    compiled = simulate(show.plan, arena, placement, config)
    numpy_only = simulate(show.plan, arena, placement, replace(config, compiled=False))
    assert np.array_equal(compiled.times, numpy_only.times)
    assert np.array_equal(compiled.poses, numpy_only.poses)
    assert np.allclose(compiled.commands, numpy_only.commands, rtol=0.0, atol=1e-12)
    assert compiled.collisions == numpy_only.collisions
    assert compiled.events == numpy_only.events


COLUMN = ("robots R1 R2 R3\ncolumn R1;R2;R3 1.8 0\nmove 3 0\nwait 2\ncircle 4 90 0.08\n"
          "move 2 0\nwait 2\nmove 3 -90\nmove 2 0\n")


def _column_run(**options: object) -> RunResult:
    from dancebots.plan.planner import PlanParameters
    from dancebots.robot import BrainOptions

    plan = plan_of(COLUMN, PlanParameters(timing="feasible"))
    arena, placement = prepare_show(place_show(plan, None))
    return simulate(plan, arena, placement,
                    SimConfig(brain=BrainOptions(follower="tracking"), **options))  # type: ignore[arg-type]


def test_a_shared_pose_formation_suffers_from_delay_where_the_virtual_leader_does_not() -> None:
    """The network experiment's mechanism (benchmarks/eval_network.py): robots that track
    their slots relative to the leader robot's broadcast pose misplace them when the pose is
    0.9 s late (extrapolated on the velocity it was sent with, wrong where the leader turns
    or stops); robots that follow the plan's virtual leader only exchange the shared clock's
    messages and do not care."""
    from dancebots.report.metrics import run_metrics

    def error(**options: object) -> float:
        metrics = run_metrics(_column_run(**options))
        assert metrics.collisions == 0
        assert metrics.rms_formation_error is not None
        return metrics.rms_formation_error

    leader, leader_late = error(), error(hold_delay=0.9)
    shared = error(formation_control="shared-pose")
    shared_late = error(formation_control="shared-pose", hold_delay=0.9)
    assert abs(leader_late - leader) < 0.005
    assert shared_late > shared + 0.01  # centimetres worse (its extrapolation is late)


def test_clock_offsets_shift_what_a_robot_runs_not_what_is_recorded() -> None:
    plain = _column_run()
    offset = _column_run(clock_offsets=(0.5, 0.0, 0.0))
    # the recorded show times are the formation's; R1 runs half a second ahead of them
    n = min(len(plain.times), len(offset.times))
    assert np.array_equal(plain.show_time[:, :n], offset.show_time[:, :n])
    ahead = np.hypot(*(offset.poses[0, :n, :2] - plain.poses[0, :n, :2]).T)
    assert ahead.max() > 0.1


def test_network_options_are_checked() -> None:
    with pytest.raises(ValueError, match="clock offsets must be finite"):
        SimConfig(clock_offsets=(float("nan"),))
    with pytest.raises(ValueError, match="unknown formation control 'mesh'"):
        SimConfig(formation_control="mesh")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="2 clock offsets for 3 robots"):
        _column_run(clock_offsets=(0.1, 0.2))
    from dancebots.robot import BrainOptions

    plan = plan_of(COLUMN)
    arena, placement = prepare_show(place_show(plan, None))
    config = SimConfig(brain=BrainOptions(follower="thesis"), formation_control="shared-pose")
    with pytest.raises(ValueError, match="needs the tracking or path follower"):
        simulate(plan, arena, placement, config)
