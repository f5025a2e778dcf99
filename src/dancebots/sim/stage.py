"""The simulated world the robots live in: bodies, room, obstacles, spectators and LIDARs.

A :class:`Stage` is the thin mutable shell around the pure kernels (kinematics, collision
tests, ray casting, spectator walks). ``simulate`` steps it with the robots' brains in the
loop; the ROS bridge (``ros1/sim_bridge.py``) steps it with commands that arrive over ROS.
Each step of ``dt`` seconds: a robot whose last command is older than ``command_timeout``
stops (the robots' 10 Hz rule, thesis ch. 2), the actuation profile turns commands into
velocities, the robots move along exact unicycle arcs, and any robot whose move would run
into another robot, a wall, an obstacle or a spectator stays where it was (the contact is
counted and reported, never passed through). Noise comes from a seeded generator.
"""

from __future__ import annotations

import collections
import itertools
import math
import weakref
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import astuple, dataclass, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.geometry import (
    Pose,
    compose_poses,
    footprint_corners,
    frame_turns,
    integrate_unicycle,
    points_to_world,
    wrap_angles,
)
from dancebots.perception.cloud import PointCloud
from dancebots.sim.collision import (
    Boundaries,
    closing_speed,
    disc_contacts,
    footprint_gaps,
    overlapping_pairs,
    rectangles_overlap,
)
from dancebots.sim.crowd import (
    CrowdState,
    crowd_start,
    crowd_step,
    wall_rings,
    wall_segments,
)
from dancebots.sim.kernels import kernel
from dancebots.sim.kinematics import Profile, actuate, fresh_commands
from dancebots.sim.lidar import LidarConfig, LidarScene, scan_clouds, scan_ranges
from dancebots.sim.setup import Arena, Placement
from dancebots.sim.spectators import spectator_discs

if TYPE_CHECKING:
    from dancebots.sim.physics import PhysicsWorld

__all__ = ["APPROACH_SPAN", "STEP_BACK", "STEP_BACK_AFTER", "CollisionEvent", "ContactKind",
           "Stage", "period_due"]

ContactKind = Literal["robot", "wall", "obstacle", "spectator"]
"""What a robot touched (a closed choice: mypy checks every use)."""

FloatArray = NDArray[np.float64]

STEP_BACK_AFTER = 2.0
"""A visitor blocked by a robot this long (s) steps back ..."""
STEP_BACK = 1.5
"""... by this much of its walking time (s), to let the robot pass."""


MOVING_SPEED = 1e-3
"""m/s and rad/s: in the physics profiles a robot faster than this, or told to drive faster,
moves (the engine's speeds are never exactly 0: a standing robot shows about 1e-11)."""


APPROACH_SPAN = 0.5
"""s over which a contact's ``CollisionEvent.approach`` looks for the fastest step of the
person towards the robot."""


@dataclass(frozen=True, slots=True)
class CollisionEvent:
    """A contact that began at ``time`` s: ``robot`` against ``other`` (a robot, "wall" or an
    obstacle's name, or a spectator's); ``kind`` says which; (x, y) the robot's centre;
    ``moving``: whether the robot was moving when it began (any speed; in the physics
    profiles driving or told to drive faster than MOVING_SPEED): a robot
    that stood still was walked into (people in the simulator never step into a robot, so
    that happens only to a robot a person already overlaps); ``closing``: with a person, how
    fast (m/s) the robot's footprint moved towards them then (``collision.closing_speed``;
    negative: away; None for robots, walls and obstacles); ``approach``: with a person, the
    fastest (m/s) they came towards the robot's centre in a step of the last
    :data:`APPROACH_SPAN` s (negative: only away; None for robots, walls and obstacles): a
    child running at a robot at 2.5 m/s, beyond the 1.6 m/s walking speed of ISO 13855 that
    the stop rules assume, reads so in the contact."""

    time: float
    robot: str
    other: str
    kind: ContactKind
    x: float
    y: float
    moving: bool = True
    closing: float | None = None
    approach: float | None = None


