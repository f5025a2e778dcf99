"""The numba kernels are cached on disk, and the first run knows when it must compile."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from dancebots.sim.kernels import kernel_modules

ROOT = Path(__file__).resolve().parents[2]

LIST = "from dancebots.sim.kernels import kernels_to_compile; print(*kernels_to_compile())"


def test_every_kernel_is_cached_on_disk() -> None:
    kernels = [value for module in (*kernel_modules(crowds=True, stop_rule="closing"),
                                    *kernel_modules(stop_rule="predicted"))
               for value in vars(module).values()
               if hasattr(value, "_cache") and hasattr(value, "py_func")]
    names = {kernel.py_func.__name__ for kernel in kernels}
    assert {"cast_scene", "perceive_columns_split", "social_acceleration_loops",
            "wall_distances", "sector_gaps_moved", "track_cloud", "fold_choices",
            } <= names  # the crowd's, closing's, the tracker's and the references' too
    assert len(kernels) >= 17
    assert {type(kernel._cache).__name__ for kernel in kernels} == {"FunctionCache"}  # not
    # NullCache: each is @njit(cache=True)


def test_only_the_first_run_on_a_machine_compiles_and_it_says_so(tmp_path: Path) -> None:
    """numba's cache in an empty directory stands for a new machine: every kernel is listed,
    the first run says it compiles them, the second run does not, and afterwards none is
    listed (they are on disk). The first run's shared clock is not paced (``--hold
    together``), the second's is (the default): the first compiles the paced clock's rates
    too."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}

    def listed() -> list[str]:
        return subprocess.run([sys.executable, "-c", LIST], env=env, capture_output=True,
                              text=True, check=True, timeout=120).stdout.split()

    def run(out: str, *options: str) -> str:
        done = subprocess.run([sys.executable, "-m", "dancebots.cli", "run",
                               "examples/thesis_7_1.dance", "--no-animation", "--out",
                               str(tmp_path / out), *options], cwd=ROOT, env=env,
                              capture_output=True, text=True, timeout=600)
        assert done.returncode in (0, 1), done.stderr  # ran (its verdict is not the point)
        assert (tmp_path / out / "metrics.json").is_file()
        return done.stderr

    fresh = listed()
    assert "dancebots.sim.raycast_jit.cast_scene" in fresh
    assert "dancebots.perception.fast.perceive_columns" in fresh
    assert len(fresh) == len(kernel_names())
    assert f"compiling the simulator's {len(fresh)} kernels" in run("first", "--hold",
                                                                      "together")
    assert "compiling" not in run("second")
    assert listed() == []


def kernel_names() -> list[str]:
    return [f"{module.__name__}.{name}" for module in kernel_modules()
            for name, value in vars(module).items() if hasattr(value, "_cache")]
