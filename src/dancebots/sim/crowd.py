"""Crowds that react: pedestrians walking with the social force model of Helbing and Molnár,
"Social force model for pedestrian dynamics", Phys. Rev. E 51 (1995) 4282 (H&M below).

Each pedestrian a (position r_a, velocity v_a, preferred speed v0_a) accelerates as

    dv_a/dt = (v0_a e_a - v_a) / tau                     (H&M eq. 2: towards its goal)
              + sum_b w(e_a, -f_ab) f_ab                  (eq. 3-5: other pedestrians)
              + sum_B f_aB                                (eq. 6: walls, obstacles, robots)

with f_ab = -grad V0 exp(-b/sigma), b the semi-minor axis of the ellipse around b's next
step (eq. 4), f_aB = -grad U0 exp(-|r_aB|/R) from the nearest point of each border, and
w = 1 for what lies within the field of view (2 phi) of the walking direction e_a, c
outside it. Its speed is capped at 1.3 v0_a (eq. 7). The parameters are the paper's (tau
0.5 s, V0 2.1 m²/s², sigma 0.3 m, U0 10 m²/s², R 0.2 m, step 2 s, phi 100 deg, c 0.5).
Robots are borders too: their footprints' nearest points, with a range of their own per
kind of pedestrian (adults keep further from a machine than children do).

What a pedestrian wants is this module's own (H&M's pedestrians walk to fixed destinations):
a goal drawn at random in its crowd's area, or, with a kind's probability, a point near a
robot to watch it from; on arrival it stands a random while, then picks the next goal.
Children change their mind at random too. A standing pedestrian still feels the forces: one
a robot comes close to steps aside.

Pure functions on a frozen :class:`CrowdState` (arrays of P pedestrians, world frame, m,
m/s); randomness only from the ``numpy.random.Generator`` passed in. The simulator
(``sim.stage``) keeps a pedestrian whose step would overlap a robot where it stands: people
do not walk into robots, so a contact is a robot's doing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields, replace
from functools import lru_cache
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.sim.kernels import kernel
from dancebots.world.model import Crowd, Obstacle

__all__ = ["KIND_BEHAVIOUR", "LEAVING_RANGE", "CrowdState", "KindBehaviour",
           "SocialForceParams", "crowd_start", "crowd_step", "social_acceleration",
           "wall_rings", "wall_segments"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, slots=True)
class SocialForceParams:
    """H&M's parameters: relaxation time tau (s); pedestrian repulsion V0 (m²/s²) and range
    sigma (m); border repulsion U0 (m²/s²) and range R (m); the step time (s) of eq. 4;
    half the field of view phi (rad) and the weight c outside it; the speed cap as a
    multiple of the preferred speed; ``substep``: the integration step (s)."""

    relaxation: float = 0.5
    pedestrian_strength: float = 2.1
    pedestrian_range: float = 0.3
    border_strength: float = 10.0
    border_range: float = 0.2
    step_time: float = 2.0
    sight: float = math.radians(100.0)
    out_of_sight: float = 0.5
    max_speed_factor: float = 1.3
    substep: float = 0.1


@dataclass(frozen=True, slots=True)
class KindBehaviour:
    """What a kind of pedestrian wants: the probability that a new goal is a place to watch a
    robot from, at ``watch_near`` to ``watch_far`` m beyond the robot's half diagonal; the
    pause at a goal (``pause_min`` to ``pause_max`` s); the rate (1/s) of changing its mind
    on the way; the range (m) of a robot's repulsion (H&M's R for robots); the rate (1/s) at
    which it heeds a robot that stopped for people and speaks (thesis 5.2: "Obstacle is too
    close, I have to stop") within :data:`HEARING` of it: it stops pausing and steps away;
    and the distance (m) at which a goal counts as reached."""

    watch: float
    watch_near: float
    watch_far: float
    pause_min: float
    pause_max: float
    change_rate: float
    robot_range: float
    heed: float
    arrive: float = 0.3


KIND_BEHAVIOUR = {
    "adult": KindBehaviour(watch=0.4, watch_near=0.8, watch_far=2.0, pause_min=3.0,
                           pause_max=12.0, change_rate=0.0, robot_range=0.5, heed=2.0),
    "child": KindBehaviour(watch=0.6, watch_near=0.3, watch_far=1.2, pause_min=0.5,
                           pause_max=5.0, change_rate=0.15, robot_range=0.25, heed=0.5),
}
"""Each kind's behaviour (``world.CROWD_KINDS`` holds its size and speed)."""

_BEHAVIOUR_FIELDS = ("watch", "watch_near", "watch_far", "pause_min", "pause_max",
                     "change_rate", "robot_range", "heed", "arrive")
_PAUSE_COLUMNS = np.array([_BEHAVIOUR_FIELDS.index(field) for field in (
    "arrive", "pause_min", "pause_max", "change_rate")], dtype=np.int64)
"""``crowd_jit.pauses``' columns of ``CrowdState.behaviour``."""
HEARING = 2.0
"""m from a speaking robot's footprint (about) within which people hear it."""
ROOM_MADE = (1.5, 3.0)
"""m: how far a person who heeds a speaking robot walks away (``_make_room``)."""
LEAVING_RANGE = 0.3
"""The share of its kind's robot range (H&M's R for robots) that a person keeps from a robot
standing still while it walks out of the formation (it heeded a robot's request for room
from inside the convex hull of the robots' centres): a real child squeezes out between two
parked robots 0.6 m apart. With the whole range the pushes of four standing robots held a
simulated person in the middle of a standing 2 x 2 formation, which waited for it until the
run's end (open-day crowd seeds 37, 138, 205, 319, 833, 880, 959 of 1,000, 7ed8825). From
a robot that moves it keeps the whole range: with the share for moving robots too, a
child walking out ran into a robot that had moved on (seeds 578, 814; docs/safety.md). The
push keeps the whole range's strength at the border (U0 / R), so with the share it is
weaker at every distance, never stronger (:meth:`CrowdState.robot_push`)."""
SHARE_TIME = 0.5
"""s: the time constant with which a person's share of its range from a robot follows
:data:`LEAVING_RANGE` or 1 (a person steps away from a robot that starts to move within
about a second; a jump of the share flung a child squeezing past a robot that started to
move into the next robot, open-day crowd seed 626 of 2234eb8)."""


@dataclass(frozen=True, slots=True, eq=False)
class CrowdState:
    """P pedestrians: position (P, 2) and velocity (P, 2) in the world frame (m, m/s), goal
    (P, 2), pause (P,) s left to stand at the goal (0 while walking), preferred speed (P,)
    m/s, radius and height (P,) m, crowd (P,) the index of each one's crowd, behaviour
    (P, 9) the columns of :class:`KindBehaviour` per pedestrian, names (P,); leaving (P,):
    walking out of the formation because a robot asked for room (:func:`_make_room`), until
    it reaches that goal or picks another (None: nobody); robot_share (P, R): the share of
    its robot range each keeps from each robot (:data:`LEAVING_RANGE`, :data:`SHARE_TIME`;
    None: the whole range from every robot)."""

    position: FloatArray
    velocity: FloatArray
    goal: FloatArray
    pause: FloatArray
    preferred: FloatArray
    radius: FloatArray
    height: FloatArray
    crowd: IntArray
    behaviour: FloatArray
    names: tuple[str, ...]
    leaving: NDArray[np.bool_] | None = None
    robot_share: FloatArray | None = None

    def column(self, field: str) -> FloatArray:
        """One :class:`KindBehaviour` field (P,) of every pedestrian."""
        return self.behaviour[:, _BEHAVIOUR_FIELDS.index(field)]

    def robot_push(self, robots: int) -> tuple[FloatArray, FloatArray]:
        """Each robot's push on each pedestrian (H&M eq. 6 for robots) as its strength and
        range (P, R): the kind's range times the share kept from that robot
        (``robot_share``), the strength U0 (``SocialForceParams.border_strength``, a factor
        here) times the share, so the push at the border stays U0 / R and is weaker than the
        whole range's at every distance."""
        ranges = np.repeat(self.column("robot_range")[:, None], robots, axis=1)
        share = self.robot_share
        if share is None or share.shape != ranges.shape:
            return np.ones_like(ranges), ranges
        return share, ranges * share


def wall_segments(room: FloatArray, obstacles: Sequence[Obstacle]) -> FloatArray:
    """The borders as segments (S, 2, 2): the room's edges and every obstacle's edges."""
    rings = [room, *(o.polygon for o in obstacles)]
    return np.concatenate([np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)
                           for ring in rings])


