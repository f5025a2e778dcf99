"""RobotBrain: the virtual leader in the robot's own frame, before-start behaviour."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from dancebots.control.follower import FollowerParams
from dancebots.robot import BrainState, Command, RobotBrain
from tests_support import plan_of

PLAN_TEXT = "robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 2 90\n"


def test_leader_in_own_frame_from_the_slot() -> None:
    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams())
    # R1's slot is (-0.5, 0.6) in the show frame; the leader starts at the show origin,
    # so in R1's own frame (origin at its start, x forward) it is at (0.5, -0.6).
    assert brain.leader_in_own_frame(0.0) == pytest.approx((0.5, -0.6))
    assert brain.leader_in_own_frame(1.0) == pytest.approx((0.85, -0.6))


def test_grid_cache_matches_exact_plan_values() -> None:
    plan = plan_of(PLAN_TEXT)
    brain = RobotBrain(plan, "R2", FollowerParams())
    on_grid = brain.leader_in_own_frame(7.3)
    off_grid = brain.leader_in_own_frame(7.3 + 1e-6)
    assert on_grid == pytest.approx(off_grid, abs=1e-5)


def test_stands_still_before_the_start_and_moves_after() -> None:
    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams())
    state = brain.initial_state()
    state, command, events = brain.step(state, -1.0, (0.0, 0.0, 0.0))
    assert (command, events) == (Command(0.0, 0.0), ())
    _, command, _ = brain.step(state, 1.0, (0.0, 0.0, 0.0))
    assert command.linear > 0.3


def test_brain_holds_for_an_obstacle_ahead_and_speaks_once() -> None:
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import SensingConfig
    from dancebots.safety import STOP_SENTENCE

    brain = RobotBrain(plan_of("robots R1\nrow R1 0 0\nmove 5 0\n"), "R1", FollowerParams(),
                       sensing=SensingConfig(force_radius=0.0))
    wall_ahead = PointCloud(0.9, np.array([[0.9, 0.0, 0.0, 1.0]]))  # 0.3 m before the front
    state = brain.initial_state()
    spoken = []
    for k in range(10, 50):
        t = k * 0.1
        state, command, events = brain.step(state, t, (0.0, 0.0, 0.0), wall_ahead)
        assert command.linear <= 0.0
        spoken.extend(events)
    assert spoken[0].text == STOP_SENTENCE
    assert [e.kind for e in spoken] == ["speech", "beep"]  # at 1.0 s, beep at 4.0 s
    assert state.status == "stopped"


def test_brain_slows_down_before_the_stop_distance() -> None:
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import SensingConfig

    brain = RobotBrain(plan_of("robots R1\nrow R1 0 0\nmove 5 0\n"), "R1", FollowerParams(),
                       sensing=SensingConfig(force_radius=0.0))
    # an obstacle 0.8 m ahead of the front edge: at most 1.0 * (0.8 - 0.55) = 0.25 m/s
    obstacle = PointCloud(0.9, np.array([[1.4, 0.0, 0.0, 1.0]]))
    _, command, events = brain.step(brain.initial_state(), 1.0, (0.0, 0.0, 0.0), obstacle)
    assert command.linear == pytest.approx(0.25)
    assert events == ()


def test_brain_for_builds_the_same_brain_for_the_simulator_and_ros() -> None:
    """One factory: a robot type's footprint and limits and the options reach the brain."""
    from dancebots.robot import BrainOptions, brain_for
    from dancebots.world import BUILTIN_ROBOT_TYPES

    plan = plan_of(PLAN_TEXT)
    husky = BUILTIN_ROBOT_TYPES["HUSKY"]
    brain = brain_for(plan, "R2", husky, BrainOptions(lidar=False, detector="thesis",
                                                      force_radius=0.5, force_steering="thesis"))
    assert brain.robot == "R2"
    assert (brain.params.vmax, brain.params.max_linear, brain.params.max_angular) == (
        plan.parameters.vmax, husky.max_speed, husky.max_angular_speed)
    assert brain.params.force_steering == "thesis"
    assert (brain.sensing.length, brain.sensing.width, brain.sensing.lidar,
            brain.sensing.detector, brain.sensing.force_radius) == (
        husky.length, husky.width, False, "thesis", 0.5)


def test_an_unknown_follower_or_stop_rule_is_refused_by_name() -> None:
    """What a ROS parameter may carry (``~follower``, ``~stop_rule``): a clear error that
    lists the choices, which formation_member logs as fatal."""
    from dancebots.robot import BrainOptions, brain_for
    from dancebots.world import BUILTIN_ROBOT_TYPES

    plan, husky = plan_of(PLAN_TEXT), BUILTIN_ROBOT_TYPES["HUSKY"]
    with pytest.raises(ValueError, match=r"^unknown stop rule 'nope'; choose from fixed, "
                       r"closing, ssm, predicted$"):
        brain_for(plan, "R2", husky, BrainOptions(stop_rule="nope"))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^unknown follower 'nope'; choose from tracking, "
                       r"path, thesis$"):
        brain_for(plan, "R2", husky, BrainOptions(follower="nope"))  # type: ignore[arg-type]


