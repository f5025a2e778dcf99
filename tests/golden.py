"""The golden corpus: which files it holds and how a valid file's plan is summarised."""

from __future__ import annotations

from pathlib import Path

from dancebots.check import check_plan
from dancebots.plan.compile import compile_scenario

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(__file__).resolve().parent / "data"
VALID_SOURCES = sorted((ROOT / "examples").glob("*.dance")) + sorted(
    (DATA / "scenarios" / "valid").glob("*.dance"))
INVALID_SOURCES = sorted((DATA / "scenarios" / "invalid").glob("*.dance"))


def plan_summary(path: Path) -> dict[str, object]:
    """What a valid file compiles to: the check report (rounded) and its warnings' lines."""
    text = path.read_text(encoding="utf-8")
    _, plan, diagnostics = compile_scenario(text, path.name)
    assert plan is not None, diagnostics
    report = check_plan(plan)
    formations = [
        {"robots": list(f.robots), "start_s": round(f.start, 3), "end_s": round(f.end, 3),
         "new_vl": f.new_vl, "line": f.span.line,
         "leader_end": [round(float(v), 3) for v in f.leader.poses[-1]]}
        for f in plan.formations
    ]
    return {
        "report": report.to_json(),
        "formations": formations,
        "warnings": [f"{d.line}:{d.col}: {d.message}" for d in diagnostics + list(
            report.diagnostics)],
    }