def wall_rings(room: FloatArray, obstacles: Sequence[Obstacle]) -> IntArray:
    """(S,) the border (0: the room, k: obstacle k - 1) of each of :func:`wall_segments`."""
    sizes = [len(room), *(len(o.polygon) for o in obstacles)]
    return np.repeat(np.arange(len(sizes)), sizes)


def _nearest_per_border(vectors: FloatArray, rings: IntArray) -> FloatArray:
    """Of vectors (P, S, 2) from each segment's nearest point, the one from each border's
    nearest point (P, B, 2) (borders: ``rings`` (S,), contiguous): H&M's eq. 6 sums over
    borders, so a corner, the nearest point of two edges, pushes once."""
    distance = np.hypot(vectors[..., 0], vectors[..., 1])  # (P, S)
    starts = np.flatnonzero(np.r_[True, rings[1:] != rings[:-1]])
    chosen = [start + np.argmin(distance[:, start:end], axis=1)
              for start, end in zip(starts, [*starts[1:], len(rings)], strict=True)]
    picks = np.stack(chosen, axis=1)  # (P, B)
    result: FloatArray = np.take_along_axis(vectors, picks[..., None], axis=1)
    return result


def _nearest_on_segments(points: FloatArray, segments: FloatArray) -> FloatArray:
    """Vectors (P, S, 2) from the nearest point of each segment (S, 2, 2) to each point
    (P, 2)."""
    start, end = segments[:, 0], segments[:, 1]
    along = end - start  # (S, 2)
    length2 = np.maximum(np.einsum("sk,sk->s", along, along), 1e-12)
    rel = points[:, None, :] - start[None]  # (P, S, 2)
    t = np.clip(np.einsum("psk,sk->ps", rel, along) / length2, 0.0, 1.0)
    result: FloatArray = rel - t[..., None] * along[None]
    return result