@pytest.mark.parametrize("follower", ["path", "tracking"])
def test_a_mate_on_its_place_does_not_push_the_robot_but_a_stranger_does(follower: str,
                                                                           ) -> None:
    """The tracking and path followers leave the points where a formation mate should be out
    of the force field (R2 stands 1.2 m to R1's right: its place), while a stranger at the
    same distance on the other side pushes R1 away; the thesis follower keeps the thesis's
    force field, which R2 pushes too."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import SensingConfig

    plan = plan_of(PLAN_TEXT)

    def force_on_r1(brain_follower: str, y: float) -> tuple[float, float]:
        brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(),
                           follower=brain_follower)  # type: ignore[arg-type]
        cloud = PointCloud(0.0, np.array([[0.0, y, 0.0, 1.0]]))
        seen = brain._perceive(cloud.columns, 0.1, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        if brain_follower == "thesis":
            return seen.force
        strangers = brain._without_mates(cloud.columns, 0.1, (0.0, 0.0, 0.0),
                                         (0.0, 0.0, 0.0), 0.0)
        return seen.force if strangers is None else strangers.force

    assert force_on_r1(follower, -0.9) == (0.0, 0.0)  # R2's side, where R2 stands
    assert force_on_r1(follower, 0.9)[1] < 0.0  # a stranger on the left pushes it right
    assert force_on_r1("thesis", -0.9)[1] > 0.0


def test_a_paced_brain_interpolates_its_place_between_the_grid_ticks() -> None:
    """A paced clock runs off the 10 Hz grid: the place between two ticks is their linear
    interpolation (headings unwrapped), on the grid the grid's row. It stays within the
    place's own step over that tick of the exact plan (2.5 cm where the inner place loops
    back round the spot turn within one tick, the grid stepping 3.2 cm there), and mostly
    within a millimetre."""
    from dancebots.robot import BrainOptions, brain_for
    from dancebots.world import DEFAULT_ROBOT_TYPE

    plan = plan_of(PLAN_TEXT)
    paced = brain_for(plan, "R1", DEFAULT_ROBOT_TYPE,
                      BrainOptions(follower="path", lidar=False, paced=True))
    exact = brain_for(plan, "R1", DEFAULT_ROBOT_TYPE, BrainOptions(follower="path", lidar=False))
    errors = []
    for tick in range(int(plan.duration * 10) - 1):
        now = tick * 0.1 + 0.037
        got, want = paced.slot_at(now), exact.slot_at(now)
        before, after = paced.slot_at(tick * 0.1), paced.slot_at((tick + 1) * 0.1)
        assert got.pose[0] == pytest.approx(0.63 * before.pose[0] + 0.37 * after.pose[0])
        assert got.speed == pytest.approx(0.63 * before.speed + 0.37 * after.speed)
        error = math.hypot(got.pose[0] - want.pose[0], got.pose[1] - want.pose[1])
        step = math.hypot(after.pose[0] - before.pose[0], after.pose[1] - before.pose[1])
        assert error <= step + 1e-3
        errors.append(error)
        assert paced.slot_at(tick * 0.1) == exact.slot_at(tick * 0.1)
    assert np.median(errors) < 1e-3


def test_the_tracking_followers_lead_their_feedforward_by_the_actuator_lag() -> None:
    """A robot whose speeds follow its commands with a first-order lag of 0.25 s: its
    reference keeps the pose of now and takes the speeds of 0.25 s later (interpolated
    between the 10 Hz grid's rows); without a lag it is the reference of now."""
    from dancebots.robot import BrainOptions, brain_for
    from dancebots.world import DEFAULT_ROBOT_TYPE

    plan = plan_of(PLAN_TEXT)
    lagging = brain_for(plan, "R1", DEFAULT_ROBOT_TYPE,
                        BrainOptions(follower="path", lidar=False, actuator_lag=0.25))
    prompt = brain_for(plan, "R1", DEFAULT_ROBOT_TYPE,
                       BrainOptions(follower="path", lidar=False))
    assert lagging.feedforward_lead == 0.25
    assert prompt.feedforward_lead == 0.0
    for now in (2.0, 5.3, 7.1):
        led, exact = lagging._reference(now), lagging.slot_at(now)
        before, after = lagging.slot_at(now + 0.2), lagging.slot_at(now + 0.3)
        assert led.pose == exact.pose
        assert led.speed == pytest.approx(0.5 * (before.speed + after.speed))
        assert led.angular_speed == pytest.approx(
            0.5 * (before.angular_speed + after.angular_speed))
        assert prompt._reference(now) == prompt.slot_at(now)
    turning = [t for t in np.arange(0.0, plan.duration, 0.1)
               if lagging._reference(t).angular_speed != lagging.slot_at(t).angular_speed]
    assert turning  # the lead does change the feedforward where the place turns


def test_a_robot_keeps_its_speed_behind_a_mate_on_its_place_but_not_behind_a_stranger(
        ) -> None:
    """The approach limit (gain 1/s, stop distance 0.55 m): 1 m of free space ahead allows
    0.45 m/s; when what is there is a formation mate on its place, the robot may keep its
    reference's speed plus the gain times the room beyond the stop distance and MATE_GAP
    (0.3 + 0.35 m/s), never more than a stranger further ahead allows, and within MATE_GAP
    of the stop distance the first limit holds."""
    from dancebots.robot import MATE_GAP, SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(), sensing=SensingConfig(),
                       follower="path")
    stop = brain.sensing.detection.stop_distance
    assert brain._approach_limit(1.0, None, 0.3) == pytest.approx(1.0 - stop)
    assert brain._approach_limit(1.0, math.inf, 0.3) == pytest.approx(
        0.3 + 1.0 - stop - MATE_GAP)
    assert brain._approach_limit(1.0, 0.8, 0.3) == pytest.approx(1.0 - stop)  # a stranger
    assert brain._approach_limit(stop + 0.5 * MATE_GAP, math.inf, 0.3) == pytest.approx(
        0.5 * MATE_GAP)


def _side_by_side_cloud(gap: float, length: float = 1.2, width: float = 0.6) -> np.ndarray:
    """Columns (K, 4) of a SIM robot standing ``gap`` m to the left of a SIM robot at the
    origin, side by side (its right side, every 2 cm, as a LIDAR sees it)."""
    xs = np.arange(-0.5 * length, 0.5 * length + 1e-9, 0.02)
    y = 0.5 * width + gap
    return np.column_stack([xs, np.full(len(xs), y), np.zeros(len(xs)), np.ones(len(xs))])


def test_a_robot_that_may_not_turn_beside_a_mate_makes_room_forwards_first() -> None:
    """Listing 7.4 with SIM robots 0.2 m apart: R2 should turn right on the spot; its tail
    would swing 0.26 m into R1 beside it. It drives straight to where the turn is free,
    forwards when the way ahead is free, backwards when it is not, and keeps the direction
    it chose while it still helps; with no way free it does not make room."""
    from dancebots.robot import SensingConfig

    plan = plan_of(PLAN_TEXT)
    brain = RobotBrain(plan, "R2", FollowerParams(), sensing=SensingConfig(), follower="path")
    here = (0.0, 0.0, 0.0)
    beside = _side_by_side_cloud(0.2)
    mate = np.array([[0.0, 0.8]])  # R1's middle: its points may turn too (turn_share)
    assert brain._make_room(beside, 0.1, here, here, -1.0, mate, 0.0) == 1.0
    # a wall 0.8 m ahead: no forward shift leaves room for the stop distance
    wall = np.column_stack([np.full(31, 1.4), np.linspace(-0.6, 0.6, 31), np.zeros(31),
                            np.ones(31)])
    assert brain._make_room(np.concatenate([beside, wall]), 0.1, here, here, -1.0, mate,
                            0.0) == -1.0
    # it keeps going backwards once it chose to, even with the way ahead free again
    assert brain._make_room(beside, 0.1, here, here, -1.0, mate, -1.0) == -1.0
    # walls close ahead and behind: nowhere to make room
    behind = wall * np.array([-1.0, 1.0, 1.0, 1.0])
    assert brain._make_room(np.concatenate([beside, wall, behind]), 0.1, here, here, -1.0,
                            mate, 0.0) == 0.0
    # 0.3 m beside a mate, a wall 1.8 m ahead: the shift forwards that leaves the turn room
    # with R1 standing is too short once R1 may turn too (it takes half of the gap): it
    # makes room backwards instead
    beside = _side_by_side_cloud(0.3)
    wall = np.column_stack([np.full(31, 1.8), np.linspace(-0.6, 0.6, 31), np.zeros(31),
                            np.ones(31)])
    standing = np.empty((0, 2))
    assert brain._make_room(np.concatenate([beside, wall]), 0.1, here, here, -1.0, standing,
                            0.0) == 1.0
    assert brain._make_room(np.concatenate([beside, wall]), 0.1, here, here, -1.0,
                            np.array([[0.0, 0.9]]), 0.0) == -1.0


