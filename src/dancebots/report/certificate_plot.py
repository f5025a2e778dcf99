"""The picture of a certification (``shows.certify.Certificate``): how near the robots came
to people over all runs, and what the people cost the show (held time, overrun)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from dancebots.report.certify import Certificate

__all__ = ["plot_certificate"]


def plot_certificate(cert: Certificate) -> Figure:
    """Two panels: the distribution of each run's smallest robot-person gap (contacts of a
    moving robot marked), and each run's held robot-seconds against its overrun."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 4.2), layout="constrained")
    gaps_ax, cost_ax = figure.subplots(1, 2)
    gaps = cert.gaps()
    if gaps.size:
        gaps_ax.hist(gaps * 100.0, bins=min(40, max(5, gaps.size // 5)), color="tab:blue")
        gaps_ax.axvline(0.0, color="tab:red", lw=1.5)
    else:
        gaps_ax.text(0.5, 0.5, "no people in the world", ha="center",
                     transform=gaps_ax.transAxes)
    touched = sum(1 for r in cert.runs if r.contacts_moving)
    gaps_ax.set_title(f"smallest robot-person gap per run ({len(cert.runs)} runs; "
                      f"{touched} with a moving robot touching a person)", fontsize=9)
    gaps_ax.set_xlabel("gap, cm")
    gaps_ax.set_ylabel("runs")
    held = np.array([r.held for r in cert.runs])
    overrun = np.array([r.overrun for r in cert.runs])
    bad = np.array([r.contacts_moving > 0 or r.robot_contacts > 0 for r in cert.runs])
    cost_ax.scatter(held[~bad], overrun[~bad], s=10, color="tab:blue", label="no contact")
    if bad.any():
        cost_ax.scatter(held[bad], overrun[bad], s=24, color="tab:red", marker="x",
                        label="a contact")
    cost_ax.set_xlabel("robots held by the stop rule, robot-s")
    cost_ax.set_ylabel("rest after the planned end, s")
    cost_ax.set_title("what the people cost the show, per run", fontsize=9)
    cost_ax.legend(loc="upper left", fontsize=8)
    verdict = "PASSED" if cert.passed else "FAILED"
    figure.suptitle(f"{verdict}: {cert.job.scenario} in {cert.job.world} "
                    f"({cert.job.profile} profile)", fontsize=10)
    return figure
