"""The reference's two sequential scans as numba kernels (``control.tracking`` calls them).

:func:`fold_choices` is the Viterbi pass of :func:`dancebots.control.tracking.choose_folds`
and :func:`rate_limited_headings` the loop of ``tracking._rate_limited``: the same
arithmetic in the same order, so that the compiled and the Python references agree to the
last bit (``math.remainder``, which numba lacks, is :func:`_remainder_tau`, exact too).
``tests/control/test_tracking.py`` holds them equal. A 20-robot, 40-minute show's brains
spent 0.9 s of their 1.5 s set-up in the Python loops.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["fold_choices", "rate_limited_headings"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def fold_choices(row_cost: FloatArray, turn_cost: FloatArray) -> NDArray[np.bool_]:
    """The folds (T,) of least total cost: ``row_cost`` (2, T) the cost of each fold at each
    row, ``turn_cost`` (2, 2, T - 1) the cost of going from fold ``[., from]`` at row k to
    fold ``[to, .]`` at row k + 1 (``choose_folds``)."""
    count = row_cost.shape[1]
    folds = np.zeros(count, dtype=np.bool_)
    if count == 0:
        return folds
    back = np.zeros((count, 2), dtype=np.int8)
    total0, total1 = row_cost[0, 0], row_cost[1, 0]
    for k in range(1, count):
        a0, a1 = total0 + turn_cost[0, 0, k - 1], total1 + turn_cost[0, 1, k - 1]
        b0, b1 = total0 + turn_cost[1, 0, k - 1], total1 + turn_cost[1, 1, k - 1]
        back[k, 0] = 0 if a0 <= a1 else 1
        back[k, 1] = 0 if b0 <= b1 else 1
        total0, total1 = min(a0, a1) + row_cost[0, k], min(b0, b1) + row_cost[1, k]
    state = 0 if total0 <= total1 else 1
    for k in range(count - 1, -1, -1):
        folds[k] = state == 1
        state = back[k, state]
    return folds


@njit(cache=True)
def _remainder_tau(angle: float) -> float:
    """``math.remainder(angle, 2 pi)`` (which numba lacks), exactly: the remainder of the
    nearest quotient, the even one at a tie. From the exact ``fmod`` by 4 pi, whose size
    gives the parity of the truncated quotient by 2 pi (Sterbenz: each subtraction of 2 pi
    below is exact)."""
    tau = 2.0 * math.pi
    twice = float(np.fmod(angle, 2.0 * tau))
    odd = abs(twice) >= tau
    rest = twice - math.copysign(tau, twice) if odd else twice  # fmod(angle, tau)
    if rest == 0.0:
        return math.copysign(0.0, angle)  # IEEE: a zero remainder has the angle's sign
    if rest > math.pi:
        return rest - tau
    if rest < -math.pi:
        return rest + tau
    if abs(rest) == math.pi and odd:  # a tie: the quotient next to the odd one
        return -rest
    return rest


@njit(cache=True)
def rate_limited_headings(steps: FloatArray, target: FloatArray) -> FloatArray:
    """Headings (T,) following ``target`` (T,) rad, turning at most ``steps`` (T - 1,) rad
    between consecutive rows, the shorter way round (``tracking._rate_limited``)."""
    result = np.empty(len(target))
    if len(target) == 0:
        return result
    current = target[0]
    result[0] = current
    for k in range(1, len(target)):
        error = _remainder_tau(target[k] - current)
        limit = steps[k - 1]
        current += error if abs(error) <= limit else math.copysign(limit, error)
        result[k] = current
    return result
