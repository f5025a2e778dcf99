"""The ``dancebots`` parser and entry point: one sub-command per module of this package."""

from __future__ import annotations

import argparse
import os
import signal
import sys
from collections.abc import Sequence

import dancebots.cli.beats as beats_command
import dancebots.cli.certify as certify_command
import dancebots.cli.check as check_command
import dancebots.cli.demo as demo_command
import dancebots.cli.follow as follow_command
import dancebots.cli.plan as plan_command
import dancebots.cli.ros as ros_command
import dancebots.cli.run as run_command
from dancebots import __version__
from dancebots.cli.common import (
    EXIT_BUG,
    EXIT_INTERRUPTED,
    interrupted,
    on_interrupt,
    raise_if_interrupted,
    reset_interrupt,
)

__all__ = ["build_parser", "main"]

COMMANDS = (check_command, plan_command, demo_command, run_command, follow_command,
            certify_command, beats_command, ros_command)
"""Each has NAME, HELP, DESCRIPTION, add_arguments(parser) and run(args) -> exit status."""

EPILOG = """exit status: 0 valid input, or a show that ran clean; 1 check --strict found warnings,
or run/follow ran a show that was not clean (a collision, a contact with a person, a robot in
its error state, a robot far from its final slot, a broken queue); 2 invalid input or
arguments (nothing was simulated or written); 130 interrupted (Ctrl-C)."""


def build_parser() -> argparse.ArgumentParser:
    """The whole command line; builds fast (no core module is imported)."""
    parser = argparse.ArgumentParser(
        prog="dancebots", description="Choreograph formations of ground robots: check a "
        "choreography, plan it, preview it in the simulator, run it through ROS.",
        epilog=EPILOG)
    parser.add_argument("--version", action="version", version=f"dancebots {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMANDS:
        sub = commands.add_parser(module.NAME, help=module.HELP,
                                  description=module.DESCRIPTION)
        module.add_arguments(sub)
        sub.set_defaults(handler=module.run, parser=sub)
    return parser


def _caused_by_interrupt(error: BaseException) -> bool:
    """Does a KeyboardInterrupt lie in the chain of causes of ``error``?"""
    seen: set[int] = set()
    cause: BaseException | None = error
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False


def _finalizer_error(unraisable: sys.UnraisableHookArgs) -> None:
    """A Ctrl-C that lands in a finalizer (``__del__``, e.g. numba's llvmlite) is not printed
    as "Exception ignored": :func:`on_interrupt` has noted it and the command stops at its next
    step. Other errors in finalizers are reported as Python does."""
    if not isinstance(unraisable.exc_value, KeyboardInterrupt):
        sys.__unraisablehook__(unraisable)


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``dancebots ARGS``; returns the exit status (argparse exits 2 on bad arguments)."""
    reset_interrupt()
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, on_interrupt)  # Ctrl-C: KeyboardInterrupt, and noted
    sys.unraisablehook = _finalizer_error
    try:
        args = build_parser().parse_args(argv)
        status: int = args.handler(args)
        raise_if_interrupted()  # a Ctrl-C that something swallowed
        return status
    except KeyboardInterrupt:
        print("dancebots: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except SystemError as error:  # Ctrl-C inside a numba kernel surfaces as a SystemError
        if not _caused_by_interrupt(error) and not interrupted():
            raise
        print("dancebots: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # e.g. `dancebots demo | head`: the reader is gone
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141
    except Exception as error:  # a bug: say so, keep the traceback for the report, exit apart
        if _caused_by_interrupt(error):  # a Ctrl-C that Python wrapped: a RuntimeError of
            # ``__set_name__`` while a library's class was created at import, and the like
            print("dancebots: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        import traceback

        traceback.print_exc()
        print("dancebots: internal error: this is a bug in dancebots, not in your input; "
              "please report it with the lines above", file=sys.stderr)
        return EXIT_BUG
