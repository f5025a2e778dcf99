"""The formation show: the robots' brains follow the plan on the stage, vectorised over robots,
deterministic.

At each control tick (10 Hz) every robot's brain ticks with the cloud the
:class:`~dancebots.sim.stage.Stage` delivers and its pose in its own map frame; the shared
loop (``shows/loop.py``) records, reports progress, moves the stage by each step of ``dt``
seconds (10 Hz rule, actuation profile, exact arcs, contacts; see ``sim/stage.py``) and ends
once every robot has stood still for a second after the show. Noise comes from a generator
seeded by the configuration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.control.tracking import follower_references, shared_pose_references
from dancebots.geometry import (
    Pose,
    compose_points,
    compose_poses,
    footprint_corners,
    frame_turns,
)
from dancebots.perception.cloud import PointCloud
from dancebots.plan.places import path_places, places_end
from dancebots.plan.planner import Plan
from dancebots.robot import BrainOptions, BrainState, RobotBrain, brain_for
from dancebots.robot_batch import BatchBrains, batch_supported
from dancebots.safety.monitor import EventKind
from dancebots.shows.loop import Clock, Progress, Tick, run_show
from dancebots.sim.kernels import kernel
from dancebots.sim.kinematics import IDEAL, Profile
from dancebots.sim.lidar import LidarConfig
from dancebots.sim.recorder import Recorder
from dancebots.sim.setup import Arena, Placement
from dancebots.sim.stage import CollisionEvent, Stage
from dancebots.sync.hold import (
    ADVANCE_MIN,
    FormationClocks,
    HoldParams,
    HoldStrategy,
    clock_rate,
    default_hold_strategy,
    formation_clocks,
    formation_receive,
    formation_tick,
)

__all__ = ["FORMATION_CONTROLS", "SCAN_AHEAD_FROM", "STATUS", "CollisionEvent", "Fault",
           "FaultKind", "FormationControl", "RobotEvent", "RunResult", "SimConfig",
           "hold_strategy", "settle_from", "simulate"]

SCAN_AHEAD_FROM = 8
"""Robots from which the stage casts each scan on a second thread (``Stage.scan_ahead``):
the loop of the 20-robot, 1,000-line show 11.5 -> 9.9 s, 16 robots 0.72 -> 0.67 s, 9 robots
0.53 -> 0.49 s; with 4 or 6 robots the hand-over costs more than the scan (0.27 -> 0.30 s,
0.117 -> 0.125 s)."""

STATUS = ("ok", "stopped", "error")
"""Codes of ``RunResult.status``: 0 moving freely, 1 held by a stop flag, 2 error state."""


FaultKind = Literal["lidar", "pose"]
"""An injected failure: a LIDAR that delivers nothing, or pose look-ups that fail."""


@dataclass(frozen=True, slots=True)
class Fault:
    """An injected failure: from show time ``start`` s, ``robot``'s LIDAR delivers nothing
    (kind "lidar") or its pose look-ups fail (kind "pose")."""

    robot: str
    kind: FaultKind
    start: float

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class SimConfig:
    """Simulation settings.

    profile: how commands become motion (ideal or realistic).
    dt: simulation step, s (one step per control tick by default: motion between ticks is
        integrated exactly along arcs, so the ideal profile loses nothing).
    control_period: the brains' tick, s (10 Hz).
    command_timeout: a robot stops when its last command is older than this, s.
    seed: seed of the noise generator. settle: extra time after the show's end (every place
        on its final slot, :func:`settle_from`), s; the run ends earlier once every robot has
        stood still for a second after it.
    lidar: the simulated LIDAR (None: robots without LIDAR, no obstacle detection).
    brain: how every robot decides (detector, force field, force steering: the options a
        real robot's node takes too); its ``lidar`` follows ``lidar`` above.
    faults: injected sensor failures.
    record_lidar: keep every scan's hits in the result (for drawing; memory grows with
        robots x rays x time).
    compiled: run the LIDAR, the perception, the collision tests and a crowd's forces as
        numba-compiled loops (the default: fast per tick; ``lidar.compiled`` and
        ``brain.compiled`` can still turn theirs off), else all as their NumPy references
        (the same results, but with crowds: their forces agree to 1e-9, and a run among a
        crowd is chaotic, so it takes another course; no numba to import and start, about
        0.75 s: faster for a short show).
    hold: ``together``: the formation shares one show clock that stops while any robot is
        held by something that is not a mate on its place (``sync.hold``), so the others wait
        on their places; ``paced``: together, and a robot a stranger slows says the pace it
        can follow, at which every show time advances (the formation slows together);
        ``alone`` (thesis 4.2): each robot's show time is the time since the start; None
        (the default): paced, alone for the thesis follower (the thesis's
        system as written: its follower knows no mates' places, so a mate would hold the
        show). hold_delay (s, below the 1 s heartbeat timeout) and hold_loss (probability,
        below 1) act on the robots' hold messages, passed in-process (the kernel here has no
        netem; the ROS nodes do not send them yet).
    max_pause: s the shared clock may fall behind the stage's before the run ends anyway (a
        person who never leaves a robot's way).
    batched: tick every robot's brain in one compiled pass (``robot_batch.BatchBrains``: the
        same decisions, several times faster) where the brains allow it (the ``tracking`` and
        ``path`` followers with the ``fixed`` stop rule, compiled); else, or when off, each
        :class:`~dancebots.robot.RobotBrain` ticks in turn (the reference).
    clock_offsets: per robot (R,), s its clock is off (the network experiment,
        ``benchmarks/eval_network.py``, injected in-process): its brain runs the show at its
        show time plus its offset; the result records the formation's show times without them
        (the audience's, against which the formation error is measured). Empty: none.
    formation_control: ``virtual-leader`` (the thesis's design, default): every robot follows
        its slot of the plan's virtual leader; ``shared-pose`` (for the network experiment: a
        leader-follower formation that shares the leader's pose): the plan's first robot
        follows its slot, and every other robot its slot relative to the pose that robot
        broadcasts at 10 Hz over the same transport as the hold messages (``hold_delay``,
        ``hold_loss``), extrapolated by the velocity it sent over the message's age on the
        receiver's clock. One formation, batched brains only.
    scan_ahead: with :data:`SCAN_AHEAD_FROM` robots or more, cast each scan on a second
        thread (``Stage.scan_ahead``; off where processes fill every core already, as
        ``certify``'s do).
    """

    profile: Profile = IDEAL
    dt: float = 0.1
    control_period: float = 0.1
    command_timeout: float = 0.1
    seed: int = 0
    settle: float = 20.0
    lidar: LidarConfig | None = field(default_factory=LidarConfig)
    brain: BrainOptions = field(default_factory=BrainOptions)
    faults: tuple[Fault, ...] = ()
    record_lidar: bool = False
    compiled: bool = True
    hold: HoldStrategy | None = None
    hold_delay: float = 0.0
    hold_loss: float = 0.0
    max_pause: float = 120.0
    batched: bool = True
    clock_offsets: tuple[float, ...] = ()
    formation_control: FormationControl = "virtual-leader"
    scan_ahead: bool = True

    def __post_init__(self) -> None:
        if not (0.0 <= self.hold_delay < HoldParams().heartbeat_timeout
                and 0.0 <= self.hold_loss < 1.0 and self.max_pause >= 0.0):
            raise ValueError("hold_delay must be 0 s or more and below the heartbeat timeout "
                             "(1 s), hold_loss in [0, 1) and max_pause 0 s or more")
        if not all(math.isfinite(offset) for offset in self.clock_offsets):
            raise ValueError("clock offsets must be finite")
        if self.formation_control not in FORMATION_CONTROLS:
            raise ValueError(f"unknown formation control {self.formation_control!r}; choose "
                             f"from {', '.join(FORMATION_CONTROLS)}")


FormationControl = Literal["virtual-leader", "shared-pose"]
FORMATION_CONTROLS: tuple[FormationControl, ...] = ("virtual-leader", "shared-pose")
"""How robots keep formation (``SimConfig.formation_control``)."""


@dataclass(frozen=True, slots=True)
class RobotEvent:
    """What a robot voiced or reported at ``time``: kind "speech", "beep", "resume", "error"."""

    time: float
    robot: str
    kind: EventKind
    text: str


@dataclass(frozen=True, slots=True, eq=False)
class RunResult:
    """A simulated show, sampled at every control tick.

    times (T,) s of the stage's clock (the time since the start). show_times (R, T): each
    robot's show time then (the plan's time it follows: ``times`` unless the formation's
    shared clock paused, ``SimConfig.hold``); holds (R, T): whether each robot held the
    show then (held by a stranger, or slowed and left behind by one: ``BrainState.
    holding_the_show``, or under ``paced`` said a pace below 1; recorded with every
    ``SimConfig.hold``). Per robot r and tick k,
    in the world frame:
    poses (R, T, 3);
    velocities (R, T, 2) actual (v, w); commands (R, T, 2) commanded (v, w); desired (R, T, 3)
    and leader (R, T, 3): where the robot believes its desired pose and its virtual leader are
    (computed in its own frame from its start pose); required_distance (R, T) its desired
    distance to the leader, m; formation (R, T) the index of the plan formation it follows.
    min_clearance: the smallest gap between two robots' footprints at any tick, m (None for
    one robot). status (R, T): codes of ``STATUS``. events: the robots' events in time order.
    spectators (C, T, 2): the spectators' positions, spectator_radii (C,). lidar (with
    ``SimConfig.record_lidar``): every scan as (time it reached the robots, per robot the
    (M, 2) world positions of its hits as they were when scanned): what the robots "see".
    reference (R, T, 5): what each robot's follower tracks
    (``control.tracking.follower_references``: its rigid slot's motion for ``tracking``, its
    place on the leader's path otherwise) in the world frame: x, y (m), heading (rad,
    continuous: the direction the place moves, or that + pi where it is driven in reverse),
    signed speed along that heading (m/s) and angular speed (rad/s).
    formation_places (R, T, 2): where the robot's formation puts it, world frame, m: its
    rigid slot for ``tracking``, its place on the leader's path otherwise, without the wait
    behind the robots ahead (``plan.places.path_places(..., wait_behind=False)``): what the
    audience expects, for the metrics' ``off_formation``. wheel_rates (R, T): in the physics
    profiles the yaw rate each robot's wheels would give without slip, rad/s
    (``sim.physics.PhysicsWorld.wheel_rates``); None in the others.
    """

    plan: Plan
    arena: Arena
    placement: Placement
    config: SimConfig
    times: FloatArray
    poses: FloatArray
    velocities: FloatArray
    commands: FloatArray
    desired: FloatArray
    leader: FloatArray
    required_distance: FloatArray
    formation: NDArray[np.int64]
    collisions: tuple[CollisionEvent, ...]
    min_clearance: float | None
    status: NDArray[np.int8]
    events: tuple[RobotEvent, ...]
    spectators: FloatArray
    spectator_radii: FloatArray
    reference: FloatArray
    lidar: tuple[tuple[float, tuple[FloatArray, ...]], ...] = ()
    show_times: FloatArray | None = None
    holds: NDArray[np.bool_] | None = None
    final_slots: FloatArray | None = None
    formation_places: FloatArray | None = None
    wheel_rates: FloatArray | None = None

    @property
    def final_slot(self) -> FloatArray:
        """(R, 3) each robot's slot at the plan's end in the world frame (x, y, heading): where
        it should end, even when the run ended before its show did (``desired`` at the last
        tick when not recorded)."""
        return self.final_slots if self.final_slots is not None else self.desired[:, -1]

    @property
    def show_time(self) -> FloatArray:
        """(R, T) each robot's show time at each tick (``times`` for every robot when none
        was recorded)."""
        if self.show_times is not None:
            return self.show_times
        return np.broadcast_to(self.times, (len(self.placement.robots), len(self.times)))

    @property
    def during_show(self) -> NDArray[np.bool_]:
        """(T,) the ticks at which the show runs: the formation's show time (the earliest of
        the robots') is within the plan's duration."""
        result: NDArray[np.bool_] = self.show_time.min(axis=0) <= self.plan.duration + 1e-9
        return result

    @property
    def robots(self) -> tuple[str, ...]:
        return self.placement.robots

    @property
    def leader_distance(self) -> FloatArray:
        """(R, T) distance from each robot to its virtual leader, m (d_act of eq. 4.4a)."""
        result: FloatArray = np.hypot(self.poses[..., 0] - self.leader[..., 0],
                                      self.poses[..., 1] - self.leader[..., 1])
        return result


def hold_strategy(config: SimConfig) -> HoldStrategy:
    """The hold strategy a configuration runs (``SimConfig.hold``; None: paced, alone for the
    thesis follower)."""
    if config.hold is not None:
        return config.hold
    return default_hold_strategy(config.brain.follower)


def settle_from(plan: Plan, follower: str) -> float:
    """The show time (s) by which every place stands on its final slot, from which a run may
    end once everything stands still, and which a finished show's clock reaches: the plan's
    end, but for the path follower, whose places follow the leader along its path, the time
    they reach their slots (``plan.places.places_end``, a few seconds later). Before (the
    plan's end for all), a robot holding the formation's clock for a person in that gap
    ended the run with the rear places short of their slots: open-day crowd seed 648, the
    clock standing at 115.98 s of 119.54 s, R3 and R4 left 0.8 m from their final slots."""
    if follower != "path":
        return plan.duration
    return float(max(plan.duration, places_end(plan)))


def _to_world(starts: FloatArray, slots: list[Pose], show: FloatArray, robot: int) -> FloatArray:
    """Show-frame poses (T, 3) as robot ``robot`` believes them in the world: start ⊕ slot0⁻¹."""
    frame = Pose(*(float(v) for v in starts[robot])).compose(slots[robot].inverse())
    return compose_poses(np.array([frame.x, frame.y, frame.theta]), show)


def simulate(plan: Plan, arena: Arena, placement: Placement, config: SimConfig = SimConfig(),
             progress: Progress | None = None) -> RunResult:
    """Run the show; ``progress(show_time, end_time)`` is called about once per second."""
    options = replace(config.brain, lidar=config.lidar is not None,
                      actuator_lag=config.profile.lag if config.brain.actuator_lag is None
                      else config.brain.actuator_lag,
                      compiled=config.brain.compiled and config.compiled,
                      paced=hold_strategy(config) == "paced")  # (the clock's, not the brain's)
    lidar = None if config.lidar is None else replace(
        config.lidar, compiled=config.lidar.compiled and config.compiled)
    brains = [brain_for(plan, robot, kind, options,
                        placement.types[:i] + placement.types[i + 1:])
              for i, (robot, kind) in enumerate(zip(placement.robots, placement.types,
                                                    strict=True))]
    stage = Stage(arena, placement, config.profile, config.dt, lidar,
                  config.command_timeout, config.seed, config.record_lidar, config.compiled,
                  scan_ahead=config.scan_ahead and len(placement.robots) >= SCAN_AHEAD_FROM)
    try:
        crew = _Crew(brains, placement.robots, stage, config)
        end = settle_from(plan, options.follower)
        clock = Clock(config.dt, end + config.settle,
                      max(1, round(config.control_period / config.dt)),
                      settle_from=end, max_pause=config.max_pause)
        recorder = run_show(stage, crew.step, clock, progress)
    except BaseException:
        stage.close(check=False)  # (the error that stopped the run is the one to see)
        raise
    stage.close()
    return _result(plan, arena, placement, config, recorder, brains, tuple(stage.collisions),
                   tuple(crew.events), tuple(stage.scans), stage.discs[:, 2].copy())


class _Crew:
    """The formation's decisions at a control tick: each robot's brain steps with the cloud
    that reaches it and its pose in its own map frame (withheld from the start of an injected
    fault) at its show time; the events the robots voiced or reported accumulate in
    ``events``. With ``hold`` = together or paced every robot keeps the formation's shared
    show clock
    (``sync.hold``) from the hold messages of the others, which reach it ``hold_delay`` s
    after they were sent unless lost (``hold_loss``, drawn from a generator of its own)."""

    def __init__(self, brains: list[RobotBrain], robots: tuple[str, ...], stage: Stage,
                 config: SimConfig) -> None:
        count = len(brains)
        faults = config.faults
        self.brains, self.robots, self.stage = brains, robots, stage
        self.states: list[BrainState] = [brain.initial_state() for brain in brains]
        self.together = hold_strategy(config) in ("together", "paced")
        self.paced = hold_strategy(config) == "paced"
        self.pacing = np.ones(count)  # each robot's pace at its last tick (1: not paced)
        self.rates = np.ones(count)  # each robot's clock's rate since its last tick
        self.clocks = formation_clocks(count, 0.0)
        # messages sent but not yet heard: (due time, per robot: sent (not lost), stamp, show
        # time, holds, position, pace), in the order sent
        self.in_flight: list[tuple[float, tuple[np.ndarray, ...]]] = []
        self.compiled_clocks = config.compiled
        self.hold_params = HoldParams()
        self.no_message = (np.zeros(count, dtype=bool), np.zeros(count), np.zeros(count),
                           np.zeros(count, dtype=bool), np.zeros((count, 2)), np.ones(count))
        # each robot's frame of the show: where it tells its mates it stands
        self.show_frames = np.array([[b.slot0.x, b.slot0.y, b.slot0.theta] for b in brains])
        self._show_frame_turns = frame_turns(self.show_frames)  # (:meth:`_tell`, every tick)
        self.delay, self.loss = config.hold_delay, config.hold_loss
        self.message_rng = np.random.default_rng([config.seed, 104_729])
        self.show_times = np.zeros(count)
        self.lidar_faults = {robots.index(f.robot): f.start for f in faults
                             if f.kind == "lidar"}
        self.pose_faults = {robots.index(f.robot): f.start for f in faults if f.kind == "pose"}
        self.events: list[RobotEvent] = []
        self.status = np.zeros(count, dtype=np.int8)
        self.holding = np.zeros(count, dtype=bool)
        self.asking = np.zeros(count, dtype=bool)
        self.waiting = np.zeros(count, dtype=bool)
        self.all_known = np.ones(count, dtype=bool)  # every pose look-up works (no fault)
        self.command = np.zeros((count, 2))
        self.batch: BatchBrains | None = None
        if config.batched and config.compiled and batch_supported(brains):
            self.batch = BatchBrains(brains)
        if config.clock_offsets and len(config.clock_offsets) != count:
            raise ValueError(f"{len(config.clock_offsets)} clock offsets for {count} robots")
        self.offsets = np.array(config.clock_offsets or [0.0] * count, dtype=float)
        self.shared = None
        if config.formation_control == "shared-pose":
            if self.batch is None:
                raise ValueError("the shared-pose formation control needs the tracking or path "
                                 "follower with the fixed stop rule (batched brains)")
            self.shared = _SharedPose(brains[0].plan, stage, self.offsets, config)

    def _show_times(self, now: float) -> None:
        """Each robot's show time at ``now``: with the shared clock, the messages due are
        heard and every clock ticks with its own robot's hold of the last tick."""
        if not self.together:
            self.show_times[:] = now
            return
        clocks = self.clocks
        due = [batch for at, batch in self.in_flight if at <= now + 1e-9]
        self.in_flight = [m for m in self.in_flight if m[0] > now + 1e-9]
        if self.compiled_clocks:  # the same in one compiled call (``sync.hold_jit``)
            for batch in due[:-1]:
                clocks = formation_receive(clocks, *batch)
            sent, stamp, shown, holds, position, pace = due[-1] if due else self.no_message
            *ticked, rates = kernel("sync.hold_jit").receive_and_tick(
                clocks.show_time, clocks.updated, clocks.stamp, clocks.sent_show_time,
                clocks.holds, clocks.position, clocks.pace, bool(due), sent, stamp, shown,
                holds, position, pace, float(now), self.holding, self.pacing,
                self.hold_params.heartbeat_timeout, ADVANCE_MIN)
            self.clocks = FormationClocks(*ticked)
        else:
            before, since = clocks.show_time, clocks.updated  # (hearing leaves them)
            for batch in due:
                clocks = formation_receive(clocks, *batch)
            self.clocks = formation_tick(clocks, now, self.holding,  # each one's last tick
                                         pace=self.pacing)
            rates = (clock_rate(self.clocks.show_time - before, now - since) if self.paced
                     else self.rates)
        self.show_times[:] = self.clocks.show_time
        if self.paced:  # how fast each clock ran since its last tick
            self.rates[:] = rates

    def _mates_heard(self) -> list[np.ndarray | None]:
        """Per robot, (K, 2) where its mates said they stand (show frame), from the latest
        message of each (None without the shared clock)."""
        if not self.together:
            return [None] * len(self.robots)
        said = np.any(~np.isnan(self.clocks.position), axis=1)
        heard = self.clocks.position[said]
        senders = np.flatnonzero(said).tolist()
        rows = np.arange(len(heard))
        return [heard[rows != senders.index(robot)] if robot in senders else heard
                for robot in range(len(self.robots))]  # without its own echo

    def _tell(self, now: float, own: np.ndarray, known: np.ndarray) -> None:
        """Every robot tells the others its show time, whether it holds the show and where it
        stands (``own`` (R, >= 2): in its own map frame, as its brain got it, where ``known``
        (R,); elsewhere a failed look-up: it does not say)."""
        if not self.together:
            return
        count = len(self.robots)
        lost = self.message_rng.random(count) < self.loss if self.loss > 0 else (
            np.zeros(count, dtype=bool))
        own = own[:, :2]
        # where each stands in the show frame (``RobotBrain.show_position``, all at once)
        position = (kernel("sim.stage_jit").compose_turned(
            self.show_frames, *self._show_frame_turns, np.ascontiguousarray(own))
            if self.compiled_clocks else compose_points(self.show_frames, own,
                                                        self._show_frame_turns))
        if np.count_nonzero(known) < len(known):
            position[~known] = np.nan
        self.in_flight.append((now + self.delay, (
            ~lost, np.full(count, now), self.show_times.copy(), self.holding.copy(),
            position, self.pacing.copy())))

    def step(self, now: float) -> Tick:
        stage = self.stage
        arrived = stage.deliveries(now)
        own = stage.own_poses()
        self._show_times(now)
        for i, start in self.lidar_faults.items():
            if now >= start:
                arrived[i] = None
        known = self.all_known if not self.pose_faults else np.array(
            [now < self.pose_faults.get(i, math.inf) for i in range(len(self.robots))])
        believed = self.show_times + self.offsets  # each robot's clock (network experiment)
        if self.batch is not None:
            override = self.shared.references(now) if self.shared is not None else None
            self._batch_step(now, believed, arrived, own, known, override)
        else:
            self._brains_step(now, believed, arrived, own, known)
        if self.shared is not None:
            self.shared.send(now)
        self._tell(now, own, known)
        stage.speaking = self.asking.copy()  # the crowd hears them (sim/crowd.py)
        record = {"poses": stage.pose, "velocities": stage.velocity,
                  "commands": self.command, "status": self.status,
                  "spectators": stage.discs[:, :2], "show_times": self.show_times,
                  # (paced: a robot that slows the clock holds it in part)
                  "holds": self.holding | (self.pacing < 1.0) if self.paced else self.holding}
        if stage.physics is not None:  # the yaw rate the wheels would give: the slip
            record["wheel_rates"] = stage.physics.wheel_rates()
        return Tick(self.command, record, float(self.show_times.min()),
                    bool(np.count_nonzero(self.waiting)))

    def _batch_step(self, now: float, show_times: np.ndarray, arrived: list[PointCloud | None],
                    own: np.ndarray, known: np.ndarray,
                    override: np.ndarray | None = None) -> None:
        """Every brain's tick in one compiled pass (``robot_batch.BatchBrains``)."""
        assert self.batch is not None
        tick = self.batch.step(now, show_times, own, known, arrived,
                               self.clocks.position if self.together else None, override,
                               self.rates if self.paced else None)
        self.command[:] = tick.commands
        self.status[:] = tick.status
        self.holding[:] = tick.holding
        self.asking[:] = tick.asking
        self.waiting[:] = tick.waiting
        self.pacing[:] = tick.pace
        self.events.extend(RobotEvent(round(now, 6), self.robots[i], e.kind, e.text)
                           for i, e in tick.events)

    def _brains_step(self, now: float, show_times: np.ndarray,
                     arrived: list[PointCloud | None], own: np.ndarray,
                     known: np.ndarray) -> None:
        """Each brain's tick in turn (``RobotBrain.step``, the reference)."""
        states = self.states
        own_poses = own.tolist()
        heard = self._mates_heard()
        for i, brain in enumerate(self.brains):
            seen = (own_poses[i][0], own_poses[i][1], own_poses[i][2]) if known[i] else None
            states[i], cmd, happened = brain.step(states[i], float(show_times[i]), seen,
                                                  arrived[i], clock=now,
                                                  mates_heard=heard[i],
                                                  rate=float(self.rates[i]))
            self.command[i] = (cmd.linear, cmd.angular)
            self.status[i] = STATUS.index(states[i].status)
            self.holding[i] = states[i].holding_the_show
            self.asking[i] = states[i].asks_for_room
            self.waiting[i] = states[i].waiting
            self.pacing[i] = states[i].pace
            if happened:
                self.events.extend(RobotEvent(round(now, 6), self.robots[i], e.kind, e.text)
                                   for e in happened)


class _SharedPose:
    """The ``shared-pose`` formation control (``SimConfig.formation_control``): robot 0
    broadcasts its pose and velocity at every control tick, stamped with its clock; the
    messages reach the others ``hold_delay`` s later unless lost (``hold_loss``, a generator
    of its own); every other robot tracks its slot relative to robot 0's slot, placed on
    robot 0's latest pose heard, extrapolated along its arc by the velocity it sent over the
    message's age on the receiver's clock (so a clock offset misplaces it)."""

    def __init__(self, plan: Plan, stage: Stage, offsets: FloatArray,
                 config: SimConfig) -> None:
        if len(plan.formations) != 1:
            raise ValueError("the shared-pose formation control takes a show of one "
                             "formation")
        formation = plan.formations[0]
        robots = plan.robots
        leader = np.array(formation.offsets[robots[0]])
        # each robot's slot in robot 0's slot frame (the slots share the leader's heading)
        self.relative = np.array([np.array(formation.offsets[r]) - leader for r in robots])
        self.stage, self.offsets = stage, offsets
        self.delay, self.loss = config.hold_delay, config.hold_loss
        self.rng = np.random.default_rng([config.seed, 7_919])
        self.in_flight: list[tuple[float, float, FloatArray, FloatArray]] = []
        self.heard: tuple[float, FloatArray, FloatArray] | None = None  # stamp, pose, (v, w)

    def send(self, now: float) -> None:
        """Robot 0's message of this tick: its clock, world pose and velocity."""
        if self.loss > 0 and self.rng.random() < self.loss:
            return
        self.in_flight.append((now + self.delay, now + float(self.offsets[0]),
                               self.stage.pose[0].copy(), self.stage.velocity[0].copy()))

    def references(self, now: float) -> FloatArray:
        """The references (R, 5) each robot tracks in its own frame (NaN rows: its plan's,
        robot 0's and all before the first message)."""
        due = [m for m in self.in_flight if m[0] <= now + 1e-9]
        self.in_flight = [m for m in self.in_flight if m[0] > now + 1e-9]
        for _, stamp, pose, velocity in due:
            if self.heard is None or stamp > self.heard[0]:
                self.heard = (stamp, pose, velocity)
        count = len(self.relative)
        rows = np.full((count, 5), np.nan)
        if self.heard is None or count < 2:
            return rows
        stamp, pose, velocity = self.heard
        ages = np.maximum(now + self.offsets[1:] - stamp, 0.0)  # (R - 1,) on each clock
        slots = shared_pose_references(pose, velocity, ages, self.relative[1:])
        rows[1:] = slots
        rows[1:, :3] = compose_poses(self.stage.to_own[1:], slots[:, :3])
        return rows


def _corners(poses: FloatArray, lengths: FloatArray | float,
             widths: FloatArray | float) -> FloatArray:
    """Footprint corners (R, 4, 2) of robots at poses (R, 3) with sizes (R,) or scalars."""
    return footprint_corners(poses[..., 0], poses[..., 1], poses[..., 2], lengths, widths)


def smallest_gap(poses: FloatArray, lengths: FloatArray, widths: FloatArray) -> float | None:
    """The smallest gap between any two robots' footprints over all ticks, m.

    poses (R, T, 3); lengths, widths (R,). Pairs whose centres are more than a metre beyond
    touching are skipped; None for fewer than two robots, inf when no pair ever comes near.
    """
    count = poses.shape[0]
    if count < 2:
        return None
    if poses.shape[1] == 0:
        return math.inf
    reach = 0.5 * np.hypot(lengths, widths)
    pairs = list(zip(*(a.tolist() for a in np.triu_indices(count, k=1)), strict=True))

    def bound(i: int, j: int) -> FloatArray:
        """A lower bound (T,) of the pair's gap at every tick: centre distance less both
        reaches."""
        centre = np.hypot(poses[i, :, 0] - poses[j, :, 0], poses[i, :, 1] - poses[j, :, 1])
        lower: FloatArray = centre - reach[i] - reach[j]
        return lower

    # the pairs are measured nearest first, each only at the ticks whose bound beats the
    # smallest gap found so far: the same answer as measuring every near tick, in less time
    nearest = [float(np.nanmin(bound(i, j), initial=math.inf)) for i, j in pairs]
    best = math.inf
    for n in np.argsort(nearest, kind="stable"):
        if nearest[n] >= min(best, 1.0):
            break
        i, j = pairs[n]
        near = np.flatnonzero(bound(i, j) < min(best, 1.0))
        if near.size == 0:
            continue
        first = shapely.polygons(_corners(poses[i, near], lengths[i], widths[i]))
        second = shapely.polygons(_corners(poses[j, near], lengths[j], widths[j]))
        best = min(best, float(shapely.distance(first, second).min()))
    return best


def _result(plan: Plan, arena: Arena, placement: Placement, config: SimConfig,
            recorder: Recorder,
            brains: list[RobotBrain], collisions: tuple[CollisionEvent, ...],
            events: tuple[RobotEvent, ...],
            scans: tuple[tuple[float, tuple[FloatArray, ...]], ...],
            spectator_radii: FloatArray) -> RunResult:
    times = recorder.times
    poses = recorder.series("poses")
    velocities = recorder.series("velocities")
    commands = recorder.series("commands")
    status = recorder.series("status")
    spectators = recorder.series("spectators")
    show_times = recorder.series("show_times")  # (R, T)
    slots = [brain.slot0 for brain in brains]
    desired, leader, required, formation, reference = [], [], [], [], []
    final_slots, formation_places = [], []
    for i, robot in enumerate(placement.robots):
        final_slots.append(_to_world(placement.starts, slots, plan.track(
            robot, np.array([plan.duration])).desired, i)[0])
        track = plan.track(robot, show_times[i])
        desired.append(_to_world(placement.starts, slots, track.desired, i))
        leader.append(_to_world(placement.starts, slots, track.leader, i))
        required.append(track.required_distance)
        formation.append(track.formation)
        frame = _to_world(placement.starts, slots, np.zeros((1, 3)), i)[0]
        if brains[i].follower == "thesis":
            rows = follower_references(plan, robot, show_times[i], config.brain.follower)
            rows[:, :2] = compose_points(frame, rows[:, :2])
            rows[:, 2] += frame[2]
        else:  # what the brain tracked, from its own frame (start = frame o slot0)
            rows = brains[i].references_at(show_times[i])
            start = placement.starts[i]
            rows[:, :2] = compose_points(start, rows[:, :2])
            rows[:, 2] += start[2]
        # where the shared clock stood, the place stood: no speed (as the brain saw it)
        rows[1:, 3:][np.diff(show_times[i]) <= ADVANCE_MIN] = 0.0
        reference.append(rows)
        if config.brain.follower == "tracking":
            formation_places.append(desired[-1][:, :2])
        else:
            formation_places.append(compose_points(frame, path_places(
                plan, robot, show_times[i], wait_behind=False)[0]))
    return RunResult(plan, arena, placement, config, times, poses, velocities, commands,
                     np.stack(desired), np.stack(leader), np.stack(required),
                     np.stack(formation), collisions,
                     smallest_gap(poses, np.array([t.length for t in placement.types]),
                                  np.array([t.width for t in placement.types])),
                     status, events, spectators,
                     spectator_radii, np.stack(reference), scans, show_times,
                     recorder.series("holds"), np.stack(final_slots),
                     np.stack(formation_places),
                     recorder.series("wheel_rates") if "wheel_rates" in recorder else None)
