"""``dancebots certify``: run a show over many seeds among people and write a certificate.

A thin shell: it checks the show once, runs the seeds on a pool of local processes
(``report.certify.run_seed`` in each), or as Ray tasks on a Ray cluster (``--ray ADDRESS``:
Ray, the distributed engine, schedules them; every node must see the show's files at the same
absolute paths and have dancebots installed), gathers the summaries into a certificate, writes
certificate.json and certificate.png through the output writer of ``cli.common`` and exits 0
when no moving robot touched a person, no robot touched a robot, wall or obstacle and every
show finished in every run, 1 otherwise. Ctrl-C and SIGTERM stop the workers; a worker whose
parent dies is stopped by the kernel (PR_SET_PDEATHSIG).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from dancebots.cli.common import (
    PROFILES,
    ShowOutcome,
    add_follower_argument,
    add_hold_argument,
    add_show_arguments,
    add_stop_rule_argument,
    add_timing_argument,
    bundled,
    in_range,
    positive,
    profile_missing,
    progress,
    refuse,
    run_show_into,
    say_compiling,
    short_path,
)

if TYPE_CHECKING:
    from dancebots.report.certify import Certificate, CertifyJob, RunSummary

NAME = "certify"
HELP = "run a show over many seeds among people and write a safety certificate"
DESCRIPTION = ("Run a show over N seeds (each a new draw of the world's crowds and of the "
               "realistic profile's noise) on local processes, and write certificate.json and "
               "certificate.png: contacts of a moving robot with a person (the robot's doing), "
               "contacts of a robot standing still, the smallest robot-person gap, the time "
               "robots were held and how much longer the show took. Exit 0 when no moving "
               "robot touched a person, no robot touched a robot, wall or obstacle and every "
               "show finished (did not wait for people beyond the run's limit) in every run; "
               "1 otherwise; 2 when the input is invalid.")
OUTPUT_NAMES = ("certificate.json", "certificate.png")
MAX_RUNS = 100_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_show_arguments(parser, scenario_help="choreography file (default: the bundled "
                       "open-day show in its hall with a crowd of adults and children)",
                       world_help="world file (TOML, docs/worlds.md) with the people: "
                       "[[crowds]] and [[spectators]]")
    parser.add_argument("--runs", type=in_range(1, MAX_RUNS, integer=True), default=100,
                        metavar="N", help="how many seeds to run (default 100)")
    parser.add_argument("--first-seed", type=in_range(0, 2**32 - 1 - MAX_RUNS, integer=True),
                        default=0, metavar="S", help="the seeds are S, S+1, ... (default 0)")
    parser.add_argument("--jobs", type=in_range(1, 1024, integer=True), default=None,
                        metavar="J", help="local processes (default: one per core)")
    parser.add_argument("--ray", metavar="ADDRESS", default=None,
                        help="run the seeds as tasks on the Ray cluster at ADDRESS "
                        "(host:port of its head, as `ray start --head` prints; needs Ray: "
                        "pip install ray) instead of local processes; every node must see the "
                        "show's files at the same paths")
    parser.add_argument("--profile", choices=PROFILES,
                        default="realistic", help="the simulator's profile (physics: MuJoCo, "
                        "no noise: the seeds draw the crowds only) (default: realistic)")
    parser.add_argument("--no-lidar", action="store_true",
                        help="robots without LIDAR (they cannot see people: for comparison)")
    add_follower_argument(parser)
    add_timing_argument(parser)
    add_hold_argument(parser)
    add_stop_rule_argument(parser)
    parser.add_argument("--final-tolerance", type=positive, default=0.5, metavar="M",
                        help="a run whose robot ends further than this from its final slot "
                        "is not clean, m (default 0.5; reported, does not fail the "
                        "certificate)")
    parser.add_argument("--out", metavar="DIR", help="output directory (default: "
                        "out/NAME-certificate); a new or empty directory, or one of an "
                        "earlier certification, whose files dancebots replaces")
    parser.add_argument("--json", action="store_true",
                        help="print the certificate as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    from dancebots.report.certify import CertifyJob, load_job

    if args.scenario is None:
        args.scenario = short_path(bundled("open_day.dance"))
        if args.world is None:
            args.world = short_path(bundled("open_day_crowd.toml"))
    if args.world is None:
        return refuse(NAME, args.json, "certify needs --world W: a world with the people "
                      "([[crowds]] or [[spectators]], docs/worlds.md)")
    missing = profile_missing(args.profile)
    if missing is not None:
        return refuse(NAME, args.json, missing)
    from dancebots.robot import default_stop_rule

    job = CertifyJob(args.scenario, args.world, args.vmax, args.profile, args.follower,
                     args.timing, not args.no_lidar, args.final_tolerance, args.hold,
                     default_stop_rule(args.follower, args.stop_rule))
    if args.ray is not None:
        refused = _ray_refusal(args.ray)
        if refused is not None:
            return refuse(NAME, args.json, refused)
    show = load_job(job)  # the check and placement every worker repeats, once here first
    if not show.valid or show.report is None or show.report.placement is None:
        return refuse(NAME, args.json, diagnostics=show.diagnostics, sources=show.sources)
    from dancebots.sim.setup import SetupError, prepare_show

    try:
        prepare_show(show.report.placement)
    except SetupError as exc:
        return refuse(NAME, args.json, str(exc))
    target = Path(args.out) if args.out else Path("out") / f"{Path(args.scenario).stem}-certificate"
    return run_show_into(NAME, target, OUTPUT_NAMES, args.json,
                         lambda staging: _certify(args, job, staging, target))


def _worker_start() -> None:
    """Workers leave Ctrl-C to the parent, which stops the pool, and die with the parent
    (Linux's PR_SET_PDEATHSIG: a parent killed outright leaves no worker behind)."""
    import contextlib
    import ctypes
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    with contextlib.suppress(OSError, AttributeError):  # not Linux: the parent stops them
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, int(signal.SIGKILL))  # PDEATHSIG