def _from_footprints(points: FloatArray, poses: FloatArray, lengths: FloatArray,
                     widths: FloatArray) -> FloatArray:
    """Vectors (P, R, 2), world frame, from each robot's footprint (poses (R, 3), sizes (R,))
    nearest point to each point (P, 2); a point inside a footprint gets the vector from the
    robot's centre instead (it is pushed out the way it lies)."""
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])  # (R,)
    dx = points[:, None, 0] - poses[None, :, 0]  # (P, R)
    dy = points[:, None, 1] - poses[None, :, 1]
    lx, ly = c * dx + s * dy, -s * dx + c * dy  # in each robot's frame
    ex = lx - np.clip(lx, -0.5 * lengths, 0.5 * lengths)
    ey = ly - np.clip(ly, -0.5 * widths, 0.5 * widths)
    inside = (ex == 0.0) & (ey == 0.0)
    ex, ey = np.where(inside, lx, ex), np.where(inside, ly, ey)
    return np.stack([c * ex - s * ey, s * ex + c * ey], axis=-1)


def _border_force(vectors: FloatArray, strength: FloatArray | float,
                  reach: FloatArray | float) -> FloatArray:
    """H&M eq. 6 summed over borders: vectors (P, B, 2) from each border's nearest point;
    -grad U0 exp(-d/R) = (U0/R) exp(-d/R) d_hat. Returns (P, 2)."""
    distance = np.hypot(vectors[..., 0], vectors[..., 1])
    safe = np.maximum(distance, 1e-9)
    magnitude = strength / reach * np.exp(-distance / reach) / safe  # (P, B)
    result: FloatArray = (magnitude[..., None] * vectors).sum(axis=1)
    return result


