"""drop_stale: a kernel's cache index older than a module its kernels call is removed (numba
would otherwise keep the callee's old machine code), a newer one is kept."""

from __future__ import annotations

import os
from pathlib import Path
from types import ModuleType, SimpleNamespace

from dancebots.jit_cache import drop_stale


def kernel(index: Path) -> SimpleNamespace:
    """Something shaped like a numba dispatcher with a disk cache at ``index``."""
    return SimpleNamespace(_cache=SimpleNamespace(_cache_file=SimpleNamespace(
        _index_path=str(index))))


def test_an_index_older_than_a_dependency_is_removed_a_newer_one_kept(tmp_path: Path) -> None:
    dependency_source = tmp_path / "fast.py"
    dependency_source.write_text("")
    os.utime(dependency_source, (1000.0, 1000.0))
    dependency = ModuleType("fast")
    dependency.__file__ = str(dependency_source)
    stale, fresh = tmp_path / "stale.nbi", tmp_path / "fresh.nbi"
    for path, stamp in ((stale, 999.0), (fresh, 1001.0)):
        path.write_text("index")
        os.utime(path, (stamp, stamp))
    module = ModuleType("kernels")
    module.stale_kernel = kernel(stale)  # type: ignore[attr-defined]
    module.fresh_kernel = kernel(fresh)  # type: ignore[attr-defined]
    module.never_compiled = kernel(tmp_path / "missing.nbi")  # type: ignore[attr-defined]
    module.helper = len  # type: ignore[attr-defined]
    assert drop_stale(module, (dependency,)) == (str(stale),)
    assert not stale.exists()
    assert fresh.read_text() == "index"
    assert drop_stale(module, ()) == ()


def test_the_batch_kernels_cache_is_not_older_than_the_perception_it_calls() -> None:
    """After import (which drops what is stale) no index of robot_batch_jit predates
    perception/fast.py."""
    from dancebots import robot_batch_jit
    from dancebots.perception import fast

    newest = os.stat(fast.__file__).st_mtime
    for value in vars(robot_batch_jit).values():
        index = getattr(getattr(getattr(value, "_cache", None), "_cache_file", None),
                        "_index_path", None)
        if isinstance(index, str) and os.path.exists(index):
            assert os.stat(index).st_mtime >= newest, index
