"""Formation metrics of a simulated show (pure functions of a :class:`RunResult`).

Per robot: the error to its desired pose (the leader's pose composed with the robot's offset,
thesis ch. 4.2) and the deviation of its distance to the leader from the desired one (d_act -
d_req, eq. 4.4a, thesis fig. 7.5). Per row of each formation: the largest change of the
distance between neighbours from their desired spacing (thesis ch. 7.2.1: "the maximal change
in the distance between the robots ... around 16 cm for 2D and 18 cm for 3D").

What a spectator sees (issue 12): per robot its heading error to its slot's heading (the
direction the slot moves, folded so that it does not jump, or the leader's heading where the
slot stands: ``RunResult.reference``), how much of the time it faces away from it, how much
of the time it drives against the direction its reference drives (a robot that turned round
and reverses), how often its commanded angular speed changes sign (chatter), its heading error
at the end; over every pair of robots in the same formation,
the change of their distance from the distance between their desired poses (the formation
error, not only row neighbours). All poses compared are in the world frame: ``RunResult.poses``
and ``RunResult.desired`` (the desired poses as each robot computes them from its start pose).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import wrap_angles
from dancebots.plan.placement import true_runs
from dancebots.shows.formation import STATUS, RunResult, settle_from
from dancebots.sim.collision import footprint_gaps

__all__ = [
    "ANGULAR_DEADBAND",
    "DESIRED_SPEED_MIN",
    "FACING_AWAY_ANGLE",
    "PERSON_NEAR",
    "REVERSE_DISTANCE_MIN",
    "REVERSE_SPEED_MIN",
    "WHEEL_TURN_MIN",
    "ClockRestarts",
    "ClockWaits",
    "FormationError",
    "OffFormation",
    "RobotMetrics",
    "RowMetrics",
    "RunMetrics",
    "against_desired",
    "clock_restarts",
    "clock_waits",
    "excess_turn",
    "formation_error",
    "heading_errors",
    "held_place_error",
    "moving_over_to_place",
    "off_formation",
    "reverse_runs",
    "run_metrics",
    "samples_per_tick",
    "sign_flips",
    "smallest_person_gap",
    "spacing_change",
    "wheel_turn_ratio",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

DESIRED_SPEED_MIN = 0.05
"""m/s: the direction of a robot's desired motion counts only while its slot moves at least
this fast (below it the slot is turning on the spot or standing)."""
REVERSE_SPEED_MIN = 0.05
"""m/s: a robot drives against its desired direction only when it drives at least this fast the
other way (above the realistic profile's velocity noise, 0.01 m/s per step, about 0.014 m/s
with its lag; a robot turning on the spot does not count)."""
REVERSE_DISTANCE_MIN = 0.05
"""m: a robot drives against its desired direction only where it drives at least this far the
other way in one go. Where its reference turns from one direction to the other, a robot
whose speed follows its commands with a lag goes on a little the old way (the realistic
profile's 0.25 s: from 0.35 m/s it coasts about 3 cm before it turns back), and a spectator
sees it brake and reverse, not drive the wrong way; ``max_reverse_distance`` still reports
the longest such way."""
ANGULAR_DEADBAND = 0.05
"""rad/s: commanded angular speeds smaller than this are ignored when counting sign flips
(chatter): 0.3 -> 0.01 -> -0.3 is one flip, 0.03 -> -0.03 none."""
PERSON_NEAR = 2.0
"""m: a person this near the footprint of a robot that holds the formation's shared show
clock explains the wait (the obstacle detection's square, ``DetectorParams.crop_half``):
:func:`clock_waits`."""
FACING_AWAY_ANGLE = 90.0
"""deg: a robot whose heading is more than this away from its desired heading faces away
from it (its back to the direction it should face)."""


@dataclass(frozen=True, slots=True)
class RobotMetrics:
    """One robot: RMS and max position error to its desired pose (its slot error), m; RMS and
    max of |d_act - d_req|, m; while the show runs (0 <= t <= show duration). stops: how often
    a stop flag held it (thesis 5.2, each spoken once); stopped_time: s held; error: why it
    went into the error state, if it did; final_error: distance from its final slot (its
    desired pose at the end of the run) at the end of the run, m.

    While the show runs: rms_heading_error, max_heading_error: |wrap(yaw - slot heading)|,
    deg (the slot's heading: ``RunResult.reference``);
    facing_away_fraction: the fraction of the ticks with a heading error above
    :data:`FACING_AWAY_ANGLE`; reverse_fraction: of the ticks in which its slot moves (at
    least :data:`DESIRED_SPEED_MIN`), the
    fraction in which the robot drives the other way (:func:`against_desired`: at least
    :data:`REVERSE_DISTANCE_MIN` in one go), 0 when its slot never moves;
    max_reverse_distance, reverse_distance: the longest way it drove against its slot's
    direction in one go and all of them together, m (:func:`reverse_runs`: every way, however
    short or slow; a robot that goes back and forth a few centimetres at a time shows in the
    total); angular_sign_flips: sign changes of its
    commanded angular speed (:func:`sign_flips`); rms_formation_error, max_formation_error:
    the formation error (:func:`formation_error`) over every pair it belongs to, m (None when
    it never shares a formation). final_heading_error: |wrap(yaw - slot heading)| at the end
    of the run, deg (the slot stands then: its heading is the leader's).
    max_off_formation: the largest distance from where its formation puts it
    (``RunResult.formation_places``), m, and off_formation_time the longest it was outside
    its formation in one go, s (:func:`off_formation`); neither counts while it moves over
    to its place in a formation it has just joined. wheel_turn_ratio: in the physics profiles, the
    median over the ticks its wheels turn it at WHEEL_TURN_MIN or more of its achieved yaw
    rate over the wheels' (1: no slip; a skid-steer robot's wheels slip sideways in a turn);
    None in the other profiles or without such ticks. excess_turn: how much more the robot
    turned than its reference over the whole run, the settling after the show included
    (:func:`excess_turn`), deg: spins, wiggles and hunting that the plan does not ask for.
    """

    robot: str
    rms_error: float
    max_error: float
    rms_leader_distance_deviation: float
    max_leader_distance_deviation: float
    stops: int = 0
    stopped_time: float = 0.0
    error: str | None = None
    final_error: float = 0.0
    rms_heading_error: float = 0.0
    max_heading_error: float = 0.0
    facing_away_fraction: float = 0.0
    reverse_fraction: float = 0.0
    angular_sign_flips: int = 0
    rms_formation_error: float | None = None
    max_formation_error: float | None = None
    final_heading_error: float = 0.0
    max_reverse_distance: float = 0.0
    reverse_distance: float = 0.0
    max_off_formation: float = 0.0
    off_formation_time: float = 0.0
    wheel_turn_ratio: float | None = None
    excess_turn: float = 0.0


@dataclass(frozen=True, slots=True)
class RowMetrics:
    """Neighbours in one row of one formation (scenario ``line``): their desired spacings (m)
    and the largest |distance - desired spacing| while they follow that formation, m."""

    line: int
    robots: tuple[str, ...]
    desired_spacings: tuple[float, ...]
    max_spacing_change: float


@dataclass(frozen=True, slots=True)
class RunMetrics:
    """Everything ``metrics.json`` holds.

    Over all robots, while the show runs (pooled over every robot's ticks, so a long-moving
    robot weighs more): rms_slot_error (m), rms_heading_error (deg), facing_away_fraction,
    reverse_fraction (of all ticks in which some robot's slot moves); rms_formation_error,
    max_formation_error over every pair of robots in the same formation (m, None for fewer
    than two robots). The maxima and sums over robots are properties.
    """

    scenario: str
    profile: str
    seed: int
    show_duration: float
    run_duration: float
    robots: tuple[RobotMetrics, ...]
    rows: tuple[RowMetrics, ...]
    collisions: int
    collision_events: tuple[dict[str, object], ...]
    min_clearance: float | None
    events: tuple[dict[str, object], ...] = ()
    rms_slot_error: float = 0.0
    rms_heading_error: float = 0.0
    facing_away_fraction: float = 0.0
    reverse_fraction: float = 0.0
    rms_formation_error: float | None = None
    max_formation_error: float | None = None
    follower: str = "thesis"
    timing: str = "thesis"
    min_person_gap: float | None = None
    held_place_error: float | None = None
    final_show_time: float | None = None
    clock_stood: float = 0.0
    clock_stood_for_people: float = 0.0
    show_end: float | None = None
    clock_restarts: int = 0
    clock_brief_runs: int = 0

    @property
    def end_show_time(self) -> float:
        """s of show time at which the show is over: ``show_end`` (the time every place
        stands on its final slot, ``shows.formation.settle_from``), else the plan's end,
        ``show_duration``."""
        return self.show_duration if self.show_end is None else self.show_end

    @property
    def finished(self) -> bool:
        """The show ran to its end: the shared show time reached :attr:`end_show_time`."""
        return self.final_show_time is None or bool(
            self.final_show_time >= self.end_show_time - 1e-6)

    @property
    def show_reached(self) -> float:
        """The share (0-1) of the show the shared clock reached by the run's end (the show
        time then over :attr:`end_show_time`); 1 for a show that finished."""
        end = self.end_show_time
        if self.finished or self.final_show_time is None or end <= 0.0:
            return 1.0
        return min(max(self.final_show_time / end, 0.0), 1.0)

    @property
    def clock_stood_otherwise(self) -> float:
        """s the shared show clock stood with no person near a robot that held it
        (:func:`clock_waits`): the robots' or the plan's doing."""
        return ClockWaits(self.clock_stood, self.clock_stood_for_people).otherwise

    @property
    def max_spacing_change(self) -> float | None:
        return max((r.max_spacing_change for r in self.rows), default=None)

    @property
    def max_slot_error(self) -> float:
        """m: the largest distance of any robot from its desired pose while the show runs."""
        return max((r.max_error for r in self.robots), default=0.0)

    @property
    def max_heading_error(self) -> float:
        """deg: the largest heading error of any robot while the show runs."""
        return max((r.max_heading_error for r in self.robots), default=0.0)

    @property
    def max_excess_turn(self) -> float:
        """deg: the most any robot turned beyond its reference (:func:`excess_turn`)."""
        return max((r.excess_turn for r in self.robots), default=0.0)

    @property
    def max_reverse_distance(self) -> float:
        """m: the longest way any robot drove against its slot's direction in one go."""
        return max((r.max_reverse_distance for r in self.robots), default=0.0)

    @property
    def reverse_distance(self) -> float:
        """m: the ways all robots drove against their slots' directions, together."""
        return sum(r.reverse_distance for r in self.robots)

    @property
    def angular_sign_flips(self) -> int:
        """Sign flips of the commanded angular speeds of all robots."""
        return sum(r.angular_sign_flips for r in self.robots)

    @property
    def max_off_formation(self) -> float:
        """m: the furthest any robot was from where its formation puts it."""
        return max((r.max_off_formation for r in self.robots), default=0.0)

    @property
    def off_formation_time(self) -> float:
        """s: the longest any robot was outside its formation in one go
        (:func:`off_formation`)."""
        return max((r.off_formation_time for r in self.robots), default=0.0)

    @property
    def max_final_error(self) -> float:
        """m: the furthest any robot ends from its final slot."""
        return max((r.final_error for r in self.robots), default=0.0)

    @property
    def max_final_heading_error(self) -> float:
        """deg: the largest heading error of any robot at the end of the run."""
        return max((r.final_heading_error for r in self.robots), default=0.0)

    def to_json(self) -> dict[str, object]:
        def r3(value: float | None) -> float | None:
            return None if value is None or not math.isfinite(value) else round(value, 4)

        return {
            "scenario": self.scenario,
            "profile": self.profile,
            "seed": self.seed,
            "follower": self.follower,
            "timing": self.timing,
            "show_duration_s": r3(self.show_duration),
            "run_duration_s": r3(self.run_duration),
            "collisions": self.collisions,
            "collision_events": list(self.collision_events),
            "min_clearance_m": r3(self.min_clearance),
            "min_person_gap_m": r3(self.min_person_gap),
            "held_place_error_m": r3(self.held_place_error),
            "final_show_time_s": r3(self.final_show_time),
            "show_end_s": r3(self.show_end),
            "clock_stood_s": r3(self.clock_stood),
            "clock_stood_for_people_s": r3(self.clock_stood_for_people),
            "clock_restarts": self.clock_restarts,
            "clock_brief_runs": self.clock_brief_runs,
            "max_spacing_change_m": r3(self.max_spacing_change),
            "rms_slot_error_m": r3(self.rms_slot_error),
            "max_slot_error_m": r3(self.max_slot_error),
            "max_final_error_m": r3(self.max_final_error),
            "rms_heading_error_deg": r3(self.rms_heading_error),
            "max_heading_error_deg": r3(self.max_heading_error),
            "max_final_heading_error_deg": r3(self.max_final_heading_error),
            "facing_away_fraction": r3(self.facing_away_fraction),
            "reverse_fraction": r3(self.reverse_fraction),
            "max_reverse_distance_m": r3(self.max_reverse_distance),
            "reverse_distance_m": r3(self.reverse_distance),
            "angular_sign_flips": self.angular_sign_flips,
            "max_excess_turn_deg": r3(self.max_excess_turn),
            "rms_formation_error_m": r3(self.rms_formation_error),
            "max_formation_error_m": r3(self.max_formation_error),
            "max_off_formation_m": r3(self.max_off_formation),
            "off_formation_s": r3(self.off_formation_time),
            "per_robot": {
                m.robot: {
                    "rms_error_m": r3(m.rms_error),
                    "max_error_m": r3(m.max_error),
                    "rms_leader_distance_deviation_m": r3(m.rms_leader_distance_deviation),
                    "max_leader_distance_deviation_m": r3(m.max_leader_distance_deviation),
                    "stops": m.stops,
                    "stopped_s": r3(m.stopped_time),
                    "error": m.error,
                    "final_error_m": r3(m.final_error),
                    "rms_heading_error_deg": r3(m.rms_heading_error),
                    "max_heading_error_deg": r3(m.max_heading_error),
                    "facing_away_fraction": r3(m.facing_away_fraction),
                    "reverse_fraction": r3(m.reverse_fraction),
                    "max_reverse_distance_m": r3(m.max_reverse_distance),
                    "reverse_distance_m": r3(m.reverse_distance),
                    "angular_sign_flips": m.angular_sign_flips,
                    "excess_turn_deg": r3(m.excess_turn),
                    "rms_formation_error_m": r3(m.rms_formation_error),
                    "max_formation_error_m": r3(m.max_formation_error),
                    "final_heading_error_deg": r3(m.final_heading_error),
                    "max_off_formation_m": r3(m.max_off_formation),
                    "off_formation_s": r3(m.off_formation_time),
                    "wheel_turn_ratio": r3(m.wheel_turn_ratio),
                } for m in self.robots
            },
            "stops": sum(m.stops for m in self.robots),
            "events": list(self.events),
            "rows": [
                {"line": row.line, "robots": list(row.robots),
                 "desired_spacings_m": [r3(s) for s in row.desired_spacings],
                 "max_spacing_change_m": r3(row.max_spacing_change)}
                for row in self.rows
            ],
        }


def run_metrics(result: RunResult) -> RunMetrics:
    """Compute the metrics of a run."""
    plan = result.plan
    during = result.during_show  # (T,) by the show's own time (paused while robots wait)
    error = np.hypot(result.poses[..., 0] - result.desired[..., 0],
                     result.poses[..., 1] - result.desired[..., 1])[:, during]
    deviation = np.abs(result.leader_distance - result.required_distance)[:, during]
    slots = result.final_slot  # (R, 3): at the plan's end, even if the run ended before it
    final = np.hypot(result.poses[:, -1, 0] - slots[:, 0],
                     result.poses[:, -1, 1] - slots[:, 1])  # (R,)
    period = float(np.median(np.diff(result.times))) if len(result.times) > 1 else 0.0
    stopped = result.status == STATUS.index("stopped")
    heading = np.degrees(heading_errors(result.poses[..., 2], result.reference[..., 2]))  # (R, T)
    tick = samples_per_tick(result)
    moving = np.empty(result.status.shape, dtype=bool)  # (R, T) the slot moves along its heading
    against = np.empty(result.status.shape, dtype=bool)  # (R, T) ... and the robot the other way
    longest, total = [], []  # per robot, the ways against its slot's direction, m
    for i in range(len(result.robots)):
        moving[i] = during & (np.abs(result.reference[i, :, 3]) >= DESIRED_SPEED_MIN)
        speed = np.where(during, result.velocities[i, :, 0], 0.0)  # while the show runs
        desired_speed = result.reference[i, :, 3]
        against[i] = moving[i] & against_desired(speed, desired_speed, tick=tick,
                                                 sample_period=period or None)
        ways = [way for _, _, way in reverse_runs(speed, desired_speed, period, tick=tick)]
        longest.append(max(ways, default=0.0))
        total.append(sum(ways))
    pairs = formation_error(result.poses[..., :2], result.desired[..., :2], result.formation,
                            during)
    flips = [sign_flips(result.commands[i, during, 1]) for i in range(len(result.robots))]
    off = [off_formation(result, i) for i in range(len(result.robots))]
    robots = tuple(
        RobotMetrics(name, float(np.sqrt(np.mean(error[i] ** 2))), float(error[i].max()),
                     float(np.sqrt(np.mean(deviation[i] ** 2))), float(deviation[i].max()),
                     sum(1 for e in result.events if e.robot == name and e.kind == "speech"),
                     float(stopped[i].sum() * period),
                     next((e.text for e in result.events
                           if e.robot == name and e.kind == "error"), None),
                     float(final[i]),
                     _rms(heading[i, during]), float(heading[i, during].max()),
                     float(np.mean(heading[i, during] > FACING_AWAY_ANGLE)),
                     _fraction(against[i], moving[i]), flips[i],
                     pairs.robot_rms[i], pairs.robot_max[i], float(heading[i, -1]),
                     longest[i], total[i],
                     float(np.where(off[i].counted, off[i].distance, 0.0).max(initial=0.0)),
                     max(((b - a) * period for a, b in true_runs(off[i].outside)),
                         default=0.0),
                     wheel_turn_ratio(result.velocities[i, during, 1],
                                      result.wheel_rates[i, during])
                     if result.wheel_rates is not None else None,
                     math.degrees(excess_turn(result.poses[i, :, 2],
                                              result.reference[i, :, 2])))
        for i, name in enumerate(result.robots))
    waits = clock_waits(result)
    restarts = clock_restarts(result)
    return RunMetrics(
        plan.scenario.path, result.config.profile.name, result.config.seed, plan.duration,
        float(result.times[-1]), robots, tuple(_rows(result)), len(result.collisions),
        tuple({"t_s": c.time, "robot": c.robot, "with": c.other, "kind": c.kind,
               "x_m": round(c.x, 3), "y_m": round(c.y, 3), "robot_moving": c.moving,
               "robot_closing_mps": None if c.closing is None else round(c.closing, 3),
               "person_approach_mps": None if c.approach is None else round(c.approach, 3)}
              for c in result.collisions),
        result.min_clearance,
        tuple({"t_s": e.time, "robot": e.robot, "kind": e.kind, "text": e.text}
              for e in result.events),
        _rms(error), _rms(heading[:, during]),
        float(np.mean(heading[:, during] > FACING_AWAY_ANGLE)), _fraction(against, moving),
        pairs.rms, pairs.max,
        follower=result.config.brain.follower, timing=plan.parameters.timing,
        min_person_gap=smallest_person_gap(
            result.poses, np.array([t.length for t in result.placement.types]),
            np.array([t.width for t in result.placement.types]), result.spectators,
            result.spectator_radii),
        held_place_error=held_place_error(
            result, stopped | (result.holds if result.holds is not None else stopped), during),
        final_show_time=float(result.show_time[:, -1].min()) if len(result.times) else None,
        clock_stood=waits.stood, clock_stood_for_people=waits.for_people,
        show_end=settle_from(plan, result.config.brain.follower),
        clock_restarts=restarts.restarts, clock_brief_runs=restarts.brief)


class ClockWaits(NamedTuple):
    """How long (s) the formation's shared show clock stood during the show (``stood``) and,
    of that, with a person within :data:`PERSON_NEAR` of a robot that held it
    (``for_people``: a wait the people explain; the rest is the robots' or the plan's)."""

    stood: float
    for_people: float

    @property
    def otherwise(self) -> float:
        """s the clock stood with nobody near a robot that held it."""
        return max(self.stood - self.for_people, 0.0)


def clock_waits(result: RunResult, near: float = PERSON_NEAR) -> ClockWaits:
    """The run's :class:`ClockWaits`. The clock stands at a tick where the formation's show
    time (the earliest robot's, ``RunResult.show_time``) is in [0, the show's end) (every
    place on its final slot, ``shows.formation.settle_from``) and has not advanced since the
    tick before. A robot holds it at that tick when
    ``RunResult.holds`` says so at that tick or at the ticks a hold message takes to reach
    the others (one tick plus ``SimConfig.hold_delay``): mates resume a tick after the
    holder. Each stood tick counts its sample period. 0 s for both without a shared clock."""
    times = result.times
    if len(times) < 2 or result.holds is None:
        return ClockWaits(0.0, 0.0)
    period = float(np.median(np.diff(times)))
    stood = _clock_stood(result)
    if not stood.any():
        return ClockWaits(0.0, 0.0)
    lag = 1 + math.ceil(result.config.hold_delay / period - 1e-9)
    holding = result.holds.copy()  # (R, T): held at the tick or within the message's lag
    for shift in range(1, lag + 1):
        holding[:, shift:] |= result.holds[:, :-shift]
    explained = np.zeros(len(times), dtype=bool)
    people = result.spectators  # (C, T, 2)
    if people.shape[0]:
        ticks = np.flatnonzero(stood)
        for r, robot_type in enumerate(result.placement.types):
            mine = ticks[holding[r, ticks]]
            if not len(mine):
                continue
            gaps = footprint_gaps(people[:, mine], result.poses[r, mine][None],
                                  robot_type.length, robot_type.width)  # (C, n)
            gaps = gaps - result.spectator_radii[:, None]  # (NaN: not in the room)
            explained[mine] |= (np.where(np.isnan(gaps), np.inf, gaps) < near).any(axis=0)
    return ClockWaits(float(stood.sum()) * period, float((stood & explained).sum()) * period)


BRIEF_RUN = 0.35
"""s: a run of the shared show clock between two stands this short or shorter is brief."""


class ClockRestarts(NamedTuple):
    """How often the formation's shared show clock ran again during the show after it had
    stood (``restarts``: the formation starts off again, what the audience sees of a wait
    ending), and of those how many ran :data:`BRIEF_RUN` s or less before it stood again
    (``brief``: the formation lurches on a few cm and stops, a hold let go and taken again)."""

    restarts: int
    brief: int


def clock_restarts(result: RunResult, brief: float = BRIEF_RUN) -> ClockRestarts:
    """The run's :class:`ClockRestarts`, on the formation's show time (the earliest robot's,
    ``RunResult.show_time`` (R, T)) while it is in [0, the show's end) as for
    :func:`clock_waits`; a run still going at the run's end is not brief. (0, 0) without a
    shared clock."""
    times = result.times
    if len(times) < 2 or result.holds is None:
        return ClockRestarts(0, 0)
    stood = _clock_stood(result)  # (T,)
    runs = np.diff(result.show_time.min(axis=0)) > 0.0  # (T-1,): advanced into tick k + 1
    starts = np.flatnonzero(runs & stood[:-1]) + 1  # the first tick a run reaches
    stops = np.flatnonzero(stood)  # (ticks at which it stood)
    after = np.searchsorted(stops, starts)  # the first stand after each start
    ended = after < len(stops)
    # it ran from the tick before its start to the tick before that stand
    lasted = times[stops[after[ended]] - 1] - times[starts[ended] - 1]
    return ClockRestarts(len(starts), int(np.count_nonzero(lasted <= brief + 1e-9)))


def _clock_stood(result: RunResult) -> NDArray[np.bool_]:
    """(T,) the ticks at which the formation's shared show clock stood during the show: its
    show time (the earliest robot's) in [0, the show's end) (``shows.formation.
    settle_from``) and not advanced since the tick before (never at the first tick)."""
    clock = result.show_time.min(axis=0)  # (T,)
    end = settle_from(result.plan, result.config.brain.follower)
    stood = np.zeros(len(clock), dtype=bool)
    stood[1:] = (np.diff(clock) <= 0.0) & (clock[1:] >= 0.0) & (clock[1:] < end - 1e-9)
    return stood


def held_place_error(result: RunResult, stopped: BoolArray, during: BoolArray,
                     grace: float = 1.0) -> float | None:
    """The largest distance (m) of any robot from its place (its follower's reference,
    ``RunResult.reference``) at a tick of the show (``during`` (T,)) at which some robot of
    the show is held by the stop rule or holds the show (``stopped`` (R, T):
    ``RunResult.holds``, a robot slowed and left behind by a person): how far the formation
    drifts apart while one robot waits for a person. Not while a robot moves over to its place in a
    formation it has just joined (:func:`moving_over_to_place`, with ``grace`` s). None when
    no robot was held."""
    held = stopped.any(axis=0) & during
    if not held.any():
        return None
    worst = 0.0
    for i in range(len(result.robots)):
        off = np.hypot(result.poses[i, :, 0] - result.reference[i, :, 0],
                       result.poses[i, :, 1] - result.reference[i, :, 1])
        counted = held & ~moving_over_to_place(result, i, off, grace)
        worst = max(worst, float(off[counted].max(initial=0.0)))
    return worst


def moving_over_to_place(result: RunResult, robot: int, distance: FloatArray,
                 grace: float) -> NDArray[np.bool_]:
    """(T,) the ticks at which ``robot`` is moving over to its place in a formation it has
    just joined: from the tick its formation changes, for as long as closing the distance
    (m, ``distance`` (T,) from its place then) takes at vmax less the place's speed then
    (at least 0.2 vmax), plus ``grace`` s. Being far from the place then is the formation
    change, not a finding."""
    times = result.times
    over = np.zeros(len(times), dtype=bool)
    vmax = result.plan.parameters.vmax
    changes = np.flatnonzero(np.diff(result.formation[robot]) != 0) + 1
    for k in changes.tolist():
        closing = max(vmax - abs(float(result.reference[robot, k, 3])), 0.2 * vmax)
        until = times[k] + float(distance[k]) / closing + grace
        over[k:int(np.searchsorted(times, until, side="right"))] = True
    return over



WHEEL_TURN_MIN = 0.1
"""rad/s: the wheels' yaw rate from which a tick counts for ``wheel_turn_ratio``."""


def wheel_turn_ratio(achieved: FloatArray, wheels: FloatArray) -> float | None:
    """The median of achieved (T,) over the wheels' (T,) yaw rate (rad/s) where the wheels turn
    the robot at WHEEL_TURN_MIN or more; None where they never do."""
    turning = np.abs(wheels) >= WHEEL_TURN_MIN
    return float(np.median(achieved[turning] / wheels[turning])) if turning.any() else None


class OffFormation(NamedTuple):
    """:func:`off_formation`'s arrays, each (T,)."""

    distance: FloatArray
    outside: BoolArray
    counted: BoolArray


def off_formation(result: RunResult, robot: int, grace: float = 1.0) -> OffFormation:
    """Whether ``robot`` is out of its formation, as the audience sees it.

    Returns distance (T,), m: from where its formation puts it
    (``RunResult.formation_places``: its rigid slot for ``tracking``, its place on the
    leader's path without the wait behind the robots ahead otherwise); outside (T,): while
    the show runs, further than its formation's depth (front row to back row, m) plus its
    own length, so that it stands clear of the formation's block (never while it is a
    formation of its own: the slot error judges it then); counted (T,): the ticks
    judged (the show runs and it is not moving over to its place in a formation it has just
    joined, :func:`moving_over_to_place` with ``grace`` s). A robot that waits behind the
    robots ahead round a corner tighter than its formation is wide (``plan.places``) is out
    of place; one that waits a formation's length is out of the formation.
    """
    places = (result.formation_places if result.formation_places is not None
              else result.reference[..., :2])
    distance = np.hypot(result.poses[robot, :, 0] - places[robot, :, 0],
                        result.poses[robot, :, 1] - places[robot, :, 1])
    name = result.robots[robot]
    depth = np.array([f.depth if name in f.offsets and len(f.offsets) > 1 else np.inf
                      for f in result.plan.formations])  # a robot alone has none to leave
    tolerance = depth[result.formation[robot]] + result.placement.types[robot].length
    counted = result.during_show & ~moving_over_to_place(result, robot, distance, grace)
    return OffFormation(distance, counted & (distance > tolerance), counted)


def smallest_person_gap(poses: FloatArray, lengths: FloatArray, widths: FloatArray,
                        people: FloatArray, radii: FloatArray) -> float | None:
    """The smallest gap (m) between a robot's footprint and a person's disc over the run:
    poses (R, T, 3), sizes (R,), people's centres (C, T, 2) and radii (C,), world frame;
    0 at a contact (negative gaps count as 0), None without people."""
    if people.shape[0] == 0 or poses.shape[0] == 0 or poses.shape[1] == 0:
        return None
    best = math.inf
    for r in range(poses.shape[0]):  # (C, T) per robot: memory stays C x T
        gaps = footprint_gaps(people, poses[r][None], lengths[r], widths[r])  # (C, T)
        best = min(best, float(np.nanmin(gaps - radii[:, None], initial=math.inf)))
    return max(best, 0.0)


def _rms(values: FloatArray) -> float:
    return float(np.sqrt(np.mean(values ** 2)))


def _fraction(part: BoolArray, whole: BoolArray) -> float:
    """The share of ``whole``'s True entries that ``part`` has (part implies whole); 0 for none."""
    count = int(whole.sum())
    return float(part.sum()) / count if count else 0.0


def heading_errors(yaw: FloatArray, desired_yaw: FloatArray) -> FloatArray:
    """|wrap(yaw - desired_yaw)| in rad, in [0, pi]; any shapes that broadcast (headings in the
    same frame, rad; e.g. (R, T) world-frame headings of ``RunResult.poses`` and ``desired``)."""
    result: FloatArray = np.abs(wrap_angles(np.asarray(yaw) - np.asarray(desired_yaw)))
    return result


def against_desired(speed: FloatArray, desired_speed: FloatArray,
                    desired_min: float = DESIRED_SPEED_MIN,
                    actual_min: float = REVERSE_SPEED_MIN, tick: int = 1,
                    sample_period: float | None = None,
                    distance_min: float = REVERSE_DISTANCE_MIN) -> BoolArray:
    """Where a robot drives against its desired direction, shape (T,); ``tick``: samples
    per control tick (:func:`samples_per_tick`).

    speed (T,): the robot's actual linear speed, m/s (``RunResult.velocities[r, :, 0]``);
    desired_speed (T,): its reference's signed speed, m/s (``RunResult.reference[r, :, 3]``:
    negative where the reference drives its slot's path in reverse). True where the reference
    drives at least ``desired_min`` one way and the robot at least ``actual_min`` the other
    way, at this tick and at the tick before: a robot that turned round and reverses while
    its reference drives forwards, or drives forwards while its reference reverses. The tick
    before counts because a robot's speed at a tick is its command of the tick before, made
    for the reference then: where the reference itself turns from forwards to reverse from
    one tick to the next (the inner place of a corner sharper than its offset, thesis ch.
    4.1), a robot that follows it exactly is not against it. With ``sample_period`` (s
    between samples): only where the robot drives at least ``distance_min`` m against it in
    one go (:data:`REVERSE_DISTANCE_MIN`, :func:`reverse_runs`).
    """
    def against(desired: FloatArray) -> BoolArray:
        result: BoolArray = (np.abs(desired) >= desired_min) & (
            speed * np.sign(desired) <= -actual_min)
        return result

    mask = against(desired_speed) & against(_before(desired_speed, tick))
    if sample_period is not None:
        for a, b, way in reverse_runs(speed, desired_speed, sample_period, desired_min, tick):
            if way < distance_min:
                mask[a:b] = False
    return mask


def reverse_runs(speed: FloatArray, desired_speed: FloatArray, sample_period: float,
                 desired_min: float = DESIRED_SPEED_MIN,
                 tick: int = 1) -> list[tuple[int, int, float]]:
    """The ways a robot drove against its reference, each in one go: every maximal run
    [a, b) of samples in which its speed (T,) m/s has the other sign than its reference's
    signed speed desired_speed (T,) m/s, now and ``tick`` samples before (a robot's speed is
    its command for the reference of the tick before: :func:`against_desired`), while the
    reference moves at least ``desired_min`` (however slow the robot: noise that dips under
    :data:`REVERSE_SPEED_MIN` does not cut one way in pieces, and a robot creeping backwards
    under it still drives a way), with the way (m) driven in it: the sum of |speed| times
    ``sample_period`` s."""
    opposite = ((speed * np.sign(desired_speed) < 0.0)
                & (speed * np.sign(_before(desired_speed, tick)) < 0.0)
                & (np.abs(desired_speed) >= desired_min))
    return [(a, b, float(np.abs(speed[a:b]).sum()) * sample_period)
            for a, b in true_runs(opposite)]


def _before(values: FloatArray, tick: int) -> FloatArray:
    """``values`` (T,) ``tick`` samples earlier (the first ones repeated at the start)."""
    lag = min(max(tick, 1), len(values))
    return np.concatenate([np.repeat(values[:1], lag), values[:len(values) - lag]])


def samples_per_tick(result: RunResult) -> int:
    """How many of the run's samples make one control tick (1 with the default step)."""
    return max(1, round(result.config.control_period / result.config.dt))


def excess_turn(yaw: FloatArray, reference_heading: FloatArray) -> float:
    """How much more (rad, 0 or more) a robot turned than what it tracks: the summed
    |change| of its yaw (T,) over the run less that of its reference's heading (T,)
    (``RunResult.reference``, continuous), both unwrapped. A robot that follows its reference
    turns as much as it does; one that spins onto a slot a few centimetres aside, wiggles
    left and right, or turns round and back adds the turns the audience sees and the plan
    does not ask for (the open-day show's R1 and R2 turned 50 deg and back onto places 4 cm
    away at its end)."""
    if len(yaw) < 2:
        return 0.0
    turned = float(np.abs(np.diff(np.unwrap(yaw))).sum())
    asked = float(np.abs(np.diff(np.unwrap(reference_heading))).sum())
    return max(turned - asked, 0.0)


def sign_flips(angular: FloatArray, deadband: float = ANGULAR_DEADBAND) -> int:
    """How often the angular speeds (T,) (rad/s, in time order) change sign, ignoring those
    with |w| < ``deadband``: the chatter of a robot that steers left, right, left."""
    signs = np.sign(angular[np.abs(angular) >= deadband])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


@dataclass(frozen=True, slots=True)
class FormationError:
    """The formation error of a run: |distance - desired distance| between two robots while
    both follow the same formation (the desired distance: between their desired poses at the
    same tick), m. rms and max over every such pair and tick (None without any); robot_rms,
    robot_max over the pairs each robot belongs to (None where it has none), per robot."""

    rms: float | None
    max: float | None
    robot_rms: tuple[float | None, ...]
    robot_max: tuple[float | None, ...]


def formation_error(positions: FloatArray, desired: FloatArray, formation: NDArray[np.int64],
                    mask: BoolArray | None = None) -> FormationError:
    """The formation error over every pair of robots in the same formation at a tick.

    positions, desired (R, T, 2): the robots' actual and desired positions, m, in one frame
    (``RunResult.poses[..., :2]`` and ``RunResult.desired[..., :2]``, world frame);
    formation (R, T): the index of the formation each follows; mask (T,): the ticks to count
    (default all). Every pair (not only row neighbours), one robot at a time against the
    robots after it, so memory stays O(R T).
    """
    count, ticks = formation.shape
    use = np.ones(ticks, dtype=bool) if mask is None else mask
    squares = np.zeros(count)
    samples = np.zeros(count, dtype=np.int64)
    largest = np.full(count, -np.inf)
    for i in range(count - 1):
        others = slice(i + 1, count)
        actual = np.hypot(positions[others, :, 0] - positions[i, :, 0],
                          positions[others, :, 1] - positions[i, :, 1])  # (R-i-1, T)
        wanted = np.hypot(desired[others, :, 0] - desired[i, :, 0],
                          desired[others, :, 1] - desired[i, :, 1])
        together = (formation[others] == formation[i]) & use  # (R-i-1, T)
        change = np.where(together, np.abs(actual - wanted), 0.0)
        squares[i] += float((change ** 2).sum())
        samples[i] += int(together.sum())
        largest[i] = max(largest[i], float(change.max(initial=-np.inf, where=together)))
        squares[others] += (change ** 2).sum(axis=1)
        samples[others] += together.sum(axis=1)
        largest[others] = np.maximum(largest[others],
                                     change.max(axis=1, initial=-np.inf, where=together))
    robot_rms = tuple(float(np.sqrt(s / n)) if n else None
                      for s, n in zip(squares.tolist(), samples.tolist(), strict=True))
    robot_max = tuple(float(m) if n else None
                      for m, n in zip(largest.tolist(), samples.tolist(), strict=True))
    pairs = int(samples.sum()) // 2  # every pair-tick is counted for both of its robots
    overall = float(np.sqrt(squares.sum() / 2.0 / pairs)) if pairs else None
    return FormationError(overall, max((m for m in robot_max if m is not None), default=None),
                          robot_rms, robot_max)


def spacing_change(first: FloatArray, second: FloatArray, spacing: float) -> float:
    """The largest change of the distance between two robots from ``spacing``, m; their
    positions first, second (T, 2 or 3) at the same times."""
    distance = np.hypot(first[:, 0] - second[:, 0], first[:, 1] - second[:, 1])
    return float(np.abs(distance - spacing).max())


def _rows(result: RunResult) -> list[RowMetrics]:
    """Rows are robots with the same longitudinal offset, ordered left to right."""
    index = {name: i for i, name in enumerate(result.robots)}
    rows: list[RowMetrics] = []
    seen: set[tuple[int, tuple[str, ...]]] = set()
    for formation in result.plan.formations:
        by_x: dict[float, list[str]] = {}
        for robot in formation.robots:
            by_x.setdefault(round(formation.offsets[robot][0], 6), []).append(robot)
        for members in by_x.values():
            if len(members) < 2:
                continue
            ordered = tuple(sorted(members, key=lambda r: -formation.offsets[r][1]))
            key = (formation.span.line, ordered)
            if key in seen:  # what remains of a split formation
                continue
            seen.add(key)
            spacings, changes = [], []
            for a, b in itertools.pairwise(ordered):
                i, j = index[a], index[b]
                spacing = abs(formation.offsets[a][1] - formation.offsets[b][1])
                active = (result.formation[i] == formation.index) & (
                    result.formation[j] == formation.index)
                if not active.any():
                    continue
                spacings.append(spacing)
                changes.append(spacing_change(result.poses[i, active],
                                              result.poses[j, active], spacing))
            if changes:
                rows.append(RowMetrics(formation.span.line, ordered, tuple(spacings),
                                       max(changes)))
    return rows
