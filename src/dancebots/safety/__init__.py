"""Safety (thesis ch. 5): failure detection and the stop / speech / beep state machine."""

from dancebots.safety.monitor import (
    STOP_SENTENCE,
    Event,
    SafetyParams,
    SafetyState,
    safety_step,
)

__all__ = ["STOP_SENTENCE", "Event", "SafetyParams", "SafetyState", "safety_step"]