def test_a_robot_makes_room_only_among_mates() -> None:
    """A robot alone, turned 90 deg from its place's heading so that it should turn on the
    spot, with a stranger 0.2 m beside it (every point of a one-robot show is a stranger):
    the turn guard and the corner cap leave it at most a slow part of the turn (its corners
    at CORNER_SPEED or less), and it does not drive off to make room for the turn (a person
    near is waited for, not pushed past); the same points where they leave room ahead would
    have it make room, were they a mate's (``_make_room`` itself)."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import CORNER_SPEED, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    state = brain.initial_state()
    beside = _side_by_side_cloud(0.2)
    turned = (0.0, 0.0, 0.5 * math.pi)  # facing left of its place's way: it must turn right
    commands = []
    for k in range(10, 30):
        state, command, _ = brain.step(state, 0.1 * k, turned, PointCloud(0.1 * k, beside),
                                       clock=0.1 * k)
        commands.append(command)
        assert state.making_room == 0.0
    half_diagonal = 0.5 * math.hypot(brain.sensing.length, brain.sensing.width)
    assert all(abs(c.linear) < 0.05 for c in commands[3:])
    assert all(abs(c.angular) * half_diagonal <= CORNER_SPEED for c in commands[3:])
    assert brain._make_room(beside, 0.1, turned, turned, -1.0, np.array([[-0.8, 0.0]]),
                            0.0) != 0.0


def test_near_a_stranger_a_robot_turns_slowly_enough_for_its_corners() -> None:
    """A robot alone (every point is a stranger) that should turn on the spot towards its
    place's heading: with nothing near it turns as fast as its tracking law says; with a
    person's points 0.8 m beside it (NEAR_GAP) its corners move at CORNER_SPEED at most;
    with the person 1.5 m away it turns freely again. Left more than SLOW_TURN_LAG behind its
    place by the slow turn, it holds the formation's show clock."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import CORNER_SPEED, NEAR_GAP, SLOW_TURN_LAG, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    turned = (0.0, 0.0, 0.5 * math.pi)
    half_diagonal = 0.5 * math.hypot(brain.sensing.length, brain.sensing.width)

    def turn_with_person_at(gap: float | None, start: int = 10) -> tuple[float, bool]:
        columns = np.zeros((0, 4)) if gap is None else np.array(
            [[x, -(0.3 + gap), 0.0, 1.7] for x in np.linspace(-0.1, 0.1, 5)])
        state = brain.initial_state()
        for k in range(start, start + 3):  # the cloud arrives and is seen
            state, command, _ = brain.step(state, 0.1 * k, turned, PointCloud(0.1 * k, columns),
                                           clock=0.1 * k)
        return command.angular, state.holds_show

    free, _ = turn_with_person_at(None)
    assert abs(free) > 1.0
    near, holds = turn_with_person_at(0.8 * NEAR_GAP)
    assert 0.0 < abs(near) * half_diagonal <= CORNER_SPEED + 1e-12
    assert turn_with_person_at(1.5 * NEAR_GAP)[0] == free
    # its place is more than SLOW_TURN_LAG ahead by then: the formation waits for its turn
    assert math.hypot(*brain.slot_at(1.2).pose[:2]) > SLOW_TURN_LAG
    assert holds
    # at the start its place is where it stands: its slow turn holds no one
    assert not turn_with_person_at(0.8 * NEAR_GAP, start=0)[1]


def test_a_turn_cut_for_a_stranger_slows_the_robot_along_the_same_arc(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A robot 0.3 m to the left of its place, which drives on at 0.35 m/s: the tracking
    law steers it back on a tight arc. With a person's points 0.8 m to its left (NEAR_GAP)
    its corners swing at CORNER_SPEED at most, and its speed drops by as much: the same
    curvature (m^-1) as without the cap (CORNER_SPEED made huge). A cut turn alone would
    widen the arc: a robot driving to a place 8 cm to its side circled it, turning round
    210 deg (open-day crowd seed 88 of a reverted variant)."""
    from dancebots import robot
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import CORNER_SPEED, NEAR_GAP, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    half_diagonal = 0.5 * math.hypot(brain.sensing.length, brain.sensing.width)

    def command_with_person_at(gap: float | None) -> Command:
        columns = np.zeros((0, 4)) if gap is None else np.array(
            [[x, 0.3 + gap, 0.0, 1.7] for x in np.linspace(-0.1, 0.1, 5)])
        state = brain.initial_state()
        for k in range(20, 23):  # the cloud arrives and is seen
            place = brain.slot_at(0.1 * k).pose
            pose = (place[0], place[1] + 0.3, place[2])
            state, command, _ = brain.step(state, 0.1 * k, pose, PointCloud(0.1 * k, columns),
                                           clock=0.1 * k)
        return command

    near = command_with_person_at(0.8 * NEAR_GAP)
    monkeypatch.setattr(robot, "CORNER_SPEED", 1e9)
    uncut = command_with_person_at(0.8 * NEAR_GAP)
    assert uncut.linear > 0.2
    assert abs(uncut.angular) * half_diagonal > 2.0 * CORNER_SPEED  # a tight arc
    assert abs(near.angular) * half_diagonal == pytest.approx(CORNER_SPEED)
    assert near.angular / near.linear == pytest.approx(uncut.angular / uncut.linear)


def test_while_the_show_clock_stands_a_robot_near_its_place_stands_still() -> None:
    """The formation's shared clock stands (the show time does not advance from one tick to
    the next): a robot 8 cm to the side of its place waits where it is (PAUSE_STILL)
    instead of turning to drive onto it, and so does one 0.3 m to its side (the paused
    law: no turn onto a point beside it); 0.3 m behind its place it drives on to it along
    its heading, 0.3 m past it it does not back up; with the clock running the same 8 cm
    are steered out on the way; the robot that held or paced the show at its last tick
    keeps closing on its place (else the clock creeps on without it: the row bystander's
    R1 fell 18 cm behind); and a clock that stood less than PAUSE_STILL_AFTER stops nobody
    (robots stopped and went at every one-tick hold)."""
    from dataclasses import replace

    from dancebots.robot import PAUSE_STILL, PAUSE_STILL_AFTER, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(lidar=False),
                       follower="path")

    def command_at(side: float, paused: bool, holds_show: bool = False,
                   pace: float = 1.0, stood: float = 1.0, behind: float = 0.0) -> Command:
        """The command at show time 2.0 s after a tick at 1.9 s, or, paused, with the show
        time standing at 2.0 s since the robot's clock read ``1.0 - stood`` s (its clock at
        this tick: 1.0 s); the robot ``side`` m to the left of its place and ``behind`` m
        behind it, facing its way."""
        x, y, heading = brain.slot_at(2.0).pose
        pose = (x - behind * math.cos(heading) - side * math.sin(heading),
                y - behind * math.sin(heading) + side * math.cos(heading), heading)
        state = brain.initial_state()
        if paused:
            state, _, _ = brain.step(state, 1.9, pose, clock=0.8 - stood)
            state, _, _ = brain.step(state, 2.0, pose, clock=0.9 - stood)
            state, _, _ = brain.step(state, 2.0, pose, clock=1.0 - stood)  # it stands
        else:
            state, _, _ = brain.step(state, 1.9, pose, clock=0.9)
        state = replace(state, holds_show=holds_show, pace=pace)
        return brain.step(state, 2.0, pose, clock=1.0)[1]

    assert PAUSE_STILL > 0.08
    assert PAUSE_STILL_AFTER < 1.0
    assert command_at(0.08, paused=True) == Command(0.0, 0.0)
    assert command_at(0.3, paused=True) == Command(0.0, 0.0)  # no turn onto a point beside
    on = command_at(0.0, paused=True, behind=0.3)
    assert on.linear > 0.2
    assert on.angular == pytest.approx(0.0, abs=1e-9)
    assert command_at(0.0, paused=True, behind=-0.3) == Command(0.0, 0.0)  # no backing up
    running = command_at(0.08, paused=False)
    assert running.linear > 0.2
    assert running.angular < 0.0  # back towards its place, on the right
    assert command_at(0.0, paused=True, holds_show=True, behind=0.08).linear > 0.0
    assert command_at(0.0, paused=True, pace=0.5, behind=0.08).linear > 0.0
    # a clock that stood a tick or two is no wait yet: the robot keeps closing on its place
    brief = command_at(0.0, paused=True, stood=PAUSE_STILL_AFTER - 0.2, behind=0.08)
    assert brief.linear > 0.0
    assert brief == command_at(0.0, paused=True, stood=PAUSE_STILL_AFTER - 0.2,
                               holds_show=True, behind=0.08)


def test_a_robot_holds_the_standing_show_while_a_person_blocks_its_way_on() -> None:
    """A person stands 0.3 m ahead of a robot on its place: it is held and holds the show.
    While the show stands its place stands, and the robot, on it, would drive nowhere; the
    hold is judged on the motion the show would ask, so it keeps holding (before, it let go
    at the next tick, the show went on, and it held again: the formation stopped and went,
    and the robot said its stop sentence, at 5 Hz). With the person gone it lets go."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    ahead = 0.5 * brain.sensing.length + 0.3
    person = np.array([[ahead, y, 0.0, 1.7] for y in np.linspace(-0.1, 0.1, 5)])
    place = brain.slot_at(2.0).pose
    state = brain.initial_state()
    holding = []
    for now, show_time, columns in ((1.9, 1.9, person), (2.0, 2.0, person),
                                    (2.1, 2.0, person), (2.2, 2.0, person),
                                    (2.3, 2.0, np.zeros((0, 4)))):
        state, command, _ = brain.step(state, show_time, place, PointCloud(now, columns),
                                       clock=now)
        holding.append((state.held, state.holds_show, command.linear == 0.0))
    assert holding[:4] == [(True, True, True)] * 4
    assert holding[4][:2] == (False, False)


