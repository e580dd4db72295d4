"""Mapping a function over many inputs, serially, on a process pool or on a Dask cluster.

Long sweeps (transition searches, continuations, Lyapunov maps) call
:func:`pmap`, which takes any :class:`concurrent.futures.Executor`
(``ProcessPoolExecutor``, ``ThreadPoolExecutor``, or a Dask client's
``get_executor()``); the default is serial. :func:`executor_for` turns the
command-line choice (``--workers N`` or ``--scheduler ADDRESS``) into such an
executor. A progress bar (tqdm) is shown only when asked for, and never when
``TQDM_DISABLE`` is set or when stderr is not a terminal, so notebook outputs
stay reproducible under nbval.

Fault tolerance on a Dask cluster is Dask's own: the tasks of a worker that
dies are rescheduled on the others (a task is given up, with
``distributed.scheduler.KilledWorker``, only after it was running on more than
``distributed.scheduler.allowed-failures`` = 3 dying workers), so a scan
returns the same result; tasks must therefore be pure functions of their input.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from numbers import Integral
from typing import TypeVar

__all__ = ["pmap", "executor_for"]

X = TypeVar("X")
Y = TypeVar("Y")


class _NoBar:
    def update(self, n=1):
        pass

    def close(self):
        pass


def _bar(total, desc, progress):
    """A tqdm bar on a terminal if asked for, else an object that ignores updates."""
    if not progress or os.environ.get("TQDM_DISABLE") or not sys.stderr.isatty():
        return _NoBar()
    try:
        from tqdm.auto import tqdm
    except ImportError:  # tqdm is optional
        return _NoBar()
    return tqdm(total=total, desc=desc)


def _call_chunk(func, chunk):
    """One task: ``func`` over a chunk of items (module level, so that it pickles)."""
    return [func(x) for x in chunk]


def pmap(
    func: Callable[[X], Y],
    items: Iterable[X],
    *,
    executor: Executor | None = None,
    progress: bool = False,
    desc: str | None = None,
    chunksize: int = 1,
) -> list[Y]:
    """``[func(x) for x in items]``, optionally through an executor.

    With an executor, the items are cut into chunks of ``chunksize`` and each
    chunk is one ``executor.submit``, all at once (as ``ProcessPoolExecutor.map``
    does; a Dask executor's ``map`` accepts ``chunksize`` but ignores it). The
    progress bar counts items as their chunk completes, in any order (``map``
    of both executors is eager but yields in input order, so a bar driven by
    it would wait behind the slowest early item); the results are returned in
    the order of ``items``. The first exception raised by ``func`` cancels the
    chunks not yet started and is re-raised.

    Parameters
    ----------
    func : callable
        Must be picklable (a module-level function) for process pools and for
        Dask workers (which must be able to import ``rotorlib``).
    items : iterable
    executor : concurrent.futures.Executor, optional
        Default: serial evaluation in this process. See :func:`executor_for`.
    progress : bool
        Show a tqdm progress bar (only on a terminal; off under ``TQDM_DISABLE``).
    desc : str, optional
        Progress-bar label.
    chunksize : int
        Items per task, >= 1. Fewer, larger tasks have less overhead (a Dask
        task costs milliseconds); a lost Dask worker costs its chunks' rerun.

    Returns
    -------
    list
        Results in the order of ``items``.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> from rotorlib.core.parallel import pmap
    >>> pmap(abs, [-3, 1, -2])
    [3, 1, 2]
    >>> with ThreadPoolExecutor(2) as ex:
    ...     pmap(abs, range(-4, 1), executor=ex, chunksize=2)
    [4, 3, 2, 1, 0]
    """
    items = list(items)
    chunksize = _positive_int(chunksize, "chunksize")
    bar = _bar(len(items), desc, progress)
    try:
        if executor is None:
            out = []
            for x in items:
                out.append(func(x))
                bar.update()
            return out
        chunks = [items[i : i + chunksize] for i in range(0, len(items), chunksize)]
        futures = [executor.submit(_call_chunk, func, c) for c in chunks]
        try:
            for f in as_completed(futures):
                bar.update(len(f.result()))  # raises the task's exception, if any
        except BaseException:
            for f in futures:
                f.cancel()
            raise
        return [r for f in futures for r in f.result()]
    finally:
        bar.close()


def _positive_int(value, name):
    """``value`` as an int >= 1 (bool, float and str are refused), else ValueError."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, not {value!r}")
    return int(value)


