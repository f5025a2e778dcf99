"""``dancebots plan``: draw the virtual leaders' and the robots' desired paths."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from dancebots.cli.common import (
    EXIT_INVALID,
    EXIT_OK,
    OutputError,
    add_show_arguments,
    add_timing_argument,
    fail,
    print_diagnostics,
    write_file,
)

NAME = "plan"
HELP = "draw the virtual leaders' and robots' paths"
DESCRIPTION = ("Draw the plan of a choreography: the virtual leaders' paths, every robot's "
               "desired path and its slots, in the world when one is given.")

CREATOR = "dancebots plan"
"""Written into the image's metadata (who made it; replacing is decided by
``cli.common.IMAGE_RECORD``)."""
FORMATS = ("png", "svg", "pdf")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_show_arguments(parser)
    add_timing_argument(parser)
    parser.add_argument("--out", "--png", dest="out", required=True, metavar="FILE",
                        help="image file to write (.png; .svg and .pdf by their extension); "
                        "an existing file is replaced only if dancebots plan wrote it")


def run(args: argparse.Namespace) -> int:
    from dancebots import __version__
    from dancebots.diagnostics import Diagnostic, has_errors
    from dancebots.loading import load_show

    show = load_show(args.scenario, args.world, args.vmax, timing=args.timing)
    print_diagnostics(show.diagnostics, show.sources)
    if show.plan is None or not show.valid:
        return EXIT_INVALID
    kind = os.path.splitext(args.out)[1].lower().lstrip(".")
    if kind not in FORMATS:
        return fail(NAME, f"{args.out}: give a file name that ends in .png, .svg or .pdf "
                    "(the image's format)")
    plan, world = show.plan, show.world
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dancebots.plan.placement import sample_show, show_transform
    from dancebots.report.plan_plot import plot_plan

    transform = None
    if world is not None:
        placement: list[Diagnostic] = []
        transform = show_transform(plan, world, sample_show(plan), placement)
        print_diagnostics(placement, show.sources)
        if has_errors(placement):
            return EXIT_INVALID
    metadata = {"Software" if kind == "png" else "Creator": CREATOR}
    figure = plot_plan(plan, world, transform)
    try:
        write_file(Path(args.out), lambda path: figure.savefig(
            path, dpi=120, format=kind, metadata=metadata), __version__)
    except OutputError as exc:
        return fail(NAME, str(exc))
    finally:
        plt.close(figure)
    print(f"wrote {args.out}")
    return EXIT_OK
