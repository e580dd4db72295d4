"""Mapping a function over many inputs, serially or with any executor.

Long sweeps (transition searches, continuations, Lyapunov maps) call
:func:`pmap`, which takes any :class:`concurrent.futures.Executor`
(``ProcessPoolExecutor``, ``ThreadPoolExecutor``, or a Dask client's
``get_executor()``); the default is serial. A progress bar (tqdm) is shown
only when asked for, and never when ``TQDM_DISABLE`` is set or when stderr is
not a terminal, so notebook outputs stay reproducible under nbval.
"""
from __future__ import annotations

import os
import sys

__all__ = ["pmap"]


def _progress(iterable, total, desc, progress):
    if not progress or os.environ.get("TQDM_DISABLE") or not sys.stderr.isatty():
        return iterable
    try:
        from tqdm.auto import tqdm
    except ImportError:        # tqdm is optional
        return iterable
    return tqdm(iterable, total=total, desc=desc)


def pmap(func, items, *, executor=None, progress=False, desc=None, chunksize=1):
    """``[func(x) for x in items]``, optionally through an executor.

    Parameters
    ----------
    func : callable
        Must be picklable (a module-level function) for process pools.
    items : iterable
    executor : concurrent.futures.Executor, optional
        Default: serial evaluation in this process.
    progress : bool
        Show a tqdm progress bar (only on a terminal; off under ``TQDM_DISABLE``).
    desc : str, optional
        Progress-bar label.
    chunksize : int
        Passed to ``executor.map`` (process pools batch work with it).

    Returns
    -------
    list
        Results in the order of ``items``.
    """
    items = list(items)
    if executor is None:
        it = map(func, items)
    else:
        try:
            it = executor.map(func, items, chunksize=chunksize)
        except TypeError:          # executors whose map has no chunksize
            it = executor.map(func, items)
    return list(_progress(it, len(items), desc, progress))
