"""RobotBrain: everything one robot decides each control tick, as pure code.

A brain knows the plan, its role, its footprint and its strategies. Each tick it gets the show
time, its pose in its *own* ``map`` frame (None when the pose look-up failed) and the LIDAR
cloud that arrived (if any), and returns a command (v, w) and events. Per tick: obstacle
points from the latest cloud (thesis 5.2, moved by the robot's own motion since the cloud's
stamp with the ``compensated`` detector), stop flags, the virtual force, the follower
(eq. 4.4), the stop flags applied to its command, then the safety state machine (thesis 5).
It computes
its virtual leader in its own frame from the plan, assuming it started on its slot of the
first formation (thesis ch. 4.2: there is no shared frame between robots): a show-frame pose
P is ``slot0^-1 ⊕ P`` in the robot's map frame.
"""

from __future__ import annotations

import bisect
import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Literal, get_args

import numpy as np

from dancebots.control.follower import (
    FollowerParams,
    FollowerState,
    ForceSteering,
    thesis_follower_step,
)
from dancebots.control.tracking import (
    FOR_GOOD,
    REFERENCE_TURN,
    SlotReference,
    TrackingParams,
    fold_reference,
    follower_places,
    follower_references,
    place_stand,
    references_from_motion,
    settling_on_slot,
    stand_ends,
    tracking_step,
)
from dancebots.geometry import Pose, compose_points, points_to_local, points_to_world, wrap_angle
from dancebots.perception.closing import ClosingParams, closing_speeds, sector_gaps, too_near
from dancebots.perception.cloud import PointCloud
from dancebots.perception.obstacles import (
    CLEAR,
    DetectorParams,
    Perception,
    StopFlags,
    clear_distances,
    compensate_motion,
    footprint_clearance,
    near_any,
    obstacle_points_from_columns,
    obstacle_points_now,
    perceive,
    predicted_points,
    turn_fraction,
    turn_reach,
)
from dancebots.perception.ssm import SsmParams, ssm_speed_limit, turn_allowed
from dancebots.plan.places import path_places, places_end
from dancebots.plan.planner import Plan, RobotTrack
from dancebots.safety.monitor import Event, SafetyParams, SafetyState, safety_step
from dancebots.sync.hold import ADVANCE_MIN
from dancebots.world import RobotType

if TYPE_CHECKING:  # SSM's tracker (SciPy) is imported where the ssm stop rule runs
    from dancebots.perception.tracks import ObstacleTracks, TrackParams

__all__ = ["DETECTORS", "FOLLOWERS", "STOP_RULES", "BrainOptions", "BrainState", "Command",
           "Detector", "Follower", "RobotBrain", "SensingConfig", "StopRule", "brain_for",
           "default_stop_rule", "predicted_stop_distance", "turns_on_the_spot"]

Follower = Literal["tracking", "path", "thesis"]
FOLLOWERS: tuple[Follower, ...] = get_args(Follower)
"""Followers: ``thesis`` (default): eq. 4.4 as written (``control/follower.py``);
``tracking`` (an addition: feedforward of the rigid slot's motion from the plan plus
Kanayama's tracking law, ``control/tracking.py``); ``path`` (an addition: the same law on
the robot's place on its leader's path, ``control.tracking.path_references``)."""

StopRule = Literal["fixed", "closing", "ssm", "predicted"]
STOP_RULES: tuple[StopRule, ...] = get_args(StopRule)
"""When a robot stops for what it sees: ``fixed`` (thesis 5.2): a point within 0.55 m ahead
of the front (behind the rear) in the corridor the robot sweeps stops it driving that way,
and the approach limit slows it before; ``closing`` (an addition): ``fixed``, and the robot
stands while a stranger approaches it faster than it could stop (its approach measured
between scans, S_p of ISO/TS 15066: ``perception.closing``); ``ssm`` (an addition, ISO/TS
15066's speed and separation monitoring: ``perception.ssm``): its speed is limited so that
it can stop before any point, approaching at its tracked speed (``perception.tracks``) or at
walking speed, comes nearer than a margin to the area it sweeps until it stands;
``predicted`` (an addition): ``fixed`` on the points as they will be: each point of a tracked
person (``perception.tracks``) moved on at its velocity for the data's age (the LIDAR's
latency and the time since the scan), so that a person who walks into the corridor while the
cloud is on its way stops the robot too (the compensated detector moves the points by the
robot's own motion only), within the stop distance plus the robot's own way until it stands
(:func:`predicted_stop_distance`); formation mates where they should be or said they are
are not tracked. The default (:func:`default_stop_rule`): ``predicted``, ``fixed`` with the
thesis's follower."""


def turns_on_the_spot(linear: float, angular: float, width: float) -> bool:
    """Whether a command (m/s, rad/s) turns a robot ``width`` m wide about a point within its
    footprint (|v / w| at most half the width): its corners sweep out at its sides, where a
    mate beside it may sweep its own (open-day crowd seed 293: two robots side by side both
    turned on the spot when the show resumed, and touched), so its turn guard leaves such a
    mate its share of the gap (``DetectorParams.turn_share``). Driving an arc, the robot
    moves on into the way ahead, which the stop zones and the formation's plan keep free."""
    return angular != 0.0 and abs(linear) <= abs(angular) * 0.5 * width


def default_stop_rule(follower: str, stop_rule: str | None = None) -> StopRule:
    """The stop rule a brain runs: ``stop_rule`` when given, else ``predicted`` (0 contacts
    of a moving robot among 1,000 open-day crowds and 200 crowds of runners, where the
    thesis's ``fixed`` touched a runner: docs/safety.md), and ``fixed`` for the ``thesis``
    follower, which reproduces the thesis as written."""
    if stop_rule:
        if stop_rule not in STOP_RULES:
            raise ValueError(f"unknown stop rule {stop_rule!r}; choose from "
                             f"{', '.join(STOP_RULES)}")
        return stop_rule
    return "fixed" if follower == "thesis" else "predicted"

Detector = Literal["thesis", "compensated"]
DETECTORS: tuple[Detector, ...] = get_args(Detector)
"""Obstacle detectors: ``thesis`` uses the latest cloud as if it were current (ch. 5.2);
``compensated`` moves its points by the robot's own motion since the cloud's stamp."""
FORCE_GAIN = 0.02
"""Gain of each obstacle point's push (see ``control.force_field.repulsive_force``)."""
MATE_GAP = 0.1
"""m beyond the stop distance at which a robot following a formation mate on its place stops
keeping its reference's speed (:meth:`RobotBrain._approach_limit`)."""
MATE_MARGIN = 0.3
"""m: LIDAR points within the robot's own half diagonal plus this of where a formation mate
should be are left out of the tracking and path followers' force field."""
MATE_BODY_MARGIN = 0.1
"""m: while a robot hears every formation mate say where it is (``sync.hold``), a LIDAR
point more than the largest mate's half diagonal (``SensingConfig.mate_reach``) plus this
from each of them is no mate's body, however near it lies to where a mate should be: the
rule that keeps a robot from turning with a stranger within the circle its footprint
sweeps, and the hold for a person on or in its footprint, judge such points as strangers
(points this near where a mate should be stay the mate's too: a mate whose message is late
is on its place).
The mates' wider discs (:data:`MATE_MARGIN` of their places, for a mate off its place) hid a
child squeezing between R1 and R2, 8 cm from R1's side: R1 drove on turning at 0.43 rad/s
and its side swept into the child (open-day crowd seed 138 of 94d2cb6, t = 92.7 s). The
margin covers a message's tick of age at the robots' speeds."""
OVERLAP = 0.01
"""m: an obstacle point nearer than this to the footprint (on or in it) holds the robot still,
neither driving nor turning (a person standing in its footprint); so does, under the
``predicted`` stop rule, a tracked stranger's point predicted this near (by now, or by the
time a stop took effect: ``PREDICTED_STOP_TIME``)."""
HOLD_LAG = 0.05
"""m: a robot this far from its place that a stranger (a point that is no mate on its place)
slows (the approach limit to it) or keeps from turning (the turn guard, with the stranger
within the turn's reach) holds the formation's shared show clock, as a held robot does
(``sync.hold``): the formation waits instead of leaving it behind."""
PAUSE_STILL = 0.15
"""m: once the formation's shared show clock has stood :data:`PAUSE_STILL_AFTER`
(``sync.hold``), a robot of the tracking and path followers this near its place stands still
instead of driving onto it, unless it held or paced the show itself at its last tick (the
robot the formation waits for keeps closing on its place, or the clock would creep on
without it): the drive to a point a few centimetres to its side turned it by up to 90 deg
and back, corners swinging beside the people the formation waits for, and its place moves
on from where it is when the show resumes (the tracking law closes the gap on the way)."""
PAUSE_STILL_AFTER = 0.3
"""s the robot must have seen the shared show clock stand (from the first tick at which its
show time did not advance, by its clock: with no clock given to ``RobotBrain.step`` the
show time stands too, and the rule never acts) before :data:`PAUSE_STILL` acts: a clock that
stands a tick or two and runs on (a hold let go at once) would otherwise stop robots that
drive on their places at every such tick, stop and go at 5 Hz (open-day crowd seeds 0-4:
556 stop-go ticks against 211 without the rule)."""
PREDICTED_STOP_TIME = 0.3
"""s: the ``predicted`` rule also moves a tracked stranger on for this beyond the data's
age, the time a robot told to stop still moves (a tick and its drive's lag; ISO 13855's
stopping time): a child running at 1.7 m/s at a robot driving to its final slot came within
its corridor in the data only when the robot could no longer stop short of it (open-day
crowd seed 668 of a variant that kept robots near their places still while the show
waited)."""
SLOWED = 0.02
"""m/s or rad/s by which a command must be cut to count as slowed (:data:`HOLD_LAG`)."""
GIVE_WAY_SPEED = 0.05
"""m/s: the fastest a robot drives while no part of the turn it should make is allowed and
what blocks it is beside its leading half (an addition; ``RobotBrain._guard_turn``): a robot
that would cut into a neighbour's lane lets it go first instead of driving on beside it,
neither able to turn (thesis listing 7.4's split), and still creeps past what stands."""
PARKED_GAP = 0.1
"""m: after the show (every reference stands on its final slot) a formation mate on its
final place stands for good: a robot parks up to this near it instead of the stop distance
(an addition: listing 7.4 puts R1's final slot 0.27 m from R2's tail, inside the 0.55 m
that held R1 short of it); strangers keep the stop distance."""
MAKE_ROOM_SPEED = 0.15
"""m/s: how fast a robot drives straight to make room for a turn it may not make where it
stands (an addition; ``RobotBrain._make_room``)."""
FINAL_NO_ROOM = 0.15
"""m: a robot this near its final slot does not make room for the turn onto it (the turn is a
correction of centimetres; making room drove it off the slot and back, for good)."""
MAKE_ROOM_FLOOR = 0.05
"""m: a robot makes room only while nothing is nearer than this to its footprint: each of
two robots making room side by side at once takes the other for standing, and if they are
not parallel they converge (the open-day certification, seed 75: R1 and R2 drove into each
other at 0.15 m/s at the join, the formation waiting)."""
MAKE_ROOM_SHIFTS = (0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6)
"""m: the straight shifts, forwards and backwards, that ``RobotBrain._make_room`` tries, the
nearest first: up to a little more than a SIM robot's length (1.2 m) beside a neighbour."""
NEAR_GAP = 1.0
"""m: with a stranger (a point that is no mate on its place: a person, a wall) this near its
footprint, a robot of the tracking and path followers under the ``fixed`` stop rule turns
at most so fast that its corners swing at :data:`CORNER_SPEED` about its centre, slowing
along the arc it was on by as much (else within the stop rule's speed; an addition: a
child who runs up at 2 m/s covers this in the half second a robot needs to see it and stop
its turn; at full turn rate a corner swings at 1-2 m/s: the open-day certification's
contacts), and
after the show (every place on its final slot: ``rest_from``, the path follower's rear
places a few seconds after the plan's end) it does not move at all: it goes to its final
slot once no
stranger is this near, or :data:`AFTER_SHOW_WAIT` after one came near (a child running round
a parking robot met it backing up). A robot held for a stranger does not turn while one is
this near (it stands)."""
CORNER_SPEED = 0.25
"""m/s: the fastest a robot's corners swing about its centre as it turns with a stranger
within :data:`NEAR_GAP` (ISO 10218-1's reduced speed for working beside people, 250 mm/s)."""
PACE_MARGIN = 0.9
"""Under the ``paced`` hold strategy (``sync.hold``) a robot that a stranger slows and leaves
behind its place says it can follow this share of what it drives of the plan's speeds (room
for it to catch up): :func:`_pace_left`."""
PACE_MIN = 0.2
"""A robot that drives less than this share of the plan's speeds holds the show instead of
pacing it (a crawl looks like a stop to the audience, and a robot creeping towards its stop
distance on its approach limit would let the clock creep on while it stands)."""


