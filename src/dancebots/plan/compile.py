"""The compiler driver: choreography text to a plan, with every diagnostic found."""

from __future__ import annotations

from dancebots.diagnostics import Diagnostic
from dancebots.plan.planner import Plan, PlanParameters, build_plan
from dancebots.scenario.model import Scenario
from dancebots.scenario.parser import parse_scenario

__all__ = ["compile_scenario"]


def compile_scenario(
    text: str, path: str, parameters: PlanParameters | None = None
) -> tuple[Scenario | None, Plan | None, list[Diagnostic]]:
    """Parse and plan; returns whatever could be built and every diagnostic so far."""
    scenario, diagnostics = parse_scenario(text, path)
    if scenario is None:
        return None, None, diagnostics
    plan, plan_diagnostics = build_plan(scenario, parameters)
    return scenario, plan, diagnostics + plan_diagnostics