def social_acceleration(state: CrowdState, walls: FloatArray, robot_poses: FloatArray,
                        robot_lengths: FloatArray, robot_widths: FloatArray,
                        params: SocialForceParams = SocialForceParams(),
                        rings: IntArray | None = None,
                        wall_vectors: FloatArray | None = None) -> FloatArray:
    """dv/dt (P, 2) of every pedestrian (H&M eq. 2-6, module docstring): towards its goal
    (or to a stand while it pauses), away from the others, the walls (segments (S, 2, 2);
    ``rings`` (S,) the border of each, :func:`wall_rings`: each border pushes from its
    nearest point; None: each segment is a border) and the robots (poses (R, 3), lengths
    and widths (R,); each pushes as :meth:`CrowdState.robot_push` says);
    ``wall_vectors``: :func:`_nearest_on_segments` of the positions and walls when the
    caller has them already."""
    position, velocity = state.position, state.velocity
    count = len(position)
    to_goal = state.goal - position
    distance = np.hypot(to_goal[:, 0], to_goal[:, 1])
    direction = to_goal / np.maximum(distance, 1e-9)[:, None]  # e_a
    walking = state.pause <= 0.0
    desired = np.where(walking[:, None], state.preferred[:, None] * direction, 0.0)
    accel = (desired - velocity) / params.relaxation  # eq. 2
    if count > 1:  # eq. 3-5: the ellipse b spanned by r_ab and r_ab - v_b step e_b
        r = position[:, None, :] - position[None, :, :]  # r_ab (P, P, 2)
        step = params.step_time * velocity[None, :, :]  # v_b step e_b
        r_next = r - step
        n_r = np.hypot(r[..., 0], r[..., 1])
        n_next = np.hypot(r_next[..., 0], r_next[..., 1])
        n_step = np.hypot(step[..., 0], step[..., 1])
        b = 0.5 * np.sqrt(np.maximum((n_r + n_next) ** 2 - n_step ** 2, 1e-12))
        grad_b = ((n_r + n_next) / (4.0 * b))[..., None] * (
            r / np.maximum(n_r, 1e-9)[..., None] + r_next / np.maximum(n_next, 1e-9)[..., None])
        force = (params.pedestrian_strength / params.pedestrian_range
                 * np.exp(-b / params.pedestrian_range))[..., None] * grad_b  # f_ab
        np.einsum("aak->ak", force)[...] = 0.0  # no force of one on itself
        heading = np.where(walking[:, None], direction, velocity / np.maximum(
            np.hypot(velocity[:, 0], velocity[:, 1]), 1e-9)[:, None])
        seen = np.einsum("ak,abk->ab", heading, -force) >= np.hypot(
            force[..., 0], force[..., 1]) * math.cos(params.sight)  # eq. 5
        accel += (np.where(seen, 1.0, params.out_of_sight)[..., None] * force).sum(axis=1)
    if len(walls):
        vectors = (_nearest_on_segments(position, walls) if wall_vectors is None
                   else wall_vectors)
        if rings is not None:
            vectors = _nearest_per_border(vectors, rings)
        accel += _border_force(vectors, params.border_strength,
                               params.border_range)
    if len(robot_poses):
        strength, reach = state.robot_push(len(robot_poses))
        accel += _border_force(
            _from_footprints(position, robot_poses, robot_lengths, robot_widths),
            params.border_strength * strength, reach)
    return accel


@lru_cache(maxsize=64)
def _area_polygon(corners: bytes) -> shapely.Polygon:
    """The prepared polygon of an area's corners (the bytes of a (K, 2) float array): built
    once per area, not at every goal drawn."""
    polygon = shapely.Polygon(np.frombuffer(corners, dtype=np.float64).reshape(-1, 2))
    shapely.prepare(polygon)
    return polygon


def _inside(area: FloatArray, points: FloatArray) -> NDArray[np.bool_]:
    """Which points (N, 2) lie inside the polygon ``area`` (K, 2)."""
    polygon = _area_polygon(np.ascontiguousarray(area, dtype=np.float64).tobytes())
    result: NDArray[np.bool_] = shapely.contains_xy(polygon, points[:, 0], points[:, 1])
    return result


WALL_CLEARANCE = 0.15
"""m: goals and start places keep a disc this far from every wall and obstacle edge."""


def _random_in(area: FloatArray, count: int, rng: np.random.Generator, walls: FloatArray,
               radius: float, compiled: bool = False) -> FloatArray:
    """``count`` points (count, 2) uniform in the polygon ``area`` (rejection from its box),
    each at least ``radius`` + :data:`WALL_CLEARANCE` from the walls (S, 2, 2); fewer when
    2,000 draws found no more (an area hardly wider than a disc). ``compiled``: the wall
    distances by ``crowd_jit.wall_distances``."""
    low, high = area.min(axis=0), area.max(axis=0)
    found = np.zeros((0, 2))
    for _ in range(50):
        if len(found) >= count:
            break
        tries = rng.uniform(low, high, size=(4 * (count - len(found)) + 40, 2))
        tries = tries[_inside(area, tries)]
        if len(walls) and len(tries):
            tries = tries[_wall_distance(tries, walls, compiled) > radius + WALL_CLEARANCE]
        found = np.concatenate([found, tries])
    return found[:count]


