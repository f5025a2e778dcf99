"""The queue show of the second seed: robots in a line, each following the object in front
of it with nothing but its own planar LIDAR and odometry (no communication).

The leader is the world's spectator named ``leader`` (a walking person). Each follower runs
a detector (A1, A2, A2-track) on its scans and a controller (B1 PID, B2 VO) every tick; the
shared loop (``shows/loop.py``) records and moves the :class:`~dancebots.sim.stage.Stage`
(10 Hz rule, contacts). Scans are planar (``sim.lidar.scan_ranges``), at the LIDAR's period
and delivered after its latency, with the pose of the robot when it scanned (its odometry,
exact here).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import Pose
from dancebots.leader_follower.controllers import (
    SEED_FIRST_GAINS,
    SEED_TUNED_GAINS,
    PidGains,
    PidParams,
    PidState,
    QueueController,
    VoParams,
    VoState,
    leader_robot_command,
    pid_step,
    vo_step,
)
from dancebots.leader_follower.detectors import (
    ClusterParams,
    ClusterState,
    QueueDetector,
    TrackingParams,
    TrackingState,
    cluster_step,
    tracking_step,
)
from dancebots.leader_follower.scan import Detection, Scan
from dancebots.shows.loop import Clock, Progress, Tick, run_show
from dancebots.sim.kinematics import IDEAL, Profile
from dancebots.sim.lidar import LidarConfig
from dancebots.sim.recorder import Recorder
from dancebots.sim.setup import Arena, Placement, SetupError
from dancebots.sim.spectators import spectator_position, walk_duration
from dancebots.sim.stage import CollisionEvent, Stage
from dancebots.world import BUILTIN_ROBOT_TYPES, RobotType, Spectator, World

__all__ = ["LEADERS", "PID_GAINS", "Gains", "Leader", "QueueConfig", "QueueResult",
           "queue_placement", "simulate_queue"]

FloatArray = NDArray[np.float64]
LEADER = "leader"
Leader = Literal["person", "robot"]
LEADERS: tuple[Leader, ...] = get_args(Leader)
LEADER_ROBOT = "L"
Gains = Literal["first", "tuned"]
"""The pid controller's seed gains: the paper's first set, or its tuned one."""
PID_GAINS: dict[Gains, PidGains] = {"first": SEED_FIRST_GAINS, "tuned": SEED_TUNED_GAINS}
KIDNAP_DISTANCE = 0.5
"""m: a target nearer than this to some object other than the one in front (and nearer to
that object than to the one in front) is a kidnapping."""


def _lds() -> LidarConfig:
    """The TurtleBot3's LDS-01: 360 beams, 0.12-3.5 m, 5 Hz; latency about a tenth of s."""
    return LidarConfig(rays=360, min_range=0.12, max_range=3.5, latency=0.1, period=0.2)


@dataclass(frozen=True, slots=True)
class QueueConfig:
    """robots: followers; detector: a1 | a2 | a2-track; controller: pid | vo; robot_type;
    standoff: the distance each keeps to the object in front, m; spacing: between
    neighbours at the start, m; lidar; dt: step and control period, s; profile; seed;
    settle: s after the leader's walk; reciprocal: RVO in the vo controller; gains: the
    pid controller's seed gain set, "first" (Kp_u 1.2, Kp_w 0.5) or "tuned" (Kp_u 0.6,
    Kp_w 0.1, Ki_w 0.01), see docs/leader-follower.md for why "first" is the default;
    leader: "person" (the world's ``leader`` spectator walks its path) or "robot" (a robot
    of the same type drives that path, timed as the person would walk it)."""

    robots: int = 3
    detector: QueueDetector = "a1"
    controller: QueueController = "pid"
    robot_type: RobotType = BUILTIN_ROBOT_TYPES["TURTLEBOT3"]
    standoff: float = 0.5
    spacing: float = 0.6
    lidar: LidarConfig = field(default_factory=_lds)
    dt: float = 0.1
    profile: Profile = IDEAL
    seed: int = 0
    settle: float = 10.0
    reciprocal: bool = False
    gains: Gains = "first"
    leader: Leader = "person"


