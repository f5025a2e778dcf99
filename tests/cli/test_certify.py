"""dancebots certify: a show over many seeds among people, on real local processes."""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dancebots.cli import main
from dancebots.report.certify import CertifyJob, RunSummary, certificate

Capture = pytest.CaptureFixture[str]


def _session_members(session: int) -> list[int]:
    """Processes (pids) of session ``session`` still alive (zombies included)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        if int(fields[3]) == session:  # field 6 of stat: the session id
            found.append(int(entry.name))
    return found


def _certify(args: list[str]) -> subprocess.CompletedProcess[str]:
    """``dancebots certify ARGS`` as a real process in a session of its own; fails the test
    if any process of that session (the pool's workers) outlives it."""
    process = subprocess.Popen([sys.executable, "-m", "dancebots.cli", "certify", *args],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    try:
        stdout, stderr = process.communicate(timeout=600)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, 9)
            process.wait()
    left = _session_members(process.pid)
    if left:
        os.killpg(process.pid, 9)
        pytest.fail(f"certify left processes running: {left}")
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def test_blind_robots_fail_the_certificate_on_the_bystander(examples: Path, data: Path,
                                                            tmp_path: Path) -> None:
    out = tmp_path / "blind"
    done = _certify([str(examples / "thesis_7_1.dance"), "--world",
                     str(data / "worlds" / "crowd_and_bystander.toml"), "--runs", "2",
                     "--jobs", "2", "--no-lidar", "--out", str(out)])
    assert done.returncode == 1, done.stderr
    cert = json.loads((out / "certificate.json").read_text())
    assert cert["passed"] is False
    assert cert["runs"] == 2
    assert cert["processes"] == 2
    assert [r["seed"] for r in cert["per_run"]] == [0, 1]
    assert cert["contacts_moving"] == 2  # R1 drives into the bystander in both runs
    assert cert["runs_with_contacts_moving"] == 2
    assert cert["contacts_standing"] == 0
    assert "2 contacts of a moving robot with a person in 2 of 2 runs (seeds 0, 1)" in (
        done.stdout)
    assert "verdict: FAILED" in done.stdout
    assert (out / "certificate.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_certified_run_is_the_run_of_that_seed(examples: Path, data: Path, tmp_path: Path,
                                                 capsys: Capture) -> None:
    """Each per-run line is what ``dancebots run`` with that seed measures."""
    world = str(data / "worlds" / "crowd_and_bystander.toml")
    out = tmp_path / "cert"
    done = _certify([str(examples / "thesis_7_1.dance"), "--world", world, "--runs", "3",
                     "--first-seed", "4", "--out", str(out)])
    # no contact, but the bystander never leaves R1's way: no show finishes, none passes
    assert done.returncode == 1, done.stderr
    cert = json.loads((out / "certificate.json").read_text())
    assert cert["passed"] is False
    assert cert["contacts_moving"] == 0
    assert cert["runs_unfinished"] == 3
    assert [r["seed"] for r in cert["per_run"]] == [4, 5, 6]
    reached = sorted(round(100 * r["show_reached"]) for r in cert["per_run"])
    assert 0 < reached[0] <= reached[-1] < 100
    assert ("3 of 3 shows did not finish: the formation waited for a held robot until the "
            "run's limit, for people within 2 m of it 100 % of the time the clock stood; they "
            f"reached {reached[1]} % of the show (median; least {reached[0]} %) (seeds 4, 5, "
            "6)") in done.stdout
    assert "people kept the robots waiting: give the show room" in done.stdout
    assert cert["runs_stalled"] == 0  # the bystander explains every stood tick
    # the bystander stands on R1's last leg for good: safe, but the formation waits for R1
    # until the run ends (SimConfig.max_pause)
    assert main(["run", str(examples / "thesis_7_1.dance"), "--world", world, "--profile",
                 "realistic", "--seed", "5", "--no-animation", "--out",
                 str(tmp_path / "run")]) == 1
    assert "the show did not finish: the formation waited for a held robot until the run" in (
        capsys.readouterr().out)
    assert cert["runs_not_clean"] == 3
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    seed5 = cert["per_run"][1]
    assert round(seed5["min_person_gap"], 4) == metrics["min_person_gap_m"]
    assert seed5["stops"] == metrics["stops"]
    assert seed5["show_reached"] == pytest.approx(
        metrics["final_show_time_s"] / metrics["show_end_s"], abs=1e-3)
    assert round(seed5["held_place_error"], 4) == metrics["held_place_error_m"]
    assert seed5["angular_sign_flips"] == metrics["angular_sign_flips"]
    assert round(seed5["reverse_fraction"], 4) == metrics["reverse_fraction"]
    assert seed5["clock_brief_runs"] == metrics["clock_brief_runs"]
    assert round(seed5["max_excess_turn"], 4) == metrics["max_excess_turn_deg"]
    turned = [r["max_excess_turn"] for r in cert["per_run"]]
    assert cert["max_excess_turn_deg"]["max"] == pytest.approx(max(turned), abs=1e-3)
    assert (f"turned beyond what it tracks, the most of any robot, deg per run: median "
            f"{statistics.median(turned):.0f}, max {max(turned):.0f}") in done.stdout
    brief = [r["clock_brief_runs"] for r in cert["per_run"]]
    assert (f"the formation lurched on (its clock ran 0.35 s or less between two stands), "
            f"times per run: median {statistics.median(brief):.0f}, max {max(brief)}"
            ) in done.stdout
    assert cert["stops"]["max"] == max(r["stops"] for r in cert["per_run"])
    flips = [r["angular_sign_flips"] for r in cert["per_run"]]
    assert cert["angular_sign_flips"]["max"] == max(flips)
    assert (f"turn-rate sign flips per run median {statistics.median(flips):.0f}, max "
            f"{max(flips)}") in done.stdout
    assert seed5["contacts_moving"] == 0
    assert metrics["collisions"] == 0
    gaps = [r["min_person_gap"] for r in cert["per_run"]]
    assert cert["min_person_gap_m"]["min"] == round(min(gaps), 4)
    assert len(set(gaps)) == 3  # every seed drew its own crowd


def test_certify_needs_a_world_with_people(examples: Path, capsys: Capture) -> None:
    assert main(["certify", str(examples / "thesis_7_1.dance")]) == 2
    assert ("certify needs --world W: a world with the people ([[crowds]] or "
            "[[spectators]], docs/worlds.md)") in capsys.readouterr().err


def test_the_certificate_counts_the_robots_doing_apart() -> None:
    def run(seed: int, moving: int, standing: int, gap: float | None) -> RunSummary:
        return RunSummary(seed, moving, standing, 0, gap, 2.0 * seed, seed, 0.1 * seed, 1.0,
                          True, 0.02, moving == 0, (), 1.0)

    job = CertifyJob("show.dance", "world.toml")
    cert = certificate(job, [run(2, 0, 1, 0.0), run(0, 0, 0, 0.3), run(1, 0, 0, None)],
                       3.0, 2)
    data = cert.to_json()
    assert cert.passed  # a robot standing still that a person stood in is not its doing
    assert data["contacts_standing"] == 1
    assert [r["seed"] for r in data["per_run"]] == [0, 1, 2]
    assert data["min_person_gap_m"] == {"min": 0.0, "p1": 0.003, "p5": 0.015, "median": 0.15,
                                        "max": 0.3}
    assert data["held_robot_s"]["max"] == 4.0
    assert data["held_place_error_m"]["max"] == 0.2
    failing = certificate(job, [run(0, 1, 0, 0.0)], 1.0, 1)
    assert not failing.passed
    assert failing.to_json()["runs_with_contacts_moving"] == 1


def test_the_certificate_says_why_shows_did_not_finish_and_fails_a_stall() -> None:
    from dancebots.cli.certify import _failures

    def run(seed: int, finished: bool, stood: float, for_people: float) -> RunSummary:
        return RunSummary(seed, 0, 0, 0, 0.2, 10.0, 3, 0.05, 0.0, finished, 0.02, finished,
                          (), 1.0, stood, for_people,
                          show_reached=1.0 if finished else 0.1 * (seed + 3))

    job = CertifyJob("show.dance", "world.toml")
    crowded = certificate(job, [run(0, True, 20.0, 20.0), run(1, False, 150.0, 60.0),
                                run(2, False, 100.0, 100.0)], 3.0, 2)
    assert not crowded.passed
    assert crowded.unfinished_for_people() == pytest.approx(160.0 / 250.0)
    assert _failures(crowded) == (
        "2 of 3 shows did not finish: the formation waited for a held robot until the run's "
        "limit, for people within 2 m of it 64 % of the time the clock stood; they reached "
        "50 % of the show (median; least 40 %) (seeds 1, 2)",
        "in 1 of 3 runs the formation stood 3 s or more with nobody within 2 m of the robots "
        "that held it (robots waiting for each other, for a wall, or for a failed or silent "
        "mate; seeds 1)")
    # a clock that stood 3 s or more with nobody near fails the certificate, finished or not
    stalled = certificate(job, [run(0, True, 20.0, 20.0), run(1, True, 13.0, 10.0)], 3.0, 2)
    assert not stalled.passed
    assert stalled.runs[1].stalled
    assert not stalled.runs[0].stalled
    assert stalled.to_json()["runs_stalled"] == 1
    assert stalled.to_json()["clock_stood_otherwise_s"]["max"] == 3.0
    assert _failures(stalled) == (
        "in 1 of 2 runs the formation stood 3 s or more with nobody within 2 m of the robots "
        "that held it (robots waiting for each other, for a wall, or for a failed or silent "
        "mate; seeds 1)",)
    assert certificate(job, [run(0, True, 20.0, 17.1)], 1.0, 1).passed


def test_sigterm_stops_certify_and_its_workers(examples: Path, data: Path,
                                               tmp_path: Path) -> None:
    import signal
    import time

    process = subprocess.Popen(
        [sys.executable, "-m", "dancebots.cli", "certify", str(examples / "thesis_7_1.dance"),
         "--world", str(data / "worlds" / "crowded_room.toml"), "--runs", "200", "--jobs", "2",
         "--out", str(tmp_path / "cert")], stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while len(_session_members(process.pid)) < 3 and time.monotonic() < deadline:
            time.sleep(0.2)  # the parent and its two workers
        assert len(_session_members(process.pid)) >= 3
        process.send_signal(signal.SIGTERM)
        status = process.wait(timeout=60)
        deadline = time.monotonic() + 10
        while _session_members(process.pid) and time.monotonic() < deadline:
            time.sleep(0.1)
        left = _session_members(process.pid)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, 9)
            process.wait()
    if left:
        os.killpg(process.pid, 9)
    assert not left, f"workers outlived a SIGTERM: {left}"
    assert status != 0
    assert not (tmp_path / "cert").exists()  # nothing half-written


def test_a_crowd_that_does_not_fit_is_refused_before_anything_is_written(
        capsys: Capture, tmp_path: Path) -> None:
    (tmp_path / "s.dance").write_text("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    (tmp_path / "w.toml").write_text(
        '[room]\nsize = 10.0\n\n[[robots]]\nname = "R1"\nx = 5.0\ny = 5.6\n\n'
        '[[robots]]\nname = "R2"\nx = 5.0\ny = 4.4\n\n[[crowds]]\ncount = 1\n'
        'area = [[4.5, 5.1], [5.5, 5.1], [5.5, 6.1], [4.5, 6.1]]\n')
    out = tmp_path / "run"
    assert main(["run", str(tmp_path / "s.dance"), "--world", str(tmp_path / "w.toml"),
                 "--no-animation", "--out", str(out)]) == 2
    assert ("dancebots run: error: crowd 'crowd 1' does not fit in its area: 0 of 1 placed "
            "clear of the robots, obstacles and others: enlarge its area, lower its count or "
            "keep it away from the robots' start poses and the walls") in capsys.readouterr().err
    assert not out.exists()


def test_certify_runs_its_seeds_on_a_ray_cluster(examples: Path, data: Path,
                                                 tmp_path: Path) -> None:
    """``--ray ADDRESS``: a real Ray head (``ray start --head``, 2 CPUs) in a network
    namespace of the test's own, where certify connects to it; every seed's summary is the
    local pool's, and no Ray process outlives the test (the namespace must be empty after
    ``ray stop``)."""
    import shutil
    import tempfile

    from tests.ros1.netns import hosts, netns_missing

    reason = netns_missing()
    if reason is not None:
        pytest.fail(reason)
    world = str(data / "worlds" / "crowd_and_bystander.toml")
    scenario = str(examples / "thesis_7_1.dance")
    local = _certify([scenario, "--world", world, "--runs", "3", "--jobs", "2", "--out",
                      str(tmp_path / "local")])
    assert local.returncode == 1, local.stderr  # the bystander never leaves: not finished
    ray = str(Path(sys.executable).parent / "ray")
    sessions = tempfile.mkdtemp(prefix="dbray", dir="/tmp")  # short: Ray's socket paths
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0")
    try:
        with hosts(()) as network:
            inside = ["ip", "netns", "exec", network.master]
            address = f"{network.master_address}:6391"
            started = subprocess.run(
                [*inside, ray, "start", "--head", f"--node-ip-address="
                 f"{network.master_address}", "--port=6391", "--num-cpus=2",
                 "--include-dashboard=false", "--disable-usage-stats",
                 f"--temp-dir={sessions}"], env=env, capture_output=True, text=True,
                timeout=180, check=False)
            try:
                assert started.returncode == 0, started.stderr[-2000:]
                done = subprocess.run(
                    [*inside, sys.executable, "-m", "dancebots.cli", "certify", scenario,
                     "--world", world, "--runs", "3", "--ray", address, "--out",
                     str(tmp_path / "ray")], env=env, capture_output=True, text=True,
                    timeout=600, check=False)
            finally:
                subprocess.run([*inside, ray, "stop", "--force"], env=env,
                               capture_output=True, timeout=120, check=False)
    finally:
        shutil.rmtree(sessions, ignore_errors=True)
    assert done.returncode == 1, done.stderr[-2000:]
    on_ray = json.loads((tmp_path / "ray" / "certificate.json").read_text())
    pooled = json.loads((tmp_path / "local" / "certificate.json").read_text())
    assert on_ray["processes"] == 2  # the cluster's CPUs
    assert [r["seed"] for r in on_ray["per_run"]] == [0, 1, 2]

    def runs(cert: dict[str, object]) -> list[dict[str, object]]:
        per_run = cert["per_run"]
        assert isinstance(per_run, list)
        return [{k: v for k, v in r.items() if k != "wall"} for r in per_run]

    assert runs(on_ray) == runs(pooled)
    assert "3 of 3 shows did not finish" in done.stdout


def test_the_certificate_tells_contacts_of_a_robot_moving_away_apart() -> None:
    """A moving robot's contacts with people all count against the certificate; those in
    which its footprint moved away from the person (ISO/TS 15066's speed towards the person
    0 or less) are told apart for the reader. The thesis's fixed distance driving into a
    walker head-on: every contact at the person."""
    from dataclasses import replace

    from dancebots.cli.certify import _failures
    from dancebots.plan.placement import place_show
    from dancebots.report.certify import summarise
    from dancebots.report.metrics import run_metrics
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim import REALISTIC, prepare_show
    from dancebots.sim.spectators import Spectator
    from tests_support import plan_of

    plan = plan_of("robots R1\nrow R1 0 0\nmove 6 0\n")
    arena, placement = prepare_show(place_show(plan))
    x, y, theta = (float(v) for v in placement.starts[0])
    ahead = np.array([np.cos(theta), np.sin(theta)])
    person = Spectator("visitor", 0.25, 1.7, 1.0, np.array(
        [[x, y] + 5.0 * ahead, [x, y] - 3.0 * ahead]), np.zeros(2), False, 1.0, 0)
    result = simulate(plan, replace(arena, spectators=(person,)), placement,
                      SimConfig(profile=REALISTIC, brain=BrainOptions(
                          follower="path", stop_rule="fixed")))
    head_on = summarise(0, run_metrics(result), (), 1.0)
    assert head_on.contacts_moving >= 1
    assert head_on.contacts_moving_away == 0

    def run(seed: int, moving: int, away: int) -> RunSummary:
        return RunSummary(seed, moving, 0, 0, 0.0, 1.0, 1, 0.1, 0.0, True, 0.02, moving == 0,
                          (), 1.0, contacts_moving_away=away)

    cert = certificate(CertifyJob("show.dance", "world.toml"),
                       [run(0, 2, 1), run(1, 0, 0), run(2, 1, 0)], 1.0, 2)
    assert not cert.passed
    assert cert.to_json()["contacts_moving_away"] == 1
    assert _failures(cert)[0] == (
        "3 contacts of a moving robot with a person in 2 of 3 runs (seeds 0, 2); in 1 of them "
        "it moved away from the person or slid past")


def test_the_certificate_tells_contacts_with_a_runner_apart() -> None:
    """A contact in which the person had run at the robot faster than the 1.6 m/s the stop
    rules assume (``metrics.json`` ``person_approach_mps``, their run-up) still counts against
    the certificate, and is told apart for the reader: the thesis's fixed distance driving
    at a visitor running head-on at 2.5 m/s, and at one walking at 1.0 m/s."""
    from dataclasses import replace

    from dancebots.cli.certify import _failures
    from dancebots.plan.placement import place_show
    from dancebots.report.certify import summarise
    from dancebots.report.metrics import run_metrics
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim import REALISTIC, prepare_show
    from dancebots.sim.spectators import Spectator
    from tests_support import plan_of

    plan = plan_of("robots R1\nrow R1 0 0\nmove 6 0\n")
    arena, placement = prepare_show(place_show(plan))
    x, y, theta = (float(v) for v in placement.starts[0])
    ahead = np.array([np.cos(theta), np.sin(theta)])
    summaries = []
    for seed, speed in enumerate((2.5, 1.0)):
        person = Spectator("visitor", 0.25, 1.7, speed, np.array(
            [[x, y] + 5.0 * ahead, [x, y] - 3.0 * ahead]), np.zeros(2), False, 1.0, 0)
        result = simulate(plan, replace(arena, spectators=(person,)), placement,
                          SimConfig(profile=REALISTIC, brain=BrainOptions(
                              follower="path", stop_rule="fixed")))
        metrics = run_metrics(result)
        first = metrics.collision_events[0]
        assert first["person_approach_mps"] == pytest.approx(speed, abs=0.05)
        summaries.append(summarise(seed, metrics, (), 1.0))
    runner, walker = summaries
    assert runner.contacts_moving_runners >= 1  # (the first at least)
    assert walker.contacts_moving >= 1
    assert walker.contacts_moving_runners == 0
    cert = certificate(CertifyJob("show.dance", "world.toml"), summaries, 1.0, 1)
    assert not cert.passed
    assert cert.to_json()["contacts_moving_runners"] == runner.contacts_moving_runners
    assert (f"; in {runner.contacts_moving_runners} of them the person ran at the robot "
            "faster than 1.6 m/s (the walking speed the stop rules assume)"
            ) in _failures(cert)[0]
