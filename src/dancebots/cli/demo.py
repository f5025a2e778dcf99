"""``dancebots demo``: print the commented example scenario."""

from __future__ import annotations

import argparse
import sys

from dancebots.cli.common import EXIT_OK, bundled

NAME = "demo"
HELP = "print a commented scenario that explains every instruction"
DESCRIPTION = ("Print a commented scenario that explains every instruction of the language "
               "(save it, e.g. `dancebots demo > my_show.dance`, then check and run it).")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """No options."""


def run(args: argparse.Namespace) -> int:
    with open(bundled("demo.dance"), encoding="utf-8") as handle:
        sys.stdout.write(handle.read())
    return EXIT_OK
