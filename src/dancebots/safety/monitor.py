"""Safety of thesis ch. 5 as a pure state machine: failure detection, stop speech and beeps.

Each control tick gets: whether the robot's pose look-up worked, whether a LIDAR cloud
arrived, and whether the robot is held by a stop flag. It returns the new state, the events
to voice (speech once when a stop begins, a beep every 3 s while it lasts, a note when the
way is clear) and whether the robot may move at all. LIDAR data older than 0.3 s or three
consecutive failed pose look-ups put the robot into an error state it never leaves (thesis
5.1: such errors need a person).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["STOP_SENTENCE", "Event", "EventKind", "SafetyParams", "SafetyState", "safety_step"]

STOP_SENTENCE = "Obstacle is too close, I have to stop"
"""What a stopped robot says (thesis ch. 5.2)."""


EventKind = Literal["speech", "beep", "resume", "error"]
"""What a robot voices or reports: its stop sentence, a beep, that the way is clear, an error."""


@dataclass(frozen=True, slots=True)
class Event:
    """Something a robot voices or reports (:data:`EventKind`), with its text."""

    kind: EventKind
    text: str = ""


@dataclass(frozen=True, slots=True)
class SafetyParams:
    """sensor_timeout: s without a new LIDAR cloud before the error state (thesis 0.3 s);
    max_lookup_failures: consecutive failed pose look-ups before it (thesis 3);
    beep_period: s between beeps while stopped (thesis 3 s)."""

    sensor_timeout: float = 0.3
    max_lookup_failures: int = 3
    beep_period: float = 3.0


@dataclass(frozen=True, slots=True)
class SafetyState:
    error: str | None = None
    lookup_failures: int = 0
    last_cloud: float | None = None  # arrival time of the latest cloud, s
    first_tick: float | None = None
    stopped_since: float | None = None
    last_beep: float | None = None


def safety_step(params: SafetyParams, state: SafetyState, now: float, pose_ok: bool,
                cloud_arrived: bool, held: bool) -> tuple[SafetyState, tuple[Event, ...],
                                                          bool]:
    """One tick. Returns (state, events, may_move); may_move is False in the error state."""
    if state.error is not None:
        return state, (), False
    first = state.first_tick if state.first_tick is not None else now
    last_cloud = now if cloud_arrived else state.last_cloud
    failures = 0 if pose_ok else state.lookup_failures + 1
    reference = last_cloud if last_cloud is not None else first
    error = None
    if failures >= params.max_lookup_failures:
        error = f"{failures} consecutive failed pose look-ups"
    elif now - reference > params.sensor_timeout + 1e-6:
        error = f"no LIDAR data for {now - reference:.1f} s"
    if error is not None:
        return (SafetyState(error, failures, last_cloud, first, None, None),
                (Event("error", error),), False)
    events: tuple[Event, ...] = ()
    stopped_since, last_beep = state.stopped_since, state.last_beep
    if held and stopped_since is None:
        stopped_since, last_beep = now, now
        events = (Event("speech", STOP_SENTENCE),)
    elif held and last_beep is not None and now - last_beep >= params.beep_period - 1e-9:
        last_beep = now
        events = (Event("beep"),)
    elif not held and stopped_since is not None:
        stopped_since, last_beep = None, None
        events = (Event("resume", "the way is clear"),)
    new = SafetyState(None, failures, last_cloud, first, stopped_since, last_beep)
    return new, events, True
