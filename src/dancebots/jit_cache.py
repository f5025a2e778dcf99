"""numba's disk cache kept true across modules.

numba keys a kernel's cached machine code by its own source file only (its modification time
and size), so a kernel that calls kernels of another module keeps their old code after that
module changed (a checkout that changes ``perception/fast.py`` but not
``robot_batch_jit.py``). :func:`drop_stale` removes the cache index of every kernel of a
module that is older than a module it calls; numba then compiles the kernel afresh and
writes a new index (the files removed are numba's index files of this package's own
kernels, which numba wrote for it).
"""

from __future__ import annotations

import os
from types import ModuleType

__all__ = ["drop_stale"]


def drop_stale(module: ModuleType, dependencies: tuple[ModuleType, ...]) -> tuple[str, ...]:
    """Remove the cache index of each numba kernel of ``module`` (``@njit(cache=True)``)
    written before the latest change of any of ``dependencies``' source files; returns the
    index files removed."""
    sources = [getattr(dependency, "__file__", None) for dependency in dependencies]
    stamps = [os.stat(source).st_mtime for source in sources if source]
    if not stamps:
        return ()
    newest = max(stamps)
    removed = []
    for value in vars(module).values():
        cache = getattr(value, "_cache", None)
        index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
        if not isinstance(index, str):
            continue
        try:
            if os.stat(index).st_mtime < newest:
                os.remove(index)
                removed.append(index)
        except OSError:  # no index yet, or another process removed it first
            continue
    return tuple(removed)
