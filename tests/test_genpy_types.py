"""ROS 1 message classes from their .msg text (genpy_types.py): the standard MD5 sums, and no
temporary file left behind, however the process ends or how many threads ask at once."""

from __future__ import annotations

import sys
import tempfile
import threading
from pathlib import Path

import pytest

from dancebots.genpy_types import message_classes
from dancebots.report.mcap_log import DEFINITIONS

ROS_MD5 = {"tf2_msgs/TFMessage": "94810edda583a504dfda3829e70d7eec"}  # rosmsg md5


@pytest.mark.parametrize("ending", ["exits", "killed"])
def test_making_the_message_classes_leaves_no_temporary_files(tmp_path: Path,
                                                              ending: str) -> None:
    """genpy's dynamic types write modules to a temporary directory that it removes only
    at a normal exit: a process that makes them (a ROS node, the bridge) and exits, or is
    killed with SIGKILL, leaves nothing in its TMPDIR, and says nothing at exit."""
    import os
    import subprocess

    scratch = tmp_path / "tmpdir"
    scratch.mkdir()
    code = ("import os, signal\n"
            "from dancebots.genpy_types import message_classes\n"
            "from dancebots.report.mcap_log import DEFINITIONS\n"
            "classes = message_classes(DEFINITIONS)\n"
            "assert classes['tf2_msgs/TFMessage']._md5sum == "
            f"{ROS_MD5['tf2_msgs/TFMessage']!r}\n"
            "print(len(os.listdir(os.environ['TMPDIR'])), flush=True)\n"
            + ("os.kill(os.getpid(), signal.SIGKILL)\n" if ending == "killed" else ""))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "TMPDIR": str(scratch)}, timeout=120,
                          check=False)
    assert done.stdout.strip() == "0", done.stderr
    assert done.returncode == (-9 if ending == "killed" else 0), done.stderr
    assert done.stderr == ""
    assert sorted(scratch.iterdir()) == []


def test_two_threads_making_message_classes_at_once_both_get_them() -> None:
    """The function swaps process-wide settings while it runs (tempfile.tempdir, genpy's
    atexit); two threads at once each get their classes and leave tempfile.tempdir as it was
    (without the lock, the one that finished first left it pointing at a deleted
    directory)."""
    before = tempfile.tempdir
    results: list[dict[str, object]] = []
    errors: list[BaseException] = []

    def make() -> None:
        try:
            results.append(message_classes(DEFINITIONS))
        except BaseException as exc:  # (reported below)
            errors.append(exc)

    threads = [threading.Thread(target=make) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=120)
    assert errors == []
    assert len(results) == 4
    assert all(r["tf2_msgs/TFMessage"]._md5sum == ROS_MD5["tf2_msgs/TFMessage"]  # type: ignore[attr-defined]
               for r in results)
    assert tempfile.tempdir == before
