"""RobotBrain: everything one robot decides each control tick, as pure code.

A brain knows the plan, its role and the follower strategy. Each tick it gets the show time
and its pose in its *own* ``map`` frame and returns a command (v, w) and events. It computes
its virtual leader in its own frame from the plan, assuming it started on its slot of the
first formation (thesis ch. 4.2: there is no shared frame between robots): a show-frame pose
P is ``slot0^-1 ⊕ P`` in the robot's map frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from dancebots.control.follower import FollowerParams, FollowerState, thesis_follower_step
from dancebots.geometry import Pose
from dancebots.plan.planner import Plan, RobotTrack

__all__ = [
    "FOLLOWERS",
    "BrainState",
    "Command",
    "RobotBrain",
]

FOLLOWERS = ("thesis",)
"""Follower strategies by name; ``thesis`` is eq. 4.4 as written."""


@dataclass(frozen=True, slots=True)
class Command:
    """A velocity command in ``base_link``: linear m/s, angular rad/s."""

    linear: float
    angular: float


STOP = Command(0.0, 0.0)


@dataclass(frozen=True, slots=True)
class BrainState:
    """What a brain carries from one tick to the next."""

    follower: FollowerState = field(default_factory=FollowerState)


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
                 follower: str = "thesis", grid_period: float = 0.1) -> None:
        if follower not in FOLLOWERS:
            raise ValueError(f"unknown follower {follower!r}; choose from {', '.join(FOLLOWERS)}")
        self.plan = plan
        self.robot = robot
        self.params = params
        self.follower = follower
        slot = plan.desired_poses(robot, np.zeros(1))[0]
        self.slot0 = Pose(float(slot[0]), float(slot[1]), float(slot[2]))
        self._to_own = self.slot0.inverse()
        self.grid_period = grid_period
        count = math.ceil(plan.duration / grid_period) + 1
        grid = np.minimum(np.arange(count + 1, dtype=np.float64) * grid_period, plan.duration)
        self._grid = self._samples(plan.track(robot, grid))

    def _samples(self, track: RobotTrack) -> list[_Sample]:
        own = self._to_own
        c, s = math.cos(own.theta), math.sin(own.theta)
        lx = own.x + c * track.leader[:, 0] - s * track.leader[:, 1]
        ly = own.y + s * track.leader[:, 0] + c * track.leader[:, 1]
        px = own.x + c * track.lateral[:, 0] - s * track.lateral[:, 1]
        py = own.y + s * track.lateral[:, 0] + c * track.lateral[:, 1]
        dx = own.x + c * track.desired[:, 0] - s * track.desired[:, 1]
        dy = own.y + s * track.desired[:, 0] + c * track.desired[:, 1]
        moving = np.any(track.leader_commands != 0.0, axis=1)
        return [_Sample((a, b), (p, q), (e, f), r, m) for a, b, p, q, e, f, r, m in zip(
            lx.tolist(), ly.tolist(), px.tolist(), py.tolist(), dx.tolist(), dy.tolist(),
            track.required_distance.tolist(), moving.tolist(), strict=True)]

    def _sample(self, show_time: float) -> _Sample:
        if show_time >= self.plan.duration:  # the plan stands still after its end
            return self._grid[-1]
        k = round(show_time / self.grid_period)
        if 0 <= k < len(self._grid) and abs(k * self.grid_period - show_time) < 1e-9:
            return self._grid[k]
        return self._samples(self.plan.track(self.robot, np.array([show_time])))[0]

    def initial_state(self) -> BrainState:
        return BrainState()

    def step(self, state: BrainState, show_time: float,
             pose: tuple[float, float, float]) -> tuple[BrainState, Command, tuple[str, ...]]:
        """One control tick: show time in s (negative before the start), pose (x, y, theta)
        in the robot's own map frame. Returns the new state, the command and events."""
        if show_time < 0.0:
            return state, STOP, ()
        sample = self._sample(show_time)
        follower, (linear, angular) = thesis_follower_step(
            self.params, state.follower, show_time, pose, sample.leader, sample.path_point,
            sample.desired, sample.required, sample.moving)
        return replace(state, follower=follower), Command(linear, angular), ()

    def leader_in_own_frame(self, show_time: float) -> tuple[float, float]:
        """The virtual leader's position in this robot's map frame at ``show_time``."""
        return self._sample(show_time).leader
