"""The ``dancebots`` command: a thin shell that reads files, calls the core, prints results.

``main.py`` is the parser, ``common.py`` what the commands share (exit statuses, printing,
the output writer), and one module per command. Importing the package is cheap: a command's
core modules are imported when it runs.
"""

import os
import signal
import sys


def _interrupted_while_starting(signum: int, frame: object) -> None:
    """Ctrl-C before ``main`` runs: nothing to clean up yet, so leave quietly with 130."""
    sys.stderr.write("dancebots: interrupted\n")
    sys.stderr.flush()
    os._exit(130)


if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
    signal.signal(signal.SIGINT, _interrupted_while_starting)  # main() restores the default

from dancebots.cli.main import main  # noqa: E402

__all__ = ["command", "main"]


def command() -> int:
    """The ``dancebots`` command (its console script and ``python -m dancebots.cli``):
    :func:`main`, then every object there is is left out of the interpreter's last garbage
    collections. Once numba has started, those walk its whole object graph for nothing (about
    0.2 s of every command that simulated). Every file the command wrote is closed by then
    and ``atexit`` and ``weakref.finalize`` callbacks still run; objects in reference
    cycles are no longer collected (their ``__del__`` does not run), which nothing of the
    command's output relies on."""
    import gc

    status = main()
    gc.freeze()
    return status