def _new_goals(state: CrowdState, which: NDArray[np.int64], areas: Sequence[FloatArray],
               walls: FloatArray, robot_poses: FloatArray, robot_reach: FloatArray,
               rng: np.random.Generator, compiled: bool = False) -> FloatArray:
    """New goals (len(which), 2) for pedestrians ``which``: a place to watch a robot from
    (with the kind's probability; inside the crowd's area), else a random place in the area;
    either clear of the walls (S, 2, 2) (else the pedestrian keeps its goal)."""
    goals = np.empty((len(which), 2))
    watch = state.column("watch")[which]
    near, far = state.column("watch_near")[which], state.column("watch_far")[which]
    for n, a in enumerate(which.tolist()):
        spot = None
        if len(robot_poses) and rng.random() < watch[n]:
            robot = int(rng.integers(len(robot_poses)))
            angle = rng.uniform(-math.pi, math.pi)
            gap = robot_reach[robot] + state.radius[a] + rng.uniform(near[n], far[n])
            spot = robot_poses[robot, :2] + gap * np.array([math.cos(angle), math.sin(angle)])
        goals[n] = _goal_at(spot, areas[int(state.crowd[a])], walls, float(state.radius[a]),
                            rng, state.goal[a], compiled)
    return goals


def _goal_at(spot: FloatArray | None, area: FloatArray, walls: FloatArray, radius: float,
             rng: np.random.Generator, keep: FloatArray, compiled: bool = False) -> FloatArray:
    """``spot`` (2,) as a pedestrian's goal if it lies in its ``area`` with the disc
    (``radius``) clear of the walls (S, 2, 2) by :data:`WALL_CLEARANCE`; else a random such
    place in the area; else (none found) ``keep``."""
    if spot is not None and _inside(area, spot[None])[0] and (
            not len(walls)
            or _wall_distance(spot[None], walls, compiled)[0] > radius + WALL_CLEARANCE):
        return spot
    drawn = _random_in(area, 1, rng, walls, radius, compiled)
    return drawn[0] if len(drawn) else keep


def crowd_start(crowds: Sequence[Crowd], robot_poses: FloatArray, robot_reach: FloatArray,
                keep_clear: shapely.Geometry | None, walls: FloatArray,
                rng: np.random.Generator) -> CrowdState:
    """Every crowd's pedestrians at random places in its area, standing, clear of the robots
    (poses (R, 3), each a disc of ``robot_reach`` (R,) m around its centre), of
    ``keep_clear`` (the obstacles), of the walls (segments (S, 2, 2)) and of each other;
    each with a preferred speed, a first goal and no pause. Raises ValueError when a crowd
    does not fit (the world loader keeps crowds to half of their free area, so this takes a
    pathological draw)."""
    names: list[str] = []
    rows: list[tuple[float, float, float, float, int]] = []  # x, y, speed, radius, crowd
    heights: list[float] = []
    behaviour: list[list[float]] = []
    for index, crowd in enumerate(crowds):
        kind = KIND_BEHAVIOUR[crowd.kind]
        placed = 0
        for _ in range(200):
            if placed == crowd.count:
                break
            for x, y in _random_in(crowd.area, crowd.count - placed, rng, walls,
                                   crowd.radius).tolist():
                if not _clear(x, y, crowd.radius, rows, robot_poses, robot_reach, keep_clear):
                    continue
                speed = float(np.clip(rng.normal(crowd.speed, crowd.speed_sd), 0.3, 2.5))
                rows.append((x, y, speed, crowd.radius, index))
                heights.append(crowd.height)
                behaviour.append([float(getattr(kind, f)) for f in _BEHAVIOUR_FIELDS])
                placed += 1
                names.append(f"{crowd.name} {placed}")
        if placed < crowd.count:
            raise ValueError(f"crowd '{crowd.name}' does not fit in its area: {placed} of "
                             f"{crowd.count} placed clear of the robots, obstacles and others")
    table = np.array(rows, dtype=float).reshape(-1, 5)
    count = len(table)
    state = CrowdState(table[:, :2].copy(), np.zeros((count, 2)), table[:, :2].copy(),
                       np.zeros(count), table[:, 2].copy(), table[:, 3].copy(),
                       np.array(heights, dtype=float), table[:, 4].astype(np.int64),
                       np.array(behaviour, dtype=float).reshape(count, len(_BEHAVIOUR_FIELDS)),
                       tuple(names))
    areas = [c.area for c in crowds]
    return replace(state, goal=_new_goals(state, np.arange(count), areas, walls, robot_poses,
                                          robot_reach, rng))


