"""BatchBrains: the brains of a whole formation, ticked in one compiled pass.

A thin shell over ``robot_batch_jit.brains_tick``: it keeps every robot's state in arrays,
looks up what each follower tracks on the brains' 10 Hz grid for all robots at once (and
asks the robot's :class:`~dancebots.robot.RobotBrain` off the grid), and turns the kernel's
event codes into the events a brain returns. The decisions are ``RobotBrain.step``'s, for
the configurations :func:`batch_supported` accepts (the defaults: ``tracking`` or ``path``
follower, ``fixed`` or ``predicted`` stop rule, ``compensated`` detector); the simulator
falls back to the brains one by one for the others. ``tests/test_robot_batch.py`` holds both equal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import accumulate

import numpy as np
from numpy.typing import NDArray

from dancebots import robot
from dancebots.control.tracking import BRIEF_STAND, FOR_GOOD, stand_ends
from dancebots.perception.cloud import PointCloud
from dancebots.perception.tracks import TrackParams
from dancebots.robot import RobotBrain
from dancebots.safety.monitor import STOP_SENTENCE, Event
from dancebots.sync.hold import ADVANCE_MIN

__all__ = ["BatchBrains", "BatchTick", "batch_supported"]

FloatArray = NDArray[np.float64]


def batch_supported(brains: list[RobotBrain]) -> bool:
    """Whether :class:`BatchBrains` decides as these brains do: one plan and grid, the
    ``tracking`` or ``path`` follower, the ``fixed`` or ``predicted`` stop rule, the
    ``compensated`` detector (or no LIDAR), the compiled perception, the same stop rule,
    detection, tracker, SSM parameters (the ``predicted`` rule brakes at their
    deceleration), safety and tracking gains for all."""
    if not brains:
        return False
    first = brains[0]
    gains = _gains(first)
    return all(
        b.follower in ("tracking", "path") and b.sensing.stop_rule in ("fixed", "predicted")
        and b.sensing.stop_rule == first.sensing.stop_rule
        and b.sensing.tracks == first.sensing.tracks
        and b.sensing.ssm == first.sensing.ssm  # (with the detection: ``_ssm_detection``)
        and (b.sensing.detector == "compensated" or not b.sensing.lidar)
        and b.sensing.compiled and b.plan is first.plan
        and b.grid_period == first.grid_period and b.sensing.lidar == first.sensing.lidar
        and b.sensing.detection == first.sensing.detection
        and b.sensing.safety == first.sensing.safety
        and b.sensing.force_radius == first.sensing.force_radius
        and b.sensing.approach_gain == first.sensing.approach_gain
        and b.feedforward_lead == first.feedforward_lead and b.paced == first.paced
        and np.array_equal(_gains(b), gains) and (b._mates is not None or len(brains) == 1)
        for b in brains)


@dataclass(frozen=True, slots=True, eq=False)
class BatchTick:
    """What the formation decided at a tick, per robot (R,): commands (R, 2) (v m/s, w
    rad/s); status codes of ``shows.formation.STATUS`` (0 ok, 1 stopped, 2 error);
    holding (``BrainState.holding_the_show``), asking (``BrainState.asks_for_room``),
    waiting (``BrainState.waiting``); events: (robot index, event) in robot order; pace
    (``BrainState.pace``)."""

    commands: FloatArray
    status: NDArray[np.int8]
    holding: NDArray[np.bool_]
    asking: NDArray[np.bool_]
    waiting: NDArray[np.bool_]
    events: tuple[tuple[int, Event], ...]
    pace: FloatArray


def _gains(brain: RobotBrain) -> FloatArray:
    """The tracking gains the kernel indexes (``robot_batch_jit.GAIN_X`` ...)."""
    t = brain.tracking
    return np.array([t.gain_x, t.gain_y, t.gain_theta, t.arrival_distance, t.settle_distance,
                     t.heading_tolerance, t.arrival_gain, t.turn_gain, t.reverse_distance,
                     t.force_gain, t.heading_speed, t.park_gain_alpha, t.park_gain_theta,
                     t.wait_speed, t.approach_distance, t.approach_heading, t.approach_gain,
                     t.approach_tilt, t.handover_turn, t.parking_turn_rate,
                     t.face_distance])


def _wrap_exact(angles: FloatArray) -> FloatArray:
    """``geometry.wrap_angle`` of every angle, bit for bit (from the exact ``fmod``; NumPy's
    ``remainder`` of ``geometry.wrap_angles`` rounds)."""
    tau = 2.0 * math.pi
    wrapped = np.fmod(angles, tau)
    wrapped = np.where(wrapped > math.pi, wrapped - tau, wrapped)
    wrapped = np.where(wrapped < -math.pi, wrapped + tau, wrapped)
    result: FloatArray = np.where(wrapped == -math.pi, math.pi, wrapped)
    return result


class BatchBrains:
    """The brains of a formation, as arrays (see the module). ``brains``: one per robot, all
    :func:`batch_supported`; they stay the reference for what the grid does not hold (their
    mates' places are shared with this batch, not copied)."""

    def __init__(self, brains: list[RobotBrain]) -> None:
        if not batch_supported(brains):
            raise ValueError("these brains are not batch_supported: tick them one by one")
        from dancebots import robot_batch_jit as jit  # imports numba

        self._jit = jit
        first = brains[0]
        sensing, detection, safety = first.sensing, first.sensing.detection, first.sensing.safety
        count = len(brains)
        self.brains = brains
        self.period = first.grid_period
        self.grid_end = first.grid_end
        self.lead = first.feedforward_lead
        self.rest_from = first.rest_from
        grids = [b._slot_grid for b in brains if b._slot_grid is not None]
        assert len(grids) == count  # the tracking and path followers' grids
        self.grid = np.stack(grids)  # (R, T, 5)
        self.paced = first.paced
        self.headings = self.grid[..., 2].copy()  # unwrapped, to interpolate (paced)
        self.grid[..., 2] = _wrap_exact(self.grid[..., 2])
        self.stand_ends = np.stack([stand_ends(grid) for grid in grids])  # (R, T)
        if count > 1:
            # every brain's mates' places (R, M, T, 2), its own frame; the brains read views
            # (filled brain by brain, each brain's own array dropped at once: a 20-robot,
            # 40-minute show's are 140 MB together)
            shape = first._mates.shape if first._mates is not None else (0, 0, 2)
            self.mates = np.empty((count, *shape))
            for i, brain in enumerate(brains):
                self.mates[i] = brain._mates
                brain._mates = self.mates[i]
            self.mates.flags.writeable = False
        else:
            self.mates = np.zeros((1, 0, len(self.grid[0]), 2))
        self.own_frames = np.array([b._own_frame for b in brains])
        self.frame_cos_sin = np.stack([np.cos(self.own_frames[:, 2]),
                                       np.sin(self.own_frames[:, 2])], axis=1)
        self.sizes = np.array([[b.sensing.length, b.sensing.width] for b in brains])
        self.limits = np.array([[b.tracking.max_linear, b.tracking.max_angular]
                                for b in brains])
        self.mate_radius = np.array([b.mate_radius for b in brains])
        self.mate_body = np.array([b.mate_body_radius for b in brains])
        self.gains = _gains(first)
        self.detect = np.array([detection.crop_half, detection.z_min, detection.z_max,
                                detection.stop_distance, detection.corridor_margin,
                                detection.turn_margin, detection.turn_horizon,
                                detection.turn_share])
        self.rules = np.array([
            sensing.force_radius, robot.FORCE_GAIN, sensing.approach_gain, robot.MATE_GAP,
            robot.OVERLAP, robot.HOLD_LAG, robot.SLOWED, robot.GIVE_WAY_SPEED,
            robot.PARKED_GAP, robot.MAKE_ROOM_SPEED, robot.MAKE_ROOM_FLOOR, robot.NEAR_GAP,
            robot.CORNER_SPEED, robot.AFTER_SHOW_WAIT, robot.SLOW_TURN_LAG,
            safety.sensor_timeout, float(safety.max_lookup_failures), safety.beep_period,
            ADVANCE_MIN, 1.0 if sensing.lidar else 0.0, first.plan.duration, first.rest_from,
            1.0 if sensing.stop_rule == "predicted" else 0.0, first._ssm_detection.crop_half,
            robot.PREDICTED_STOP_TIME, 1.0 if first.paced else 0.0, robot.PACE_MARGIN,
            robot.PACE_MIN, robot.PAUSE_STILL, robot.PAUSE_STILL_AFTER, robot.FINAL_NO_ROOM,
            sensing.ssm.deceleration])
        tracker = sensing.tracks or TrackParams()
        self.track_params = np.array([
            tracker.cluster_gap, tracker.max_width, tracker.gate, float(tracker.min_hits),
            float(tracker.max_misses), tracker.acceleration_noise, tracker.measurement_noise])
        # state
        self.history = np.zeros((count, robot.HISTORY_LENGTH + 1, 4))
        self.history_size = np.zeros(count, dtype=np.int64)
        self.seen_from = np.zeros((count, 3))
        self.has_seen_from = np.zeros(count, dtype=bool)
        self.last_show_time = np.full(count, np.nan)
        self.making_room = np.zeros(count)
        self.near_since = np.full(count, np.nan)
        self.safety = np.full((count, 5), np.nan)
        self.safety[:, 0] = 0.0
        self.lookup_failures = np.zeros(count, dtype=np.int64)
        self.latest: list[FloatArray] = [np.zeros((0, 4))] * count
        self.columns = np.zeros((0, 4))
        self.offsets = np.zeros(count + 1, dtype=np.int64)
        self.height_steps = np.full(count, 0.1)
        # the ``predicted`` rule's tracker (grown before a tick that could overflow it)
        self.track_states = np.zeros((count, 0, 4))
        self.track_covariances = np.zeros((count, 0, 4, 4))
        self.track_hits = np.zeros((count, 0), dtype=np.int64)
        self.track_misses = np.zeros((count, 0), dtype=np.int64)
        self.track_count = np.zeros(count, dtype=np.int64)
        self.track_stamp = np.full(count, np.nan)
        self.cloud_stamp = np.full(count, np.nan)
        self.point_velocity = np.zeros((count, 0, 2))
        self.point_kind = np.zeros((count, 0), dtype=np.int8)
        self.point_count = np.full(count, -1, dtype=np.int64)
        # outputs
        self.commands = np.zeros((count, 2))
        self.flags = np.zeros((count, 4), dtype=bool)
        self.events = np.zeros(count, dtype=np.int64)
        self.event_values = np.zeros(count)
        self.paces = np.ones(count)
        self.paused_since = np.full(count, np.nan)
        self.settling = np.zeros(count, dtype=bool)
        self.no_rates = np.ones(count)

    def references(self, show_times: FloatArray,
                   ) -> tuple[FloatArray, NDArray[np.bool_], FloatArray]:
        """What each follower tracks (R, 6: ``robot_batch_jit.grid_lookups``) at its show
        time (R,) s, whether its slot stands
        for good (R,) and where its mates should be (R, M, 2): ``RobotBrain._reference``,
        from the grid for all robots at once (``robot_batch_jit.grid_lookups``, a paced
        clock's times between two ticks interpolated there too) and from the brain where a
        time falls off it otherwise (before the show, an unpaced clock between ticks)."""
        rows, on, mates = self._jit.grid_lookups(
            self.grid, self.mates, self.period, self.grid_end, self.lead,
            np.ascontiguousarray(show_times, dtype=np.float64), self.stand_ends, BRIEF_STAND,
            self.paced, self.headings)
        if np.count_nonzero(on) < len(on):
            for i in np.flatnonzero(~on).tolist():
                brain, show_time = self.brains[i], float(show_times[i])
                exact = brain._reference(show_time)
                rows[i] = (*exact.pose, exact.speed, exact.angular_speed,
                           brain._place_stand(show_time))
        # a place that never moves again is final before the others reach theirs
        return rows, (show_times >= self.rest_from) | (rows[:, 5] == FOR_GOOD), mates

    def step(self, now: float, show_times: FloatArray, poses: FloatArray,
             pose_known: NDArray[np.bool_], arrived: list[PointCloud | None],
             heard: FloatArray | None, override: FloatArray | None = None,
             rates: FloatArray | None = None) -> BatchTick:
        """One tick of every robot (``RobotBrain.step`` with ``clock=now``): show times (R,)
        s; poses (R, 3) in each robot's own map frame where ``pose_known`` (R,); the clouds
        that arrived (None: none); ``heard`` (R, 2) where each robot last said it stands
        (show frame, NaN: nothing heard; None: no shared clock, ``mates_heard`` None);
        ``override`` (R, 5): references to track instead of the plan's where its row is not
        NaN (own frame; the ``shared-pose`` formation control), never final; ``rates`` (R,):
        the clock's rate of each since its last tick (paced brains; None: 1)."""
        count = len(self.brains)
        present = [cloud is not None for cloud in arrived]
        arrivals = np.array(present, dtype=bool)
        stamps = np.zeros(count)
        if any(present):
            for i, cloud in enumerate(arrived):
                if cloud is not None:
                    self.latest[i] = cloud.columns
                    self.height_steps[i] = cloud.height_step
                    stamps[i] = cloud.stamp
            self.columns = np.concatenate(self.latest) if count > 1 else self.latest[0]
            sizes = [len(c) for c in self.latest]
            self.offsets[1:] = list(accumulate(sizes))
            if self.rules[self._jit.PREDICTED] != 0.0:
                self._make_room_for_tracks(max(sizes))
        references, finals, mates = self.references(show_times)
        if override is not None:
            given = ~np.isnan(override[:, 0])
            references[given, :5] = override[given]
            references[given, 5] = 0.0
            finals = finals & ~given
        self._jit.brains_tick(
            now, np.ascontiguousarray(show_times, dtype=np.float64),
            np.ascontiguousarray(poses, dtype=np.float64), pose_known, arrivals, stamps,
            self.columns, self.offsets, self.height_steps, references, finals,
            mates, heard if heard is not None else np.zeros((count, 2)),
            heard is not None, self.frame_cos_sin, self.own_frames, self.sizes, self.limits,
            self.mate_radius, self.mate_body, self.gains, self.detect, self.rules, self.history,
            self.history_size, self.seen_from, self.has_seen_from, self.last_show_time,
            self.making_room, self.near_since, self.safety, self.lookup_failures,
            self.commands, self.flags, self.events, self.event_values, self.track_params,
            self.track_states, self.track_covariances, self.track_hits, self.track_misses,
            self.track_count, self.track_stamp, self.cloud_stamp, self.point_velocity,
            self.point_kind, self.point_count,
            self.no_rates if rates is None else np.ascontiguousarray(rates, dtype=np.float64),
            self.paces, self.paused_since, self.settling)
        status, holding, asking, waiting = self._jit.tick_outputs(self.flags, self.safety)
        events = (tuple((i, self._event(i)) for i in np.flatnonzero(self.events).tolist())
                  if np.count_nonzero(self.events) else ())
        return BatchTick(self.commands.copy(), status, holding, asking, waiting, events,
                         self.paces.copy())

    def _make_room_for_tracks(self, points: int) -> None:
        """Grow the tracker's arrays so that a cloud of up to ``points`` columns fits: every
        track now plus one new track per point, one velocity and kind per point."""
        tracks = max(self.track_count.tolist(), default=0) + points
        if tracks > self.track_states.shape[1]:
            grow = max(tracks, 2 * self.track_states.shape[1]) - self.track_states.shape[1]
            count = len(self.track_count)
            self.track_states = np.concatenate([self.track_states, np.zeros((count, grow, 4))],
                                               axis=1)
            self.track_covariances = np.concatenate(
                [self.track_covariances, np.zeros((count, grow, 4, 4))], axis=1)
            self.track_hits = np.concatenate(
                [self.track_hits, np.zeros((count, grow), dtype=np.int64)], axis=1)
            self.track_misses = np.concatenate(
                [self.track_misses, np.zeros((count, grow), dtype=np.int64)], axis=1)
        if points > self.point_velocity.shape[1]:
            grow = max(points, 2 * self.point_velocity.shape[1]) - self.point_velocity.shape[1]
            count = len(self.point_count)
            self.point_velocity = np.concatenate(
                [self.point_velocity, np.zeros((count, grow, 2))], axis=1)
            self.point_kind = np.concatenate(
                [self.point_kind, np.zeros((count, grow), dtype=np.int8)], axis=1)

    def _event(self, robot_index: int) -> Event:
        """The event of the kernel's code for ``robot_index`` (``safety_step``'s texts)."""
        jit, code = self._jit, int(self.events[robot_index])
        value = float(self.event_values[robot_index])
        if code == jit.EVENT_SPEECH:
            return Event("speech", STOP_SENTENCE)
        if code == jit.EVENT_BEEP:
            return Event("beep")
        if code == jit.EVENT_RESUME:
            return Event("resume", "the way is clear")
        if code == jit.EVENT_ERROR_POSE:
            return Event("error", f"{round(value)} consecutive failed pose look-ups")
        return Event("error", f"no LIDAR data for {value:.1f} s")
