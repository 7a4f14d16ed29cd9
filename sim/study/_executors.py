"""Where a sweep's trials run: this process, local worker processes, or a Dask cluster.

Each executor pulls trials from an iterator only when it has room for them (twice the
workers in flight), so a sweep claims trials as it goes (two sweeps on one file share the
work), an interruption finds little queued, and ``--trials 10**12`` never builds a list.
Local workers ignore Ctrl-C (the driving process alone handles it, then terminates them)
and exit by themselves within half a second of their parent's death (``kill -9``). On a
cluster, a scheduler left without any worker for :data:`NO_WORKER_SECONDS` ends the sweep
with :class:`WorkersLost` (a Dask scheduler would otherwise keep the trials waiting for a
worker for ever).
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
import queue
import signal
import threading
import time
from collections.abc import Callable, Iterable, Iterator

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["NO_WORKER_SECONDS", "SchedulerLost", "WorkersLost", "run_cluster", "run_local"]

#: Seconds a cluster sweep waits while its scheduler has no worker before giving up.
NO_WORKER_SECONDS = 30.0

# How often the driver looks for finished trials, and asks the scheduler for its workers.
_POLL, _ASK_EVERY = 0.05, 1.0


class SchedulerLost(InvalidArgumentError):
    """The Dask scheduler went away during a sweep."""


class WorkersLost(InvalidArgumentError):
    """The Dask scheduler has had no worker for :data:`NO_WORKER_SECONDS`."""


class _Failure:
    def __init__(self, error: BaseException) -> None:
        self.error = error


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os.kill(os.getpid(), signal.SIGKILL)  # no clean-up: the parent is gone


def _worker_start(parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # discards a Ctrl-C held since the fork
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) back while the pool forks its workers, then deliver it.

    A SIGINT that arrives during ``fork`` raises KeyboardInterrupt inside an at-fork hook,
    where Python prints "Exception ignored" and drops it: the sweep then ran to its end.
    Held, it is raised in the driving loop once the workers exist (and the workers, which
    inherit the held signal, discard it as they start ignoring SIGINT).
    """
    main = threading.current_thread() is threading.main_thread()
    if not main or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def run_local(task: Callable, specs: Iterable, workers: int | None) -> Iterator:
    """``task(spec)`` for each spec, on ``workers`` processes (1: in this process)."""
    if workers == 1:  # in process: no pickling, easy to debug and profile
        yield from map(task, specs)
        return
    size = workers or os.cpu_count() or 1
    done: queue.SimpleQueue = queue.SimpleQueue()
    pending, in_flight, pool = iter(specs), 0, None
    try:
        with _sigint_held():  # a Ctrl-C held here is raised on leaving, pool made
            pool = multiprocessing.get_context().Pool(size, _worker_start, (os.getpid(),))
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
        if pool is not None:
            pool.terminate()  # running trials are abandoned: their rows were never stored
            pool.join()


def run_cluster(
    task: Callable,
    specs: Iterable,
    address: str,
    window: int = 0,
    patience: float | None = None,
) -> Iterator:
    """``task(spec)`` for each spec on the Dask scheduler at ``address``; ends with
    :class:`WorkersLost` once the scheduler has had no worker for ``patience`` seconds
    (:data:`NO_WORKER_SECONDS` by default)."""
    patience = NO_WORKER_SECONDS if patience is None else patience
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
    quiet = _Quiet()  # a lost scheduler: our one-line error, not the client's tracebacks
    try:
        window = window or 2 * max(1, sum(client.nthreads().values()))
        pending = iter(specs)
        running = distributed.as_completed()
        for spec in _take(pending, window):
            running.add(client.submit(task, spec, pure=False))
        while not running.is_empty():
            for future in _finished(running, client, address, patience):
                row = future.result()
                yield row
                for spec in _take(pending, 1):
                    running.add(client.submit(task, spec, pure=False))
    except Exception as exc:
        if client.status == "running" and not isinstance(
            exc, (OSError, TimeoutError, distributed.CancelledError)
        ):
            raise  # a trial failed: a bug, shown as one
        raise SchedulerLost(
            f"lost the Dask scheduler at {address} ({type(exc).__name__})",
            hint="the finished trials are stored: restart the scheduler and run again "
            "with --resume",
        ) from None
    finally:
        try:
            client.close(timeout=2)
        except Exception:  # closing a client whose scheduler died: nothing to add
            pass
        quiet.restore()


def _finished(running, client, address: str, patience: float) -> list:
    """The trials finished so far, waiting for one; :class:`WorkersLost` when the
    scheduler has had no worker for ``patience`` seconds meanwhile."""
    alone_since, asked = None, 0.0
    while not running.has_ready():
        now = time.monotonic()
        if now - asked >= _ASK_EVERY:
            asked = now
            if client.nthreads():
                alone_since = None
            elif alone_since is None:
                alone_since = now
        if alone_since is not None and now - alone_since > patience:
            raise WorkersLost(
                f"the Dask scheduler at {address} has had no worker for {patience:g} s; "
                f"{running.count()} trials are waiting for one",
                hint="the finished trials are stored: start workers (`dask worker "
                f"{address}`) and run again with --resume",
            )
        time.sleep(_POLL)
    return running.next_batch(block=False)


class _Quiet:
    """Silence Dask's loggers (reconnection tracebacks) until :meth:`restore`."""

    ROOTS = ("distributed", "asyncio", "tornado")

    def __init__(self) -> None:
        names = [n for n in list(logging.root.manager.loggerDict) if n.split(".")[0] in self.ROOTS]
        # each configured child logger has a level of its own (distributed.client: ...)
        self.loggers = [logging.getLogger(name) for name in {*self.ROOTS, *names}]
        self.levels = [lg.level for lg in self.loggers]
        for lg in self.loggers:
            lg.setLevel(logging.CRITICAL + 1)

    def restore(self) -> None:
        for lg, level in zip(self.loggers, self.levels, strict=True):
            lg.setLevel(level)


def _take(items: Iterator, count: int) -> list:
    out = []
    for item in items:
        out.append(item)
        if len(out) == count:
            break
    return out
