"""The choreography language (thesis ch. 6): parsing, the scenario model, the demo text."""

from dancebots.scenario.model import Circle, Formation, Instruction, Move, Scenario, Shape, Span
from dancebots.scenario.parser import parse_scenario

__all__ = [
    "Circle",
    "Formation",
    "Instruction",
    "Move",
    "Scenario",
    "Shape",
    "Span",
    "parse_scenario",
]