def _clear(x: float, y: float, radius: float, rows: list[tuple[float, float, float, float, int]],
           robot_poses: FloatArray, robot_reach: FloatArray,
           keep_clear: shapely.Geometry | None) -> bool:
    if len(robot_poses) and np.any(np.hypot(robot_poses[:, 0] - x, robot_poses[:, 1] - y)
                                   < robot_reach + radius + 0.3):
        return False
    if any(math.hypot(px - x, py - y) < pr + radius + 0.1 for px, py, _, pr, _ in rows):
        return False
    return keep_clear is None or shapely.distance(keep_clear, shapely.Point(x, y)) > radius + 0.1


def crowd_step(state: CrowdState, dt: float, areas: Sequence[FloatArray], walls: FloatArray,
               robot_poses: FloatArray, robot_lengths: FloatArray, robot_widths: FloatArray,
               rng: np.random.Generator,
               params: SocialForceParams = SocialForceParams(),
               speaking: NDArray[np.bool_] | None = None,
               rings: IntArray | None = None, compiled: bool = False,
               robot_standing: NDArray[np.bool_] | None = None) -> CrowdState:
    """The crowd ``dt`` s later: people near a robot that stopped for people and speaks
    (``speaking`` (R,)) heed it at their kind's rate and step away (from inside the
    formation, keeping :data:`LEAVING_RANGE` of their range from the robots that stand
    still, ``robot_standing`` (R,), None: none, the share following with the time constant
    :data:`SHARE_TIME`); goals reached start a
    pause, pauses that end and children who change their mind pick new goals (``areas``:
    each crowd's polygon), then the social forces (:func:`social_acceleration`) move
    everyone in substeps of ``params.substep``, speeds capped at ``max_speed_factor`` times
    the preferred speed (H&M eq. 7). ``compiled``: the substeps in one call of
    ``sim.crowd_jit.walk`` (its forces the same to 1e-9), else as NumPy arrays."""
    count = len(state.position)
    if count == 0:
        return state
    reach = 0.5 * np.hypot(robot_lengths, robot_widths)
    if speaking is not None and np.count_nonzero(speaking):
        state = _make_room(state, robot_poses[speaking], reach[speaking], dt, areas, walls,
                           rng, robot_poses, reach, compiled)
    if compiled:  # the same operations in one call (``crowd_jit.pauses``), the same draws
        draws = rng.random(count)
        arrived, pause, rethink = kernel("sim.crowd_jit").pauses(
            state.pause, state.goal, state.position, state.behaviour, _PAUSE_COLUMNS, draws,
            rng.random(count), dt)
    else:
        low, high = state.column("pause_min"), state.column("pause_max")
        arrived = (state.pause <= 0.0) & (np.hypot(*(state.goal - state.position).T)
                                          < state.column("arrive"))
        # ``rng.uniform(low, high)`` as it computes it (the same draws), without its
        # broadcasting
        pause = np.where(arrived, low + (high - low) * rng.random(count), state.pause)
        was_pausing = pause > 0.0
        pause = np.maximum(pause - dt, 0.0)
        rethink = (was_pausing & (pause <= 0.0)) | (
            (pause <= 0.0) & (rng.random(count) < state.column("change_rate") * dt))
    goal = state.goal
    if np.count_nonzero(rethink):
        goal = goal.copy()
        which = np.flatnonzero(rethink)
        goal[which] = _new_goals(state, which, areas, walls, robot_poses, reach, rng, compiled)
    leaving = state.leaving  # out of the formation: until at that goal or off to another
    if leaving is not None and np.count_nonzero(leaving):
        leaving = leaving & ~arrived & ~rethink
    moving = _evolve(state, goal=goal, pause=pause, leaving=leaving,
                     robot_share=_robot_share(state.robot_share, leaving, robot_standing,
                                              count, len(robot_poses), dt))
    steps = max(1, math.ceil(dt / params.substep - 1e-9))
    h = dt / steps
    if compiled:  # the substeps in one call, the same operations (``crowd_jit.walk``)
        position, velocity = kernel("sim.crowd_jit").walk(
            moving.position, moving.velocity, moving.goal, moving.pause <= 0.0,
            moving.preferred, *moving.robot_push(len(robot_poses)), moving.radius, walls,
            rings if rings is not None else np.arange(len(walls)), robot_poses,
            robot_lengths, robot_widths, params.relaxation, params.pedestrian_strength,
            params.pedestrian_range, params.border_strength, params.border_range,
            params.step_time, math.cos(params.sight), params.out_of_sight,
            params.max_speed_factor, steps, h)
        return _evolve(moving, position=position, velocity=velocity)
    position, velocity = moving.position, moving.velocity
    cap = params.max_speed_factor * moving.preferred
    for _ in range(steps):
        # the walls' nearest points, once per substep: the walls' push and the step's check
        vectors = _nearest_on_segments(position, walls) if len(walls) else None
        accel = social_acceleration(_evolve(moving, position=position, velocity=velocity),
                                    walls, robot_poses, robot_lengths, robot_widths,
                                    params, rings, vectors)
        before = (None if vectors is None
                  else np.hypot(vectors[..., 0], vectors[..., 1]).min(axis=1))
        velocity = velocity + h * accel
        speed = np.hypot(velocity[:, 0], velocity[:, 1])
        velocity = velocity * np.minimum(1.0, cap / np.maximum(speed, 1e-12))[:, None]
        ahead = position + h * velocity
        if before is not None:  # no step through a wall: a disc that would touch one stands
            after = _wall_distance(ahead, walls)
            touch = (after < moving.radius) & (after < before)
            ahead[touch] = position[touch]
            velocity[touch] = 0.0
        position = ahead
    return _evolve(moving, position=position, velocity=velocity)