def predicted_stop_distance(stop_distance: float, speed: float, deceleration: float) -> float:
    """m: a tracked stranger's predicted point (moved on for the data's age and
    :data:`PREDICTED_STOP_TIME`) nearer than this ahead (behind) in its corridor stops a
    robot that would drive ``speed`` m/s (either sign) and brakes at ``deceleration``
    m/s^2 under the ``predicted`` rule: the stop distance (thesis 5.2's 0.55 m) plus the
    robot's own way until it stands, |v| T + v^2 / 2a (T: a tick and the drive's lag, in
    which it drives on; the robot's terms of ISO/TS 15066's S_p,
    ``perception.ssm.protective_distance``).
    The person's way while the robot brakes (v_h v / a) is not added: ``ssm`` counts it and
    stalls crowded shows. Before, the person was moved on and the robot was not: a child ran
    head-on at 1.8-2.0 m/s at R2 driving at 0.39 m/s; R2 stopped when the child's predicted
    point came within 0.55 m and moved at 0.12 m/s a tick before they met (closing at
    0.08 m/s; dense open-day crowd seed 223 of 62d78ab, t = 58.6 s)."""
    return stop_distance + abs(speed) * PREDICTED_STOP_TIME + speed * speed / (
        2.0 * deceleration)


def _pace_left(linear: float, angular: float, speed: float, angular_speed: float,
               wanted_linear: float, wanted_angular: float) -> float:
    """The pace (0 to :data:`PACE_MARGIN`) a robot slowed to ``linear`` m/s and ``angular``
    rad/s can follow of a plan that asks ``speed`` and ``angular_speed`` there at the full
    pace: the smaller share of the two, times :data:`PACE_MARGIN`. Where the plan asks no
    speed (a place that stands) the share is of what its follower wanted (``wanted_linear``,
    ``wanted_angular``: a robot kept from closing on a standing place drives nothing of it),
    1 where neither asks any."""
    share = 1.0
    for got, planned, wanted in ((linear, speed, wanted_linear),
                                 (angular, angular_speed, wanted_angular)):
        asked = planned if planned != 0.0 else wanted
        if asked != 0.0:
            share = min(share, abs(got) / abs(asked))
    return PACE_MARGIN * share


AFTER_SHOW_WAIT = 10.0
"""s: the longest a robot waits after the show for strangers within :data:`NEAR_GAP` to
leave before it goes to its final slot anyway (with the corner cap and the stop flags): a
wall or a person who stays must not hold it for good."""
SLOW_TURN_LAG = 0.3
"""m: a robot this far from its place whose turn :data:`CORNER_SPEED` slows holds the
formation's shared show clock (``sync.hold``), so that its mates do not drive on into the
corners it still swings."""
SETTLE_LAGS = 2.0
"""Actuator lags the ``closing`` rule adds to the data's age: a robot whose speed follows its
command with a first-order lag still moves for about two lags after it is told to stop, in
which a person comes on (``ssm`` counts the same)."""
HISTORY_LENGTH = 15
"""Own poses kept for the lag compensation (1.5 s at 10 Hz: five times the thesis's lag)."""


@dataclass(frozen=True, slots=True)
class Command:
    """A velocity command in ``base_link``: linear m/s, angular rad/s."""

    linear: float
    angular: float


STOP = Command(0.0, 0.0)


@dataclass(frozen=True, slots=True)
class SensingConfig:
    """The robot's footprint (m), whether it has a LIDAR (without one: no obstacle detection,
    no sensor-age check), its detector, the force field's reach (m, 0: off), the approach
    gain (1/s, 0: off), whether to use the compiled perception (else the NumPy reference;
    same results), the detection and safety parameters, the stop rule (:data:`STOP_RULES`)
    and, for ``ssm``, its parameters and its tracker's (None: ``TrackParams()``; ``predicted``
    tracks too, and brakes at ``ssm.deceleration``: :func:`predicted_stop_distance`);
    ``mate_reach``: the largest half diagonal of a formation mate, m (None: the robot's own),
    for :data:`MATE_BODY_MARGIN`.

    Approach limit (an addition): the speed towards an obstacle in the robot's corridor is at
    most approach_gain * (free distance - stop distance), so a robot closes up to the stop
    distance smoothly instead of driving into the stop zone and being held there again and
    again (a robot behind another in a formation that shrinks in a turn); the stop flags
    remain for what appears suddenly (a spectator stepping in). Turn guard (an addition): a
    robot does not swing a corner into an obstacle (``RobotBrain._guard_turn``).
    """

    length: float = 1.2
    width: float = 0.6
    lidar: bool = True
    detector: Detector = "compensated"
    force_radius: float = 1.0
    approach_gain: float = 1.0
    compiled: bool = True
    detection: DetectorParams = field(default_factory=DetectorParams)
    safety: SafetyParams = field(default_factory=SafetyParams)
    stop_rule: StopRule = "fixed"
    ssm: SsmParams = field(default_factory=SsmParams)
    closing: ClosingParams = field(default_factory=ClosingParams)
    tracks: TrackParams | None = None
    mate_reach: float | None = None


@dataclass(frozen=True, slots=True, eq=False)
class BrainState:
    """What a brain carries from one tick to the next: the follower's queue, the safety
    state, the latest cloud's columns (K, 4) in ``base_link`` at the pose ``seen_from`` (own
    map frame) with their height step, and the recent own poses (t, x, y, theta); after the
    show, since when (its clock, s) a stranger is within :data:`NEAR_GAP` and whether it
    waits for it to leave (``waiting``); with the ``closing`` stop rule, the stamp (s) and
    the strangers' points (N, 2) in the own map frame of the latest cloud it could use
    (``strangers_seen``), and what they gave (``closing``: that stamp, each bearing sector's
    gap (S,) m, moved to the pose at that cloud, and how fast it closed since the cloud
    before (S,) m/s); the robot's clock (s) at the first tick at which its show time had
    not advanced (``paused_since``, None while it advances); whether it settles on its final
    slot (``settling``, :func:`control.tracking.settling_on_slot`)."""

    follower: FollowerState = field(default_factory=FollowerState)
    safety: SafetyState = field(default_factory=SafetyState)
    obstacles: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    height_step: float = 0.1
    seen_from: tuple[float, float, float] | None = None
    history: tuple[tuple[float, float, float, float], ...] = ()
    held: bool = False
    holds_show: bool = False
    show_time: float | None = None
    tracks: ObstacleTracks | None = None
    point_velocity: np.ndarray | None = None
    point_kind: np.ndarray | None = None
    cloud_stamp: float | None = None
    making_room: float = 0.0
    stranger_near_since: float | None = None
    waiting: bool = False
    strangers_seen: tuple[float, np.ndarray] | None = None
    closing: tuple[float, np.ndarray, np.ndarray] | None = None
    pace: float = 1.0
    paused_since: float | None = None
    settling: bool = False

    @property
    def holding_the_show(self) -> bool:
        """Whether this robot holds the formation's shared show clock (``sync.hold``): held
        by something that is not a formation mate on its place, or in its error state."""
        return self.holds_show or self.safety.error is not None

    @property
    def asks_for_room(self) -> bool:
        """Whether it stands held by people and speaks (thesis 5.2's stop sentence and beeps):
        people near it hear that they should make room (``sim.crowd``)."""
        return self.holds_show and self.status == "stopped"

    @property
    def status(self) -> str:
        """"error", "stopped" (held by a stop flag) or "ok"."""
        if self.safety.error is not None:
            return "error"
        return "stopped" if self.safety.stopped_since is not None else "ok"