def _terminate(signum: int, frame: object) -> None:
    """SIGTERM in the parent: stop like Ctrl-C (the pool's workers are terminated)."""
    raise KeyboardInterrupt


RAY_CONNECT_TIMEOUT = 5.0
"""s to wait for a Ray head to accept a connection before certify refuses (ray.init itself
waits minutes for an address where nothing answers)."""


def _ray_refusal(address: str) -> str | None:
    """Why ``--ray ADDRESS`` cannot be used (None: Ray is installed and something listens
    there): Ray missing, an address that is not host:port, or nothing answering."""
    import importlib.util
    import socket

    if importlib.util.find_spec("ray") is None:
        return ("certify --ray needs Ray, which is not installed here: pip install ray (or "
                "run without --ray on local processes)")
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        return (f"--ray {address!r} is not HOST:PORT (the address `ray start --head` prints, "
                "e.g. 127.0.0.1:6379)")
    try:
        with socket.create_connection((host, int(port)), timeout=RAY_CONNECT_TIMEOUT):
            pass
    except OSError as exc:
        return (f"no Ray cluster answers at {address} ({exc}); start one with `ray start "
                "--head` there, or run without --ray")
    return None


def _on_ray(address: str, job: CertifyJob, seeds: list[int],
            update: Callable[[int, int], None]) -> tuple[list[RunSummary], int]:
    """The seeds' summaries run as Ray tasks on the cluster at ``address`` (the show's files
    by absolute path: the tasks run in the workers' own directories), and how many CPUs the
    cluster has."""
    from dataclasses import replace

    import ray

    from dancebots.report.certify import run_seed

    remote_job = replace(job, scenario=str(Path(job.scenario).resolve()),
                         world=str(Path(job.world).resolve()))
    import logging

    ray.init(address=address, log_to_driver=False, logging_level=logging.ERROR,
             configure_logging=False)
    try:
        task = ray.remote(num_cpus=1, max_retries=0)(run_seed)
        pending = [task.remote(remote_job, seed) for seed in seeds]
        cpus = int(ray.cluster_resources().get("CPU", 1))  # type: ignore[no-untyped-call]
        done: dict[int, RunSummary] = {}
        try:
            while pending:
                ready, pending = ray.wait(pending, num_returns=len(pending), timeout=0.5)
                for summary in ray.get(ready):
                    done[summary.seed] = summary
                update(len(done), len(seeds))
        except BaseException:
            for ref in pending:  # a run in progress is not waited for
                ray.cancel(ref, force=True)
            raise
        return [done[seed] for seed in seeds], cpus
    finally:
        ray.shutdown()