_STATE_FIELDS = tuple(f.name for f in fields(CrowdState))


def _evolve(state: CrowdState, **changes: Any) -> CrowdState:
    """``dataclasses.replace(state, **changes)`` without its checks, which cost tens of
    microseconds a call: the crowd changes every step."""
    values: list[Any] = [changes[name] if name in changes else getattr(state, name)
                         for name in _STATE_FIELDS]
    return CrowdState(*values)


def _make_room(state: CrowdState, speakers: FloatArray, reach: FloatArray, dt: float,
               areas: Sequence[FloatArray], walls: FloatArray,
               rng: np.random.Generator, robots: FloatArray,
               robot_reach: FloatArray, compiled: bool = False) -> CrowdState:
    """People within :data:`HEARING` of a speaking robot (poses (S, 3), half diagonals (S,))
    heed it with probability heed * dt: they stop pausing and walk to a point
    :data:`ROOM_MADE` m from where they stand, away from the nearest speaker by the way that
    keeps clearest of every robot (poses (R, 3), half diagonals (R,); :func:`_way_out`: a
    person inside a formation leaves between two robots instead of walking into the one
    behind the speaker) (or, where that leaves their area or nears a wall, anywhere in their
    area)."""
    offsets = state.position[:, None, :] - speakers[None, :, :2]  # (P, S, 2)
    distance = np.hypot(offsets[..., 0], offsets[..., 1]) - reach[None, :]
    nearest = np.argmin(distance, axis=1)
    hears = distance[np.arange(len(distance)), nearest] < HEARING
    heeds = hears & (rng.random(len(hears)) < state.column("heed") * dt)
    if not np.count_nonzero(heeds):
        return state
    goal, pause = state.goal.copy(), state.pause.copy()
    leaving = (np.zeros(len(goal), dtype=bool) if state.leaving is None
               else state.leaving.copy())
    leaving[heeds] = _inside_formation(robots[:, :2], state.position[heeds])
    for a in np.flatnonzero(heeds).tolist():
        away = offsets[a, nearest[a]]
        direction = _way_out(state.position[a], away, robots[:, :2], robot_reach,
                             float(state.radius[a]))
        spot = state.position[a] + direction * rng.uniform(*ROOM_MADE)
        goal[a] = _goal_at(spot, areas[int(state.crowd[a])], walls, float(state.radius[a]),
                           rng, goal[a], compiled)
        pause[a] = 0.0
    return _evolve(state, goal=goal, pause=pause, leaving=leaving)