@dataclass(frozen=True, slots=True, eq=False)
class QueueResult:
    """A queue run sampled every tick. robots (R,) followers, front to back; times (T,) s;
    poses (R, T, 3) world; commands (R, T, 2) (u, w); targets (R, T, 2) the detector's
    target in the world (NaN: none); ahead (R, T, 2) the true position of the object in
    front (the leader or the previous robot); spectators (C, T, 2) with names and radii;
    collisions; leader (T, 2) where the leader was (the person or the leader robot),
    leader_extent: its radius or half length, m."""

    config: QueueConfig
    arena: Arena
    robots: tuple[str, ...]
    times: FloatArray
    poses: FloatArray
    commands: FloatArray
    targets: FloatArray
    ahead: FloatArray
    spectators: FloatArray
    spectator_names: tuple[str, ...]
    spectator_radii: FloatArray
    collisions: tuple[CollisionEvent, ...]
    leader: FloatArray
    leader_extent: float

    @property
    def kidnapped(self) -> NDArray[np.bool_]:
        """(R, T): ticks at which a follower's target lies within KIDNAP_DISTANCE of
        something other than the object in front (a person other than the leader, another
        robot, or, from the second follower on, the leader) and nearer to it than to the
        object in front. Computed on each access."""
        people = [self.spectators[k] for k, name in enumerate(self.spectator_names)
                  if name != LEADER]
        result = np.zeros(self.targets.shape[:2], dtype=bool)
        for i in range(len(self.robots)):
            others = people + [self.poses[j, :, :2] for j in range(len(self.robots))
                               if j not in (i, i - 1)] + ([self.leader] if i > 0 else [])
            to_ahead = np.hypot(*(self.targets[i] - self.ahead[i]).T)
            for other in others:
                to_other = np.hypot(*(self.targets[i] - other).T)
                result[i] |= (to_other < KIDNAP_DISTANCE) & (to_other < to_ahead)
        return result

    @property
    def gap(self) -> FloatArray:
        """(R, T) distance from each follower to the object in front, m."""
        result: FloatArray = np.hypot(self.poses[..., 0] - self.ahead[..., 0],
                                      self.poses[..., 1] - self.ahead[..., 1])
        return result

    @property
    def lost(self) -> NDArray[np.bool_]:
        """(R, T): ticks without a target."""
        result: NDArray[np.bool_] = np.isnan(self.targets[..., 0])
        return result


def queue_placement(world: World, config: QueueConfig) -> tuple[Arena, Placement]:
    """The arena of ``world`` and the robots in a line behind its ``leader`` spectator,
    facing along the leader's first leg: the followers F1..FN, and with a robot leader the
    robot L first, on the path's start (the person then leaves the arena)."""
    leaders = [s for s in world.spectators if s.name == LEADER]
    if not leaders:
        raise SetupError(f"{world.path}: the queue show needs a spectator named "
                         f"'{LEADER}' (the person the queue follows)")
    if config.leader not in LEADERS:
        raise SetupError(f"unknown leader {config.leader!r}; use person or robot")
    leader = leaders[0]
    points = leader.waypoints
    heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0]) if len(
        points) > 1 else 0.0
    back = np.array([-math.cos(heading), -math.sin(heading)])
    kind = config.robot_type
    robot_leader = config.leader == "robot"
    first = (0.5 * kind.length if robot_leader else leader.radius) + config.spacing
    starts = [[*(points[0] + back * (first + k * (config.spacing + kind.length))), heading]
              for k in range(config.robots)]
    names = [f"F{k + 1}" for k in range(config.robots)]
    spectators = tuple(world.spectators)
    if robot_leader:
        starts.insert(0, [float(points[0, 0]), float(points[0, 1]), heading])
        names.insert(0, LEADER_ROBOT)
        spectators = tuple(s for s in spectators if s.name != LEADER)
    arena = Arena.of_world(world, spectators)
    return arena, Placement(tuple(names), (kind,) * len(names), np.array(starts),
                            Pose(0.0, 0.0, 0.0))


def simulate_queue(world: World, config: QueueConfig = QueueConfig(),
                   progress: Progress | None = None) -> QueueResult:
    """Run the queue until the leader has walked (or driven) its path and ``settle`` s more."""
    arena, placement = queue_placement(world, config)
    lead = 1 if config.leader == "robot" else 0  # robots before the followers in the stage
    stage = Stage(arena, placement, config.profile, config.dt, None, seed=config.seed)
    leader = next(s for s in world.spectators if s.name == LEADER)
    queue = _Queue(config, stage, leader, lead,
                   None if lead else [s.name for s in arena.spectators].index(LEADER))
    clock = Clock(config.dt, walk_duration(leader) + config.settle)
    recorder = run_show(stage, queue.step, clock, progress)
    extent = 0.5 * config.robot_type.length if lead else leader.radius
    return _result(config, arena, placement.robots[lead:], stage, recorder, extent)


