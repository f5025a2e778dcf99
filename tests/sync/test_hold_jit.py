"""The compiled step of the formation's clocks (sync/hold_jit.py) is ``formation_receive``
then ``formation_tick`` of sync/hold.py, bit for bit."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.sync.hold import (
    ADVANCE_MIN,
    FormationClocks,
    HoldParams,
    clock_rate,
    formation_receive,
    formation_tick,
)

PACES = st.sampled_from([1.0, 0.0, 0.5, 0.25, 0.9, 1e-300])
TIMES = st.sampled_from([0.0, -0.0, 0.1, 0.35, 1.0, 2.5, math.nan, math.inf, -math.inf,
                         1e-300, 3.0, -1.0])


@settings(max_examples=300, deadline=None)
@given(count=st.integers(0, 6), data=st.data())
def test_the_compiled_clocks_step_is_receive_then_tick(count: int,
                                                        data: st.DataObject) -> None:
    """Random clocks (nothing heard yet, old, holding, ahead or behind), a batch of messages
    or none (lost ones, stamps and show times that are not numbers, signed zeros) and the
    robots' own holds and paces: the seven arrays equal, bit for bit."""
    from dancebots.sync.hold_jit import receive_and_tick

    def floats(n: int) -> np.ndarray:
        return np.array(data.draw(st.lists(TIMES, min_size=n, max_size=n)), dtype=float)

    def paces(n: int) -> np.ndarray:
        return np.array(data.draw(st.lists(PACES, min_size=n, max_size=n)), dtype=float)

    def flags(n: int) -> np.ndarray:
        return np.array(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)),
                        dtype=bool)

    clocks = FormationClocks(floats(count), floats(count), floats(count), floats(count),
                             flags(count), floats(2 * count).reshape(count, 2), paces(count))
    message = data.draw(st.booleans())
    batch = (flags(count), floats(count), floats(count), flags(count),
             floats(2 * count).reshape(count, 2), paces(count))
    now = data.draw(st.sampled_from([0.0, -0.0, 0.1, 1.3, 5.0]))
    holding = flags(count)
    own_pace = paces(count)
    with np.errstate(invalid="ignore"):  # (inf - inf in the reference: no number, as here)
        expected = formation_tick(formation_receive(clocks, *batch) if message else clocks,
                                  now, holding, pace=own_pace)
    got = receive_and_tick(clocks.show_time, clocks.updated, clocks.stamp,
                           clocks.sent_show_time, clocks.holds, clocks.position, clocks.pace,
                           message, *batch, now, holding, own_pace,
                           HoldParams().heartbeat_timeout, ADVANCE_MIN)
    for name, value in zip(("show_time", "updated", "stamp", "sent_show_time", "holds",
                            "position", "pace"), got[:7], strict=True):
        assert value.tobytes() == getattr(expected, name).tobytes(), name
    # and how fast each clock ran since its last tick (what a paced brain follows)
    with np.errstate(invalid="ignore"):
        rates = np.asarray(clock_rate(expected.show_time - clocks.show_time,
                                      now - clocks.updated), dtype=float)
    assert got[7].tobytes() == rates.reshape(count).tobytes()


def test_a_tie_of_signed_zeros_is_numpys() -> None:
    """``np.maximum(-0.0, 0.0)`` is 0.0 and ``np.maximum(0.0, -0.0)`` -0.0 (NumPy 2.x as
    measured): a robot whose age and mate's show time are signed zeros gets NumPy's zero."""
    from dancebots.sync.hold_jit import receive_and_tick

    clocks = FormationClocks(np.array([-1.0, 0.0]), np.array([-1.0, 0.0]), np.zeros(2),
                             np.array([0.0, -0.0]), np.zeros(2, dtype=bool), np.zeros((2, 2)),
                             np.ones(2))
    batch = (np.zeros(2, dtype=bool), np.zeros(2), np.zeros(2), np.zeros(2, dtype=bool),
             np.zeros((2, 2)), np.ones(2))
    expected = formation_tick(clocks, -0.0, np.zeros(2, dtype=bool))
    got = receive_and_tick(clocks.show_time, clocks.updated, clocks.stamp,
                           clocks.sent_show_time, clocks.holds, clocks.position, clocks.pace,
                           False, *batch, -0.0, np.zeros(2, dtype=bool), np.ones(2),
                           HoldParams().heartbeat_timeout, ADVANCE_MIN)
    assert got[0].tobytes() == expected.show_time.tobytes()
    assert str(expected.show_time[0]) == "0.0"


RATIO_PARTS = st.sampled_from([0.0, -0.0, 0.1, 0.0999999999, 0.1000000001, 0.05, -0.02, 1.0,
                               1e-300, 1e-12, 3.0, math.nan])


@settings(max_examples=200, deadline=None)
@given(advance=st.lists(RATIO_PARTS, min_size=0, max_size=6), data=st.data())
def test_the_compiled_clock_rates_are_clock_rate(advance: list[float],
                                                 data: st.DataObject) -> None:
    """``hold_jit.clock_rates`` (the paced formation's rates each tick) equals
    ``hold.clock_rate`` of the same arrays bit for bit: full ticks (1 exactly), slowed and
    stood clocks, a clock that ran back, no time elapsed, tiny and NaN advances."""
    from dancebots.sync.hold_jit import clock_rates

    elapsed = np.array(data.draw(st.lists(RATIO_PARTS, min_size=len(advance),
                                          max_size=len(advance))), dtype=float)
    ahead = np.array(advance, dtype=float)
    compiled, reference = clock_rates(ahead, elapsed), np.asarray(clock_rate(ahead, elapsed))
    assert compiled.tobytes() == reference.astype(float).tobytes()