@pytest.mark.parametrize("paced", [False, True], ids=["together", "paced"])
def test_a_robot_that_crept_up_to_its_standing_place_keeps_holding_for_a_person_ahead(
        paced: bool) -> None:
    """A visitor stands a few cm beyond the stop distance ahead of a robot: the approach limit
    lets it creep, so it falls behind its place and holds the show. While the show stands it
    creeps up to its standing place; judged there it would let go, the show would run a tick,
    it would fall behind and hold again, and its mates lurched on at every let-go (thesis
    7.1's row with a visitor in R1's lane: R2 drove 3.5 cm at a time, and on ROS once 0.37 m
    as R1's cable was pulled just after a let-go). It keeps holding while the person would
    cut the motion the show asks, and says so (held: its stop sentence, so that the person
    hears they should make room); with the person a little farther, a paced robot says the
    pace it could follow instead; with the person gone it lets go."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import HOLD_LAG, PACE_MARGIN, PACE_MIN, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path",
                       paced=paced)
    front = 0.5 * brain.sensing.length + brain.sensing.detection.stop_distance

    def person(gap: float) -> np.ndarray:
        return np.array([[front + gap, y, 0.0, 1.7] for y in np.linspace(-0.1, 0.1, 5)])

    def short_of_place(show_time: float, by: float) -> tuple[float, float, float]:
        place = brain.slot_at(show_time).pose
        return (place[0] - by * math.cos(place[2]), place[1] - by * math.sin(place[2]),
                place[2])

    def holds(gap: float | None) -> tuple[bool, bool, float]:
        state = brain.initial_state()
        steps = ((1.9, 1.9, short_of_place(1.9, 0.12), 0.03),  # running, left behind: holds
                 (2.0, 2.0, short_of_place(2.0, 0.1), 0.03),
                 (2.1, 2.0, short_of_place(2.0, 0.1), 0.03),  # the show stands
                 (2.2, 2.0, short_of_place(2.0, 0.5 * HOLD_LAG), gap))  # crept up to its place
        for now, show_time, pose, ahead in steps:
            columns = np.zeros((0, 4)) if ahead is None else person(ahead)
            state, _, _ = brain.step(state, show_time, pose, PointCloud(now, columns),
                                     clock=now)
            if show_time == 2.0 and now < 2.2:
                assert state.holds_show  # the lag rule's hold
                assert not state.held
        return state.holds_show, state.held, state.pace

    assert holds(0.03) == (True, True, 1.0)  # the person would cut the show to a crawl
    assert holds(None) == (False, False, 1.0)  # gone: the show goes on
    farther = holds(0.15)
    if paced:  # it could follow a share of the show's speed: it says so
        assert farther[:2] == (False, False)
        assert PACE_MIN * PACE_MARGIN < farther[2] < PACE_MARGIN
    else:
        assert farther == (True, True, 1.0)


def test_after_the_show_a_robot_goes_to_its_final_slot_only_with_no_stranger_near() -> None:
    """After the plan's end nothing is late: a robot 0.5 m short of its final slot with a
    person 0.8 m beside it (NEAR_GAP) stands, held and holding the show (it asks for room);
    with the person gone it drives to its slot. During the show the same person does not
    stop it."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import NEAR_GAP, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    person = np.array([[x, -(0.3 + 0.8 * NEAR_GAP), 0.0, 1.7]
                       for x in np.linspace(-0.1, 0.1, 5)])

    def step_at(show_time: float, columns: np.ndarray) -> tuple[Command, bool]:
        final = brain.slot_at(plan.duration).pose
        pose = (final[0] - 0.5, final[1], final[2]) if show_time >= plan.duration else (
            brain.slot_at(show_time).pose)
        state = brain.initial_state()
        for k in range(3):
            now = show_time + 0.1 * k
            state, command, _ = brain.step(state, now, pose, PointCloud(now, columns),
                                           clock=now)
        return command, state.holds_show and state.held

    after = plan.duration + 1.0
    assert step_at(after, person) == (Command(0.0, 0.0), True)
    moving, holds = step_at(after, np.zeros((0, 4)))
    assert moving.linear > 0.1
    assert not holds
    during, holds = step_at(2.0, person)
    assert during.linear > 0.1
    assert not holds


