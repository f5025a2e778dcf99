"""Where a simulated show takes place: the arena and every robot's start pose.

Pure: a placed show in (:class:`~dancebots.plan.placement.PlacedShow`), an :class:`Arena` and
a :class:`Placement` out, or a :class:`SetupError` with a one-line message and the diagnostics
behind it. What the setup refuses is decided by the placement, the object ``check`` reports
over, so a show that checks without errors always sets up.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic
from dancebots.geometry import Pose
from dancebots.plan.placement import PlacedShow
from dancebots.world import Crowd, Obstacle, RobotType, Spectator, World

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
    spectators and crowds."""

    room: FloatArray
    wall_height: float
    obstacles: tuple[Obstacle, ...]
    source: str | None
    spectators: tuple[Spectator, ...] = ()
    crowds: tuple[Crowd, ...] = ()

    @classmethod
    def of_world(cls, world: World, spectators: Sequence[Spectator] | None = None) -> Arena:
        """The world's room, walls, obstacles and (unless given) spectators."""
        return cls(world.room, world.wall_height, tuple(world.obstacles), world.path,
                   tuple(world.spectators if spectators is None else spectators),
                   tuple(world.crowds))


@dataclass(frozen=True, slots=True, eq=False)
class Placement:
    """The robots of a show in the world: names (R,), types (R,), start poses (R, 3) in the
    world frame, and the pose of the show frame in the world frame."""

    robots: tuple[str, ...]
    types: tuple[RobotType, ...]
    starts: FloatArray
    show_to_world: Pose


def open_arena(show: PlacedShow, margin: float = 2.0) -> Arena:
    """A square-cornered room around everything the show's desired footprints cover, plus a
    margin in m, with its corners on whole metres (the show frame is the world frame)."""
    low, high = show.footprint_extent()
    low, high = np.floor(low - margin), np.ceil(high + margin)
    room = np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]],
                     [low[0], high[1]]])
    return Arena(room, 2.0, (), None)


def prepare_show(show: PlacedShow) -> tuple[Arena, Placement]:
    """The arena and start poses of a placed show
    (:func:`~dancebots.plan.placement.place_show`). Without a world the robots start on the
    slots of the first formation in an open arena; with one they start where it says (or, if
    it places no robot, on their slots with the show centred in the room). Raises
    :class:`SetupError` with the placement's errors (the show leaves the room, robots start
    on each other, ...): the errors ``check`` reports."""
    if show.errors:
        raise SetupError.from_diagnostics(show.errors)
    assert show.transform is not None  # no errors: the show is placed
    assert show.starts is not None
    arena = open_arena(show) if show.world is None else Arena.of_world(show.world)
    return arena, Placement(show.plan.robots, show.types, show.starts, show.transform)
