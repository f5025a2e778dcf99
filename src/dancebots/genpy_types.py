"""ROS 1 message classes made at run time from their ``.msg`` text by genpy's dynamic types,
leaving no temporary files (the MCAP logs of ``report.mcap_log`` and the sound_play requests
of ``ros1.sound``). Light to import: a robot's node imports it at start."""

from __future__ import annotations

import threading
from collections.abc import Mapping
from typing import Any

__all__ = ["genpy_module", "message_classes"]

_LOCK = threading.Lock()
"""One :func:`message_classes` at a time: it swaps process-wide settings while it runs."""


def genpy_module() -> Any:
    """ROS's own genpy where ROS is installed (messages that are ``genpy.Message``), else the
    copy mcap-ros1-support carries (as its decoder does)."""
    try:
        import genpy  # type: ignore[import-not-found,unused-ignore]
    except ImportError:
        from mcap_ros1._vendor import genpy  # type: ignore[import-untyped,unused-ignore]
    return genpy


def message_classes(definitions: Mapping[str, str]) -> dict[str, Any]:
    """The message classes of ``definitions`` (type name -> ``.msg`` text with its
    dependencies, as ``gendeps --cat`` gives it) by type name, sub-types included: genpy's
    ``generate_dynamic``, which writes each type's code to a module in a new temporary
    directory and removes that only when the process exits normally (a node killed with
    SIGKILL, or ended by SIGTERM without a handler, left a ``genpy_*`` directory in /tmp at
    every start). Here the modules are written into a directory of our own that is removed
    once they are imported: a run leaves nothing behind, however it ends. While it runs it
    points :data:`tempfile.tempdir` at that directory and stubs genpy's exit-time removal;
    a lock keeps two threads from doing so at once."""
    import atexit
    import sys
    import tempfile
    from importlib import import_module

    dynamic = import_module(genpy_module().__name__ + ".dynamic")
    classes: dict[str, Any] = {}
    with _LOCK, tempfile.TemporaryDirectory(prefix="dancebots-genpy-") as scratch:
        previous, tempfile.tempdir = tempfile.tempdir, scratch
        # (its exit-time removal of a directory already gone: no error at exit)
        setattr(dynamic, "atexit", _NoExitCalls())  # noqa: B010 (a module's global)
        try:
            for name, text in definitions.items():
                classes.update(dynamic.generate_dynamic(name, text))
        finally:
            tempfile.tempdir = previous
            setattr(dynamic, "atexit", atexit)  # noqa: B010
            sys.path[:] = [entry for entry in sys.path if not entry.startswith(scratch)]
    return classes


class _NoExitCalls:
    """Stands in for :mod:`atexit` in genpy.dynamic while :func:`message_classes` runs."""

    @staticmethod
    def register(function: Any, *args: Any, **kwargs: Any) -> Any:
        return function
