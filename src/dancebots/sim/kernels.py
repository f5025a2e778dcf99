"""The simulator's numba kernels and whether they are compiled on disk yet.

Every kernel is ``@njit(cache=True)``: numba compiles it on the first run on a machine (about
20 s for all of them on a 2-core machine) and stores the machine code next to its module
(``__pycache__``), so later runs load it in milliseconds. Shells use
:func:`kernels_to_compile` to say so before that first, slow run.
"""

from __future__ import annotations

import importlib
import os
from functools import cache
from types import ModuleType

__all__ = ["kernel", "kernel_modules", "kernels_to_compile"]


@cache
def kernel(module: str) -> ModuleType:
    """The kernel module ``dancebots.<module>`` (e.g. ``"sim.stage_jit"``), imported on the
    first call (importing it imports numba): what a hot loop calls each tick instead of an
    import statement, which costs microseconds every time."""
    return importlib.import_module(f"dancebots.{module}")


def kernel_modules(crowds: bool = False, stop_rule: str = "predicted",
                   ) -> tuple[ModuleType, ...]:
    """The modules that hold numba kernels (importing them imports numba): those every
    formation show runs (its brains' batch and references among them), with ``crowds`` the
    crowds' social forces too, and those of ``stop_rule`` (``robot.STOP_RULES``; by
    default the default's, ``robot.default_stop_rule``): the ``closing`` rule's sectors, the
    ``ssm`` and ``predicted`` rules' obstacle tracker."""
    from dancebots import robot_batch_jit
    from dancebots.control import tracking_jit
    from dancebots.perception import fast
    from dancebots.sim import collision_jit, raycast_jit, stage_jit
    from dancebots.sync import hold_jit

    modules: tuple[ModuleType, ...] = (raycast_jit, collision_jit, stage_jit, fast,
                                       robot_batch_jit, tracking_jit, hold_jit)
    if crowds:
        from dancebots.sim import crowd_jit

        modules = (*modules, crowd_jit)
    if stop_rule == "closing":
        from dancebots.perception import closing_jit

        modules = (*modules, closing_jit)
    if stop_rule in ("ssm", "predicted"):
        from dancebots.perception import tracks_jit

        modules = (*modules, tracks_jit)
    return modules


def kernels_to_compile(crowds: bool = False, stop_rule: str = "predicted") -> tuple[str, ...]:
    """``module.function`` of every kernel with no compiled code in numba's disk cache (of a
    show with ``crowds`` too, and ``stop_rule``'s: :func:`kernel_modules`)."""
    missing = []
    for module in kernel_modules(crowds, stop_rule):
        for name, value in vars(module).items():
            cache = getattr(value, "_cache", None)
            cache_file = getattr(cache, "_cache_file", None)
            index = getattr(cache_file, "_index_path", None)
            if isinstance(index, str) and not os.path.exists(index):
                missing.append(f"{module.__name__}.{name}")
    return tuple(missing)
