"""The formation's shared show clocks (``sync.hold``) stepped in one compiled call.

:func:`formation_receive` and :func:`formation_tick` of ``sync.hold`` are some twenty NumPy
calls on arrays of a robot each, every control tick: their per-call cost, not the
arithmetic, is their time. :func:`receive_and_tick` does both, operation for operation (the
same numbers, bit for bit: tested against them). Importing this module imports numba.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["clock_rates", "receive_and_tick"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def receive_and_tick(show_time: FloatArray, updated: FloatArray, stamp: FloatArray,
                     sent_show_time: FloatArray, holds: NDArray[np.bool_],
                     position: FloatArray, pace: FloatArray, message: bool,
                     sent: NDArray[np.bool_], message_stamp: FloatArray,
                     message_show_time: FloatArray, message_holds: NDArray[np.bool_],
                     message_position: FloatArray, message_pace: FloatArray, now: float,
                     holding: NDArray[np.bool_], own_pace: FloatArray,
                     heartbeat_timeout: float, advance_min: float,
                     ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray,
                                NDArray[np.bool_], FloatArray, FloatArray, FloatArray]:
    """The clocks (``FormationClocks``' seven arrays: show_time, updated, stamp,
    sent_show_time, holds (R,), position (R, 2), pace (R,)) after, where ``message``, one
    batch of messages is heard (sent, stamp, show time, holds (R,), positions (R, 2), paces
    (R,) of each sender: ``formation_receive``), then ticked at ``now`` s with each robot's
    own hold ``holding`` (R,) and pace ``own_pace`` (R,) (``formation_tick``). Returns the
    seven new arrays and how fast each clock ran since its last tick (R,)
    (:func:`clock_rates` of its advance over ``now - updated``: what a paced brain follows
    its place at); the inputs are left as they were."""
    count = show_time.shape[0]
    stamp, sent_show_time = stamp.copy(), sent_show_time.copy()
    holds, position, pace = holds.copy(), position.copy(), pace.copy()
    for r in range(count if message else 0):
        new = (sent[r] and math.isfinite(message_stamp[r])
               and math.isfinite(message_show_time[r])
               and not stamp[r] >= message_stamp[r])  # NaN: nothing heard yet
        if new:
            stamp[r] = message_stamp[r]
            sent_show_time[r] = message_show_time[r]
            holds[r] = message_holds[r]
            position[r, 0] = message_position[r, 0]
            position[r, 1] = message_position[r, 1]
            pace[r] = message_pace[r]
    reach = np.empty(count)
    paces = np.empty(count)
    bad_count = 0
    bad = np.empty(count, dtype=np.bool_)
    for r in range(count):
        age = now - stamp[r]
        heard = not math.isnan(stamp[r]) and not age > heartbeat_timeout
        bad[r] = (not heard) or holds[r]
        if bad[r]:
            bad_count += 1
        reach[r] = (sent_show_time[r] + (0.0 if holds[r] else pace[r] * _maximum(age, 0.0))
                    if heard else math.inf)
        paces[r] = pace[r] if heard else 1.0
    first, second = _two_smallest(reach)
    slow, slower = _two_smallest(paces)
    new_show_time = np.empty(count)
    for r in range(count):
        ceiling = (reach[second] if r == first else reach[first]) if count > 1 else math.inf
        others_bad = (bad_count - (1 if bad[r] else 0)) > 0
        waiting = holding[r] or others_bad
        rate = (paces[slower] if r == slow else paces[slow]) if count > 1 else 1.0
        rate = _minimum(rate, own_pace[r])
        elapsed = _maximum(now - updated[r], 0.0)
        ahead = _minimum(show_time[r] + elapsed * rate, ceiling)
        runs = not waiting and ahead > show_time[r] + advance_min
        new_show_time[r] = ahead if runs else show_time[r]
    rates = clock_rates(new_show_time - show_time, now - updated)
    return (new_show_time, np.full(count, now), stamp, sent_show_time, holds, position, pace,
            rates)


@njit(cache=True)
def _two_smallest(values: FloatArray) -> tuple[int, int]:
    """The indices of the two smallest values (R,) as a stable sort orders them (NaN last;
    -1 where there are fewer)."""
    first, second = -1, -1
    for r in range(values.shape[0]):
        if first < 0 or _before(values[r], values[first]):
            second, first = first, r
        elif second < 0 or _before(values[r], values[second]):
            second = r
    return first, second


@njit(cache=True)
def _maximum(a: float, b: float) -> float:
    """``np.maximum`` of two floats, signed zeros and NaN as NumPy 2.x has them (measured:
    on a tie of zeros the second): ``a`` where it is larger or not a number, else ``b``."""
    return a if (a > b or math.isnan(a)) else b


@njit(cache=True)
def _minimum(a: float, b: float) -> float:
    """``np.minimum`` of two floats, signed zeros and NaN as NumPy 2.x has them (measured:
    on a tie of zeros the second): ``a`` where it is smaller or not a number, else ``b``."""
    return a if (a < b or math.isnan(a)) else b


@njit(cache=True)
def _before(a: float, b: float) -> bool:
    """Does ``a`` sort strictly before ``b`` (NaN after every number)?"""
    if math.isnan(a):
        return False
    return math.isnan(b) or a < b


@njit(cache=True)
def clock_rates(advance: FloatArray, elapsed: FloatArray) -> FloatArray:
    """``hold.clock_rate`` of arrays (R,) in one call: how fast each show clock ran (0-1)
    that advanced ``advance`` s of show time over ``elapsed`` s of its own clock."""
    rates = np.empty(advance.shape[0])
    for r in range(advance.shape[0]):
        ratio = advance[r] / max(elapsed[r], 1e-9)
        if ratio >= 1.0 - 1e-9 or elapsed[r] <= 0.0:
            rates[r] = 1.0
        else:  # (np.clip's, NaN kept)
            rates[r] = 0.0 if ratio < 0.0 else (1.0 if ratio > 1.0 else ratio)
    return rates