@contextlib.contextmanager
def executor_for(
    workers: int | None = None, scheduler: str | None = None, *, timeout: float = 10.0
) -> Iterator[Executor | None]:
    """The executor for ``--workers N`` or ``--scheduler ADDRESS``, closed on exit.

    Parameters
    ----------
    workers : int, optional
        Number of local worker processes. ``None`` or 1: serial (yields
        ``None``, which :func:`pmap` evaluates in this process); ``N >= 2``: a
        :class:`concurrent.futures.ProcessPoolExecutor` with ``N`` processes.
    scheduler : str, optional
        ``tcp://`` address of a running Dask scheduler, e.g. ``"tcp://127.0.0.1:8786"``
        (started with ``dask scheduler``, its workers with ``dask worker
        ADDRESS``; they must run the same ``rotorlib``). Yields the executor
        of a ``distributed.Client`` connected to it (``pure=False``: every
        task runs); the client is closed on exit. Needs the optional
        dependency ``dask[distributed]``, which nothing else in ``rotorlib``
        uses; it is imported only here.
    timeout : float
        Seconds to wait for the scheduler to answer and to have at least one
        worker.

    Yields
    ------
    concurrent.futures.Executor or None

    Raises
    ------
    ValueError
        ``workers`` not an integer >= 1; both ``workers`` and ``scheduler``
        given; ``dask[distributed]`` not installed; the scheduler address
        malformed, unreachable, or without workers within ``timeout``.

    Examples
    --------
    >>> from rotorlib.core.parallel import executor_for, pmap
    >>> with executor_for(workers=1) as ex:  # serial: no executor
    ...     ex is None, pmap(abs, [-1, 2], executor=ex)
    (True, [1, 2])
    >>> with executor_for(workers=2) as ex:
    ...     type(ex).__name__
    'ProcessPoolExecutor'
    """
    if scheduler is None:
        n = 1 if workers is None else _positive_int(workers, "workers")
        if n == 1:
            yield None
            return
        ex = ProcessPoolExecutor(n)
        try:
            yield ex
        finally:
            ex.shutdown(wait=True, cancel_futures=True)
        return

    if workers is not None:
        raise ValueError("give either workers or scheduler, not both")
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ValueError(
            f"scheduler must be an address such as tcp://127.0.0.1:8786, not {scheduler!r}"
        )
    try:
        from distributed import Client
        from distributed.comm import parse_address, resolve_address
    except ImportError:
        raise ValueError(
            "--scheduler needs Dask: pip install 'dask[distributed]'"
        ) from None
    try:
        # Checked first: Client leaves a half-started client behind (noise and a delay at exit) on
        # malformed addresses, but not on unreachable ones.
        if parse_address(scheduler)[0] != "tcp":
            raise ValueError("only tcp://HOST:PORT addresses are supported")
        resolve_address(scheduler)  # host and port present, host name known
        client = Client(scheduler, timeout=timeout, set_as_default=False)
    except (OSError, ValueError, TypeError) as exc:  # OSError includes timeouts
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ValueError(
            f"cannot connect to Dask scheduler {scheduler}: {reason}"
        ) from None
    try:
        try:
            client.wait_for_workers(1, timeout=timeout)
        except (OSError, TimeoutError):
            raise ValueError(
                f"Dask scheduler {scheduler} has no worker after {timeout:g} s"
            ) from None
        ex = client.get_executor(pure=False)
        try:
            yield ex
        finally:
            ex.shutdown(wait=False)  # cancels whatever an interrupted scan left running
    finally:
        client.close()
