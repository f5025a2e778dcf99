"""The physics profile in MuJoCo: robots drive, skid-steer ones slip in turns as Coulomb
friction predicts, walls and people stop them, and a whole show runs on it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the physics profile's engine (the dev extra installs it)")

from dancebots.sim.physics import PhysicsWorld
from dancebots.world.model import BUILTIN_ROBOT_TYPES, RobotType

ROOM = np.array([[-10.0, -10.0], [10.0, -10.0], [10.0, 10.0], [-10.0, 10.0]])
NOBODY = np.zeros((0, 2))


def steady(world: PhysicsWorld, command: tuple[float, float], seconds: float = 3.0,
           ) -> np.ndarray:
    """The mean achieved (v, w) of robot 0 over the second half of ``seconds`` s."""
    achieved = []
    for _ in range(round(seconds / 0.1)):
        _, velocity = world.step(np.array([command]), 0.1, NOBODY)
        achieved.append(velocity[0])
    result: np.ndarray = np.mean(achieved[len(achieved) // 2:], axis=0)
    return result


@pytest.mark.parametrize("name", ["HUSKY", "TRADR", "SIM", "TURTLEBOT3"])
def test_every_robot_drives_straight_at_its_commanded_speed(name: str) -> None:
    kind = BUILTIN_ROBOT_TYPES[name]
    world = PhysicsWorld([kind], np.zeros((1, 3)), ROOM, 1.0, [], NOBODY)
    v, w = steady(world, (kind.max_speed, 0.0))
    assert v == pytest.approx(kind.max_speed, rel=0.01)
    assert abs(w) < 1e-3
    pose = world.poses()[0]
    assert abs(pose[1]) < 0.01
    assert abs(pose[2]) < 0.01


def test_skid_steer_robots_slip_when_they_turn_and_a_differential_one_does_not() -> None:
    """On the spot at 1 rad/s commanded with the plain track (``geometric``): a HUSKY turns at
    about 0.55 rad/s, which Coulomb friction at its four wheels predicts (wheelbase 0.512 m,
    track 0.5708 m: the wheels' friction moments balance at w = b u / (a^2 + b^2), a and b half
    the wheelbase and track, u the wheels' speed); with the track widened by that ratio
    (``calibrated``, as real drivers do) it turns at about the commanded rate; a TurtleBot3 on
    two wheels and casters turns at the commanded rate either way."""
    husky = BUILTIN_ROBOT_TYPES["HUSKY"]
    a, b = 0.512 / 2, 0.5708 / 2
    coulomb = b * b / (a * a + b * b)  # w / w_commanded, with u = w_commanded b
    world = PhysicsWorld([husky], np.zeros((1, 3)), ROOM, 1.0, [], NOBODY, "geometric")
    _, w = steady(world, (0.0, 1.0))
    assert w == pytest.approx(coulomb, abs=0.05)
    assert w < 0.7  # slip is visible
    world = PhysicsWorld([husky], np.zeros((1, 3)), ROOM, 1.0, [], NOBODY, "calibrated")
    _, w = steady(world, (0.0, 1.0))
    assert w == pytest.approx(1.0, abs=0.1)
    for drive in ("geometric", "calibrated"):
        tb3 = PhysicsWorld([BUILTIN_ROBOT_TYPES["TURTLEBOT3"]], np.zeros((1, 3)), ROOM, 1.0,
                           [], NOBODY, drive)  # type: ignore[arg-type]
        _, w = steady(tb3, (0.0, 1.0))
        assert w == pytest.approx(1.0, abs=0.02)


def test_a_wall_and_a_person_stop_a_robot() -> None:
    """A HUSKY driven at the room's wall for 15 s ends against it, not through it; one driven
    at a person standing in its way stops in front of the person."""
    kind = BUILTIN_ROBOT_TYPES["HUSKY"]
    world = PhysicsWorld([kind], np.array([[7.0, 0.0, 0.0]]), ROOM, 1.0, [], NOBODY)
    for _ in range(150):
        world.step(np.array([[1.0, 0.0]]), 0.1, NOBODY)
    x = world.poses()[0, 0]
    assert 10.0 - kind.length / 2 - 0.1 < x < 10.0 - kind.length / 2 + 0.03
    person = np.array([[0.25, 1.7]])
    world = PhysicsWorld([kind], np.zeros((1, 3)), ROOM, 1.0, [], person)
    for _ in range(60):
        world.step(np.array([[0.5, 0.0]]), 0.1, np.array([[2.0, 0.0, 0.25]]))
    assert world.poses()[0, 0] < 2.0 - 0.25 - kind.length / 2 + 0.03


def test_a_show_runs_on_the_physics_profiles_and_the_slip_shows_in_the_log(examples: Path,
                                                                          ) -> None:
    """Listing 7.1 (two SIM robots, LIDAR on, the path follower): no contact, both end on their
    slots. With the plain track (``physics-geometric``) the robots turn at about 0.4 of the
    commanded rate on turns (their achieved angular speed is the engine's, as log.csv writes
    it) and the row bends (the distance between the two changes by decimetres); with the
    drivers' widening (``physics``) they turn about as commanded and the row holds within
    5 cm, as in the ideal profile."""
    from dancebots.plan.placement import place_show
    from dancebots.plan.planner import PlanParameters
    from dancebots.report.metrics import run_metrics
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim import PROFILES, prepare_show
    from tests_support import plan_of

    plan = plan_of((examples / "thesis_7_1.dance").read_text(),
                   PlanParameters(timing="feasible"))
    from dancebots.sim.physics_model import physical_type

    sim = physical_type(BUILTIN_ROBOT_TYPES["SIM"])
    a, b = sim.wheelbase / 2, sim.track / 2
    ratios, spacings = {}, {}
    for profile in ("physics-geometric", "physics"):
        result = simulate(plan, *prepare_show(place_show(plan)),
                          SimConfig(profile=PROFILES[profile],
                                    brain=BrainOptions(follower="path")))
        metrics = run_metrics(result)
        assert metrics.collisions == 0
        assert metrics.max_final_error < 0.1
        commanded, achieved = result.commands[..., 1], result.velocities[..., 1]
        turning = np.abs(commanded) > 0.1
        ratios[profile] = float(np.median(achieved[turning] / commanded[turning]))
        spacings[profile] = metrics.max_spacing_change or math.nan
        # the slip itself, in both: the SIM robot turns at about 0.40 of what its wheels
        # would give (Coulomb: (b/2)^2 / (a^2 + (b/2)^2), a and b/2 half its wheelbase and
        # track)
        for robot in metrics.robots:
            assert robot.wheel_turn_ratio == pytest.approx(b * b / (a * a + b * b), abs=0.05)
    assert 0.3 < ratios["physics-geometric"] < 0.5, ratios
    assert 0.9 < ratios["physics"] < 1.1, ratios


@pytest.mark.parametrize("kind", [RobotType("TINY", 0.01, 0.01, 0.01, 0.01),
                                  RobotType("HUGE", 100.0, 100.0, 100.0, 100.0),
                                  RobotType("THIN", 5.0, 0.05, 1.0, 1.0),
                                  RobotType("FAST", 1.0, 0.6, 100.0, 100.0)],
                         ids=lambda kind: kind.name)
def test_hostile_robot_types_of_a_world_file_stay_finite(kind: RobotType) -> None:
    """The world loader accepts robot types from 1 cm to 100 m and 100 m/s: the engine builds
    and steps every one without NaN; a 5 x 0.05 m body (turn expansion capped at 3) stays on
    the floor when told to spin instead of being flung off it by its wheels."""
    room = np.array([[-300.0, -300.0], [300.0, -300.0], [300.0, 300.0], [-300.0, 300.0]])
    world = PhysicsWorld([kind], np.zeros((1, 3)), room, 1.0, [], NOBODY)
    for command in ((kind.max_speed, 0.0), (0.0, kind.max_angular_speed)):
        for _ in range(20):
            poses, velocities = world.step(np.array([command]), 0.1, NOBODY)
            assert np.all(np.isfinite(poses))
            assert np.all(np.isfinite(velocities))
    if kind.name == "THIN":
        assert world.data.qpos[2] < 0.1  # its wheels' centres, on the floor


def test_the_stage_records_a_physics_robots_contact_with_a_wall_and_an_obstacle() -> None:
    """In the physics profile the engine's walls stop a robot at the polygon's edge (the wall
    box lies outside the room, inside an obstacle), so the stage's contact test sees the
    contact, as in the other profiles; the robot drove into it (moving)."""
    from dancebots.geometry import Pose
    from dancebots.sim import PROFILES
    from dancebots.sim.setup import Arena, Placement
    from dancebots.sim.stage import Stage
    from dancebots.world.model import Obstacle

    husky = BUILTIN_ROBOT_TYPES["HUSKY"]
    box = np.array([[3.0, 2.0], [4.0, 2.0], [4.0, 4.0], [3.0, 4.0]])
    arena = Arena(ROOM, 1.0, (Obstacle("crate", box, 0.5, 1),), None)
    placement = Placement(("A", "B"), (husky, husky), np.array([[8.0, 0.0, 0.0],
                                                                 [0.0, 3.0, 0.0]]), Pose(0, 0, 0))
    stage = Stage(arena, placement, PROFILES["physics"], 0.1, None)
    for k in range(60):
        stage.advance(0.1 * k, np.array([[1.0, 0.0], [1.0, 0.0]]), np.full(2, 0.1 * k))
    kinds = {(c.robot, c.kind, c.other, c.moving) for c in stage.collisions}
    assert kinds == {("A", "wall", "wall", True), ("B", "obstacle", "crate", True)}
    assert stage.pose[0, 0] + husky.length / 2 < 10.0 + 0.01  # against the wall, not through
    assert stage.pose[1, 0] + husky.length / 2 < 3.0 + 0.01


def test_the_log_has_the_wheels_yaw_rate_in_the_physics_profile_only(examples: Path,
                                                                    tmp_path: Path) -> None:
    """log.csv gains ``w_wheels`` (what the wheels would turn the robot at without slip) in
    the physics profile; pandas reads it; the ideal profile's log keeps its columns."""
    import pandas as pd

    from dancebots.cli import main

    show = str(examples / "thesis_7_1.dance")
    assert main(["run", show, "--profile", "physics", "--no-animation",
                 "--out", str(tmp_path / "physics")]) == 0
    log = pd.read_csv(tmp_path / "physics" / "log.csv")
    assert list(log.columns[-2:]) == ["formation", "w_wheels"]
    turning = log[log["w_wheels"].abs() > 0.1]
    assert (turning["w"] / turning["w_wheels"]).median() < 0.6  # the SIM robots slip
    assert main(["run", show, "--no-animation", "--out", str(tmp_path / "ideal")]) == 0
    assert "w_wheels" not in pd.read_csv(tmp_path / "ideal" / "log.csv").columns


def test_a_physics_robot_creeping_into_a_wall_is_the_robots_contact() -> None:
    """A HUSKY told to creep at 0.02 m/s into the wall 5 cm ahead: the contact is the robot's
    (moving), as in the other profiles, although the engine has stopped it by the time the
    stage sees the contact (judged by the speed after the step alone it was "standing")."""
    from dancebots.geometry import Pose
    from dancebots.sim import PROFILES
    from dancebots.sim.setup import Arena, Placement
    from dancebots.sim.stage import Stage

    husky = BUILTIN_ROBOT_TYPES["HUSKY"]
    placement = Placement(("A",), (husky,), np.array([[10.0 - husky.length / 2 - 0.05, 0.0,
                                                       0.0]]), Pose(0, 0, 0))
    stage = Stage(Arena(ROOM, 1.0, (), None), placement, PROFILES["physics"], 0.1, None)
    for k in range(60):
        stage.advance(0.1 * k, np.array([[0.02, 0.0]]), np.full(1, 0.1 * k))
    assert [(c.kind, c.moving) for c in stage.collisions] == [("wall", True)]
