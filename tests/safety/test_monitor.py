"""The safety state machine (thesis ch. 5): speech once, beeps every 3 s, errors for good."""

from __future__ import annotations

from dancebots.safety.monitor import (
    STOP_SENTENCE,
    Event,
    SafetyParams,
    SafetyState,
    safety_step,
)

PARAMS = SafetyParams()


def run(ticks: list[tuple[float, bool, bool, bool]]) -> list[tuple[float, tuple[Event, ...],
                                                                  bool]]:
    state = SafetyState()
    out = []
    for now, pose_ok, cloud, held in ticks:
        state, events, may_move = safety_step(PARAMS, state, now, pose_ok, cloud, held)
        out.append((now, events, may_move))
    return out


def test_speech_once_then_beeps_every_three_seconds_then_resume() -> None:
    ticks = [(round(0.1 * k, 1), True, True, 1.0 <= 0.1 * k < 8.05) for k in range(100)]
    happened = [(t, e) for t, events, _ in run(ticks) for e in events]
    assert happened == [
        (1.0, Event("speech", STOP_SENTENCE)),
        (4.0, Event("beep")),
        (7.0, Event("beep")),
        (8.1, Event("resume", "the way is clear")),
    ]


def test_lidar_silence_is_an_error_for_good() -> None:
    ticks = [(round(0.1 * k, 1), True, k < 20, False) for k in range(40)]
    results = run(ticks)
    first_error = next(t for t, events, _ in results if events)
    assert first_error == 2.3  # last cloud at 1.9 s; 2.3 - 1.9 > 0.3
    assert all(not may_move for t, _, may_move in results if t >= first_error)
    assert [e.kind for _, events, _ in results for e in events] == ["error"]


def test_three_failed_pose_lookups_are_an_error() -> None:
    ticks = [(0.0, True, True, False), (0.1, False, True, False), (0.2, False, True, False),
             (0.3, True, True, False), (0.4, False, True, False), (0.5, False, True, False),
             (0.6, False, True, False), (0.7, True, True, False)]
    results = run(ticks)
    assert [t for t, events, _ in results if events] == [0.6]
    assert results[-1][1:] == ((), False)  # recovered look-ups do not clear the error


def test_first_cloud_may_take_the_timeout() -> None:
    results = run([(0.0, True, False, False), (0.1, True, False, False),
                   (0.2, True, False, False), (0.3, True, True, False)])
    assert all(may_move for _, _, may_move in results)
