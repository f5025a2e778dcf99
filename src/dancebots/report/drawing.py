"""Drawing parts shared by every picture of a show: the room and its obstacles."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.world import Obstacle

__all__ = ["draw_arena"]


def draw_arena(axes: Any, room: NDArray[np.float64], obstacles: Sequence[Obstacle],
               margin: float | None = None, label: str | None = None) -> None:
    """The room's walls (polygon (N, 2), world frame, m) and its obstacles on ``axes``, in the
    one style of every picture; with ``margin`` (m) the axes frame the room that much wider;
    ``label``: the walls' legend entry."""
    from matplotlib.patches import Polygon

    axes.add_patch(Polygon(room, closed=True, fill=False, edgecolor="black", linewidth=2.0,
                           label=label))
    for obstacle in obstacles:
        axes.add_patch(Polygon(obstacle.polygon, closed=True, facecolor="0.35",
                               edgecolor="black"))
    if margin is not None:
        low, high = room.min(axis=0), room.max(axis=0)
        axes.set_xlim(low[0] - margin, high[0] + margin)
        axes.set_ylim(low[1] - margin, high[1] + margin)
