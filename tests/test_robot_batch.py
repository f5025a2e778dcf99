"""BatchBrains (one compiled pass over a formation's brains) decides as RobotBrain does: the
same shows run through both give the same poses, commands, events and contacts."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots import robot
from dancebots.check import CheckOptions
from dancebots.geometry import wrap_angle
from dancebots.loading import load_show
from dancebots.plan.placement import place_show
from dancebots.robot import BrainOptions, brain_for
from dancebots.robot_batch import BatchBrains, batch_supported
from dancebots.shows.formation import Fault, RunResult, SimConfig, simulate
from dancebots.sim import REALISTIC, prepare_show
from dancebots.world import BUILTIN_ROBOT_TYPES
from tests_support import plan_of

ROOT = Path(__file__).resolve().parents[1]


def both(scenario: Path, world: Path | None, config: SimConfig) -> tuple[RunResult, RunResult]:
    """The show run by the brains one by one (the reference) and by the batch."""
    show = load_show(str(scenario), str(world) if world else None, None,
                     check=CheckOptions(), timing="feasible")
    assert show.report is not None
    assert show.report.placement is not None
    arena, placement = prepare_show(show.report.placement)
    assert show.plan is not None
    reference = simulate(show.plan, arena, placement, replace(config, batched=False))
    batched = simulate(show.plan, arena, placement, replace(config, batched=True))
    return reference, batched


def assert_same_run(reference: RunResult, batched: RunResult) -> None:
    assert np.array_equal(reference.times, batched.times)
    # the same decisions: poses to rounding (Python's and libm's hypot may differ in the last
    # bit), every event and contact at the same tick
    assert np.allclose(reference.poses, batched.poses, rtol=0.0, atol=1e-12)
    assert np.allclose(reference.commands, batched.commands, rtol=0.0, atol=1e-12)
    assert np.array_equal(reference.status, batched.status)
    assert np.array_equal(reference.show_time, batched.show_time)
    assert reference.holds is not None
    assert batched.holds is not None
    assert np.array_equal(reference.holds, batched.holds)
    assert reference.events == batched.events
    assert reference.collisions == batched.collisions


PATH = SimConfig(brain=BrainOptions(follower="path"))  # the default stop rule: predicted
FIXED = SimConfig(brain=BrainOptions(follower="path", stop_rule="fixed"))  # the thesis's


@pytest.mark.parametrize(("name", "config"), [
    ("thesis_7_1", PATH),
    # SIM robots side by side: the turn guard gives way and makes room
    ("thesis_7_4", PATH),
    ("thesis_7_2", replace(PATH, profile=REALISTIC, brain=BrainOptions(follower="tracking"))),
    # stops, speech and beeps (robots in each other's way), each robot's own show clock
    ("thesis_6_3", replace(PATH, hold="alone")),
    # hold messages late and lost, the default paced clock and the together one
    ("square_path", replace(PATH, hold_delay=0.3, hold_loss=0.2, seed=3)),
    ("square_path", replace(PATH, hold="together", hold_delay=0.3, hold_loss=0.2, seed=3)),
    # the thesis's fixed stop rule batched too
    ("thesis_7_4", FIXED),
    ("thesis_6_3", replace(FIXED, hold="alone")),
])
def test_batch_runs_the_examples_as_the_brains_do(examples: Path, name: str,
                                                   config: SimConfig) -> None:
    reference, batched = both(examples / f"{name}.dance", None, config)
    assert_same_run(reference, batched)
    if name == "thesis_6_3":
        assert {e.kind for e in batched.events} >= {"speech", "beep", "resume"}


@pytest.mark.parametrize("config", [PATH, replace(FIXED, hold="together")],
                         ids=["predicted-paced", "fixed-together"])
def test_batch_runs_a_show_among_a_crowd_as_the_brains_do(config: SimConfig) -> None:
    """The open day among a random crowd, realistic profile: people hold robots, are told to
    make room, walk into their way (the strangers' rules, the mates heard where they are),
    with the default stop rule and hold strategy and with the thesis's stop rule and the
    ``together`` clock."""
    data = ROOT / "src" / "dancebots" / "data"
    reference, batched = both(data / "open_day.dance", data / "open_day_crowd.toml",
                              replace(config, profile=REALISTIC, seed=5))
    assert_same_run(reference, batched)
    assert any(e.kind == "speech" for e in batched.events)


def test_batch_runs_the_paced_clock_as_the_brains_do(monkeypatch: pytest.MonkeyPatch) -> None:
    """The ``paced`` hold strategy: robots slowed and left behind by people say a pace, every
    clock runs at the smallest, and each place follows at its clock's rate (open-day crowd,
    realistic profile; a seed where paces below 1 and stops both happen, where robots hold
    the standing show for people in the way it would go on, and where robots near their
    places wait still once it has stood ``robot.PAUSE_STILL_AFTER``)."""
    data = ROOT / "src" / "dancebots" / "data"
    holding_paused, waiting_still = [0], [0]
    step = robot.RobotBrain.step

    def counted(brain: robot.RobotBrain, state: robot.BrainState, show_time: float,
                *args: object, **kwargs: object) -> object:
        done = step(brain, state, show_time, *args, **kwargs)  # type: ignore[arg-type]
        after, command = done[0], done[1]
        paused = state.show_time is not None and show_time <= state.show_time
        clock = kwargs.get("clock")
        if paused and after.holds_show:
            holding_paused[0] += 1
        if (paused and after.paused_since is not None and isinstance(clock, float)
                and clock - after.paused_since >= robot.PAUSE_STILL_AFTER
                and command == robot.STOP and not after.held):
            waiting_still[0] += 1
        return done

    monkeypatch.setattr(robot.RobotBrain, "step", counted)
    reference, batched = both(data / "open_day.dance", data / "open_day_crowd.toml",
                              replace(PATH, profile=REALISTIC, seed=2, hold="paced"))
    assert_same_run(reference, batched)
    assert holding_paused[0] >= 100  # held robots holding the standing show (713 ticks)
    assert waiting_still[0] >= 100  # robots waiting still while it stands (1,214 ticks)
    clock = batched.show_time.min(axis=0)
    steps = np.diff(clock)
    during = clock[1:] < batched.plan.duration
    # the clock ran slow (neither stood nor ran at the full 0.1 s a tick) for a while
    assert np.count_nonzero(during & (steps > 1e-6) & (steps < 0.1 - 1e-6)) >= 20


@pytest.mark.parametrize("config", [PATH, replace(PATH, profile=REALISTIC, hold="together")],
                         ids=["paced", "realistic-together"])
def test_a_visitor_who_stays_in_a_lane_stops_the_row_once(examples: Path,
                                                          config: SimConfig) -> None:
    """Thesis 7.1's row with a visitor standing in R1's lane for good: R1 creeps up to the
    visitor on its approach limit and paces (``paced``: the show slows) or holds the show;
    once the show stands it stands for good, R1 holds it and R2 stands where it stopped
    (before, R1 let go each time it had crept up to its standing place, the show ran a tick
    and R2 lurched on 3.5 cm: ``RobotBrain.step``'s hold on the motion the show would ask).
    The batch decides as the brains do."""
    reference, batched = both(examples / "thesis_7_1.dance",
                              ROOT / "tests" / "data" / "worlds" / "visitor_in_lane.toml",
                              replace(config, max_pause=12.0))
    assert_same_run(reference, batched)
    assert batched.holds is not None
    r1, r2 = batched.placement.robots.index("R1"), batched.placement.robots.index("R2")
    clock = batched.show_time[r2]
    first = int(np.argmax(batched.holds[r1]))  # R1 slowed: it paces or holds
    stood = first + int(np.argmax(np.diff(clock[first:]) <= 0.0))  # the show first stands
    assert np.ptp(batched.show_time[:, stood:]) < 1e-9  # and never runs on (before: 2-5 times)
    assert batched.holds[r1, stood:].all()  # R1 holds it for good
    assert batched.times[-1] > batched.times[stood] + 10.0  # watched for 10 s
    # R2 slows with the show and never speeds up again once it stands
    assert np.diff(batched.commands[r2, stood:, 0]).max() < 0.01
    settled = stood + 20  # R2 brakes (the realistic profile's lag) within 2 s
    drift = np.hypot(*(batched.poses[r2, settled:, :2] - batched.poses[r2, settled, :2]).T)
    assert drift.max() < 0.005


@pytest.mark.parametrize(("world", "seed"), [("open_day_crowd.toml", 13),
                                             ("open_day_children.toml", 5),
                                             ("open_day_runners.toml", 9)])
def test_batch_runs_the_predicted_stop_rule_as_the_brains_do(
        world: str, seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """The ``predicted`` rule in the batch (the tracker's kernel per cloud and robot, the
    stop on where tracked strangers will be, no turn while one will be within the circle the
    footprint sweeps): the same runs as the brains one by one, among the open-day crowd and
    among children and among runners (seeds where the rule stops robots; in the crowd's, a
    stranger will be within that circle at some ticks, and the turn guard cuts turns that
    would take more than its share of the gap to a mate while turning on the spot,
    ``DetectorParams.turn_share``; among the children a person near a mate's place but beyond
    its body, where it should be and said it is, keeps a robot from turning:
    ``MATE_BODY_MARGIN``, and children walking up to robots stand them still before they
    arrive)."""
    data = ROOT / "src" / "dancebots" / "data"
    path = data / world if world == "open_day_crowd.toml" else ROOT / "examples" / "worlds" / world
    config = replace(PATH, profile=REALISTIC, seed=seed,
                     brain=BrainOptions(follower="path", stop_rule="predicted"))
    within: list[float] = []
    stood: list[float] = []  # a tracked stranger predicted on a footprint
    gaps = robot.RobotBrain._predicted_gaps

    def counted(brain: robot.RobotBrain, *args: object, **kwargs: object,
                ) -> tuple[float, float, float]:
        found = gaps(brain, *args, **kwargs)  # type: ignore[arg-type]
        if found[2] < brain.sweep_reach:
            within.append(found[2])
        if found[2] <= robot.OVERLAP:
            stood.append(found[2])
        return found

    monkeypatch.setattr(robot.RobotBrain, "_predicted_gaps", counted)
    beside: list[float] = []
    beyond = robot.RobotBrain._nearest_beyond_mates

    def beyond_counted(brain: robot.RobotBrain, *args: object) -> float:
        found = beyond(brain, *args)  # type: ignore[arg-type]
        if found < brain.sweep_reach:
            beside.append(found)
        return found

    monkeypatch.setattr(robot.RobotBrain, "_nearest_beyond_mates", beyond_counted)
    shared: list[float] = []  # turns the guard cut for a mate's own turn (turn_share)
    guard = robot.RobotBrain._guard_turn

    def guard_counted(brain: robot.RobotBrain, *args: object) -> tuple[float, float, float]:
        found = guard(brain, *args)  # type: ignore[arg-type]
        mates = args[6]
        assert isinstance(mates, np.ndarray)
        if len(mates):
            standing = guard(brain, *args[:6], np.empty((0, 2)), *args[7:])  # type: ignore[arg-type]
            if abs(found[1]) < abs(standing[1]):
                shared.append(found[1])
        return found

    monkeypatch.setattr(robot.RobotBrain, "_guard_turn", guard_counted)
    reference, batched = both(data / "open_day.dance", path, config)
    assert_same_run(reference, batched)
    if world == "open_day_crowd.toml":
        assert shared  # the guard left mates room for their own turns
        assert within  # the turn rule had its say
    if world == "open_day_children.toml":
        assert beside  # a stranger beside a mate was no mate's body
        # a child was predicted on a footprint (the stand rule's first condition; the rule
        # stands the robot where the child is within ``sweep_reach`` too), so the equal
        # runs above cover the kernel's stand
        assert stood
    assert any(e.kind == "speech" for e in batched.events)
    # the prediction did stop robots: the fixed rule decides otherwise in the same crowd
    fixed = simulate(batched.plan, batched.arena, batched.placement,
                     replace(config, brain=BrainOptions(follower="path", stop_rule="fixed")))
    assert (fixed.commands.shape != batched.commands.shape
            or not np.array_equal(fixed.commands, batched.commands))


def test_batch_runs_faults_and_blind_robots_as_the_brains_do(examples: Path) -> None:
    faults = (Fault("R1", "lidar", 6.0), Fault("R2", "pose", 9.0))
    reference, batched = both(examples / "thesis_7_1.dance", None,
                              replace(PATH, faults=faults))
    assert_same_run(reference, batched)
    errors = sorted(e.text for e in batched.events if e.kind == "error")
    assert errors == ["3 consecutive failed pose look-ups", "no LIDAR data for 0.4 s"]
    reference, batched = both(examples / "thesis_7_1.dance", None, replace(PATH, lidar=None))
    assert_same_run(reference, batched)


def test_batch_runs_a_single_robot_as_its_brain_does() -> None:
    plan = plan_of("robots R1\nstart\nrow R1 0 1\nmove 2 1\ncircle 1 90 0.2\n")
    arena, placement = prepare_show(place_show(plan, None))
    reference = simulate(plan, arena, placement, replace(PATH, batched=False))
    batched = simulate(plan, arena, placement, PATH)
    assert_same_run(reference, batched)


def test_only_the_brains_it_mirrors_are_batched() -> None:
    plan = plan_of("robots A B\nstart\nrow A,B 0 1\nmove 2 0\n")

    def brains(**options: object) -> list[robot.RobotBrain]:
        return [brain_for(plan, name, BUILTIN_ROBOT_TYPES["SIM"], BrainOptions(**options))  # type: ignore[arg-type]
                for name in plan.robots]

    assert batch_supported(brains(follower="path"))
    assert batch_supported(brains(follower="tracking", lidar=False))
    assert batch_supported(brains(follower="path", stop_rule="predicted"))
    assert not batch_supported(brains(follower="thesis"))
    assert not batch_supported(brains(follower="path", stop_rule="ssm"))
    assert not batch_supported(brains(follower="path", stop_rule="closing"))
    assert not batch_supported(brains(follower="path", detector="thesis"))
    assert not batch_supported(brains(follower="path", compiled=False))
    assert not batch_supported([])
    with pytest.raises(ValueError, match="not batch_supported"):
        BatchBrains(brains(follower="thesis"))
    # the ``predicted`` rule brakes at the SSM deceleration: one for all, or no batch
    mixed = brains(follower="path", stop_rule="predicted")
    mixed[1].sensing = replace(mixed[1].sensing, ssm=replace(mixed[1].sensing.ssm,
                                                             deceleration=0.5))
    assert not batch_supported(mixed)


def test_the_kernel_shares_the_brains_constants() -> None:
    from dancebots import robot_batch_jit

    assert robot_batch_jit.MAKE_ROOM_SHIFTS == robot.MAKE_ROOM_SHIFTS
    plan = plan_of("robots A B\nstart\nrow A,B 0 1\nmove 2 0\n")
    batch = BatchBrains([brain_for(plan, name, BUILTIN_ROBOT_TYPES["SIM"], BrainOptions(
        follower="path", stop_rule="predicted")) for name in plan.robots])
    first = batch.brains[0]
    rules = batch.rules
    assert len(rules) == robot_batch_jit.SSM_DECELERATION + 1  # (the last index)
    assert rules[robot_batch_jit.SSM_DECELERATION] == first.sensing.ssm.deceleration
    assert rules[robot_batch_jit.PREDICTED_STOP_TIME] == robot.PREDICTED_STOP_TIME
    assert rules[robot_batch_jit.OVERLAP] == robot.OVERLAP
    assert rules[robot_batch_jit.FINAL_NO_ROOM] == robot.FINAL_NO_ROOM


@given(st.one_of(st.floats(-1e6, 1e6), st.sampled_from(
    [0.0, -0.0, 1e-300, math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 2 * math.pi, 1e15])))
def test_the_kernels_wrap_is_wrap_angle(angle: float) -> None:
    from dancebots.robot_batch import _wrap_exact
    from dancebots.robot_batch_jit import _wrap

    assert _wrap(angle) == wrap_angle(angle)
    assert float(_wrap_exact(np.array([angle]))[0]) == wrap_angle(angle)
    assert math.isnan(_wrap(math.nan))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.booleans(), st.booleans(), st.booleans(),
                          st.sampled_from([0.0, 1.0, -0.0])), min_size=0, max_size=6))
def test_the_kernels_tick_outputs_are_the_flags(rows: list[tuple[bool, ...]]) -> None:
    """``robot_batch_jit.tick_outputs``: status 2 on a safety error, else 1 where stopped, else
    0; holding where the robot holds the show or is in error; asking where it holds the show,
    stopped and in no error; waiting as flagged."""
    from dancebots.robot_batch_jit import tick_outputs

    flags = np.array([row[:4] for row in rows], dtype=bool).reshape(-1, 4)
    safety = np.zeros((len(rows), 5))
    safety[:, 0] = [row[4] for row in rows]
    status, holding, asking, waiting = tick_outputs(flags, safety)
    error, stopped, holds = safety[:, 0] != 0.0, flags[:, 3], flags[:, 1]
    assert status.dtype == np.int8
    assert status.tolist() == np.where(error, 2, np.where(stopped, 1, 0)).tolist()
    assert holding.tolist() == (holds | error).tolist()
    assert asking.tolist() == (holds & stopped & ~error).tolist()
    assert waiting.tolist() == flags[:, 2].tolist()


@settings(max_examples=30, deadline=None)
@given(follower=st.sampled_from(["path", "tracking"]), lead=st.sampled_from([0.0, 0.15]),
       paced=st.booleans(), times=st.lists(st.one_of(
           st.floats(-1.0, 30.0), st.sampled_from([0.0, 0.1, 1e-10, 2.05, 2.1 - 1e-10])),
           min_size=3, max_size=3))
def test_the_batch_looks_up_what_each_brain_tracks(follower: str, lead: float, paced: bool,
                                                   times: list[float]) -> None:
    """``BatchBrains.references`` (the grid's rows, a paced clock's times between two ticks
    interpolated in the kernel, the brain's exact rows otherwise) equals each brain's
    ``_reference`` and ``_place_stand``, bit for bit, at show times on and off the grid,
    before the show and after its end."""
    plan = plan_of("robots A B C\nstart\nrow A,B,C 0 1\nmove 2 0\nwait 1\ncircle 1 90 0.3\n"
                   "move 1.5 40\n")
    brains = [brain_for(plan, name, BUILTIN_ROBOT_TYPES["SIM"], BrainOptions(
        follower=follower, paced=paced, actuator_lag=lead)) for name in plan.robots]  # type: ignore[arg-type]
    rows, _, _ = BatchBrains(brains).references(np.array(times))
    for brain, show_time, row in zip(brains, times, rows, strict=True):
        exact = brain._reference(show_time)
        expected = np.array([*exact.pose, exact.speed, exact.angular_speed,
                             brain._place_stand(show_time)])
        assert row.tobytes() == expected.tobytes(), (show_time, row, expected)