@dataclass(frozen=True, slots=True)
class _Sample:
    leader: tuple[float, float]
    path_point: tuple[float, float]
    desired: tuple[float, float]
    required: float
    moving: bool


class RobotBrain:
    """The decisions of one robot. Holds only immutable configuration; state is passed in.

    The plan's values are precomputed on the 10 Hz control grid (a cache: ticks off the grid
    are computed exactly from the plan), so a tick costs a few microseconds.
    """

    def __init__(self, plan: Plan, robot: str, params: FollowerParams,
                 grid_period: float = 0.1, sensing: SensingConfig | None = None,
                 follower: Follower = "thesis", feedforward_lead: float = 0.0,
                 paced: bool = False) -> None:
        self.sensing = sensing or SensingConfig(lidar=False)
        if self.sensing.detector not in DETECTORS:
            raise ValueError(f"unknown detector {self.sensing.detector!r}; choose from "
                             f"{', '.join(DETECTORS)}")
        if follower not in FOLLOWERS:
            raise ValueError(f"unknown follower {follower!r}; choose from "
                             f"{', '.join(FOLLOWERS)}")
        if self.sensing.stop_rule not in STOP_RULES:
            raise ValueError(f"unknown stop rule {self.sensing.stop_rule!r}; choose from "
                             f"{', '.join(STOP_RULES)}")
        self.plan = plan
        self.robot = robot
        self.params = params
        self.follower = follower
        self.feedforward_lead = feedforward_lead
        self.paced = paced and follower != "thesis"
        self.tracking = TrackingParams(max_linear=params.max_linear,
                                       max_angular=params.max_angular)
        slot = plan.desired_poses(robot, np.zeros(1))[0]
        self.slot0 = Pose(float(slot[0]), float(slot[1]), float(slot[2]))
        self._to_own = self.slot0.inverse()
        self.grid_period = grid_period
        grid = _grid_times(plan, grid_period)
        self.grid_end = float(grid[-1])
        self.rest_from = places_end(plan)  # s: from then on every reference stands for good
        # the cache of the follower in use only: (leader, path point, ...) or slot references
        self._grid = self._samples(plan.track(robot, grid)) if follower == "thesis" else []
        self._slot_grid = self._grid_slot_rows(grid_period) if follower != "thesis" else None
        # the same rows as Python floats (a row of them is read at every tick; made at the
        # first: the batched brains read the array)
        self._slot_list: list[list[float]] | None = None
        # where each row's stand ends (``control.tracking.stand_ends``; made at first use)
        self._stand_ends: np.ndarray | None = None
        # the other robots' places on the same grid (show frame), for the tracking and path
        # followers' force field, which ignores what a formation mate on its place explains
        self._mates: np.ndarray | None = None
        if follower != "thesis" and len(plan.robots) > 1:
            places = _places(plan, grid_period, follower)
            mates = np.delete(places, plan.robots.index(robot), axis=0)  # (M, T, 2)
            self._mates = compose_points(
                np.array([self._to_own.x, self._to_own.y, self._to_own.theta]), mates)
            self._mates.flags.writeable = False  # mates_at hands out views of it
        self.mate_radius = 0.5 * math.hypot(self.sensing.length, self.sensing.width) + MATE_MARGIN
        reach = self.sensing.mate_reach
        if reach is not None and not (math.isfinite(reach) and reach > 0.0):
            raise ValueError(f"a mate's half diagonal must be a finite length above 0 m, not "
                             f"{reach!r}")
        self.mate_body_radius = (0.5 * math.hypot(self.sensing.length, self.sensing.width)
                                 if reach is None else reach) + MATE_BODY_MARGIN
        # the rules for strangers (points that are no mate on its place) need the mates'
        # places: the tracking and path followers; the thesis follower, which knows none,
        # keeps thesis 5.2's rules as written
        self.knows_strangers = self._mates is not None or len(plan.robots) == 1
        self._own_frame = np.array([self._to_own.x, self._to_own.y, self._to_own.theta])
        # m: how far beyond its sides the footprint's corners swing as it turns on the spot
        # what SSM watches: the detector's heights in a wider square (``SsmParams.reach``)
        self._ssm_detection = replace(self.sensing.detection, crop_half=self.sensing.ssm.reach)
        self.sweep_reach = (0.5 * math.hypot(self.sensing.length, self.sensing.width)
                            - 0.5 * min(self.sensing.length, self.sensing.width))

    @property
    def show_frame(self) -> Pose:
        """The show frame's pose in the robot's own map frame (``slot0^-1``): the thesis's
        ``/role/vl_map`` frame, in which the virtual leader moves (ch. 4.1)."""
        return self._to_own

    def show_position(self, pose: tuple[float, float, float]) -> tuple[float, float]:
        """Where a robot at ``pose`` (its own map frame) stands in the show frame, m (what
        it tells its mates: ``sync.hold.HoldMessage.position``)."""
        x, y = points_to_world(np.array([pose[:2]]), self.slot0)[0]
        return float(x), float(y)

    def _grid_index(self, show_time: float, length: int) -> int | None:
        """The index on the 10 Hz grid (of ``length`` entries) of ``show_time`` s: the last
        entry after the plan's end, None off the grid."""
        if length == 0:
            return None
        if show_time >= self.grid_end:  # the references stand still after their end
            return length - 1
        k = round(show_time / self.grid_period)
        return k if 0 <= k < length and abs(k * self.grid_period - show_time) < 1e-9 else None

    def _samples(self, track: RobotTrack) -> list[_Sample]:
        own = self._to_own
        leader = points_to_world(track.leader[:, :2], own).tolist()
        lateral = points_to_world(track.lateral[:, :2], own).tolist()
        desired = points_to_world(track.desired[:, :2], own).tolist()
        moving = np.any(track.leader_commands != 0.0, axis=1)
        return [_Sample(tuple(a), tuple(p), tuple(e), r, m) for a, p, e, r, m in zip(
            leader, lateral, desired, track.required_distance.tolist(), moving.tolist(),
            strict=True)]

    def _slot_rows(self, times: np.ndarray) -> np.ndarray:
        """The references (T, 5) at show times (T,) in the robot's own frame
        (``follower_references``)."""
        return self._to_own_rows(follower_references(self.plan, self.robot, times,
                                                     self.follower, self.sensing.compiled))

    def _grid_slot_rows(self, grid_period: float) -> np.ndarray:
        """:meth:`_slot_rows` on the brains' grid; the path follower's from the places on
        the grid that every brain of the plan shares (``_grid_path_places``)."""
        if self.follower != "path":
            return self._slot_rows(_grid_times(self.plan, grid_period))
        points, heading, motion, speed = _grid_path_places(self.plan, grid_period)[
            self.plan.robots.index(self.robot)]
        return self._to_own_rows(references_from_motion(
            _grid_times(self.plan, grid_period), points, motion, speed, heading,
            compiled=self.sensing.compiled))

    def _to_own_rows(self, rows: np.ndarray) -> np.ndarray:
        """Reference rows (T, 5), show frame, moved to the robot's own frame, in place."""
        own = self._to_own
        rows[:, :2] = points_to_world(rows[:, :2], own)
        rows[:, 2] += own.theta
        return rows

    def slot_at(self, show_time: float) -> SlotReference:
        """The slot's reference at ``show_time`` s in the robot's own frame, for the tracking
        follower: from the 10 Hz grid; off it, its pose and speed computed exactly from the
        plan, folded to continue the grid's heading and with the grid's angular speed over
        that step (``fold_reference``); for a paced brain (``BrainOptions.paced``), whose
        clock runs off the grid, interpolated linearly between the grid's two ticks."""
        grid = self._slot_grid
        assert grid is not None, "slot_at serves the tracking follower"
        k = self._grid_index(show_time, len(grid))
        if k is not None:
            if self._slot_list is None:
                self._slot_list = grid.tolist()
            x, y, heading, speed, angular_speed = self._slot_list[k]
            return SlotReference((x, y, wrap_angle(heading)), speed, angular_speed,
                                 show_time >= self.rest_from)
        if self.paced and 0.0 <= show_time < self.grid_end and len(grid) >= 2:
            # a paced clock is mostly off the grid: between its two ticks, linearly (the
            # place moves at most a few cm a tick; the exact plan costs a millisecond)
            if self._slot_list is None:
                self._slot_list = grid.tolist()
            k = min(math.floor(show_time / self.grid_period), len(grid) - 2)
            start = k * self.grid_period  # (the grid's last step ends at grid_end)
            span = min((k + 1) * self.grid_period, self.grid_end) - start
            weight = min(max((show_time - start) / span, 0.0), 1.0) if span > 0.0 else 0.0
            a, b = self._slot_list[k], self._slot_list[k + 1]
            x, y, heading, speed, angular_speed = (
                (1.0 - weight) * p + weight * q for p, q in zip(a, b, strict=True))
            return SlotReference((x, y, wrap_angle(heading)), speed, angular_speed,
                                 show_time >= self.rest_from)
        before = grid[min(max(int(show_time / self.grid_period), 0), len(grid) - 1)]
        exact = self._slot_rows(np.array([min(max(show_time, 0.0), self.grid_end)]))[0]
        row = fold_reference(exact, float(before[2]))
        row[4] = before[4]
        return SlotReference((float(row[0]), float(row[1]), wrap_angle(float(row[2]))),
                             float(row[3]), float(row[4]), show_time >= self.rest_from)

    def references_at(self, show_times: np.ndarray) -> np.ndarray:
        """The slot references (T, 5) the tracking or path follower tracked at show times
        (T,) s, own frame (``slot_at``, without the feedforward lead): the grid's rows, and
        where a time falls off the grid (a paused shared clock), the row computed there
        (its heading wrapped)."""
        grid = self._slot_grid
        assert grid is not None, "references_at serves the tracking and path followers"
        times = np.asarray(show_times, dtype=float)
        length = len(grid)
        k = np.rint(times / self.grid_period)
        after = times >= self.grid_end
        on = after | ((np.abs(k * self.grid_period - times) < 1e-9) & (k >= 0) & (k < length))
        rows = grid[np.where(after, length - 1, np.clip(k, 0, length - 1)).astype(np.int64)]
        for i in np.flatnonzero(~on).tolist():
            exact = self.slot_at(float(times[i]))
            rows[i] = (*exact.pose, exact.speed, exact.angular_speed)
        return rows

    def _place_stand(self, show_time: float) -> float:
        """``control.tracking.place_stand`` of the place at ``show_time`` s: from the grid
        row of that time (the last from the grid's end on), or where a paced clock falls
        between two rows, the earlier; 0.0 before the show."""
        grid = self._slot_grid
        assert grid is not None, "serves the tracking and path followers"
        k = self._grid_index(show_time, len(grid))
        if k is None:
            if not 0.0 <= show_time < self.grid_end:
                return 0.0
            k = min(math.floor(show_time / self.grid_period), len(grid) - 1)
        if self._stand_ends is None:
            self._stand_ends = stand_ends(grid)
        return place_stand(grid, self._stand_ends, k, show_time, self.grid_period)

    def _reference(self, show_time: float) -> SlotReference:
        """What the tracking and path followers track at ``show_time`` s: the reference's
        pose then, its speeds ``feedforward_lead`` s later (interpolated on the grid: a robot
        whose speeds follow its commands with a first-order lag of time constant tau reaches
        a commanded speed about tau later, so the commands lead by tau)."""
        reference = self.slot_at(show_time)
        if self.feedforward_lead <= 0.0:
            return reference
        steps = (show_time + self.feedforward_lead) / self.grid_period
        first = math.floor(steps)
        weight = steps - first  # between the two grid ticks around the time ahead
        before = self.slot_at(first * self.grid_period)
        after = self.slot_at((first + 1) * self.grid_period)
        return SlotReference(
            reference.pose, (1.0 - weight) * before.speed + weight * after.speed,
            (1.0 - weight) * before.angular_speed + weight * after.angular_speed,
            reference.final)

    def _sample(self, show_time: float) -> _Sample:
        k = self._grid_index(show_time, len(self._grid))
        if k is not None:
            return self._grid[k]
        return self._samples(self.plan.track(
            self.robot, np.array([min(show_time, self.plan.duration)])))[0]

    def initial_state(self) -> BrainState:
        return BrainState()

    def step(self, state: BrainState, show_time: float,
             pose: tuple[float, float, float] | None, cloud: PointCloud | None = None,
             clock: float | None = None, mates_heard: np.ndarray | None = None,
             rate: float = 1.0) -> tuple[BrainState, Command, tuple[Event, ...]]:
        """One control tick: show time in s (negative before the start), pose (x, y, theta)
        in the robot's own map frame or None (a failed look-up), the cloud that arrived, and
        the robot's clock (s, the time base of the clouds' stamps; None: the show time, as
        when every robot's show time is its clock since the start), and where its mates said
        they are (``mates_heard`` (K, 2), show frame, m: the shared clock's messages), so that
        a mate off its place does not pass for a person.
        Returns the new state, the command and the events of this tick.

        A show time that did not advance since the last tick (the formation's shared clock
        paused: ``sync.hold``) stands the reference still: the robot stops on its place
        instead of driving on with the speeds the plan has there. A paced brain
        (``BrainOptions.paced``) follows its place at the clock's ``rate`` (the show time's
        advance over the clock's since the last tick, 0-1) and says the pace it can follow
        (``BrainState.pace``: where ``together`` would hold the show for being slowed and
        left behind, the share of the plan's speeds it drives, :func:`_pace_left`)."""
        now = show_time if clock is None else clock
        sensing = self.sensing
        if mates_heard is not None and len(mates_heard) and not np.isfinite(mates_heard).all():
            # a NaN place would hide everything
            mates_heard = mates_heard[np.isfinite(mates_heard).all(axis=1)]
        history = state.history
        obstacles, seen_from = state.obstacles, state.seen_from
        height_step = state.height_step
        if pose is not None and sensing.lidar and sensing.detector == "compensated":
            history = (*history[-HISTORY_LENGTH:], (now, *pose))
        tracks, point_velocity, point_kind = state.tracks, state.point_velocity, state.point_kind
        cloud_stamp = state.cloud_stamp
        strangers_seen, closing = state.strangers_seen, state.closing
        if cloud is not None and sensing.lidar:
            obstacles = cloud.columns  # filtered at every tick, with the pose of that tick
            height_step = cloud.height_step
            seen_from = self._pose_at(history, cloud.stamp) if (
                sensing.detector == "compensated") else None
            cloud_stamp = cloud.stamp
            taken_at = seen_from or pose
            if sensing.stop_rule in ("ssm", "predicted") and taken_at is not None:
                # the obstacles tracked in the own map frame (SSM needs their speeds)
                from dancebots.perception.tracks import ObstacleTracks, TrackParams, track_step

                points = points_to_world(obstacle_points_from_columns(
                    obstacles, height_step, self._ssm_detection), taken_at)
                tracks, point_velocity, point_kind = track_step(
                    sensing.tracks or TrackParams(), tracks or ObstacleTracks(), points,
                    cloud.stamp, sensing.compiled,
                    self._near_mates(points, show_time, mates_heard)
                    if sensing.stop_rule == "predicted" else None)
            if sensing.stop_rule == "closing" and taken_at is not None and pose is not None:
                strangers_seen, closing = self._closing(
                    strangers_seen, closing, obstacles, height_step, taken_at, pose,
                    show_time, cloud.stamp, mates_heard)
        command = STOP
        pace = 1.0
        full_speed = full_angular = 0.0
        held = holds_show = waiting = settling = False
        near_since: float | None = None  # after the show: since when a stranger is near
        stranger_limit: float | None = None  # m/s: SSM's speed limit for strangers alone
        paused = state.show_time is not None and show_time <= state.show_time + ADVANCE_MIN
        paused_since = ((now if state.paused_since is None else state.paused_since)
                        if paused else None)
        stood_for = 0.0 if paused_since is None else now - paused_since  # s the clock stood
        if pose is not None and show_time >= 0.0:
            seen = CLEAR
            strangers: Perception | None = None  # the points that are no mate on its place
            if sensing.lidar and len(obstacles):
                seen, strangers = self._perceive_all(obstacles, height_step, seen_from or pose,
                                                     pose, show_time)
                if strangers is not None:  # (the constructor: replace() costs 3 us a tick)
                    seen = Perception(seen.flags, seen.front_free, seen.rear_free,
                                      seen.nearest, strangers.force)
            reference_speed = 0.0
            behind = 0.0  # m from its place (the tracking and path followers)
            final = False  # its place stands on its final slot (the same)
            going: tuple[float, float] | None = None  # paused: what the show would ask
            if self.follower != "thesis":
                follower = state.follower
                reference = self._reference(show_time)
                way = 0.0 if reference.final else self._place_stand(show_time)
                if way == FOR_GOOD:  # its place never moves again: its final slot
                    reference = replace(reference, final=True)
                final = reference.final
                full_speed, full_angular = reference.speed, reference.angular_speed
                briefly = way in (1.0, -1.0) and not reference.moving  # stands a moment
                if paused and not reference.final:
                    going = tracking_step(self.tracking, pose, replace(
                        reference, paused=True, backwards=way < 0.0) if briefly else reference,
                        seen.force, state.settling)
                if paused:  # the shared show clock stopped: the place stands where it is
                    reference = replace(reference, speed=0.0, angular_speed=0.0, paused=True,
                                        backwards=reference.speed < 0.0)
                elif briefly and not final:
                    # it stands a moment on its path: as if the clock stood
                    reference = replace(reference, paused=True, backwards=way < 0.0)
                elif self.paced and rate < 1.0:  # the clock runs slow: so does the place
                    reference = replace(reference, speed=reference.speed * rate,
                                        angular_speed=reference.angular_speed * rate)
                reference_speed = abs(reference.speed)
                behind = math.hypot(reference.pose[0] - pose[0], reference.pose[1] - pose[1])
                if (going is not None and behind <= PAUSE_STILL
                        and stood_for >= PAUSE_STILL_AFTER - 1e-9
                        and not state.holds_show and state.pace >= 1.0):
                    linear, angular = 0.0, 0.0  # near its place it waits where it is
                else:
                    linear, angular = tracking_step(self.tracking, pose, reference,
                                                    seen.force, state.settling)
                settling = settling_on_slot(self.tracking, pose, reference, state.settling)
            else:
                sample = self._sample(show_time)
                follower, (linear, angular) = thesis_follower_step(
                    self.params, state.follower, show_time, pose, sample.leader,
                    sample.path_point, sample.desired, sample.required, sample.moving,
                    seen.force)
            wanted = linear, angular  # the follower's, before what it sees cuts them
            near = strangers if strangers is not None else seen
            if mates_heard is not None and len(mates_heard) and self._mates is not None and (
                    seen.flags.front or seen.flags.rear or behind > HOLD_LAG
                    or near.nearest < (NEAR_GAP if sensing.stop_rule != "ssm"
                                       else self.sweep_reach)):
                # (only where a rule below may use it:) a mate off its place, where it said
                # it is, is no stranger either
                near = self._without_mates(obstacles, height_step, seen_from or pose, pose,
                                           show_time, compose_points(self._own_frame,
                                                                     mates_heard)) or near
            knows_strangers = self.knows_strangers
            # after the show mates on their final places stand for good (PARKED_GAP)
            parked = show_time >= self.rest_from and knows_strangers
            flags = near.flags if parked else seen.flags
            # a stranger within NEAR_GAP: slow corners, and after the show a wait
            stranger_near = (sensing.stop_rule != "ssm" and knows_strangers
                             and near.nearest < NEAR_GAP)
            # (after the show: once every place stands on its final slot; from the plan's
            # end, a robot on its place waited for a person and held the shared clock while
            # the path follower's rear places still drove on: open-day crowd seed 648)
            if stranger_near and show_time >= self.rest_from:
                near_since = now if state.stranger_near_since is None else (
                    state.stranger_near_since)
            # ``predicted``: where the tracked strangers will be by now (m ahead, behind, from
            # the footprint; inf: none)
            predicted = (math.inf, math.inf, math.inf)
            # the stop rules that hold the show judge, while it stands, the motion it would
            # ask (``going``): judged on the standing place, a robot that held it let go at
            # the next tick, the show went on, it held again, stopping the formation and
            # speaking at 5 Hz (open-day crowd seed 0: 94 stop sentences). The ``predicted``
            # rule and the stop flags do (the kernel's rules); ``closing`` and ``ssm`` still
            # judge the robot's own command
            go_linear, go_angular = going if going is not None else (linear, angular)
            if (sensing.stop_rule == "predicted" and (go_linear != 0.0 or go_angular != 0.0)
                    and point_velocity is not None and point_kind is not None):
                predicted = self._predicted_gaps(
                    obstacles, height_step, seen_from or pose, pose, point_velocity,
                    point_kind, now - (cloud_stamp if cloud_stamp is not None else now),
                    show_time, mates_heard)
            # the nearest point that is no mate's body where every mate should be or said it
            # is (a stranger beside a mate, within its place's wider disc: MATE_BODY_MARGIN);
            # never farther than the strangers' nearest
            body_nearest = near.nearest
            if (knows_strangers and seen.nearest < self.sweep_reach
                    and near.nearest > seen.nearest and mates_heard is not None
                    and len(mates_heard) and self._mates is not None
                    and len(mates_heard) == len(self._mates)):
                body_nearest = min(near.nearest, self._nearest_beyond_mates(
                    obstacles, height_step, seen_from or pose, pose,
                    self._mate_centres(show_time, mates_heard), seen.nearest))
            if body_nearest <= OVERLAP and knows_strangers:
                # something that is no mate on its place on or in its footprint (a person who
                # stands in it: the stop zones ahead and behind do not see it): it stays
                # still until the person leaves (the thesis follower, which knows no mates'
                # places, would freeze beside a mate it touches: not for it)
                held = holds_show = True
                linear = angular = 0.0
            elif (predicted[2] <= OVERLAP and body_nearest < self.sweep_reach
                  and knows_strangers):
                # ``predicted``: a tracked stranger will be on its footprint by now or before
                # a stop took effect: it stands, neither driving nor turning, so that the
                # person meets a robot standing still (children crowd seed 17, t = 113.1 s: a
                # child walking up at 0.3-0.5 m/s, 0.10 m from R1's rear corner in a cloud
                # 0.3 s old, touched it as the clock ran on and R1 drove off)
                held = holds_show = True
                linear = angular = 0.0
            elif (near_since is not None and now - near_since < AFTER_SHOW_WAIT
                  and (linear != 0.0 or angular != 0.0)):
                # after the show nothing is late: a robot still parking waits, asking for
                # room, until no stranger is near (a child running round it), for a while
                held = holds_show = waiting = True
                linear = angular = 0.0
            elif (closing is not None and (linear != 0.0 or angular != 0.0)
                  and too_near(closing[1], closing[2], linear,
                               # the data's age, and the lags in which the speed dies away
                               now - closing[0] + SETTLE_LAGS * self.feedforward_lead,
                               sensing.ssm.reaction_time + self.feedforward_lead,
                               sensing.ssm.deceleration, sensing.closing)):
                # a stranger closes in faster than the robot could stop: it stands (neither
                # driving nor turning a corner out) and speaks until the approach ends
                held = holds_show = True
                linear = angular = 0.0
            elif sensing.stop_rule == "ssm":
                if point_velocity is not None and point_kind is not None:
                    limit, stranger_limit, may_turn = self._separation_limits(
                        obstacles, height_step, seen_from or pose, pose, show_time,
                        mates_heard, point_velocity, point_kind,
                        now - (cloud_stamp if cloud_stamp is not None else now), linear)
                    if limit < abs(linear):
                        if stranger_limit <= SLOWED < abs(linear):
                            held = holds_show = True  # a stranger: thesis 5.2's stop
                            limit = 0.0
                        linear = math.copysign(limit, linear)
                    if abs(linear) <= SLOWED and not may_turn:
                        # standing, it does not swing a corner out at a person walking up
                        linear = angular = 0.0
            elif (sensing.stop_rule == "predicted" and go_linear != 0.0
                  and (predicted[0] if go_linear > 0 else predicted[1])
                  < predicted_stop_distance(sensing.detection.stop_distance, go_linear,
                                            sensing.ssm.deceleration)):
                # a tracked person will be in the corridor by now: thesis 5.2's stop, on
                # where it will be (it holds the show: a person, not a mate on its place),
                # with the robot's own way until it stands (:func:`predicted_stop_distance`)
                held = holds_show = True
                linear = 0.0
            elif (flags.front and linear > 0) or (flags.rear and linear < 0):
                held = True  # thesis 5.2: the flags prevent moving that way
                # it holds the formation's show clock unless only a mate on its place holds it
                # (that mate moves on with the show; holding the clock for it would stall)
                holds_show = bool((near.flags.front and linear > 0)
                                  or (near.flags.rear and linear < 0))
                linear = 0.0
            elif going is not None and ((near.flags.front and go_linear > 0)
                                        or (near.flags.rear and go_linear < 0)):
                held = holds_show = True  # a stranger in the way the show would go on
                linear = 0.0
            elif sensing.approach_gain > 0:
                if linear > 0:
                    linear = min(linear, self._approach_limit(
                        seen.front_free, strangers.front_free if strangers else None,
                        reference_speed, parked))
                elif linear < 0:
                    linear = max(linear, -self._approach_limit(
                        seen.rear_free, strangers.rear_free if strangers else None,
                        reference_speed, parked))
            if stranger_near:
                top = CORNER_SPEED / (0.5 * math.hypot(sensing.length, sensing.width))
                if abs(angular) > top:  # corners swing at CORNER_SPEED at most, and the
                    # robot slows along the same arc (a cut turn alone widens it: one that
                    # drove to a place 8 cm to its side circled it, turning round 210 deg)
                    linear = linear * (top / abs(angular))
                    angular = min(max(angular, -top), top)
            making_room = 0.0
            # turning on the spot, the guard leaves mates (points near where one should be or
            # said it is) room for their own turn (``DetectorParams.turn_share``)
            mates_now = (self._mate_centres(show_time, mates_heard)
                         if turns_on_the_spot(linear, angular, sensing.width)
                         else np.empty((0, 2)))
            if angular != 0.0 and seen.nearest < turn_reach(
                    sensing.length, sensing.width, linear, sensing.detection,
                    sensing.detection.turn_share if len(mates_now) else 1.0):
                # it may make room for a turn only among mates (not held; no stranger near),
                # and not for the last centimetres onto its final slot (a SIM robot 7 cm
                # beside it, a mate at its side, hunted to and fro at 0.15 m/s to the run's
                # end in the physics profiles)
                may_make_room = (not held and knows_strangers and near.nearest >= turn_reach(
                    sensing.length, sensing.width, MAKE_ROOM_SPEED, sensing.detection)
                    and seen.nearest >= MAKE_ROOM_FLOOR
                    and not (final and behind <= FINAL_NO_ROOM))
                linear, angular, making_room = self._guard_turn(
                    obstacles, height_step, seen_from or pose, pose, linear, angular,
                    mates_now, state.making_room if may_make_room else None)
            if angular != 0.0 and knows_strangers and body_nearest < self.sweep_reach:
                # it turns only when nothing but mates on their places is within the circle
                # its footprint sweeps (its corners' swing beyond its sides); once only when
                # held, and a standing robot that the show moved on turned its rear corner
                # into a child squeezing past it (children crowd seed 34, t = 218.0 s)
                angular = 0.0
            if (angular != 0.0 and held and holds_show and knows_strangers
                    and sensing.stop_rule != "ssm" and body_nearest < NEAR_GAP):
                # held for a stranger, it stands: no turn while one is within NEAR_GAP (its
                # turn only corrects its heading; the show waits for it anyway). A held R4
                # turned at 0.045 rad/s, nothing within the circle its footprint sweeps by
                # 9 mm in a cloud 0.3 s old, and its corner met a child who had turned and
                # run at it meanwhile (dense crowd seed 94, t = 109.9 s)
                angular = 0.0
            if angular != 0.0 and predicted[2] < self.sweep_reach:
                # ``predicted``: nor while a tracked stranger will be within that circle by
                # now (a child running at its side)
                angular = 0.0
            if not held and behind > HOLD_LAG:
                # falling behind its place, slowed or kept from turning by a stranger (not by
                # a mate on its place or where it said it is: the mate moves on with the
                # show): it holds the show as if held
                free = near.front_free if wanted[0] >= 0.0 else near.rear_free
                by_stranger = (stranger_limit if stranger_limit is not None else
                               self._approach_limit(free, None, 0.0)) < abs(wanted[0]) - SLOWED
                turn_cut = abs(angular) < abs(wanted[1]) - SLOWED and (
                    (stranger_near and behind > SLOW_TURN_LAG) or near.nearest < turn_reach(
                        sensing.length, sensing.width, linear, sensing.detection))
                holds_show = (abs(linear) < abs(wanted[0]) - SLOWED and by_stranger) or turn_cut
                if self.paced and holds_show:  # slows the clock to what it drives instead
                    pace = _pace_left(linear, angular, full_speed, full_angular, *wanted)
                    holds_show = pace < PACE_MIN * PACE_MARGIN
                    if holds_show:
                        pace = 1.0  # (it holds the show: no pace to say)
            if (going is not None and (state.holds_show or state.pace < 1.0) and not held
                    and not holds_show and pace >= 1.0 and go_linear != 0.0):
                # it held or paced the show and has crept up to its standing place (the
                # approach limit to a person who stays): judged on that place it would let
                # go, the show would run a tick at full pace, it would fall behind and hold
                # again, and its mates lurched on at every let-go (a visitor in R1's lane:
                # 3.5 cm at a time). While a stranger would cut the motion the show would
                # ask (``going``, as the lag rule above judges a cut) it keeps holding, and
                # says so (thesis 5.2's stop sentence and beeps: the formation stands for the
                # person in its way, who hears that they should make room; held silently,
                # people stood on and shows waited to the run's limit); paced, it says the
                # pace it could follow where that is PACE_MIN or more
                go_limit = self._approach_limit(
                    near.front_free if go_linear > 0.0 else near.rear_free, None, 0.0)
                if go_limit < abs(go_linear) - SLOWED:
                    held = holds_show = True
                    if self.paced:
                        pace = _pace_left(go_limit, 0.0, full_speed, 0.0, go_linear, 0.0)
                        held = holds_show = pace < PACE_MIN * PACE_MARGIN
                        if holds_show:
                            pace = 1.0
            command = Command(linear, angular)
        else:
            follower = state.follower
        safety, events, may_move = safety_step(
            sensing.safety, state.safety, now, pose is not None,
            cloud is not None or not sensing.lidar, held)
        if not may_move:
            command = STOP
        new_state = BrainState(follower=follower, safety=safety, obstacles=obstacles,
                               height_step=height_step, seen_from=seen_from, history=history,
                               held=held, holds_show=holds_show, show_time=show_time,
                               tracks=tracks, point_velocity=point_velocity,
                               point_kind=point_kind, cloud_stamp=cloud_stamp,
                               making_room=making_room if may_move and command != STOP
                               else 0.0, stranger_near_since=near_since,
                               waiting=waiting, strangers_seen=strangers_seen,
                               closing=closing, pace=pace, paused_since=paused_since,
                               settling=settling)
        return new_state, command, events

    def _guard_turn(self, columns: np.ndarray, height_step: float,
                    seen_from: tuple[float, float, float], pose: tuple[float, float, float],
                    linear: float, angular: float, mates: np.ndarray,
                    making_room: float | None = None) -> tuple[float, float, float]:
        """The turn guard (an addition), for a command (m/s, rad/s) that turns while a point is
        within reach of the turn (``perception.obstacles.turn_reach``): the largest fraction
        of the turn that swings no corner into anything (``turn_fraction``), the points
        within ``mate_radius`` of ``mates`` (J, 2), own map frame, taken as mates that may
        turn too (:meth:`_turn_points`). When none is left
        and what blocks it is beside the robot's leading half (the front driving forwards),
        the robot gives way: it creeps at :data:`GIVE_WAY_SPEED`, so that a robot that would
        cut into a neighbour's lane lets the neighbour go first instead of driving on beside
        it. A robot that should turn almost on the spot, or that made room at the last tick
        (``making_room``: +1 forwards, -1 backwards, 0 not; None: it may not, a person is
        near or it is held), and may not turn at all makes room instead
        (:meth:`_make_room`). Returns the command and the direction it makes room in (0.0:
        none)."""
        sensing, detection = self.sensing, self.sensing.detection
        length, width = sensing.length, sensing.width

        def fraction_of(leading: bool) -> float:
            if sensing.compiled:
                from dancebots.perception.fast import turn_fraction_columns  # imports numba

                return float(turn_fraction_columns(
                    columns, height_step, detection.crop_half, detection.z_min,
                    detection.z_max, np.array(seen_from), np.array(pose), length, width,
                    linear, angular, detection.turn_margin, detection.turn_horizon,
                    detection.turn_share, points_to_local(mates, seen_from),
                    self.mate_radius, leading))
            points, moving = self._turn_points(columns, height_step, seen_from, pose, mates)
            if leading:
                ahead = points[:, 0] * (1.0 if linear >= 0.0 else -1.0) > 0.0
                points, moving = points[ahead], moving[ahead]
            return turn_fraction(points, length, width, linear, angular, detection, moving)

        fraction = fraction_of(False)
        if fraction == 0.0 and making_room is not None and (
                abs(linear) < GIVE_WAY_SPEED or making_room != 0.0):
            room = self._make_room(columns, height_step, seen_from, pose, angular, mates,
                                   making_room)
            if room != 0.0:
                return room * MAKE_ROOM_SPEED, 0.0, room
        if fraction == 0.0 and fraction_of(True) == 0.0:
            linear = math.copysign(min(abs(linear), GIVE_WAY_SPEED), linear)
        return linear, fraction * angular, 0.0

    def _turn_points(self, columns: np.ndarray, height_step: float,
                     seen_from: tuple[float, float, float], pose: tuple[float, float, float],
                     mates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The obstacle points (M, 2) of the cloud's columns (``base_link`` at ``seen_from``) in
        ``base_link`` at ``pose``, and (M,) which lie within ``mate_radius`` of a centre of
        ``mates`` (J, 2), own map frame: a mate that may turn as the robot does."""
        detection = self.sensing.detection
        points = obstacle_points_from_columns(columns, height_step, detection)
        moving = near_any(points, points_to_local(mates, seen_from), self.mate_radius)
        if seen_from != pose:
            points = compensate_motion(points, seen_from, pose)
        return points, moving

    def _mate_centres(self, show_time: float, mates_heard: np.ndarray | None) -> np.ndarray:
        """(J, 2) where the formation mates should be at ``show_time`` and where they said they
        are (``mates_heard`` (K, 2), show frame), own map frame; none for a robot that knows
        no mates."""
        if self._mates is None:
            return np.empty((0, 2))
        where = self.mates_at(show_time)
        if mates_heard is not None and len(mates_heard):
            where = np.concatenate([where, compose_points(self._own_frame, mates_heard)])
        return where

    def _make_room(self, columns: np.ndarray, height_step: float,
                   seen_from: tuple[float, float, float], pose: tuple[float, float, float],
                   angular: float, mates: np.ndarray, previous: float) -> float:
        """The direction (+1.0 forwards, -1.0 backwards, 0.0 none) in which a robot that should
        turn on the spot at ``angular`` rad/s, and may not turn at all where it stands, drives
        straight to make room for the turn (an addition, like a driver who pulls forward out
        of a tight row before turning; thesis listing 7.4 with SIM robots 0.2 m apart: R2's
        tail would swing into R1 beside it): towards one of :data:`MAKE_ROOM_SHIFTS` after
        which the turn, with every obstacle point where it is (those within ``mate_radius``
        of ``mates`` (J, 2), own map frame, a mate's that may turn too), is allowed
        (``perception.obstacles.turn_fraction``) and to which the way is free beyond the stop
        distance and :data:`MATE_GAP`; forwards when any such shift lies ahead (a robot that
        backs off looks wrong to the audience), else backwards. It keeps the direction of the
        last tick (``previous``) while any shift that way works, so it does not shuttle."""
        detection = self.sensing.detection
        length, width = self.sensing.length, self.sensing.width
        points, moving = self._turn_points(columns, height_step, seen_from, pose, mates)
        front, rear = clear_distances(points, length, width, detection)
        for direction in ((previous,) if previous != 0.0 else ()) + (1.0, -1.0):
            free = front if direction > 0.0 else rear
            for shift in MAKE_ROOM_SHIFTS:
                if shift + detection.stop_distance + MATE_GAP > free:
                    break
                moved = points - np.array([direction * shift, 0.0])
                if turn_fraction(moved, length, width, 0.0, angular, detection, moving) > 0.0:
                    return direction
        return 0.0

    def _near_mates(self, points: np.ndarray, show_time: float,
                    mates_heard: np.ndarray | None) -> np.ndarray | None:
        """(N,) which points (N, 2), own map frame, lie within ``mate_radius`` of where a
        formation mate should be at ``show_time`` or said it is (``mates_heard`` (K, 2),
        show frame): the ``predicted`` rule does not track them (a formation of 20 robots
        would track every mate's body at every scan); None for a robot that knows no
        mates."""
        if self._mates is None:
            return None
        return near_any(points, self._mate_centres(show_time, mates_heard), self.mate_radius)

    def _predicted_gaps(self, columns: np.ndarray, height_step: float,
                        seen_from: tuple[float, float, float],
                        pose: tuple[float, float, float], velocity: np.ndarray,
                        kind: np.ndarray, age: float, show_time: float,
                        mates_heard: np.ndarray | None = None) -> tuple[float, float, float]:
        """The ``predicted`` stop rule: the points of tracked moving strangers (``kind``
        TRACKED, ``velocity`` (N, 2) in the own map frame, of the cloud's columns seen from
        ``seen_from``) moved on at their velocity for ``age`` s and for ``age`` +
        :data:`PREDICTED_STOP_TIME` s, and how far (m) the nearest
        of them is ahead and behind in the corridor the robot sweeps
        (``perception.obstacles.clear_distances``) and from its footprint
        (``footprint_clearance``); inf where none. A stranger: no point within
        ``mate_radius`` of where a formation mate should be at ``show_time`` or said it is
        (``mates_heard`` (K, 2), show frame); a mate moves with the show, and a rule that
        held the show for it stalled the formation (seed 41 of the open-day crowd: R4 held
        for its moving mates until the run's limit)."""
        from dancebots.perception.tracks import TRACKED

        points = obstacle_points_now(columns, height_step, seen_from, pose,
                                     self._ssm_detection)
        if len(points) != len(kind) or not len(points):  # tracks of an older cloud
            return math.inf, math.inf, math.inf
        moving = kind == TRACKED
        if self._mates is not None and moving.any():
            local = points_to_local(self._mate_centres(show_time, mates_heard), pose)
            moving &= ~near_any(points, local, self.mate_radius)  # (base_link now)
        if not moving.any():
            return math.inf, math.inf, math.inf
        ahead = np.concatenate([  # now, and by the time a stop took effect
            predicted_points(points, velocity, moving, pose[2], age),
            predicted_points(points, velocity, moving, pose[2], age + PREDICTED_STOP_TIME)])
        ahead = ahead[np.isfinite(ahead).all(axis=1)]  # (as the kernel's min skips NaN)
        front, rear = clear_distances(ahead, self.sensing.length, self.sensing.width,
                                      self.sensing.detection)
        return front, rear, footprint_clearance(ahead, self.sensing.length,
                                                self.sensing.width)

    def _separation_limits(self, columns: np.ndarray, height_step: float,
                           seen_from: tuple[float, float, float],
                           pose: tuple[float, float, float], show_time: float,
                           heard: np.ndarray | None, velocity: np.ndarray, kind: np.ndarray,
                           latency: float, linear: float) -> tuple[float, float, bool]:
        """Speed and separation monitoring (``SensingConfig.stop_rule`` ssm): the fastest
        (m/s, at most |linear|) the robot may drive the way ``linear`` points, with every
        obstacle point of the cloud's columns (``base_link`` at ``seen_from``), moved to
        ``pose``, predicted on and kept at its margin from what the robot sweeps until it
        stands (``perception.ssm.ssm_speed_limit``); and the same for the strangers alone
        (points that are no mate where it should be or said it is: ``heard`` (K, 2), show
        frame). A stranger moves at its tracked velocity (``velocity`` (N, 2), own map frame,
        and ``kind`` (N,) per point: ``perception.tracks.point_motion``); a mate where it
        should be moves as its place does in the plan, one where it said it is stands, both
        with the mates' margin and no uncertainty (they keep to the plan). The data are
        ``latency`` s old; the robot reacts within a tick and its actuator's lag, and its
        speed dies away two more lags later. Third: whether, standing, it may turn
        (``perception.ssm.turn_allowed``, strangers only)."""
        from dancebots.perception.tracks import point_motion

        sensing, params = self.sensing, self.sensing.ssm
        points = obstacle_points_now(columns, height_step, seen_from, pose,
                                     self._ssm_detection)
        if len(points) != len(kind):  # the tracks are of an older cloud: trust nothing
            kind = np.full(len(points), 2, dtype=np.int8)
            velocity = np.zeros((len(points), 2))
        moving, spread = point_motion(velocity, kind, params.walking_speed, params.speed_margin)
        c, s = math.cos(pose[2]), math.sin(pose[2])
        moving = moving @ np.array([[c, -s], [s, c]])  # own map frame -> base_link axes
        margins = np.full(len(points), params.margin)
        mate = np.zeros(len(points), dtype=bool)
        if self._mates is not None and len(points):
            where = self.mates_at(show_time)
            # the places' velocities (M, 2), own map frame, from the plan's grid
            ahead = self.mates_at(show_time + self.grid_period)
            place_velocity = (ahead - where) / self.grid_period
            if heard is not None and len(heard):
                where = np.concatenate([where, compose_points(self._own_frame, heard)])
                place_velocity = np.concatenate([place_velocity, np.zeros((len(heard), 2))])
            mates = points_to_local(where, pose)
            gaps = np.hypot(points[:, None, 0] - mates[None, :, 0],
                            points[:, None, 1] - mates[None, :, 1])  # (N, M)
            nearest = gaps.argmin(axis=1)
            mate = gaps[np.arange(len(points)), nearest] <= self.mate_radius
            moving[mate] = place_velocity[nearest[mate]] @ np.array([[c, -s], [s, c]])
            spread[mate] = 0.0
            margins[mate] = params.mate_margin
        direction = 1.0 if linear >= 0.0 else -1.0
        reaction = params.reaction_time + self.feedforward_lead  # a tick and the actuator lag
        settle = 2.0 * self.feedforward_lead
        latency = max(latency, 0.0)

        def limit(keep: np.ndarray) -> float:
            return ssm_speed_limit(points[keep], moving[keep], spread[keep], margins[keep],
                                   sensing.length, sensing.width, direction, abs(linear),
                                   latency, reaction, params.deceleration, settle)

        everything = limit(np.ones(len(points), dtype=bool))
        strangers = everything if not mate.any() else limit(~mate)
        may_turn = turn_allowed(points[~mate], moving[~mate], spread[~mate], margins[~mate],
                                0.5 * math.hypot(sensing.length, sensing.width), latency,
                                reaction + settle)
        return everything, strangers, may_turn

    def _closing(self, seen: tuple[float, np.ndarray] | None,
                 closing: tuple[float, np.ndarray, np.ndarray] | None, columns: np.ndarray,
                 height_step: float, seen_from: tuple[float, float, float],
                 pose: tuple[float, float, float], show_time: float, stamp: float,
                 heard: np.ndarray | None,
                 ) -> tuple[tuple[float, np.ndarray] | None,
                            tuple[float, np.ndarray, np.ndarray] | None]:
        """The ``closing`` stop rule at a new cloud (columns (K, 4) in ``base_link`` at
        ``seen_from``, taken at ``stamp`` s): (stamp, the strangers' points (N, 2) in the own
        map frame), and, from them and the last cloud's (``seen``), both moved to ``pose``,
        (stamp, each bearing sector's gap (S,) m, how fast it closed (S,) m/s)
        (``perception.closing``); None after the first cloud. A cloud that cannot be used
        (a stamp that is not finite or not after the last one's, a pose that is not finite)
        changes nothing: ``seen`` and ``closing`` are returned as they were, so a repeated
        stamp does not release a robot that a person approaches."""
        if not (math.isfinite(stamp) and all(map(math.isfinite, (*pose, *seen_from)))) or (
                seen is not None and not stamp > seen[0]):
            return seen, closing
        points = self._stranger_points(columns, height_step, seen_from, show_time, heard)
        if seen is None:
            return (stamp, points), None
        sensing, params = self.sensing, self.sensing.closing
        length, width, sectors = sensing.length, sensing.width, params.sectors
        if sensing.compiled:
            from dancebots.perception.closing_jit import sector_gaps_moved  # imports numba

            at = np.array(pose)
            gaps_before = sector_gaps_moved(seen[1], at, length, width, sectors)
            gaps = sector_gaps_moved(points, at, length, width, sectors)
        else:
            gaps_before = sector_gaps(points_to_local(seen[1], pose), length, width, sectors)
            gaps = sector_gaps(points_to_local(points, pose), length, width, sectors)
        return (stamp, points), (stamp, gaps, closing_speeds(gaps_before, gaps,
                                                             stamp - seen[0], params.max_speed))

    def _stranger_points(self, columns: np.ndarray, height_step: float,
                         seen_from: tuple[float, float, float], show_time: float,
                         heard: np.ndarray | None) -> np.ndarray:
        """The obstacle points (N, 2) of the cloud's columns (``base_link`` at ``seen_from``)
        in SSM's wider square (``SsmParams.reach``), in the own map frame, without those
        within ``mate_radius`` of where a mate should be or said it is (``heard``, show
        frame; none for a robot that knows no mates' places: the thesis follower's, for which
        a formation mate is a stranger too)."""
        mates = self._mate_centres(show_time, heard)
        detection = self._ssm_detection
        if self.sensing.compiled:
            from dancebots.perception.closing_jit import stranger_points_columns  # imports numba

            return stranger_points_columns(columns, height_step, detection.crop_half,
                                           detection.z_min, detection.z_max,
                                           np.array(seen_from), mates, self.mate_radius)
        kept = columns[self._far_from_mates(columns, seen_from, mates)]
        return points_to_world(obstacle_points_from_columns(kept, height_step, detection),
                               seen_from)

    def mates_at(self, show_time: float) -> np.ndarray:
        """(M, 2) where the other robots should be at ``show_time`` s (their followers'
        places, from the 10 Hz grid, nearest row), in this robot's own frame."""
        assert self._mates is not None
        k = min(max(round(show_time / self.grid_period), 0), self._mates.shape[1] - 1)
        return self._mates[:, k]

    def _approach_limit(self, free: float, strangers_free: float | None,
                        reference_speed: float, parked: bool = False) -> float:
        """The fastest (m/s) the robot may drive towards what it sees ``free`` m ahead (or
        behind): approach_gain * (free - stop distance). Where the nearest of it is a
        formation mate on its place (``strangers_free``: the free distance without the mates'
        points, None when none was left out), the mate moves with the formation, so the robot
        may keep its own reference's speed ``reference_speed`` (m/s) until it is within
        :data:`MATE_GAP` of the stop distance (adaptive cruise control: the gap closes
        only as fast as the mate drives away); the stop flags still hold it at the stop
        distance, and anything else within reach keeps the first limit. ``parked``: the
        show is over, so a mate on its final place stands for good and the robot may close
        up to :data:`PARKED_GAP` of it (strangers keep the stop distance)."""
        sensing = self.sensing
        stop = sensing.detection.stop_distance
        limit = sensing.approach_gain * max(free - stop, 0.0)
        if parked and strangers_free is not None:  # after the show, mates stand for good
            return sensing.approach_gain * max(min(free - PARKED_GAP, strangers_free - stop),
                                               0.0)
        if strangers_free is None or free <= stop + MATE_GAP:
            return limit
        cruise = reference_speed + sensing.approach_gain * (free - stop - MATE_GAP)
        return max(limit, min(cruise, sensing.approach_gain * max(strangers_free - stop, 0.0)))

    def _perceive_all(self, columns: np.ndarray, height_step: float,
                      seen_from: tuple[float, float, float], pose: tuple[float, float, float],
                      show_time: float) -> tuple[Perception, Perception | None]:
        """:meth:`_perceive` of the cloud's columns and, for a robot that knows its mates'
        places, :meth:`_without_mates` (else None), in one compiled pass unless
        ``SensingConfig.compiled`` is off (same results)."""
        if self._mates is None:
            return self._perceive(columns, height_step, seen_from, pose), None
        if not self.sensing.compiled:
            return (self._perceive(columns, height_step, seen_from, pose),
                    self._without_mates(columns, height_step, seen_from, pose, show_time))
        from dancebots.perception.fast import perceive_columns_split  # imports numba

        sensing, detection = self.sensing, self.sensing.detection
        everything, strangers, left_out = perceive_columns_split(
            columns, height_step, detection.crop_half, detection.z_min, detection.z_max,
            np.array(seen_from), np.array(pose), sensing.length, sensing.width,
            detection.stop_distance, detection.corridor_margin, sensing.force_radius,
            FORCE_GAIN, self.mates_at(show_time), self.mate_radius)
        return (self._perception(*everything),
                self._perception(*strangers) if left_out else None)

    def _perception(self, front: float, rear: float, nearest: float, fx: float,
                    fy: float) -> Perception:
        """The perception of the compiled kernels' figures (free distances ahead and behind,
        nearest point to the footprint, m; force)."""
        stop = self.sensing.detection.stop_distance
        return Perception(StopFlags(front < stop, rear < stop), front, rear, nearest, (fx, fy))

    def _without_mates(self, columns: np.ndarray, height_step: float,
                       seen_from: tuple[float, float, float],
                       pose: tuple[float, float, float], show_time: float,
                       heard: np.ndarray | None = None) -> Perception | None:
        """The perception of the cloud's columns (K, 4) (``base_link`` at ``seen_from``)
        without the points within ``mate_radius`` of where a formation mate should be, or
        None when no point is left out (an addition of the tracking and path followers: a
        mate on its place is part of the plan: its force and the approach limit,
        :meth:`_approach_limit`, leave it out; the stop flags and the turn guard still see
        every point). ``heard`` (K, 2), own map frame: more mates, where they said they are."""
        where = self.mates_at(show_time) if heard is None else np.concatenate(
            [self.mates_at(show_time), heard])
        keep = self._far_from_mates(columns, seen_from, where)
        if keep.all():
            return None
        return self._perceive(columns[keep], height_step, seen_from, pose)

    def _far_from_mates(self, columns: np.ndarray, seen_from: tuple[float, float, float],
                        mates: np.ndarray, radius: float | None = None) -> np.ndarray:
        """(K,) True for the cloud's columns (``base_link`` at ``seen_from``) more than
        ``radius`` (None: ``mate_radius``) from every mate's place ``mates`` (M, 2), own map
        frame (all of them for no mate): compiled (``perception.fast.far_from_all``) unless
        ``SensingConfig.compiled`` is off."""
        radius = self.mate_radius if radius is None else radius
        local = points_to_local(mates, seen_from)  # (M, 2) base_link
        if self.sensing.compiled:
            from dancebots.perception.fast import far_from_all  # imports numba

            keep: np.ndarray = far_from_all(columns, local, radius)
            return keep
        gaps = np.hypot(columns[:, None, 0] - local[None, :, 0],
                        columns[:, None, 1] - local[None, :, 1])  # (K, M)
        far: np.ndarray = gaps.min(axis=1, initial=np.inf) > radius
        return far

    def _nearest_beyond_mates(self, columns: np.ndarray, height_step: float,
                              seen_from: tuple[float, float, float],
                              pose: tuple[float, float, float], mates: np.ndarray,
                              everything: float) -> float:
        """The gap (m) from the footprint to the nearest of the cloud's columns (K, 4)
        (``base_link`` at ``seen_from``) that lies more than ``mate_body_radius`` from every
        mate where it should be and where it said it is (``mates`` (M, 2), own map frame): no
        mate's body (:data:`MATE_BODY_MARGIN`); ``everything``: the nearest of all of them."""
        keep = self._far_from_mates(columns, seen_from, mates, self.mate_body_radius)
        if keep.all():
            return everything
        return self._perceive(columns[keep], height_step, seen_from, pose).nearest

    def _perceive(self, columns: np.ndarray, height_step: float,
                  seen_from: tuple[float, float, float],
                  pose: tuple[float, float, float]) -> Perception:
        """The latest cloud's columns seen at ``seen_from``: obstacle points (thesis 5.2),
        moved to ``pose``, then ``perceive`` (in one compiled pass unless
        ``SensingConfig.compiled`` is off; the NumPy functions are the tested reference)."""
        sensing, detection = self.sensing, self.sensing.detection
        if sensing.compiled:
            from dancebots.perception.fast import perceive_columns  # imports numba

            return self._perception(*perceive_columns(
                columns, height_step, detection.crop_half, detection.z_min, detection.z_max,
                np.array(seen_from), np.array(pose), sensing.length, sensing.width,
                detection.stop_distance, detection.corridor_margin, sensing.force_radius,
                FORCE_GAIN))
        current = obstacle_points_now(columns, height_step, seen_from, pose, detection)
        return perceive(current, sensing.length, sensing.width, detection,
                        sensing.force_radius, FORCE_GAIN)

    @staticmethod
    def _pose_at(history: tuple[tuple[float, float, float, float], ...],
                 stamp: float) -> tuple[float, float, float] | None:
        """The own pose recorded nearest to ``stamp`` (None without history; the history is
        in time order, the earlier of two equally near records wins)."""
        if not history:
            return None
        after = bisect.bisect_left(history, stamp, key=_record_time)
        if after == len(history) or (after > 0 and stamp - history[after - 1][0]
                                     <= history[after][0] - stamp):
            after -= 1
        best = history[after]
        return best[1], best[2], best[3]

    def leader_in_own_frame(self, show_time: float) -> tuple[float, float]:
        """The virtual leader's position (x, y in m) in this robot's map frame at
        ``show_time`` s, as the brain sees it (from its 10 Hz cache on the grid)."""
        return self._sample(show_time).leader


@functools.lru_cache(maxsize=4)
def _places(plan: Plan, grid_period: float, follower: Follower) -> np.ndarray:
    """Every robot's follower place (R, T, 2), show frame, on the brains' grid (shared by
    the brains of one plan in the simulator)."""
    if follower == "tracking":
        return follower_places(plan, _grid_times(plan, grid_period), follower)
    return np.stack([placed[0] for placed in _grid_path_places(plan, grid_period)])


@functools.lru_cache(maxsize=2)
def _grid_path_places(plan: Plan, grid_period: float,
                      ) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], ...]:
    """Every robot's place on its leader's path on the brains' grid (``path_places``: per
    robot positions (T, 2), heading, motion, speed (T,)), computed once for the brains of a
    plan: the path follower's references and every brain's mates' places."""
    times = _grid_times(plan, grid_period)
    return tuple(path_places(plan, robot, times) for robot in plan.robots)


def _grid_times(plan: Plan, grid_period: float) -> np.ndarray:
    """The brains' control grid (T,): every ``grid_period`` s from 0 to the end of the
    references (the plan's end, or later while places on the path go to their slots:
    ``places_end``, and a half turn at ``REFERENCE_TURN`` more, in which a reference whose
    heading is rate-limited turns to its slot's: without it a robot was left 16 deg off its
    final heading in listing 7.4), the last entries the end itself."""
    end = places_end(plan) + math.pi / REFERENCE_TURN
    count = math.ceil(end / grid_period) + 1
    return np.minimum(np.arange(count + 1, dtype=np.float64) * grid_period, end)


def _record_time(record: tuple[float, float, float, float]) -> float:
    """The time of a pose record (t, x, y, theta)."""
    return record[0]


@dataclass(frozen=True, slots=True)
class BrainOptions:
    """How a robot's brain works, the same in the simulator and on a real robot.

    follower: ``FOLLOWERS``; lidar: False for a robot without obstacle detection (no stops,
    no force field, no sensor-age check); detector: ``DETECTORS``; force_radius: the virtual
    force field's reach, m (0: off); force_steering: how the force steers the thesis
    follower (``FollowerParams.force_steering``); actuator_lag: the first-order time
    constant (s) with which the robot's speeds follow its commands, by which the tracking and
    path followers lead their feedforward speeds (None: the simulator's profile's; 0 on ROS
    unless ``~actuator_lag`` says); compiled: the perception as numba-compiled loops, else
    the NumPy reference (``SensingConfig.compiled``); stop_rule: :data:`STOP_RULES` (None:
    :func:`default_stop_rule` of the follower); paced: the formation's shared clock runs at
    paces (``sync.hold``'s ``paced`` strategy): the brain says the pace it can follow
    (``BrainState.pace``) and follows its place at the clock's rate (the simulator sets it
    from ``SimConfig.hold``, the ROS node from ``~hold``).
    """

    follower: Follower = "thesis"
    lidar: bool = True
    detector: Detector = "compensated"
    force_radius: float = 1.0
    force_steering: ForceSteering = "blend"
    actuator_lag: float | None = None
    compiled: bool = True
    stop_rule: StopRule | None = None
    paced: bool = False


def brain_for(plan: Plan, robot: str, robot_type: RobotType,
              options: BrainOptions = BrainOptions(),
              mate_types: Sequence[RobotType] = ()) -> RobotBrain:
    """The brain of ``robot`` (a role of the plan) on a robot of ``robot_type`` (footprint and
    limits), among formation mates of ``mate_types`` (their footprints; none known: its own):
    the one factory that the simulator and the ROS node both use, so that they cannot drift
    apart."""
    mate_reach = max((0.5 * math.hypot(t.length, t.width) for t in mate_types), default=None)
    return RobotBrain(plan, robot, FollowerParams(
        vmax=plan.parameters.vmax, max_linear=robot_type.max_speed,
        max_angular=robot_type.max_angular_speed, force_steering=options.force_steering),
        sensing=SensingConfig(
            robot_type.length, robot_type.width, lidar=options.lidar,
            detector=options.detector, force_radius=options.force_radius,
            compiled=options.compiled,
            stop_rule=default_stop_rule(options.follower, options.stop_rule),
            mate_reach=mate_reach),
        follower=options.follower, feedforward_lead=options.actuator_lag or 0.0,
        paced=options.paced)
