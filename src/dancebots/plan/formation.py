"""Formation shapes -> robot offsets in the virtual leader's frame (thesis ch. 4.2, ch. 6)."""

from __future__ import annotations

from dancebots.scenario.model import Formation

__all__ = ["DEFAULT_LEAD", "formation_offsets"]

DEFAULT_LEAD = 0.5
"""The virtual leader is placed this far ahead of the first row, m (thesis ch. 6, newVL)."""


def formation_offsets(
    formation: Formation, lead: float = DEFAULT_LEAD
) -> dict[str, tuple[float, float]]:
    """Offsets (x, y) in m of every robot in the virtual leader's frame (x forward, y left).

    The leader is ``lead`` ahead of the first row and centred laterally; every row is centred
    on the leader's x axis; the first robot listed in a row is the leftmost (largest y).
    """
    offsets: dict[str, tuple[float, float]] = {}
    x = -lead
    for index, row in enumerate(formation.rows):
        if index > 0:
            x -= formation.row_distances[index - 1]
        gaps = formation.spacings[index]
        y = 0.5 * sum(gaps)
        for position, role in enumerate(row):
            if position > 0:
                y -= gaps[position - 1]
            offsets[role] = (x, y + 0.0)  # + 0.0 turns -0.0 into 0.0
    return offsets
