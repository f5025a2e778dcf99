"""Where a simulated show takes place: the arena and every robot's start pose.

Pure: a plan and an optional world in, an :class:`Arena` and a :class:`Placement` out, or a
:class:`SetupError` with a one-line message that says what to do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.check import place_plan_in_world, robot_types, world_violations
from dancebots.diagnostics import Diagnostic
from dancebots.geometry import Pose, footprint_corners
from dancebots.plan.planner import Plan
from dancebots.world import DEFAULT_ROBOT_TYPE, Obstacle, RobotType, Spectator, World

__all__ = ["Arena", "Placement", "SetupError", "prepare_show"]

FloatArray = NDArray[np.float64]


class SetupError(Exception):
    """The show cannot be simulated as asked; ``str(error)`` is a one-line explanation."""


@dataclass(frozen=True, slots=True, eq=False)
class Arena:
    """The room polygon (N, 2) in the world frame, its wall height (m), the obstacles,
    ``source``: the world file, or None for an open arena sized to the show, and the
    spectators."""

    room: FloatArray
    wall_height: float
    obstacles: tuple[Obstacle, ...]
    source: str | None
    spectators: tuple[Spectator, ...] = ()


@dataclass(frozen=True, slots=True, eq=False)
class Placement:
    """The robots of a show in the world: names (R,), types (R,), start poses (R, 3) in the
    world frame, and the pose of the show frame in the world frame."""

    robots: tuple[str, ...]
    types: tuple[RobotType, ...]
    starts: FloatArray
    show_to_world: Pose


def _slots(plan: Plan, transform: Pose) -> FloatArray:
    slots = np.stack([plan.desired_poses(r, np.zeros(1))[0] for r in plan.robots])
    c, s = math.cos(transform.theta), math.sin(transform.theta)
    return np.stack([transform.x + c * slots[:, 0] - s * slots[:, 1],
                     transform.y + s * slots[:, 0] + c * slots[:, 1],
                     slots[:, 2] + transform.theta], axis=1)


def open_arena(plan: Plan, types: list[RobotType], margin: float = 2.0) -> Arena:
    """A square-cornered room around everything the show's desired footprints cover, plus a
    margin in m, with its corners on whole metres."""
    times = np.arange(0.0, plan.duration + 0.5, 0.5)
    points = []
    for robot, kind in zip(plan.robots, types, strict=True):
        poses = plan.desired_poses(robot, times)
        points.append(footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], kind.length,
                                        kind.width).reshape(-1, 2))
    every = np.concatenate(points)
    low = np.floor(every.min(axis=0) - margin)
    high = np.ceil(every.max(axis=0) + margin)
    room = np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]],
                     [low[0], high[1]]])
    return Arena(room, 2.0, (), None)


def prepare_show(plan: Plan, world: World | None,
                 default_type: RobotType = DEFAULT_ROBOT_TYPE) -> tuple[Arena, Placement]:
    """The arena and start poses. Without a world the robots start on the slots of the first
    formation in an open arena; with one they start where it says (or, if it places no robot,
    on their slots with the show centred in the room), and the show must fit in the room."""
    types = robot_types(plan, world, default_type)
    if world is None:
        identity = Pose(0.0, 0.0, 0.0)
        return open_arena(plan, types), Placement(plan.robots, tuple(types),
                                                  _slots(plan, identity), identity)
    named = [r.name for r in world.robots]
    missing = [r for r in plan.robots if r not in named]
    if named and missing:
        raise SetupError(f"the scenario's robots {' '.join(missing)} are not in the world "
                         f"{world.path} (it has {' '.join(named)}); add a [[robots]] entry "
                         "for each")
    problems: list[Diagnostic] = []
    transform = place_plan_in_world(plan, world, problems)
    if transform is None:  # pragma: no cover - the missing-robot case is handled above
        raise SetupError(problems[0].message if problems else "cannot place the show")
    leaving = [v for v in world_violations(plan, world, transform, types) if v.obstacle is None]
    if leaving:
        first = leaving[0]
        raise SetupError(f"the show does not fit in the room of {world.path}: {first.robot} "
                         f"would leave it at t = {first.start:.1f} s ({plan.scenario.path}:"
                         f"{first.line}); move the start poses or use a bigger room")
    if named:
        starts = np.array([[p.start.x, p.start.y, p.start.theta] for p in (
            world.robot(r) for r in plan.robots) if p is not None])
    else:
        starts = _slots(plan, transform)
    arena = Arena(world.room, world.wall_height, world.obstacles, world.path, world.spectators)
    return arena, Placement(plan.robots, tuple(types), starts, transform)
