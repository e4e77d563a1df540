"""Independent pieces of an analysis on several cores: forked worker processes that inherit
what the pieces read.

The fits of one participant (every condition's breakpoint test, E_s fit and its sensitivity
refits, the joint E_s) read nothing of another participant's, and the population fit of one
sample nothing of another sample's. :func:`forked_map` runs such a function over its items in
worker processes forked from this one, so the function may be a closure over the study's tables
and models (nothing of them is pickled; only the items and the results travel). Each worker runs
BLAS on one thread, as :func:`~fingerpad.measure.analyse_study` does: the results are the same,
bit for bit, as computed here one after another.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from ..errors import FingerpadError

__all__ = ["fork_ready", "forked_map", "own_streams", "resolve_workers", "usable_cpus"]

#: The function the workers run: set before they fork, so that each inherits it.
_FUNCTION: list[Callable[[Any], Any]] = []


def usable_cpus() -> int:
    """CPUs this process may use."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def resolve_workers(workers: int | None, n_items: int) -> int:
    """Processes for ``n_items`` independent pieces: ``workers``, or with ``None`` one per usable
    CPU (at most 8); never more than the pieces, at least one."""
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise FingerpadError(f"workers must be a whole number >= 1 or None, got {workers!r}")
    chosen = min(usable_cpus(), 8) if workers is None else workers
    return max(1, min(chosen, n_items))


@contextlib.contextmanager
def fork_ready() -> Iterator[None]:
    """This process ready to fork workers, until exit (fork before exit).

    Two things: (1) the objects that exist on entry are out of the garbage collector's reach (in
    processes forked meanwhile: for good): a collection in a worker would otherwise write to
    every object it inherited, copying their memory pages (copy on write); half the workers'
    extra CPU (3x8's fits, both workers on one core: 0.9 -> 0.45 s over 5.7 s in one process).
    (2) the FFTs' thread pool parked (:func:`fingerpad.contact.greens.fft_threads_parked`: a
    fork once hung for good in ducc0's fork handler). The same results."""
    import gc

    from ..contact.greens import fft_threads_parked

    with fft_threads_parked():
        gc.freeze()
        try:
            yield
        finally:
            gc.unfreeze()


def own_streams() -> None:
    """A worker's own ``sys.stdout`` and ``sys.stderr`` (new objects on copies of the same
    descriptors). The workers are forked from a process where a progress bar's thread may
    write to stderr ten times a second: a fork in the middle of such a write leaves the inherited
    stream's lock held by a thread that does not exist in the child, and the child's first
    warning would wait on it forever."""
    for name, fd in (("stdout", 1), ("stderr", 2)):
        stream = getattr(sys, name, None)
        try:
            setattr(sys, name, io.TextIOWrapper(io.FileIO(os.dup(fd), "w"), encoding=getattr(stream, "encoding", None),
                                                errors=getattr(stream, "errors", None), line_buffering=True))
        except OSError:  # no such descriptor (a daemon): keep what is there
            pass


#: The process whose BLAS :func:`one_blas_thread` put on one thread (a forked child inherits the
#: list, not the limit's bookkeeping: it checks its own id).
_ONE_BLAS_THREAD: list[int] = []


def one_blas_thread() -> None:
    """BLAS on one thread in this worker process, for the rest of its life: as
    :func:`~.analysis.analyse_study`, the same last bits whatever the core count. Once per
    process: ``threadpool_limits`` looks up every loaded library each time it is entered
    (~2 ms), which, once per task, was ~1.5 % of ``fingerpad analyse``'s CPU on 540 recordings."""
    if _ONE_BLAS_THREAD != [os.getpid()]:
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1, user_api="blas")
        _ONE_BLAS_THREAD[:] = [os.getpid()]


def _run(items: list[Any]) -> list[Any]:
    one_blas_thread()
    return [_FUNCTION[0](item) for item in items]


def forked_map(function: Callable[[Any], Any], items: Sequence[Any], workers: int = 1, chunksize: int = 1
               ) -> list[Any]:
    """``[function(item) for item in items]``, by ``workers`` processes forked from this one.

    The items go out in order, ``chunksize`` consecutive ones at a time (many small pieces cost
    more in messages than in work one by one), to whichever worker is free; the results come
    back in the order of ``items``. One worker, fewer than two items, or a platform without
    ``fork`` (Windows, or macOS's default): computed here, one after another. An exception in
    ``function`` is raised here, as it would be without workers."""
    import multiprocessing

    items = list(items)
    workers = max(1, min(int(workers), len(items)))
    if workers <= 1 or "fork" not in multiprocessing.get_all_start_methods():
        return [function(item) for item in items]
    from concurrent.futures import ProcessPoolExecutor

    _FUNCTION[:] = [function]
    try:
        with fork_ready(), ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                                                initializer=own_streams) as pool:
            size = max(1, int(chunksize))
            chunks = [items[i:i + size] for i in range(0, len(items), size)]
            return [out for chunk in pool.map(_run, chunks) for out in chunk]
    finally:
        _FUNCTION.clear()