def _robot_share(share: FloatArray | None, leaving: NDArray[np.bool_] | None,
                 standing: NDArray[np.bool_] | None, people: int, robots: int,
                 dt: float) -> FloatArray | None:
    """The share (P, R) of its robot range each pedestrian keeps from each robot ``dt`` s
    later: it follows :data:`LEAVING_RANGE` from the robots ``standing`` (R,) for the
    pedestrians ``leaving`` (P,), 1 otherwise, with the time constant :data:`SHARE_TIME`.
    None: the whole range from every robot (nobody leaving, nobody back to the whole)."""
    if share is None and (leaving is None or standing is None):
        return None  # (the common case, without allocating)
    who = np.zeros(people, dtype=bool) if leaving is None else leaving
    past = np.zeros(robots, dtype=bool) if standing is None else standing
    near = bool(who.any() and past.any())
    if share is None or share.shape != (people, robots):
        if not near:
            return None
        share = np.ones((people, robots))
    target = np.ones((people, robots))
    target[np.ix_(who, past)] = LEAVING_RANGE
    result: FloatArray = target + (share - target) * math.exp(-dt / SHARE_TIME)
    if not near and np.all(result > 1.0 - 1e-6):
        return None
    return result


def _inside_formation(centres: FloatArray, points: FloatArray) -> NDArray[np.bool_]:
    """Which points (N, 2) lie inside the convex hull of the robots' centres (R, 2) (none
    for fewer than three robots, or robots in a line or not known)."""
    known = centres[np.isfinite(centres).all(axis=1)]
    if len(known) < 3 or len(points) == 0:
        return np.zeros(len(points), dtype=bool)
    hull = shapely.convex_hull(shapely.multipoints(known))
    if not isinstance(hull, shapely.Polygon):  # (in a line: no inside)
        return np.zeros(len(points), dtype=bool)
    result: NDArray[np.bool_] = shapely.contains_xy(hull, points[:, 0], points[:, 1])
    return result


WAYS_OUT = 16
"""Directions :func:`_way_out` weighs, evenly spaced."""
WAY_SPAN = (0.3, ROOM_MADE[1])
"""m along a way out that :func:`_way_out` keeps clear of the robots: as far as a person who
heeds a robot walks (:data:`ROOM_MADE`), from 0.3 m on (the first 0.3 m are as near the
robots as the person is, whichever the way)."""


def _way_out(position: FloatArray, away: FloatArray, robots: FloatArray, reach: FloatArray,
             radius: float) -> FloatArray:
    """The unit direction (2,) in which a person at ``position`` (2,) of ``radius`` m leaves
    the robots (centres (R, 2), half diagonals (R,)): of :data:`WAYS_OUT` directions, the one
    whose :data:`WAY_SPAN` passes furthest from every robot's disc (or leaves room for the
    person), the nearest to ``away`` (2,) (from the speaker) among those that pass as far to
    within 5 cm."""
    angles = np.linspace(-math.pi, math.pi, WAYS_OUT, endpoint=False)
    ways = np.stack([np.cos(angles), np.sin(angles)], axis=1)  # (D, 2)
    known = np.isfinite(robots).all(axis=1) & np.isfinite(reach)
    relative = robots[known] - position[None, :]  # (R, 2)
    reach = reach[known]
    if len(relative) == 0:  # no robot where it is known: straight away
        relative, reach = np.zeros((1, 2)) - 1e9, np.zeros(1)
    along = np.clip(relative @ ways.T, *WAY_SPAN)  # (R, D) where each way passes nearest
    closest = along[..., None] * ways[None, :, :] - relative[:, None, :]  # (R, D, 2)
    clearance = (np.hypot(closest[..., 0], closest[..., 1]) - reach[:, None]).min(axis=0)
    norm = float(np.hypot(*away))
    heading = away / norm if norm > 1e-9 else np.array([1.0, 0.0])
    good = clearance >= min(clearance.max(), radius) - 0.05
    best = int(np.argmax(np.where(good, ways @ heading, -np.inf)))
    result: FloatArray = ways[best]
    return result


def _wall_distance(points: FloatArray, walls: FloatArray,
                   compiled: bool = False) -> FloatArray:
    """The distance (P,) from each point (P, 2) to the nearest wall segment (S, 2, 2)
    (``compiled``: by ``crowd_jit.wall_distances``, the same operations)."""
    if compiled and len(walls):
        distances: FloatArray = kernel("sim.crowd_jit").wall_distances(
            np.ascontiguousarray(points, dtype=float), walls)
        return distances
    vectors = _nearest_on_segments(points, walls)
    result: FloatArray = np.hypot(vectors[..., 0], vectors[..., 1]).min(axis=1)
    return result