class Stage:
    """The world of one show. Times are the stage's clock in s (the show time in
    ``simulate``); arrays hold one row per robot of ``placement`` (R robots).

    pose (R, 3) world x, y, theta; velocity (R, 2) actual (v, w); discs (C, 3) spectators
    (x, y, radius); collisions: contacts so far; scans: with ``record_lidar``, every scan as
    (time it reached the robots, per robot its hits (M, 2) in the world frame).
    """

    def __init__(self, arena: Arena, placement: Placement, profile: Profile, dt: float,
                 lidar: LidarConfig | None, command_timeout: float = 0.1, seed: int = 0,
                 record_lidar: bool = False, compiled: bool = True,
                 scan_ahead: bool = False) -> None:
        self.compiled = compiled  # collision tests compiled with numba, else NumPy
        # scans cast on a second thread while the caller goes on (:meth:`deliveries`)
        self.scan_ahead = scan_ahead
        self._scanner: ThreadPoolExecutor | None = None
        self.arena, self.placement, self.profile, self.dt = arena, placement, profile, dt
        self.lidar, self.command_timeout, self.record_lidar = lidar, command_timeout, record_lidar
        self.rng = np.random.default_rng(seed)
        count = len(placement.robots)
        starts = placement.starts.astype(float)
        self.to_own = np.array([astuple(Pose(*(float(v) for v in starts[i])).inverse())
                                for i in range(count)]).reshape(count, 3)
        self._to_own_turn = frame_turns(self.to_own)  # (:meth:`own_poses`, every tick)
        self.lengths = np.array([t.length for t in placement.types])
        self.widths = np.array([t.width for t in placement.types])
        self.reach = 0.5 * np.hypot(self.lengths, self.widths)
        self.limits = np.array([[t.max_speed, t.max_angular_speed] for t in placement.types])
        self.boundaries = Boundaries(arena.room, [o.polygon for o in arena.obstacles],
                                     compiled)
        self.names = {-1: "wall", **{k: o.name for k, o in enumerate(arena.obstacles)}}
        self.scene = LidarScene.build(arena.room, arena.wall_height,
                                      [(o.polygon, o.height) for o in arena.obstacles])
        self.spectators = arena.spectators
        self.walked = np.zeros(len(self.spectators))
        self.waiting = np.zeros(len(self.spectators))
        self.crowd: CrowdState | None = None
        self.speaking = np.zeros(count, dtype=bool)  # robots stopped for people, speaking
        if arena.crowds:  # its own generator: a crowd leaves the robots' noise as it was
            self.crowd_rng = np.random.default_rng([seed, *(c.seed for c in arena.crowds)])
            self.walls = wall_segments(arena.room, arena.obstacles)
            self.wall_rings = wall_rings(arena.room, arena.obstacles)
            keep_clear = shapely.union_all([shapely.Polygon(o.polygon)
                                            for o in arena.obstacles]) if arena.obstacles else None
            try:
                self.crowd = crowd_start(arena.crowds, starts, self.reach, keep_clear,
                                         self.walls, self.crowd_rng)
            except ValueError as exc:
                from dancebots.sim.setup import SetupError

                raise SetupError(f"{exc}: enlarge its area, lower its count or keep it away "
                                 "from the robots' start poses and the walls") from None
        self.disc_names = (*(p.name for p in self.spectators),
                           *(self.crowd.names if self.crowd is not None else ()))
        self.disc_heights = np.array([p.height for p in self.spectators] + (
            self.crowd.height.tolist() if self.crowd is not None else []))
        self.discs = self._discs(spectator_discs(self.spectators, self.walked))
        # the people's discs over the last APPROACH_SPAN s (a contact's run-up)
        self._disc_track: collections.deque[FloatArray] = collections.deque(
            [self.discs], maxlen=round(APPROACH_SPAN / self.dt) + 1)
        self.physics: PhysicsWorld | None = None
        if profile.engine == "mujoco":  # the physics profile: MuJoCo moves the robots
            from dancebots.sim.physics import PhysicsWorld

            self.physics = PhysicsWorld(
                placement.types, starts, arena.room, arena.wall_height,
                [(o.polygon, o.height) for o in arena.obstacles],
                np.column_stack([self.discs[:, 2], self.disc_heights]),
                "geometric" if profile.drive == "geometric" else "calibrated")
        self._free_step_data: tuple[Any, ...] | None = None
        self._noisy = profile.linear_noise > 0.0 or profile.angular_noise > 0.0
        self._no_noise = np.zeros((count, 2))  # the free step's draws in a quiet profile
        if compiled and self.physics is None:
            # a step free of contacts in one compiled call (``sim.stage_jit``)
            obstacles = [np.asarray(o.polygon, dtype=float).reshape(-1, 2)
                         for o in arena.obstacles]
            lagging = profile.lag > 0.0
            self._free_step_data = (
                lagging, 1.0 - math.exp(-dt / profile.lag) if lagging else 0.0,
                np.array([profile.linear_acceleration, profile.angular_acceleration]) * dt,
                np.array(profile.standstill, dtype=float), float(dt), self.lengths,
                self.widths, self.reach, np.ascontiguousarray(arena.room, dtype=float),
                np.concatenate(obstacles) if obstacles else np.zeros((0, 2)),
                np.concatenate([[0], np.cumsum([len(o) for o in obstacles])]).astype(np.int64),
                *self.boundaries.edges(), self._noisy,
                np.array([profile.linear_noise, profile.angular_noise]))
        self.pose = starts.copy()
        self.velocity = np.zeros((count, 2))
        # this step's commands (R, 2), when (R,) s and now (s), among crowds (:meth:`_standing`)
        self._given: tuple[FloatArray, FloatArray, float] = (
            np.zeros((count, 2)), np.full(count, -math.inf), 0.0)
        self.corners = self._footprints(self.pose)  # where the robots stand now
        self.pending: list[tuple[float, list[PointCloud] | Future[list[PointCloud]]]] = []
        self.planar_pending: list[tuple[float, float, FloatArray, FloatArray]] = []
        self.collisions: list[CollisionEvent] = []
        self.scans: list[tuple[float, tuple[FloatArray, ...]]] = []
        self._active: dict[tuple[int, int | str], float] = {}
        if lidar is not None:  # the LIDARs run before the start: clouds arrive from t = 0
            for k in range(-math.ceil(lidar.latency / lidar.period - 1e-9), 0):
                stamp = k * lidar.period
                self.pending.append((stamp + lidar.latency, scan_clouds(
                    lidar, stamp, self.pose, self.corners, self.scene, self.discs,
                    self.disc_heights)))

    def deliveries(self, now: float) -> list[PointCloud | None]:
        """Scan when a LIDAR period is due at ``now``, and return each robot's cloud that
        reaches it at ``now`` after the LIDAR's latency (None for robots that get none).

        With ``scan_ahead`` (and a compiled LIDAR with a latency, scans not recorded) the
        scan is cast on a second thread: the caster lets go of Python's lock, so it runs
        on the other core while the caller decides and moves the robots, and its clouds are
        taken when they reach the robots, the latency later. The same clouds: the scan reads
        copies of the stage's arrays at ``now``."""
        count = len(self.pose)
        lidar = self.lidar
        if lidar is not None and period_due(now, lidar.period):
            if (self.scan_ahead and lidar.compiled and lidar.latency > 1e-9
                    and not self.record_lidar):
                if self._scanner is None:
                    self._scanner = ThreadPoolExecutor(1, thread_name_prefix="dancebots-lidar")
                    weakref.finalize(self, self._scanner.shutdown, wait=False)
                self.pending.append((now + lidar.latency, self._scanner.submit(
                    scan_clouds, lidar, now, self.pose.copy(), self.corners.copy(),
                    self.scene, self.discs.copy(), self.disc_heights)))
            else:
                clouds = scan_clouds(lidar, now, self.pose, self.corners, self.scene,
                                     self.discs, self.disc_heights)
                self.pending.append((now + lidar.latency, clouds))
                if self.record_lidar:
                    self.scans.append((now + lidar.latency, _world_points(clouds, self.pose)))
        arrived: list[PointCloud | None] = [None] * count
        while self.pending and self.pending[0][0] <= now + 1e-9:
            scan = self.pending.pop(0)[1]
            arrived = list(scan.result() if isinstance(scan, Future) else scan)
        return arrived

    def close(self, check: bool = True) -> None:
        """Let the scanning thread go (``scan_ahead``; the scans not begun yet are dropped),
        then, with ``check``, raise the error of a scan cast but never taken (a stage can
        still step after)."""
        if self._scanner is None:
            return
        self._scanner.shutdown(wait=True, cancel_futures=True)
        self._scanner = None
        scans = [scan for _, scan in self.pending if isinstance(scan, Future)]
        self.pending = [(due, scan) for due, scan in self.pending
                        if not isinstance(scan, Future)]
        for scan in scans:
            error = None if scan.cancelled() else scan.exception()
            if check and error is not None:
                raise error

    def planar_deliveries(self, now: float, lidar: LidarConfig,
                          ) -> list[tuple[float, FloatArray, FloatArray]]:
        """The planar LIDARs of the queue show: when a period of ``lidar`` is due at ``now``
        every robot scans (ranges (R, N) in m along ``lidar.angles()``, taken at the robots'
        poses (R, 3)); returns the scans (stamp s, ranges, poses) that reach the robots at
        ``now`` after the latency, oldest first."""
        if period_due(now, lidar.period):
            ranges = scan_ranges(lidar, self.pose, self.corners, self.scene, self.discs,
                                 self.disc_heights)
            self.planar_pending.append((now + lidar.latency, now, ranges, self.pose.copy()))
        arrived = []
        while self.planar_pending and self.planar_pending[0][0] <= now + 1e-9:
            _, stamp, ranges, poses = self.planar_pending.pop(0)
            arrived.append((stamp, ranges, poses))
        return arrived

    def own_poses(self) -> FloatArray:
        """Each robot's pose (R, 3) in its own map frame (its start pose is the origin)."""
        if self.compiled:  # the same operations in one call
            own: FloatArray = kernel("sim.stage_jit").compose_turned(
                self.to_own, *self._to_own_turn, self.pose)
            return own
        return compose_poses(self.to_own, self.pose, self._to_own_turn)

    def advance(self, now: float, command: FloatArray, issued: FloatArray) -> None:
        """Move everything by one ``dt`` from ``now``: commands (R, 2) (v, w) issued at
        ``issued`` (R,) s act under the 10 Hz rule; contacts block and are recorded."""
        # the profile's noise, drawn once for whichever way the step goes (``actuate``)
        noise = (self.rng.normal(0.0, 1.0, size=self.velocity.shape) if self._noisy
                 and self.physics is None else None)
        if self.crowd is not None:  # (the crowd tells standing robots from moving ones)
            self._given = (command, issued, now)
        if self._free_step_data is not None:
            proposed, corners, velocity, free = kernel("sim.stage_jit").free_step(
                self.pose, self.velocity, np.ascontiguousarray(command, dtype=float),
                np.ascontiguousarray(issued, dtype=float), float(now),
                float(self.command_timeout), self.limits,
                noise if noise is not None else self._no_noise, self.discs,
                *self._free_step_data)
            if free:  # no contact, none near: what the steps below give, in one call
                self.pose, self.corners, self.velocity = proposed, corners, velocity
                if len(self.discs):
                    self._walk_spectators()
                return
        dt, count = self.dt, len(self.pose)
        pose, corners_now = self.pose, self.corners
        wanted = fresh_commands(np.clip(command, -self.limits, self.limits), issued, now,
                                self.command_timeout)
        if self.physics is not None:  # the engine moves them, its contacts push back
            before = np.maximum(np.abs(self.velocity), np.abs(wanted))
            proposed, velocity = self.physics.step(wanted, dt, self.discs)
            # moving: driven or told to drive into it (after the step a contact has stopped
            # it; the engine's speeds are never exactly 0)
            moving = np.any(np.maximum(before, np.abs(velocity)) > MOVING_SPEED, axis=1)
        else:
            velocity = actuate(self.profile, self.velocity, wanted, dt, self.rng, noise)
            moving = np.any(velocity != 0.0, axis=1)  # before a contact blocks it
            x, y, theta = integrate_unicycle(pose[:, 0], pose[:, 1], pose[:, 2],
                                             velocity[:, 0], velocity[:, 1], np.full(count, dt))
            proposed = np.stack([x, y, wrap_angles(theta)], axis=1)
        corners = self._footprints(proposed)
        blocked = np.zeros(count, dtype=bool)
        contacts: list[tuple[int, int | str, ContactKind, int]] = []  # (disc or -1)
        pairs = overlapping_pairs(corners, self.reach, self.compiled)
        if pairs:
            # a robot is stopped when its move runs into where the other one stands now;
            # one that moves away from a contact goes on (else touching robots lock up)
            first, second = np.array(pairs).T
            first_in = rectangles_overlap(corners[first], corners_now[second])
            second_in = rectangles_overlap(corners_now[first], corners[second])
            for (i, j), a, b in zip(pairs, first_in.tolist(), second_in.tolist(), strict=True):
                if a or not b:
                    blocked[i] = True
                if b or not a:
                    blocked[j] = True
                contacts.append((i, self.placement.robots[j], "robot", -1))
        for i, what in self.boundaries.contacts(corners, self.reach):
            blocked[i] = True
            contacts.append((i, self.names[what], "wall" if what == -1 else "obstacle", -1))
        if len(self.discs):
            for i, k in disc_contacts(proposed, self.lengths, self.widths, self.discs):
                blocked[i] = True
                contacts.append((i, self.disc_names[k], "spectator", k))
        # how each robot drove into the step (in the engine a contact has already stopped
        # it: what it was told)
        driven = velocity if self.physics is None else wanted
        for i, other, kind, disc in contacts:
            key = (i, other)
            if now + dt - self._active.get(key, -math.inf) > 1.0:  # a new contact
                self.collisions.append(CollisionEvent(
                    round(now + dt, 6), self.placement.robots[i], str(other), kind,
                    float(pose[i, 0]), float(pose[i, 1]), bool(moving[i]),
                    closing_speed(pose[i], driven[i], float(self.lengths[i]),
                                  float(self.widths[i]), self.discs[disc, :2])
                    if disc >= 0 else None,
                    self._approach(disc, pose[i]) if disc >= 0 else None))
            self._active[key] = now + dt
        if self.physics is None:  # in the engine the bodies' contacts stop them
            proposed[blocked] = pose[blocked]
            corners[blocked] = corners_now[blocked]
            velocity[blocked] = 0.0
        self.pose, self.corners, self.velocity = proposed, corners, velocity
        if len(self.discs):
            self._walk_spectators()

    def _walk_spectators(self) -> None:
        """Visitors walk on unless a robot stands where they would step; one kept waiting
        for STEP_BACK_AFTER s steps back along its way to let the robot pass."""
        spectators, dt = self.spectators, self.dt
        scripted = np.zeros((0, 3))  # (no scripted spectators)
        if spectators:
            ahead = spectator_discs(spectators, self.walked + dt)
            now = spectator_discs(spectators, self.walked)
            free = ~self._steps_into_robots(now[:, :2], ahead[:, :2], now[:, 2])
            self.waiting = np.where(free, 0.0, self.waiting + dt)
            walked = self.walked + np.where(free, dt, 0.0)
            for k in np.flatnonzero(self.waiting >= STEP_BACK_AFTER).tolist():
                back = walked.copy()
                back[k] = max(spectators[k].start, walked[k] - STEP_BACK)
                if not any(j == k for _, j in disc_contacts(
                        self.pose, self.lengths, self.widths,
                        spectator_discs(spectators, back))):
                    walked = back
                self.waiting[k] = 0.0
            self.walked = walked
            scripted = spectator_discs(spectators, walked)
        crowd = self.crowd
        if crowd is not None:
            moved = crowd_step(crowd, dt, [c.area for c in self.arena.crowds], self.walls,
                               self.pose, self.lengths, self.widths, self.crowd_rng,
                               speaking=self.speaking, rings=self.wall_rings,
                               compiled=self.compiled, robot_standing=self._standing())
            stands = self._steps_into_robots(crowd.position, moved.position, crowd.radius)
            if np.count_nonzero(stands):
                position, velocity = moved.position.copy(), moved.velocity.copy()
                position[stands], velocity[stands] = crowd.position[stands], 0.0
                moved = replace(moved, position=position, velocity=velocity)
            self.crowd = moved
        self.discs = self._discs(scripted)
        self._disc_track.append(self.discs)

    def _standing(self) -> NDArray[np.bool_]:
        """(R,) the robots standing still: no speed nor command of this step above
        :data:`MOVING_SPEED` (m/s and rad/s; a robot told to drive moves, whatever its lag):
        a person walking out of the formation squeezes past these
        (``crowd.LEAVING_RANGE``)."""
        command, issued, now = self._given
        if self.compiled:  # the same comparisons in one call
            standing: NDArray[np.bool_] = kernel("sim.crowd_jit").robots_standing(
                self.velocity, np.ascontiguousarray(command, dtype=float),
                np.ascontiguousarray(issued, dtype=float), float(now),
                float(self.command_timeout), self.limits, MOVING_SPEED)
            return standing
        commanded = fresh_commands(np.clip(command, -self.limits, self.limits), issued, now,
                                   self.command_timeout)
        result: NDArray[np.bool_] = (np.all(np.abs(self.velocity) <= MOVING_SPEED, axis=1)
                                     & np.all(np.abs(commanded) <= MOVING_SPEED, axis=1))
        return result

    def _steps_into_robots(self, before: FloatArray, after: FloatArray,
                           radii: FloatArray) -> NDArray[np.bool_]:
        """(P,) the people (centres (P, 2) before and after a step, disc radii (P,)) whose step
        would reach into a robot's footprint from outside: people do not walk into robots,
        so they stand instead; one who already stands in a robot walks on (out of it)."""
        if self.compiled and len(self.pose):
            result_jit: NDArray[np.bool_] = kernel("sim.crowd_jit").steps_into_robots(
                np.ascontiguousarray(before, dtype=float), np.ascontiguousarray(after, dtype=float),
                np.ascontiguousarray(radii, dtype=float), self.pose, self.lengths, self.widths)
            return result_jit
        gap_before = _footprint_gaps(self.pose, self.lengths, self.widths, before)
        gap_after = _footprint_gaps(self.pose, self.lengths, self.widths, after)
        result: NDArray[np.bool_] = (gap_after < radii) & (gap_before >= radii)
        return result

    def _approach(self, disc: int, pose: FloatArray) -> float:
        """m/s: the fastest person ``disc`` (an index of ``discs``) came towards the centre of
        a robot at ``pose`` (3,) in a step of the last :data:`APPROACH_SPAN` s: a person
        stands rather than step into a robot, so their speed at the contact itself is nil;
        this is their run-up (a child running at a robot: about 2.5 m/s). 0 without a step
        to measure."""
        centre = pose[:2]
        distances = [math.hypot(float(d[disc, 0] - centre[0]), float(d[disc, 1] - centre[1]))
                     for d in self._disc_track if len(d) == len(self.discs)]
        steps = [(a - b) / self.dt for a, b in itertools.pairwise(distances)]
        return max(steps, default=0.0)

    def _discs(self, scripted: FloatArray) -> FloatArray:
        """All people as discs (C, 3) = x, y, radius: the scripted spectators, then the
        crowds' pedestrians."""
        if self.crowd is None:
            return scripted
        scripted = scripted.reshape(-1, 3)
        discs = np.empty((len(scripted) + len(self.crowd.radius), 3))
        discs[:len(scripted)] = scripted
        discs[len(scripted):, :2] = self.crowd.position
        discs[len(scripted):, 2] = self.crowd.radius
        return discs

    def _footprints(self, poses: FloatArray) -> FloatArray:
        return footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], self.lengths,
                                 self.widths)


def _footprint_gaps(poses: FloatArray, lengths: FloatArray, widths: FloatArray,
                    points: FloatArray) -> FloatArray:
    """The distance (P,) from each point (P, 2) to the nearest robot footprint (poses (R, 3),
    sizes (R,)), m; 0 inside one, inf without robots."""
    if len(poses) == 0:
        return np.full(len(points), math.inf)
    result: FloatArray = footprint_gaps(points[None, :, :], poses[:, None, :],
                                        lengths[:, None], widths[:, None]).min(axis=0)
    return result


def _world_points(clouds: list[PointCloud], poses: FloatArray) -> tuple[FloatArray, ...]:
    """Each robot's hits (M, 2) in the world frame, from its cloud and its pose (R, 3)."""
    return tuple(points_to_world(cloud.columns[:, :2], (x, y, theta))
                 for cloud, (x, y, theta) in zip(clouds, poses.tolist(), strict=True))


def period_due(now: float, period: float) -> bool:
    """Is ``now`` a multiple of ``period`` (within rounding)?"""
    k = round(now / period)
    return abs(k * period - now) < 1e-6

