"""Small helpers shared by tests."""

from __future__ import annotations

from dancebots.plan import Plan, PlanParameters
from dancebots.plan.compile import compile_scenario


def plan_of(text: str, parameters: PlanParameters | None = None,
            path: str = "test.dance") -> Plan:
    """The plan of a scenario text that must compile (its diagnostics otherwise)."""
    _, plan, diagnostics = compile_scenario(text, path, parameters)
    assert plan is not None, diagnostics
    return plan