def test_after_the_show_a_robot_waits_for_a_stranger_only_so_long() -> None:
    """A stranger that stays within NEAR_GAP after the show (a wall, a person who does not
    leave) holds a robot short of its final slot for AFTER_SHOW_WAIT s, not for good: then
    it drives to its slot, no longer waiting."""
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import AFTER_SHOW_WAIT, NEAR_GAP, SensingConfig

    plan = plan_of("robots R1\nrow R1 0 0\nmove 4 0\n")
    brain = RobotBrain(plan, "R1", FollowerParams(), sensing=SensingConfig(), follower="path")
    wall = np.array([[x, -(0.3 + 0.8 * NEAR_GAP), 0.0, 1.7] for x in np.linspace(-1, 1, 21)])
    final = brain.slot_at(plan.duration).pose
    pose = (final[0] - 0.5, final[1], final[2])
    state = brain.initial_state()
    start = plan.duration + 1.0
    waited = []
    for k in range(round((AFTER_SHOW_WAIT + 1.0) / 0.1)):
        now = start + 0.1 * k
        state, command, _ = brain.step(state, now, pose, PointCloud(now, wall), clock=now)
        waited.append(state.waiting)
    assert all(waited[1:round(AFTER_SHOW_WAIT / 0.1) - 1])
    assert not state.waiting
    assert command.linear > 0.1


def _step_with_tracked(brain: RobotBrain, now: float, pose: tuple[float, float, float],
                       at: tuple[float, float], velocity: tuple[float, float],
                       ) -> tuple[Command, BrainState]:
    """One step of ``brain`` at ``pose`` with one tracked point seen 0.3 s ago at ``at``
    (``base_link`` at ``pose``, m), moving at ``velocity`` (own map frame, m/s)."""
    from dancebots.perception.tracks import TRACKED

    state = BrainState(obstacles=np.array([[at[0], at[1], 0.0, 1.0]]), seen_from=pose,
                       cloud_stamp=now - 0.3, point_velocity=np.array([velocity]),
                       point_kind=np.array([TRACKED], dtype=np.int8))
    state, command, _ = brain.step(state, now, pose, None, clock=now)
    return command, state


def test_the_predicted_stop_holds_for_a_stranger_but_not_for_a_moving_mate() -> None:
    """The ``predicted`` stop rule moves tracked points on at their velocity for the data's
    age (0.3 s here) and stops where they land within the stop distance ahead, holding the
    show; a cluster where a formation mate should be moves with the show and does not stop
    it (that held the formation for its own mates: seed 41 of the open-day crowd stalled).
    R1 drives forward; R2's place is 1.2 m to its right; both clusters head into R1's
    corridor 0.35 m before its front."""
    from dancebots.perception.tracks import TRACKED
    from dancebots.robot import BrainState, SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(),
                       sensing=SensingConfig(stop_rule="predicted"), follower="path")
    now = 1.0
    pose = brain.slot_at(now).pose
    mate = brain.mates_at(now)[0]  # own frame
    c, s = math.cos(pose[2]), math.sin(pose[2])

    def step(at: np.ndarray, velocity: tuple[float, float]) -> BrainState:
        dx, dy = at[0] - pose[0], at[1] - pose[1]  # base_link at pose
        local = (c * dx + s * dy, -s * dx + c * dy)
        columns = np.array([[local[0], local[1], 0.0, 1.0]])
        state = BrainState(obstacles=columns, seen_from=pose, cloud_stamp=now - 0.3,
                           point_velocity=np.array([velocity]),
                           point_kind=np.array([TRACKED], dtype=np.int8))
        return brain.step(state, now, pose, None, clock=now)[0]

    # from beside R1 (where R2 should be, or 1.5 m beyond it: beyond the mate radius) into
    # its corridor by now
    ahead = (0.95 - 0.0) / 0.3  # m/s along x: to 0.95 m ahead of the centre (0.35 m gap)
    to_mate = mate - np.array(pose[:2])
    across = -to_mate[1] / 0.3
    assert not step(mate, (ahead, across)).held
    stranger = mate + np.array([0.0, -1.5 if to_mate[1] < 0 else 1.5])
    assert np.hypot(*(stranger - mate)) > brain.mate_radius
    held = step(stranger, (ahead, -(stranger - np.array(pose[:2]))[1] / 0.3))
    assert held.held
    assert held.holds_show


def test_the_predicted_stop_looks_ahead_by_the_robots_stopping_time(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A stranger seen 0.3 s ago 0.35 m before R1's front, beside its corridor, running
    across it at 1 m/s: moved on for the data's age it is still 0.15 m beside the corridor,
    moved on for PREDICTED_STOP_TIME more it is 0.15 m inside it: R1 stops and holds the show
    now, not a stopping time too late (without the stopping time it drives on)."""
    from dancebots import robot
    from dancebots.robot import PREDICTED_STOP_TIME, SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(),
                       sensing=SensingConfig(stop_rule="predicted"), follower="path")
    now = 1.0
    pose = brain.slot_at(now).pose
    c, s = math.cos(pose[2]), math.sin(pose[2])
    corridor = 0.5 * brain.sensing.width + brain.sensing.detection.corridor_margin
    assert pytest.approx(0.3) == PREDICTED_STOP_TIME
    seen = (0.5 * brain.sensing.length + 0.35, corridor + 0.45)  # base_link, 0.3 s ago
    across = (s * 1.0, -c * 1.0)  # -y in base_link at 1 m/s, in the own map frame

    def step() -> tuple[Command, BrainState]:
        return _step_with_tracked(brain, now, pose, seen, across)

    command, state = step()
    assert command.linear == 0.0
    assert state.held
    assert state.holds_show
    monkeypatch.setattr(robot, "PREDICTED_STOP_TIME", 0.0)
    command, state = step()
    assert command.linear > 0.1
    assert not state.held


def test_the_predicted_stop_distance_adds_the_robots_own_way_until_it_stands() -> None:
    """|v| T + v^2 / 2a on top of the stop distance, either way, and nothing standing."""
    from dancebots.robot import PREDICTED_STOP_TIME, predicted_stop_distance

    assert predicted_stop_distance(0.55, 0.0, 1.0) == 0.55
    for speed in (0.4, -0.4):
        assert predicted_stop_distance(0.55, speed, 1.0) == pytest.approx(
            0.55 + 0.4 * PREDICTED_STOP_TIME + 0.08)
    assert predicted_stop_distance(0.55, 0.4, 0.5) == pytest.approx(
        0.55 + 0.4 * PREDICTED_STOP_TIME + 0.16)


def test_the_predicted_stop_counts_the_robots_own_way_to_a_stranger_running_at_it(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A stranger running head-on at R1 at 1.5 m/s whose predicted point lands a little
    beyond the stop distance ahead of R1's front, but within it plus R1's own way until it
    stands (``predicted_stop_distance``): R1 stops and holds the show (dense open-day crowd
    seed 223: R2 at 0.39 m/s stopped when the child's point came within 0.55 m and was still
    braking when they met). Without the robot's own way it drives on; so does R1 with the
    stranger beyond the stop distance plus its own way."""
    from dancebots import robot
    from dancebots.robot import PREDICTED_STOP_TIME, BrainState, SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(),
                       sensing=SensingConfig(stop_rule="predicted"), follower="path")
    now = 1.0
    pose = brain.slot_at(now).pose
    c, s = math.cos(pose[2]), math.sin(pose[2])
    free = brain.step(BrainState(), now, pose, None, clock=now)[1].linear
    assert free > 0.2  # what R1 drives with nothing near
    stop = brain.sensing.detection.stop_distance
    own_way = robot.predicted_stop_distance(stop, free, brain.sensing.ssm.deceleration) - stop
    speed = 1.5  # m/s, head-on (-x in base_link)
    running = (-c * speed, -s * speed)  # own map frame

    def step(gap: float) -> tuple[Command, BrainState]:
        """The stranger's predicted point (0.3 s of age and PREDICTED_STOP_TIME) ``gap`` m
        before R1's front."""
        seen = (0.5 * brain.sensing.length + gap + speed * (0.3 + PREDICTED_STOP_TIME), 0.0)
        return _step_with_tracked(brain, now, pose, seen, running)

    command, state = step(stop + 0.5 * own_way)
    assert command.linear == 0.0
    assert state.held
    assert state.holds_show
    command, state = step(stop + 1.5 * own_way)
    assert command.linear > 0.2
    assert not state.held
    monkeypatch.setattr(robot, "predicted_stop_distance",
                        lambda stop_distance, speed, deceleration: stop_distance)
    command, state = step(stop + 0.5 * own_way)
    assert command.linear > 0.2
    assert not state.held


