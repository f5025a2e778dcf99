"""The numba kernels are cached on disk, and the first run knows when it must compile."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from dancebots.sim.kernels import kernel_modules, kernels_to_compile

LIST = "from dancebots.sim.kernels import kernels_to_compile; print(*kernels_to_compile())"


def test_every_kernel_is_cached_on_disk() -> None:
    kernels = [value for module in kernel_modules() for value in vars(module).values()
               if hasattr(value, "_cache") and hasattr(value, "py_func")]
    assert len(kernels) >= 9
    assert {type(kernel._cache).__name__ for kernel in kernels} == {"FunctionCache"}  # not
    # NullCache: each is @njit(cache=True)


def test_an_empty_cache_means_every_kernel_must_compile(tmp_path: Path) -> None:
    """With numba's cache in an empty directory (a new machine) every kernel is listed; after
    a run on this machine (the tests ran the simulator already) none is."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    fresh = subprocess.run([sys.executable, "-c", LIST], env=env, capture_output=True,
                           text=True, check=True, timeout=120).stdout.split()
    assert "dancebots.sim.raycast_jit.cast_scene" in fresh
    assert "dancebots.perception.fast.perceive_columns" in fresh
    assert len(fresh) >= 9
    from dancebots.perception.fast import perceive_columns

    if perceive_columns.signatures:  # compiled (and so cached) in this process
        assert kernels_to_compile() == ()
