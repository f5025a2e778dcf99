"""The least-cost assignment of tracks to detections, written once for NumPy and numba.

:func:`least_cost_assignment` is the shortest augmenting path algorithm of D. F. Crouse, "On
implementing 2D rectangular assignment algorithms", IEEE Trans. AES 52(4), 2016, as SciPy's
``linear_sum_assignment`` implements it, in the same order of search: the same assignment,
ties included (``tests/perception/test_tracks.py`` holds them equal). It is plain Python on
NumPy arrays, so that the obstacle tracker's NumPy reference runs it as it is (importing
``scipy.optimize`` cost a short show's check 0.36 s) and ``perception.tracks_jit`` compiles
the same function with numba: the two trackers then pick the same tracks where costs tie.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["least_cost_assignment"]


def least_cost_assignment(cost: NDArray[np.float64],
                          ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The rows and columns (ascending rows) of the assignment of least total ``cost``
    (R, C) that assigns every row (R <= C) or every column (R > C): ``scipy.optimize.
    linear_sum_assignment``'s answer. Where SciPy raises, on NaN or on infinities that
    leave no finite assignment, a NaN counts as no way (as an infinity) and a matrix with no
    finite assignment gives none (empty arrays)."""
    rows, cols = cost.shape
    if rows == 0 or cols == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    wide = rows <= cols
    matrix = cost if wide else np.ascontiguousarray(cost.T)
    count, width = matrix.shape
    u = np.zeros(count)
    v = np.zeros(width)
    shortest = np.empty(width)
    path = np.full(width, -1, dtype=np.int64)
    col4row = np.full(count, -1, dtype=np.int64)
    row4col = np.full(width, -1, dtype=np.int64)
    seen_rows = np.zeros(count, dtype=np.bool_)
    seen_cols = np.zeros(width, dtype=np.bool_)
    remaining = np.empty(width, dtype=np.int64)
    for current in range(count):
        minimum = 0.0
        left = width
        for it in range(width):
            remaining[it] = width - it - 1
        seen_rows[:] = False
        seen_cols[:] = False
        shortest[:] = math.inf
        sink = -1
        i = current
        while sink == -1:
            index = -1
            lowest = math.inf
            seen_rows[i] = True
            for it in range(left):
                j = remaining[it]
                reduced = minimum + matrix[i, j] - u[i] - v[j]
                if reduced < shortest[j]:
                    path[j] = i
                    shortest[j] = reduced
                if shortest[j] < lowest or (shortest[j] == lowest and row4col[j] == -1):
                    lowest = shortest[j]
                    index = it
            if index < 0 or lowest == math.inf:  # NaN or no finite way: infeasible
                return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
            minimum = lowest
            j = remaining[index]
            if row4col[j] == -1:
                sink = j
            else:
                i = row4col[j]
            seen_cols[j] = True
            left -= 1
            remaining[index] = remaining[left]
        u[current] += minimum
        for i in range(count):
            if seen_rows[i] and i != current:
                u[i] += minimum - shortest[col4row[i]]
        for j in range(width):
            if seen_cols[j]:
                v[j] -= minimum - shortest[j]
        j = sink
        while True:
            i = path[j]
            row4col[j] = i
            col4row[i], j = j, col4row[i]
            if i == current:
                break
    if wide:
        return np.arange(count), col4row
    order = np.argsort(col4row)  # the columns' rows, in the order of the rows
    return col4row[order], order.astype(np.int64)