def test_the_predicted_rule_stands_a_robot_still_before_a_stranger_reaches_it(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A tracked stranger seen 0.3 s ago 0.10 m beside R1's rear corner, walking at it at
    0.5 m/s, is on its footprint by now: R1, told to drive on along its place, stands
    (neither driving nor turning) and holds the show, so the person meets a robot standing
    still (children crowd seed 17: a child walking up touched R1's rear corner as it drove
    off). At 0.2 m/s it is there only by the time a stop took effect (PREDICTED_STOP_TIME
    more): R1 stands too, and without that time drives on. The same stranger standing, or
    walking away, does not stop it, nor one heading at it from beyond the circle its
    footprint sweeps (``sweep_reach``)."""
    from dancebots import robot
    from dancebots.robot import SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(),
                       sensing=SensingConfig(stop_rule="predicted"), follower="path")
    now = 1.0
    pose = brain.slot_at(now).pose
    c, s = math.cos(pose[2]), math.sin(pose[2])
    seen = (-0.5 * brain.sensing.length + 0.05, 0.5 * brain.sensing.width + 0.10)  # left
    assert brain.sweep_reach > 0.10

    def step(speed_towards: float, gap: float = 0.10) -> tuple[Command, BrainState]:
        towards = (s * speed_towards, -c * speed_towards)  # -y in base_link, own map frame
        return _step_with_tracked(brain, now, pose, (seen[0], 0.5 * brain.sensing.width + gap),
                                  towards)

    for speed in (0.5, 0.2):  # 0.2 m/s: there only by the time a stop took effect
        command, state = step(speed)
        assert command == Command(0.0, 0.0)
        assert state.held
        assert state.holds_show
    for speed in (0.0, -0.5):
        command, state = step(speed)
        assert command.linear > 0.1
        assert not state.held
    # one heading at it from beyond the circle its footprint sweeps (people walking past
    # swerve; the corridor and turn rules judge them): it drives on
    farther = brain.sweep_reach + 0.05
    command, state = step(2.0 * farther / 0.6, farther)
    assert command.linear > 0.1
    assert not state.held
    monkeypatch.setattr(robot, "PREDICTED_STOP_TIME", 0.0)
    command, state = step(0.2)
    assert command.linear > 0.1


def test_the_default_stop_rule_is_predicted_but_fixed_for_the_thesis_follower() -> None:
    """``default_stop_rule``: the thesis's follower keeps the thesis's fixed rule (it
    reproduces the thesis as written); the project's followers predict tracked people; a
    rule given is kept, an unknown one refused."""
    from dancebots.robot import BrainOptions, brain_for, default_stop_rule
    from dancebots.world import DEFAULT_ROBOT_TYPE

    assert default_stop_rule("thesis") == "fixed"
    assert default_stop_rule("path") == default_stop_rule("tracking") == "predicted"
    assert default_stop_rule("path", "closing") == "closing"
    assert default_stop_rule("thesis", "predicted") == "predicted"
    with pytest.raises(ValueError, match=r"^unknown stop rule 'x'; choose from fixed, "):
        default_stop_rule("path", "x")
    plan = plan_of(PLAN_TEXT)
    assert brain_for(plan, "R1", DEFAULT_ROBOT_TYPE,
                     BrainOptions(follower="path")).sensing.stop_rule == "predicted"
    assert brain_for(plan, "R1", DEFAULT_ROBOT_TYPE,
                     BrainOptions()).sensing.stop_rule == "fixed"


def _turning_robot() -> tuple[RobotBrain, float, tuple[float, float, float]]:
    """R1 of PLAN_TEXT (path follower, ``predicted`` rule), the show time 1 s and a pose on its
    place with its heading 0.5 rad off the place's: its follower turns it."""
    from dancebots.robot import SensingConfig

    brain = RobotBrain(plan_of(PLAN_TEXT), "R1", FollowerParams(),
                       sensing=SensingConfig(stop_rule="predicted"), follower="path")
    now = 1.0
    slot = brain.slot_at(now).pose
    return brain, now, (slot[0], slot[1], slot[2] + 0.5)


def test_the_predicted_rule_keeps_a_robot_from_turning_into_a_stranger_running_at_its_side(
) -> None:
    """A robot that turns (its heading 0.5 rad off its place's) with a tracked stranger
    0.3 s ago beside it, outside the circle its footprint sweeps: the stranger standing, it
    turns; the stranger running at its side at 1 m/s, which by now puts it within that
    circle (``sweep_reach`` of the footprint), it does not (in dense crowds children ran
    into the sides of robots turning slowly on the spot: docs/safety.md, "Stop rules")."""
    from dancebots.perception.tracks import TRACKED
    from dancebots.robot import BrainState

    brain, now, pose = _turning_robot()
    half_width = 0.5 * brain.sensing.width
    predicted_gap = 0.5 * brain.sweep_reach  # where the stranger will be, from the side
    side = half_width + predicted_gap + 0.3  # where it was seen 0.3 s ago (1 m/s)
    assert side - half_width > brain.sweep_reach  # seen outside the circle

    def command(velocity: float) -> tuple[float, bool]:
        local = (0.0, side)  # beside the robot's centre, on its left
        c, s = math.cos(pose[2]), math.sin(pose[2])
        world_velocity = (-s * velocity, c * velocity)  # towards the robot: -y in base_link
        state = BrainState(obstacles=np.array([[local[0], local[1], 0.0, 1.0]]),
                           seen_from=pose, cloud_stamp=now - 0.3,
                           point_velocity=np.array([world_velocity]),
                           point_kind=np.array([TRACKED], dtype=np.int8))
        state, cmd, _ = brain.step(state, now, pose, None, clock=now)
        return cmd.angular, state.held

    turning, _ = command(0.0)
    assert abs(turning) > 0.1
    kept, _ = command(-1.0)
    assert kept == 0.0


def test_a_robot_that_is_not_held_does_not_turn_into_a_stranger_beside_it() -> None:
    """A robot that turns (its heading 0.5 rad off its place's), not held, with a stranger
    standing beside it: within the circle its footprint sweeps (``sweep_reach`` beyond its
    side) it does not turn, outside it it does. The rule once held only for held robots, and
    a standing robot that the show moved on turned its rear corner into a child squeezing
    past it (children crowd seed 34, t = 218.0 s: docs/safety.md, "People walk out")."""
    from dancebots.robot import BrainState

    brain, now, pose = _turning_robot()
    half_width = 0.5 * brain.sensing.width

    def command(gap: float) -> tuple[float, bool]:
        local = (-0.2, half_width + gap)  # beside its rear, on its left (R2 is on its right)
        state = BrainState(obstacles=np.array([[local[0], local[1], 0.0, 1.0]]),
                           seen_from=pose, cloud_stamp=now)
        state, cmd, _ = brain.step(state, now, pose, None, clock=now)
        return cmd.angular, state.held

    turning, held = command(brain.sweep_reach + 0.05)
    assert abs(turning) > 0.1
    assert not held
    kept, held = command(0.5 * brain.sweep_reach)
    assert kept == 0.0
    assert not held


@pytest.mark.parametrize("gap", [0.40, 0.50])
def test_a_robot_held_for_a_stranger_does_not_turn_while_one_is_near(gap: float) -> None:
    """A robot held for a stranger standing in its corridor (within the stop distance, beyond
    the circle its footprint sweeps) and turned 0.5 rad off its place's heading stands
    still: no turn while a stranger is within NEAR_GAP (it turned at 0.37 rad/s, its corners
    swinging at 0.25 m/s beside the person; dense crowd seed 94, t = 109.9 s: a held R4
    turned at 0.045 rad/s and its corner met a child who ran at it within the LIDAR's
    latency)."""
    from dancebots.robot import SensingConfig

    brain, now, pose = _turning_robot()
    assert brain.sweep_reach < gap < brain.sensing.detection.stop_distance
    ahead = np.array([[0.5 * brain.sensing.length + gap, 0.0, 0.0, 1.0]])
    state, command, _ = brain.step(BrainState(obstacles=ahead, seen_from=pose, cloud_stamp=now),
                                   now, pose, None, clock=now)
    assert command == Command(0.0, 0.0)
    assert state.held
    assert state.holds_show
    # the thesis's follower is as written: held, it turns (thesis 5.2's rotation rule)
    thesis = RobotBrain(brain.plan, "R1", FollowerParams(), follower="thesis",
                        sensing=SensingConfig(stop_rule="fixed"))
    state, turning, _ = thesis.step(BrainState(obstacles=ahead, seen_from=pose, cloud_stamp=now),
                                    now, pose, None, clock=now)
    assert state.held
    assert turning.linear == 0.0
    assert abs(turning.angular) > 0.1


def test_a_stranger_beside_a_mate_does_not_hide_in_the_mates_disc_from_the_turn_rule(
) -> None:
    """A robot that turns (its heading 0.5 rad off its place's) with a child between it and
    R2, R2 on its place: the child is 5 cm from the robot's side, within the disc round R2's
    place that hides a mate off its place (``mate_radius``) but beyond R2's body where R2
    should be and said it is (``mate_body_radius``). Hearing nothing from R2 the robot knows
    no better and turns (the thesis's ``--hold alone``); hearing R2 it does not: a child
    squeezing between R1 and R2 was hidden so, and R1 drove on turning into it (open-day
    crowd seed 138 of 94d2cb6, t = 92.7 s: ``robot.MATE_BODY_MARGIN``). R2's own corner
    within the circle the robot's footprint sweeps stays R2's: the robot turns, with R2
    heard where it is and with R2's message late (heard 0.3 m off: it is on its place)."""
    from dancebots.geometry import Pose, compose_points
    from dancebots.robot import BrainState

    brain, now, pose = _turning_robot()
    mate = brain.mates_at(now)[0]  # R2's place, own map frame
    towards = (mate - np.array(pose[:2])) / np.hypot(*(mate - np.array(pose[:2])))
    child = np.array(pose[:2]) + 0.4 * towards  # own map frame
    corner = mate - 0.5 * towards  # a point of R2's body, its corner towards the robot
    show_frame = Pose(*brain._own_frame).inverse()
    to_show = np.array([show_frame.x, show_frame.y, show_frame.theta])
    half_width = 0.5 * brain.sensing.width

    def angular(points: list[np.ndarray], heard: np.ndarray | None) -> float:
        local = [Pose(*pose).to_local(float(x), float(y)) for x, y in points]
        state = BrainState(obstacles=np.array([[x, y, 0.0, 1.0] for x, y in local]),
                           seen_from=pose, cloud_stamp=now)
        return brain.step(state, now, pose, None, clock=now, mates_heard=None if heard is None
                          else compose_points(to_show, heard[None]))[1].angular

    assert brain.mate_body_radius < np.hypot(*(child - mate)) < brain.mate_radius
    assert abs(Pose(*pose).to_local(*child)[1]) - half_width < brain.sweep_reach
    assert abs(Pose(*pose).to_local(*corner)[1]) - half_width < brain.sweep_reach
    assert abs(angular([child, corner], None)) > 0.1  # the child hidden in R2's disc
    assert angular([child, corner], mate) == 0.0  # R2 heard: the child is a stranger
    assert abs(angular([corner], mate)) > 0.1  # R2's corner is R2's
    assert abs(angular([corner], mate + 0.3 * towards)) > 0.1  # so with R2's message late


def test_the_wait_after_the_show_starts_once_every_place_stands_on_its_slot() -> None:
    """A robot with a stranger within NEAR_GAP (beside it, not in its way) waits for it
    (holding the show) only after the show, once every place stands on its final slot
    (``rest_from``: the path follower's rear places reach theirs 3.6 s after the bundled
    show's plan ends); between the plan's end and then it drives on to its slot. Waiting
    from the plan's end, a robot held the shared clock and the rear places stopped short of
    their slots (open-day crowd seed 648: R3 and R4 0.8 m)."""
    from dancebots.check import CheckOptions
    from dancebots.loading import load_show
    from dancebots.perception.cloud import PointCloud
    from dancebots.plan.placement import places_followed
    from dancebots.robot import NEAR_GAP, SensingConfig

    show = load_show(str(Path(__file__).resolve().parents[1] / "src" / "dancebots" / "data"
                         / "open_day.dance"),
                     check=CheckOptions(places=places_followed("path")), timing="feasible")
    plan = show.plan
    assert plan is not None
    brain = RobotBrain(plan, "R3", FollowerParams(), sensing=SensingConfig(), follower="path")
    assert brain.rest_from > plan.duration + 1.0

    def waits(show_time: float) -> bool:
        place = brain.slot_at(show_time).pose
        pose = (place[0] - 0.3 * math.cos(place[2]), place[1] - 0.3 * math.sin(place[2]),
                place[2])  # 0.3 m behind its place, facing its way
        wall = np.array([[x, 0.3 + 0.5 * NEAR_GAP, 0.0, 1.7] for x in np.linspace(-1, 1, 21)])
        state, _, _ = brain.step(brain.initial_state(), show_time, pose,
                                 PointCloud(show_time, wall), clock=show_time)
        return state.waiting

    assert not waits(0.5 * (plan.duration + brain.rest_from))
    assert waits(brain.rest_from + 1.0)


def test_a_turn_about_a_point_within_the_footprint_is_on_the_spot() -> None:
    """``turns_on_the_spot``: the turn centre (|v / w| m to the side) within half the width;
    open-day crowd seed 293's robots (0.04 m/s at 2.04 rad/s, a HUSKY 0.67 m wide) were;
    an arc of the show (0.35 m/s at 0.2 rad/s) and driving straight are not."""
    from dancebots.robot import turns_on_the_spot

    assert turns_on_the_spot(0.04, 2.04, 0.67)
    assert turns_on_the_spot(0.0, -0.5, 0.67)
    assert turns_on_the_spot(-0.3, 1.0, 0.67)  # 0.3 m: within 0.335 m
    assert not turns_on_the_spot(0.35, 0.2, 0.67)
    assert not turns_on_the_spot(0.35, 0.0, 0.67)
    assert not turns_on_the_spot(0.0, 0.0, 0.67)


@pytest.mark.parametrize("approach", [True, False])
@pytest.mark.parametrize("no_room_within", [None, 0.0])
def test_a_robot_a_few_centimetres_off_its_final_slot_does_not_make_room(
        no_room_within: float | None, approach: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """After the show, R2 of a row 0.8 m apart stands 7 cm to the right of its final slot,
    facing its heading, R1 on its own beside it. With the approach law
    (``control.tracking.approach_step``, the default) it asks for no turn and stands. With
    the posture law alone (approach_distance 0) it would turn left towards the slot, the
    turn guard allows none of that turn (R1's side is within its corners' swing), and making
    room for it drove a SIM robot 0.15 m/s ahead and back again to the run's end (listing
    7.1 in the physics profiles): within FINAL_NO_ROOM of its final slot it stands instead;
    with that rule off (0 m) the same robot makes room, so the guard does block there."""
    import dancebots.robot as robot_module
    from dancebots.perception.cloud import PointCloud
    from dancebots.robot import MAKE_ROOM_SPEED, SensingConfig

    if no_room_within is not None:
        monkeypatch.setattr(robot_module, "FINAL_NO_ROOM", no_room_within)
    plan = plan_of("robots R1 R2\nrow R1,R2 0 0.8\nmove 2 0\n")
    brain = RobotBrain(plan, "R2", FollowerParams(), sensing=SensingConfig(), follower="path")
    if not approach:
        brain.tracking = replace(brain.tracking, approach_distance=0.0)
    after = brain.rest_from + 1.0
    slot = brain.slot_at(after)
    assert slot.final
    x, y, heading = slot.pose
    pose = (x + 0.07 * math.sin(heading), y - 0.07 * math.cos(heading), heading)  # to its right
    beside = _side_by_side_cloud(0.8 + 0.07 - 0.6)  # R1's right side, on its final place
    state = brain.initial_state()
    commands = []
    for k in range(5):
        now = after + 0.1 * k
        state, command, _ = brain.step(state, now, pose, PointCloud(now, beside), clock=now)
        commands.append(command)
    if approach:
        assert all(c.linear == 0.0 and c.angular == 0.0 for c in commands)
        assert state.making_room == 0.0
    elif no_room_within is None:
        assert all(abs(c.linear) < 0.01 and c.angular == 0.0 for c in commands)
        assert state.making_room == 0.0
    else:
        assert any(abs(c.linear) == pytest.approx(MAKE_ROOM_SPEED) for c in commands)


def test_a_place_standing_a_moment_is_tracked_as_if_the_clock_stood() -> None:
    """``RobotBrain._place_stand`` on a plan that stands 1 s, then 5 s, then for good: the
    1 s stand, and the last 2 s of the 5 s one, are brief (``control.tracking.BRIEF_STAND``;
    the place moves on forwards), the end is for good. A robot 0.2 m to the right of its
    place while it stands a moment turns at most gently (the paused law), where at the start
    of the 5 s stand it turns towards the place to drive onto it (0.2 m short of a corner
    where their places stood 0.4 s, the open-day show's rear robots swung 55 deg out and
    back)."""
    from dancebots.control.tracking import FOR_GOOD
    from dancebots.robot import SensingConfig

    plan = plan_of("robots R1 R2\nrow R1,R2 0 0.8\nmove 2 0\nwait 1\nmove 2 0\nwait 5\n"
                   "move 1 0\n")
    brain = RobotBrain(plan, "R2", FollowerParams(), sensing=SensingConfig(lidar=False),
                       follower="path")
    times = np.arange(0.0, brain.grid_end, 0.1)
    rows = brain.references_at(times)
    standing = np.abs(rows[:, 3]) + np.abs(rows[:, 4]) < 1e-9
    starts = times[1:][np.diff(standing.astype(int)) == 1]  # where each stand begins
    assert len(starts) == 3
    brief, wait, end = starts.tolist()
    assert brain._place_stand(brief + 0.4) == 1.0
    assert brain._place_stand(wait + 0.5) == 0.0
    assert brain._place_stand(wait + 4.0) == 1.0  # 1 s left
    assert brain._place_stand(end + 0.5) == FOR_GOOD
    assert brain._place_stand(1.0) == 0.0  # it moves

    def command_beside(show_time: float) -> tuple[float, float]:
        x, y, heading = brain.slot_at(show_time).pose
        pose = (x + 0.2 * math.sin(heading), y - 0.2 * math.cos(heading), heading)
        _, command, _ = brain.step(brain.initial_state(), show_time, pose, None,
                                   clock=show_time)
        return command.linear, command.angular

    tracking = brain.tracking
    assert abs(command_beside(brief + 0.4)[1]) <= tracking.heading_speed * tracking.gain_theta
    assert abs(command_beside(wait + 0.5)[1]) > 1.0
