"""``dancebots ros``: the commands it would run, and its errors (no ROS needed)."""

from __future__ import annotations

import re
import shlex
import socket
from pathlib import Path

import pytest

from dancebots.cli import main

EXAMPLE = Path(__file__).parents[2] / "examples" / "thesis_7_1.dance"


def test_formation_runs_formation_launch_for_the_role(capsys, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.delenv("HOSTNAME", raising=False)
    assert main(["ros", "formation", str(EXAMPLE), "--role", "R2", "--print-command"]) == 0
    words = shlex.split(capsys.readouterr().out)
    assert words[:3] == ["roslaunch", "dancebots_ros", "formation.launch"]
    assert f"scenario:={EXAMPLE.resolve()}" in words
    assert "role:=R2" in words
    assert f"hostname:={socket.gethostname()}" in words  # HOSTNAME is not exported
    monkeypatch.setenv("HOSTNAME", "husky-robot")
    assert main(["ros", "formation", str(EXAMPLE), "--role", "R1", "--print-command"]) == 0
    assert "hostname:=husky-robot" in shlex.split(capsys.readouterr().out)


def test_a_role_outside_the_scenario_is_refused(capsys) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit) as exit_info:
        main(["ros", "formation", str(EXAMPLE), "--role", "R9", "--print-command"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: dancebots ros formation ")  # the sub-command's own usage
    assert err.endswith("dancebots ros formation: error: --role 'R9' is not one of the "
                        "scenario's robots (R1, R2)\n")


def test_a_broken_scenario_is_reported_with_its_position(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    bad = tmp_path / "bad.dance"
    bad.write_text("robots R1\nmove 1\n")
    assert main(["ros", "simulate", str(bad), "--print-command"]) == 2
    assert f"{bad}:2:" in capsys.readouterr().err


@pytest.mark.parametrize("record", ["", "run.npz"])
def test_simulate_prints_its_launch_file(capsys, record: str) -> None:  # type: ignore[no-untyped-def]
    arguments = ["ros", "simulate", str(EXAMPLE), "--print-command"]
    if record:
        arguments += ["--record", record]
    assert main(arguments) == 0
    text = capsys.readouterr().out
    assert text.count('<include file="$(find dancebots_ros)/launch/formation.launch">') == 2
    assert ('name="record" value=""' in text) == (not record)


def test_the_strategies_reach_every_node(capsys) -> None:  # type: ignore[no-untyped-def]
    """--follower, --timing and --stop-rule go to formation.launch (formation_member's
    ~follower and ~stop_rule, and ~timing, which sets the plan, on every robot) and to the
    simulation's bridge."""
    strategies = ["--follower", "tracking", "--timing", "feasible", "--stop-rule", "closing",
                  "--print-command"]
    assert main(["ros", "formation", str(EXAMPLE), "--role", "R1", *strategies]) == 0
    words = shlex.split(capsys.readouterr().out)
    assert "follower:=tracking" in words
    assert "timing:=feasible" in words
    assert "stop_rule:=closing" in words
    assert main(["ros", "simulate", str(EXAMPLE), *strategies]) == 0
    launch = capsys.readouterr().out
    assert launch.count('<arg name="follower" value="tracking"/>') == 2  # R1 and R2
    assert launch.count('<arg name="timing" value="feasible"/>') == 2
    assert launch.count('<arg name="stop_rule" value="closing"/>') == 2
    assert '<param name="timing" value="feasible"/>' in launch  # the bridge's plan
    package = Path(__file__).parents[2] / "src" / "dancebots" / "ros1" / "package"
    formation = (package / "dancebots_ros" / "launch" / "formation.launch").read_text()
    assert '<param name="follower" value="$(arg follower)"/>' in formation
    assert '<param name="timing" value="$(arg timing)"/>' in formation
    assert '<param name="stop_rule" value="$(arg stop_rule)"/>' in formation


def test_start_at_sets_the_timecode_start(capsys) -> None:  # type: ignore[no-untyped-def]
    import argparse
    import datetime

    from dancebots.cli.ros import start_time

    assert main(["ros", "formation", str(EXAMPLE), "--role", "R1", "--start-at",
                 "2026-11-27T20:00:00+01:00", "--print-command"]) == 0
    words = shlex.split(capsys.readouterr().out)
    expected = datetime.datetime(2026, 11, 27, 19, 0, tzinfo=datetime.UTC).timestamp()
    assert "start_strategy:=timecode" in words
    assert f"start_at:={expected!r}" in words
    assert start_time("1795810800") == 1795810800.0
    assert start_time("+30", now=1000.0) == 1030.0
    for bad in ("soon", "+", "nan", "+inf", "0", "2026-13-40", "1e999"):
        with pytest.raises(argparse.ArgumentTypeError, match="is not a time: give an ISO"):
            start_time(bad)
    with pytest.raises(SystemExit) as exit_info:
        main(["ros", "formation", str(EXAMPLE), "--role", "R1", "--start-strategy",
              "timecode", "--print-command"])
    assert exit_info.value.code == 2
    assert capsys.readouterr().err.endswith(
        "error: --start-strategy timecode needs --start-at TIME\n")


@pytest.mark.parametrize(("hold", "waits"), [("", True), ("paced", True), ("alone", False)])
def test_simulate_ends_with_the_show_within_the_runs_limit(capsys, hold: str,  # type: ignore[no-untyped-def]
                                                           waits: bool) -> None:
    """The bridge ends the run at the show's end (the path follower's places' end, read on
    /hold) and at the latest after the start's allowance, the show, the settling and, for a
    formation that waits together, the run's longest wait (``SimConfig``); a formation
    that sends no hold messages (``--hold alone``) has no show end to wait for."""
    from dancebots.loading import load_show
    from dancebots.plan.places import places_end
    from dancebots.ros1.launching import START_ALLOWANCE
    from dancebots.shows.formation import SimConfig

    arguments = ["ros", "simulate", str(EXAMPLE), "--print-command"]
    assert main([*arguments, "--hold", hold] if hold else arguments) == 0
    launch = capsys.readouterr().out

    def param(name: str) -> float:
        found = re.search(rf'<param name="{name}" value="([^"]*)"/>', launch)
        assert found is not None, name
        return float(found.group(1))

    plan = load_show(str(EXAMPLE), timing="feasible").plan  # as the command loads it
    assert plan is not None
    end = max(plan.duration, places_end(plan))
    limits = SimConfig()
    assert param("show_end") == (pytest.approx(end) if waits else 0.0)
    assert param("settle") == limits.settle
    assert param("stop_after") == pytest.approx(
        end + START_ALLOWANCE + limits.settle + (limits.max_pause if waits else 0.0))
