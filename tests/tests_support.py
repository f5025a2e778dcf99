"""Small helpers shared by tests."""

from __future__ import annotations

from dancebots.check import compile_scenario
from dancebots.plan import Plan


def plan_of(text: str) -> Plan:
    _, plan, diagnostics = compile_scenario(text, "test.dance")
    assert plan is not None, diagnostics
    return plan
