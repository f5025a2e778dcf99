"""Where a simulated show takes place: the arena and every robot's start pose.

Pure: a plan and an optional world in, an :class:`Arena` and a :class:`Placement` out, or a
:class:`SetupError` with a one-line message and the diagnostics behind it. What the setup
refuses is decided by :func:`dancebots.check.place_show`, the function ``check`` reports with,
so a show that checks without errors always sets up.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.check import ShowPlacement, place_show, robot_types
from dancebots.diagnostics import Diagnostic
from dancebots.geometry import Pose, footprint_corners
from dancebots.plan.planner import Plan
from dancebots.world import DEFAULT_ROBOT_TYPE, Obstacle, RobotType, Spectator, World

__all__ = ["Arena", "Placement", "SetupError", "prepare_show"]

FloatArray = NDArray[np.float64]


class SetupError(Exception):
    """The show cannot be simulated as asked; ``str(error)`` is a one-line explanation and
    ``diagnostics`` the positioned errors behind it (empty when it has none)."""

    def __init__(self, message: str, diagnostics: Sequence[Diagnostic] = ()) -> None:
        super().__init__(message)
        self.diagnostics = tuple(diagnostics)

    @classmethod
    def from_diagnostics(cls, errors: Sequence[Diagnostic]) -> SetupError:
        """The first error's headline, and how many more there are."""
        more = len(errors) - 1
        return cls(errors[0].headline() + (f" (and {more} more: see `dancebots check`)"
                                           if more > 0 else ""), errors)


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


def open_arena(plan: Plan, types: list[RobotType], margin: float = 2.0) -> Arena:
    """A square-cornered room around everything the show's desired footprints cover, plus a
    margin in m, with its corners on whole metres."""
    times = np.arange(0.0, plan.duration + 0.5, 0.5)
    low, high = np.full(2, np.inf), np.full(2, -np.inf)
    for robot, kind in zip(plan.robots, types, strict=True):  # one robot at a time: memory
        poses = plan.desired_poses(robot, times)                # O(samples), not O(R samples)
        corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], kind.length,
                                    kind.width).reshape(-1, 2)
        low, high = np.minimum(low, corners.min(axis=0)), np.maximum(high, corners.max(axis=0))
    low, high = np.floor(low - margin), np.ceil(high + margin)
    room = np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]],
                     [low[0], high[1]]])
    return Arena(room, 2.0, (), None)


def prepare_show(plan: Plan, world: World | None,
                 default_type: RobotType = DEFAULT_ROBOT_TYPE,
                 placed: ShowPlacement | None = None) -> tuple[Arena, Placement]:
    """The arena and start poses. Without a world the robots start on the slots of the first
    formation in an open arena; with one they start where it says (or, if it places no robot,
    on their slots with the show centred in the room). Raises :class:`SetupError` with the
    errors of :func:`dancebots.check.place_show` (the show leaves the room, robots start on
    each other, ...). ``placed``: that answer when the caller has it already (a
    :class:`~dancebots.check.CheckReport`'s ``placement``, for the same plan, world and
    default type), so that it is not computed twice."""
    types = robot_types(plan, world, default_type)
    placed = placed or place_show(plan, world, types)
    if placed.errors:
        raise SetupError.from_diagnostics(placed.errors)
    assert placed.transform is not None  # no errors: the show is placed
    assert placed.starts is not None
    if world is None:
        arena = open_arena(plan, types)
    else:
        arena = Arena(world.room, world.wall_height, world.obstacles, world.path,
                      world.spectators)
    return arena, Placement(plan.robots, tuple(types), placed.starts, placed.transform)