class _Queue:
    """The queue's decisions at a control tick: each follower's detector takes the scans that
    reach it, its controller steers towards the detection; a leader robot (``lead`` 1, the
    stage's first robot) drives towards where the person would be."""

    def __init__(self, config: QueueConfig, stage: Stage, leader: Spectator, lead: int,
                 leader_index: int | None) -> None:
        count = config.robots
        self.count, self.stage, self.leader, self.lead = count, stage, leader, lead
        self.leader_index, self.kind, self.lidar = leader_index, config.robot_type, config.lidar
        self.angles = config.lidar.angles()
        self.detect, self.control = _parts(config)
        self.detector_states: list[Any] = [None] * count
        self.controller_states: list[Any] = [None] * count
        self.detections: list[Detection | None] = [None] * count
        self.command = np.zeros((count + lead, 2))

    def step(self, now: float) -> Tick:
        stage, count, lead, command = self.stage, self.count, self.lead, self.command
        detector_states, controller_states = self.detector_states, self.controller_states
        detections = self.detections
        for stamp, ranges, poses in stage.planar_deliveries(now, self.lidar):
            for i in range(count):
                scan = Scan(stamp, ranges[lead + i], self.angles,
                            tuple(poses[lead + i].tolist()))
                detector_states[i], detections[i] = self.detect(detector_states[i], scan)
        if lead:
            command[0] = leader_robot_command(
                spectator_position(self.leader, now), tuple(stage.pose[0].tolist()),
                self.kind.max_speed, self.kind.max_angular_speed)
        targets = np.full((count, 2), np.nan)
        for i in range(count):
            pose = tuple(stage.pose[lead + i].tolist())
            controller_states[i], (u, w) = self.control(controller_states[i], pose,
                                                        detections[i])
            command[lead + i] = (u, w)
            detection = detections[i]
            if detection is not None and detection.target is not None:
                targets[i] = detection.target.position
        leader_at = stage.pose[0, :2] if lead else stage.discs[self.leader_index, :2]
        ahead = np.vstack([leader_at, stage.pose[lead:lead + count - 1, :2]])
        return Tick(command, {"poses": stage.pose[lead:], "commands": command[lead:],
                              "targets": targets, "ahead": ahead,
                              "spectators": stage.discs[:, :2], "leader": leader_at})


def _parts(config: QueueConfig) -> tuple[Callable[[Any, Scan], tuple[Any, Detection]],
                                         Callable[[Any, tuple[float, ...], Detection | None],
                                                  tuple[Any, tuple[float, float]]]]:
    """The detector and the controller of the configuration, as (state, input) -> (state,
    output) functions that start from a None state."""
    kind = config.robot_type
    if config.detector == "a1":
        cluster = ClusterParams()

        def detect(state: Any, scan: Scan) -> tuple[Any, Detection]:
            return cluster_step(cluster, state or ClusterState(), scan)
    elif config.detector in ("a2", "a2-track"):
        tracking = TrackingParams(rule="seed" if config.detector == "a2" else "track")

        def detect(state: Any, scan: Scan) -> tuple[Any, Detection]:
            return tracking_step(tracking, state or TrackingState(), scan)
    else:
        raise ValueError(f"unknown detector {config.detector!r}; use a1, a2 or a2-track")
    if config.controller == "pid":
        if config.gains not in PID_GAINS:
            raise ValueError(f"unknown gains {config.gains!r}; use {' or '.join(PID_GAINS)}")
        pid = PidParams(PID_GAINS[config.gains], standoff=config.standoff,
                        max_linear=kind.max_speed, max_angular=kind.max_angular_speed)

        def control(state: Any, pose: tuple[float, ...],
                    detection: Detection | None) -> tuple[Any, tuple[float, float]]:
            return pid_step(pid, state or PidState(), (pose[0], pose[1], pose[2]), detection)
    elif config.controller == "vo":
        vo = VoParams(standoff=config.standoff, max_linear=kind.max_speed,
                      max_angular=kind.max_angular_speed,
                      radius=0.5 * math.hypot(kind.length, kind.width),
                      reciprocal=config.reciprocal, dt=config.dt)

        def control(state: Any, pose: tuple[float, ...],
                    detection: Detection | None) -> tuple[Any, tuple[float, float]]:
            return vo_step(vo, state or VoState(), (pose[0], pose[1], pose[2]), detection)
    else:
        raise ValueError(f"unknown controller {config.controller!r}; use pid or vo")
    return detect, control


def _result(config: QueueConfig, arena: Arena, robots: tuple[str, ...], stage: Stage,
            recorder: Recorder, leader_extent: float) -> QueueResult:
    times = recorder.times
    poses = recorder.series("poses")
    commands = recorder.series("commands")
    targets = recorder.series("targets")
    ahead = recorder.series("ahead")
    spectators = recorder.series("spectators")  # (C, T, 2)
    leader = recorder.series("leader", axis=0)
    contacts = tuple(c for c in stage.collisions if c.robot in robots)
    return QueueResult(config, arena, robots, times, poses, commands, targets, ahead,
                       spectators, tuple(s.name for s in arena.spectators),
                       np.array([s.radius for s in arena.spectators]), contacts, leader,
                       leader_extent)
