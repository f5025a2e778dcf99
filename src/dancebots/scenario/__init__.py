"""The choreography language (thesis ch. 6): parsing, the scenario model, the demo text."""

from dancebots.scenario.model import (
    Circle,
    Cue,
    Formation,
    Instruction,
    Motion,
    Move,
    Scenario,
    Shape,
    Span,
    Tempo,
    Wait,
)
from dancebots.scenario.parser import parse_scenario

__all__ = [
    "Circle",
    "Cue",
    "Formation",
    "Instruction",
    "Motion",
    "Move",
    "Scenario",
    "Shape",
    "Span",
    "Tempo",
    "Wait",
    "parse_scenario",
]