def _certify(args: argparse.Namespace, job: CertifyJob, staging: Path,
             target: Path) -> ShowOutcome:
    from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

    from rich.console import Console

    from dancebots.report.certify import job_has_crowds, run_seed
    from dancebots.sim.kernels import kernels_to_compile

    console = Console(stderr=True, soft_wrap=True)
    compile_first = kernels_to_compile(crowds=job_has_crowds(job), stop_rule=job.stop_rule)
    if compile_first:
        say_compiling(console, len(compile_first))
        run_seed(job, args.first_seed)  # compiled once here, cached on disk for the workers
    seeds = list(range(args.first_seed, args.first_seed + args.runs))
    if args.ray is not None:
        started = time.perf_counter()
        with progress(console, f"certifying  (Ray cluster at {args.ray}, runs)") as update:
            on_ray, cpus = _on_ray(args.ray, job, seeds, update)
        return _outcome(job, on_ray, time.perf_counter() - started, cpus, staging, target)
    processes = min(args.jobs or os.cpu_count() or 1, len(seeds))
    summaries: list[RunSummary] = []
    started = time.perf_counter()
    import signal

    signal.signal(signal.SIGTERM, _terminate)
    pool = ProcessPoolExecutor(processes, initializer=_worker_start)
    try:
        label = f"{processes} {'process' if processes == 1 else 'processes'}"
        with progress(console, f"certifying  ({label}, runs)") as update:
            pending: set[Future[RunSummary]] = {pool.submit(run_seed, job, s) for s in seeds}
            while pending:
                done, pending = wait(pending, timeout=0.5, return_when=FIRST_COMPLETED)
                summaries.extend(f.result() for f in done)
                update(len(summaries), len(seeds))
    except BaseException:
        workers = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in workers:  # a run in progress is not waited for
            process.terminate()
        raise
    pool.shutdown()
    return _outcome(job, summaries, time.perf_counter() - started, processes, staging, target)


def _outcome(job: CertifyJob, summaries: list[RunSummary], wall: float, processes: int,
             staging: Path, target: Path) -> ShowOutcome:
    """The certificate of the runs, written into ``staging``, with its verdict."""
    from dancebots.report.certify import certificate
    from dancebots.report.verdict import Verdict

    cert = certificate(job, summaries, wall, processes)
    written = _write(cert, staging)
    failures = _failures(cert)
    return ShowOutcome(written, cert.wall, Verdict(failures), cert.to_json(),
                       lambda: _summary(cert, target, written))


def _failures(cert: Certificate) -> tuple[str, ...]:
    from dancebots.report.certify import RUNNING_SPEED
    from dancebots.report.metrics import PERSON_NEAR
    from dancebots.report.verdict import STALL_CAUSES, STALL_TOLERANCE

    lines = []
    if cert.contacts_moving:
        runs = [r.seed for r in cert.runs if r.contacts_moving]
        away = (f"; in {cert.contacts_moving_away} of them it moved away from the person or "
                "slid past" if cert.contacts_moving_away else "")
        if cert.contacts_moving_runners:
            away += (f"; in {cert.contacts_moving_runners} of them the person ran at the "
                     f"robot faster than {RUNNING_SPEED:g} m/s (the walking speed the stop "
                     "rules assume)")
        lines.append(f"{cert.contacts_moving} contacts of a moving robot with a person in "
                     f"{len(runs)} of {len(cert.runs)} runs (seeds {_seeds(runs)}){away}")
    if cert.robot_contacts:
        runs = [r.seed for r in cert.runs if r.robot_contacts]
        lines.append(f"{cert.robot_contacts} contacts of robots with robots, walls or "
                     f"obstacles in {len(runs)} runs (seeds {_seeds(runs)})")
    if cert.unfinished:
        runs = [r.seed for r in cert.runs if not r.finished]
        share = cert.unfinished_for_people()
        why = "" if share is None else (
            f", for people within {PERSON_NEAR:g} m of it {100.0 * share:.0f} % of the time "
            "the clock stood")
        reached = sorted(100.0 * r.show_reached for r in cert.runs if not r.finished)
        lines.append(f"{cert.unfinished} of {len(cert.runs)} shows did not finish: the "
                     f"formation waited for a held robot until the run's limit{why}; they "
                     f"reached {reached[len(reached) // 2]:.0f} % of the show (median; least "
                     f"{reached[0]:.0f} %) (seeds {_seeds(runs)})")
        if cert.people_kept_waiting:
            lines.append("  people kept the robots waiting: give the show room (a crowd's "
                         "`area` in the world file that leaves the formation's ground free) "
                         "or fewer people")
    if cert.stalled:
        runs = [r.seed for r in cert.runs if r.stalled]
        lines.append(f"in {cert.stalled} of {len(cert.runs)} runs the formation stood "
                     f"{STALL_TOLERANCE:g} s or more with nobody within {PERSON_NEAR:g} m of the "
                     f"robots that held it ({STALL_CAUSES}; seeds {_seeds(runs)})")
    return tuple(lines)


def _seeds(seeds: list[int]) -> str:
    shown = ", ".join(str(s) for s in seeds[:8])
    return shown + (", ..." if len(seeds) > 8 else "")


