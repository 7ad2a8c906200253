"""Worker processes that share the independent fits of one analysis."""

from __future__ import annotations

import gc
import multiprocessing
from collections.abc import Callable, Sequence
from contextlib import contextmanager

# start values, unit indices) and its result, and each worker pays its first-task copy-on-write
# faults (about 0.3 s) once rather than at every parallel step.
_ANALYSIS: list[tuple] = []


@contextmanager
def worker_pool(problem, data, scales, workers: int):
    """Worker processes for one analysis (``workers`` ≤ 1: none, tasks run in this process);
    one analysis at a time (not nested: a nested pool would unfreeze the collector early)."""
    if workers <= 1:
        yield
        return
    _ANALYSIS.append(((problem, data, scales), None))
    gc.freeze()  # the workers' garbage collections skip the inherited heap
    try:
        with multiprocessing.get_context("fork").Pool(workers) as pool:
            _ANALYSIS[-1] = (_ANALYSIS[-1][0], pool)
            yield
    finally:
        gc.unfreeze()
        _ANALYSIS.pop()


def _in_worker(task: Callable, args: tuple):
    return task(*_ANALYSIS[-1][0], *args)


def mapped(task: Callable, calls: Sequence[tuple], problem, data, scales) -> list:
    """[task(problem, data, scales, *args) for args in calls], shared among the analysis's
    worker processes when it has them (the same results either way)."""
    if _ANALYSIS and len(calls) > 1:
        (p, d, s), pool = _ANALYSIS[-1]
        if pool is not None and p is problem and d is data and s is scales:
            return pool.starmap(_in_worker, [(task, args) for args in calls], chunksize=1)
    return [task(problem, data, scales, *args) for args in calls]
