"""Where a sweep's trials run: this process, local worker processes, or a Dask cluster.

Each executor pulls trials from an iterator only when it has room for them (twice the
workers in flight), so a sweep claims trials as it goes (two sweeps on one file share the
work), an interruption finds little queued, and ``--trials 10**12`` never builds a list.
Local workers ignore Ctrl-C (the driving process alone handles it, then terminates them)
and exit by themselves within half a second of their parent's death (``kill -9``).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import queue
import signal
import threading
import time
from collections.abc import Callable, Iterable, Iterator

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["SchedulerLost", "run_cluster", "run_local"]


class SchedulerLost(InvalidArgumentError):
    """The Dask scheduler went away during a sweep."""


class _Failure:
    def __init__(self, error: BaseException) -> None:
        self.error = error


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os.kill(os.getpid(), signal.SIGKILL)  # no clean-up: the parent is gone


def _worker_start(parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def run_local(task: Callable, specs: Iterable, workers: int | None) -> Iterator:
    """``task(spec)`` for each spec, on ``workers`` processes (1: in this process)."""
    if workers == 1:  # in process: no pickling, easy to debug and profile
        yield from map(task, specs)
        return
    size = workers or os.cpu_count() or 1
    pool = multiprocessing.get_context().Pool(size, _worker_start, (os.getpid(),))
    done: queue.SimpleQueue = queue.SimpleQueue()
    pending, in_flight = iter(specs), 0
    try:
        while True:
            while in_flight < 2 * size:
                spec = next(pending, None)
                if spec is None:
                    break
                pool.apply_async(
                    task, (spec,), callback=done.put, error_callback=lambda e: done.put(_Failure(e))
                )
                in_flight += 1
            if in_flight == 0:
                return
            result = done.get()
            in_flight -= 1
            if isinstance(result, _Failure):
                raise result.error
            yield result
    finally:
        pool.terminate()  # running trials are abandoned: their rows were never stored
        pool.join()


def run_cluster(task: Callable, specs: Iterable, address: str, window: int = 0) -> Iterator:
    """``task(spec)`` for each spec on the Dask scheduler at ``address``."""
    try:
        import distributed
    except ImportError as exc:
        raise InvalidArgumentError(
            "running on a cluster needs Dask's distributed package",
            hint="install the cluster extra: pip install 'epistemica[cluster]'",
        ) from exc
    try:
        client = distributed.Client(address, timeout="10s")
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        raise InvalidArgumentError(
            f"cannot reach the Dask scheduler at {address} ({exc})",
            hint="start one with `dask scheduler` and pass its tcp://HOST:PORT",
        ) from None
    window = window or 2 * max(1, sum(client.nthreads().values()))
    pending = iter(specs)
    running = distributed.as_completed(with_results=True)
    lost = False
    try:
        for spec in _take(pending, window):
            running.add(client.submit(task, spec, pure=False))
        for _, row in running:
            yield row
            for spec in _take(pending, 1):
                running.add(client.submit(task, spec, pure=False))
    except (OSError, TimeoutError, distributed.CancelledError) as exc:
        lost = True
        raise SchedulerLost(
            f"lost the Dask scheduler at {address} ({type(exc).__name__})",
            hint="the finished trials are stored: restart the scheduler and run again "
            "with --resume",
        ) from None
    finally:
        _close(client, quiet=lost)


def _take(items: Iterator, count: int) -> list:
    out = []
    for item in items:
        out.append(item)
        if len(out) == count:
            break
    return out


def _close(client, quiet: bool) -> None:
    loggers = [logging.getLogger(n) for n in ("distributed", "asyncio", "tornado")]
    levels = [lg.level for lg in loggers]
    if quiet:  # a dead scheduler: no reconnection tracebacks on the way out
        for lg in loggers:
            lg.setLevel(logging.CRITICAL + 1)
    try:
        client.close(timeout=2)
    except Exception:
        pass
    finally:
        for lg, level in zip(loggers, levels, strict=True):
            lg.setLevel(level)