def _write(cert: Certificate, directory: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    from dancebots.report.certificate_plot import plot_certificate

    (directory / "certificate.json").write_text(json.dumps(cert.to_json(), indent=2) + "\n",
                                                encoding="utf-8")
    plot_certificate(cert).savefig(directory / "certificate.png", dpi=110)
    return list(OUTPUT_NAMES)


def _summary(cert: Certificate, target: Path, written: list[str]) -> None:
    from rich.console import Console

    out = Console(soft_wrap=True, width=None if sys.stdout.isatty() else 120)
    data = cert.to_json()
    gap = data["min_person_gap_m"]
    held = data["held_robot_s"]
    overrun = data["overrun_s"]
    assert isinstance(gap, dict)
    assert isinstance(held, dict)
    assert isinstance(overrun, dict)
    out.print(f"{cert.job.scenario} in {cert.job.world}: {len(cert.runs)} runs "
              f"({cert.job.profile} profile, seeds {cert.runs[0].seed}-{cert.runs[-1].seed}) "
              f"in {cert.wall:.0f} s on {cert.processes} "
              f"{'process' if cert.processes == 1 else 'processes'}", highlight=False)
    out.print(f"contacts with people: {cert.contacts_moving} by a moving robot, "
              f"{cert.contacts_standing} with a robot standing still; robots with robots, "
              f"walls or obstacles: {cert.robot_contacts}", highlight=False,
              style="bold red" if cert.contacts_moving or cert.robot_contacts else "green")
    if gap["min"] is not None:
        out.print(f"smallest robot-person gap per run, m: min {gap['min']:.3f}, 1 % "
                  f"{gap['p1']:.3f}, 5 % {gap['p5']:.3f}, median {gap['median']:.3f}",
                  highlight=False)
    stops = data["stops"]
    assert isinstance(stops, dict)
    out.print(f"held by the stop rule, robot-s per run: median {held['median']:.1f}, max "
              f"{held['max']:.1f}, in stops (each with its stop sentence): median "
              f"{stops['median']:.0f}, max {stops['max']:.0f}; rest after the planned end, "
              f"s: median {overrun['median']:.1f}, max {overrun['max']:.1f}", highlight=False)
    stood, otherwise = data["clock_stood_s"], data["clock_stood_otherwise_s"]
    assert isinstance(stood, dict)
    assert isinstance(otherwise, dict)
    out.print(f"the shared show clock stood, s per run: median {stood['median']:.1f}, max "
              f"{stood['max']:.1f}; of it with nobody near the robots that held it: median "
              f"{otherwise['median']:.1f}, max {otherwise['max']:.1f}", highlight=False)
    flips, reverse = data["angular_sign_flips"], data["reverse_fraction"]
    turned = data["max_excess_turn_deg"]
    assert isinstance(flips, dict)
    assert isinstance(reverse, dict)
    assert isinstance(turned, dict)
    out.print(f"how the robots looked: turn-rate sign flips per run median "
              f"{flips['median']:.0f}, max {flips['max']:.0f}; driving against the slot's "
              f"direction, share of the moving ticks: median {reverse['median']:.1%}, max "
              f"{reverse['max']:.1%}; turned beyond what it tracks, the most of any robot, "
              f"deg per run: median {turned['median']:.0f}, max {turned['max']:.0f}",
              highlight=False)
    brief = data["clock_brief_runs"]
    assert isinstance(brief, dict)
    out.print(f"the formation lurched on (its clock ran 0.35 s or less between two stands), "
              f"times per run: median {brief['median']:.0f}, max {brief['max']:.0f}",
              highlight=False)
    apart = data["held_place_error_m"]
    assert isinstance(apart, dict)
    if apart["max"] is not None:
        out.print(f"farthest a robot was from its place while one was held, m: median "
                  f"{apart['median']:.2f}, max {apart['max']:.2f}", highlight=False)
    not_clean = sum(1 for r in cert.runs if not r.clean)
    if not_clean:
        out.print(f"{not_clean} runs were not clean for other reasons (see per_run in "
                  "certificate.json)", highlight=False)
    out.print(f"wrote {target}/: {', '.join(written)}", highlight=False)
    if cert.passed:
        out.print("verdict: PASSED (no moving robot touched a person, no robot touched a "
                  "robot, wall or obstacle, every show finished, no formation stood for "
                  "nothing)", style="bold green",
                  highlight=False)
        return
    out.print("verdict: FAILED", style="bold red", highlight=False)
    for failure in _failures(cert):
        out.print(f"  - {failure}", style="red", highlight=False)
