"""Run metrics on constructed results with known answers, and on scenario 7.1."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.report.metrics import run_metrics
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim import prepare_show


def result_for(text: str) -> RunResult:
    _, plan, diagnostics = compile_scenario(text, "t.dance")
    assert plan is not None, diagnostics
    arena, placement = prepare_show(place_show(plan, None))
    return simulate(plan, arena, placement, SimConfig(lidar=None))


def test_metrics_of_a_perfect_run_are_zero() -> None:
    result = result_for("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    # replace the robots' poses by their desired poses: a perfect follower
    perfect = RunResult(**{**{f: getattr(result, f) for f in result.__dataclass_fields__},
                           "poses": result.desired.copy()})
    metrics = run_metrics(perfect)
    assert all(m.max_error == 0.0 for m in metrics.robots)
    assert all(m.max_leader_distance_deviation == pytest.approx(0.0, abs=1e-12)
               for m in metrics.robots)
    assert metrics.max_spacing_change == pytest.approx(0.0, abs=1e-12)
    assert metrics.rows[0].robots == ("R1", "R2")
    assert metrics.rows[0].desired_spacings == (1.2,)


def test_metrics_of_a_shifted_robot() -> None:
    result = result_for("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    poses = result.desired.copy()
    poses[1, :, 1] -= 0.1  # R2 0.1 m further right all the time
    shifted = RunResult(**{**{f: getattr(result, f) for f in result.__dataclass_fields__},
                           "poses": poses})
    metrics = run_metrics(shifted)
    r1, r2 = metrics.robots
    assert r1.max_error == 0.0
    assert r2.max_error == pytest.approx(0.1)
    assert r2.rms_error == pytest.approx(0.1)
    assert metrics.max_spacing_change == pytest.approx(0.1)
    # d_req = hypot(0.5, 0.6) = 0.781; d_act = hypot(0.5, 0.7) = 0.860
    assert r2.max_leader_distance_deviation == pytest.approx(
        np.hypot(0.5, 0.7) - np.hypot(0.5, 0.6))


def test_metrics_json_of_scenario_7_1(examples: Path) -> None:
    metrics = run_metrics(result_for((examples / "thesis_7_1.dance").read_text()))
    data = metrics.to_json()
    assert data["collisions"] == 0
    assert set(data["per_robot"]) == {"R1", "R2"}  # type: ignore[arg-type]
    assert data["show_duration_s"] == pytest.approx(23.35)
    assert 0.05 < data["max_spacing_change_m"] < 0.25  # type: ignore[operator]
