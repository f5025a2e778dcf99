"""What a show loop records at each control tick, by name: one recorder for both shows.

A loop calls ``recorder.add(time, poses=..., commands=...)`` with arrays of per-robot (or
per-spectator) values, the same names every tick; the result's arrays come out of
:meth:`Recorder.series` stacked along a new time axis.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Recorder"]


class Recorder:
    """Named samples over time (a thin shell: it only copies and stacks arrays)."""

    def __init__(self) -> None:
        self._times: list[float] = []
        self._samples: dict[str, list[NDArray[Any]]] = {}

    def add(self, time: float, **values: NDArray[Any]) -> None:
        """Record ``values`` (copied) at ``time`` s; the same names at every call."""
        if self._samples and values.keys() != self._samples.keys():
            raise ValueError(f"recorded {sorted(values)} after {sorted(self._samples)}")
        self._times.append(time)
        for name, value in values.items():
            self._samples.setdefault(name, []).append(np.array(value, copy=True))

    @property
    def times(self) -> NDArray[np.float64]:
        """(T,) the times of the samples, s."""
        return np.array(self._times, dtype=np.float64)

    def __contains__(self, name: object) -> bool:
        """Whether ``name`` was recorded."""
        return name in self._samples

    def series(self, name: str, axis: int = 1) -> NDArray[Any]:
        """The samples of ``name`` stacked along ``axis``: per-robot values (R, ...) give
        (R, T, ...) with the default axis 1; axis 0 gives (T, ...)."""
        return np.stack(self._samples[name], axis=axis)
