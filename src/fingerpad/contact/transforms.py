"""The real 2-D FFTs of the NumPy backend, with the same bits on any number of cores.

ducc0 splits a threaded transform's lines (the rows of one pass, the columns of the other)
among its threads, and transforms each thread's lines in groups of the vector width, the
remainder of a thread's share one by one: a line's last bits depend on where the shares end,
i.e. on the number of threads. Measured (ducc0 0.42): a 256 x 448 or larger transform with 2, 3
or 4 threads differs from one thread's in the last bits, and so did a solve of the default cap
cell at 256^2 with 2 FFT threads against 1; from 128 x 224 down, ducc0 keeps to one thread and
the bits agree. A prediction at 256^2 on the 2-core CI machine would not have the bits of the
same prediction on a 16-core workstation. SciPy's transforms agree across threads.

So ducc0's transforms here run on one thread per call, and a large field is cut into blocks of
lines fixed by its shape alone (:data:`BLOCK_LINES`), each block one single-threaded call,
the blocks shared among ``workers`` threads: a line's bits depend on its block, never on the
threads. Blocks of at least :data:`BLOCK_LINES` lines (ducc0's per-call cost: blocks of 64 cost
~14 % at 256 x 448 on one thread, of 128 ~5 %), at most :data:`MAX_BLOCKS` a pass (the threads
a pass can use: 2 at 256^2, 8 at 1024^2, 16 from 2048^2). Fields under :data:`THREADED_MIN_POINTS` points take one single-threaded call of the
whole 2-D transform (the bits ducc0 gave them before, its threads unused at these sizes).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

__all__ = ["BLOCK_LINES", "MAX_BLOCKS", "THREADED_MIN_POINTS", "ducc0_transforms", "scipy_transforms"]

#: Fields of at least this many points are transformed in blocks of lines (below it one call on
#: one thread: ducc0 used no more there, 128 x 224 measured).
THREADED_MIN_POINTS = 2**16
#: Least lines per block (a multiple of any vector width) ...
BLOCK_LINES = 128
#: ... and most blocks per pass, so that large fields use more threads.
MAX_BLOCKS = 16

_POOLS: dict[int, ThreadPoolExecutor] = {}
_POOLS_LOCK = threading.Lock()


def _forget_pools() -> None:
    # a forked child has the pools' objects but not their threads: start afresh there
    _POOLS.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pools)


def block_lines(n: int) -> int:
    """Lines per block of a pass over ``n`` lines: at least :data:`BLOCK_LINES`, at most
    :data:`MAX_BLOCKS` blocks, a multiple of 8 (by ``n`` alone)."""
    per = -(-n // MAX_BLOCKS)
    return max(BLOCK_LINES, -(-per // 8) * 8)


def _run_blocks(n: int, work: Callable[[slice], Any], threads: int) -> None:
    """``work(block)`` for the blocks of ``range(n)`` (:func:`block_lines` each), on ``threads``
    threads (the calling one among them); the blocks do not depend on ``threads``."""
    size = block_lines(n)
    blocks = [slice(i, min(i + size, n)) for i in range(0, n, size)]
    helpers = min(threads, len(blocks)) - 1
    if helpers <= 0:
        for b in blocks:
            work(b)
        return
    with _POOLS_LOCK:
        pool = _POOLS.get(helpers)
        if pool is None:
            pool = _POOLS[helpers] = ThreadPoolExecutor(max_workers=helpers, thread_name_prefix="fingerpad-fft")
    # the calling thread takes every (helpers + 1)-th block itself; ducc0 releases the GIL
    futures = [pool.submit(work, b) for k, b in enumerate(blocks) if k % (helpers + 1)]
    for b in blocks[:: helpers + 1]:
        work(b)
    for f in futures:
        f.result()


def ducc0_transforms(workers: int) -> tuple[Any, Any]:
    """Real 2-D FFTs of ducc0 (the successor of the pocketfft inside SciPy, by its author), the
    same bits on any number of ``workers`` (module docstring)."""
    import ducc0.fft as dfft  # noqa: PLC0415

    def rfft2(a: np.ndarray, s: tuple[int, int] | None = None) -> np.ndarray:
        if a.dtype not in (np.float32, np.float64):
            a = a.astype(np.float64)  # ducc0 transforms float32/float64 only; SciPy converts
        if s is not None and tuple(s) != a.shape:
            # zero padding of finite bodies (scipy pads through its `s` argument)
            padded = np.zeros(s, dtype=a.dtype)
            padded[: a.shape[0], : a.shape[1]] = a
            a = padded
        if a.size < THREADED_MIN_POINTS:
            return dfft.r2c(a, axes=(0, 1), nthreads=1)
        n0, n1 = a.shape
        out = np.empty((n0, n1 // 2 + 1), dtype=np.complex64 if a.dtype == np.float32 else np.complex128)
        # the rows' real transforms, then the columns' complex ones, in place
        _run_blocks(n0, lambda r: dfft.r2c(a[r], axes=(1,), nthreads=1, out=out[r]), workers)
        _run_blocks(out.shape[1], lambda c: dfft.c2c(out[:, c], axes=(0,), nthreads=1, out=out[:, c]), workers)
        return out

    def irfft2(a: np.ndarray, s: tuple[int, int]) -> np.ndarray:
        # Every spectrum the operators invert is a temporary (FFTOperator), so it may serve as
        # scratch space: no extra spectrum-sized allocation per inverse transform. (It is
        # overwritten: a caller that keeps its spectrum must hand over a copy.)
        if s[0] * s[1] < THREADED_MIN_POINTS:
            return dfft.c2r(a, axes=(0, 1), lastsize=s[1], forward=False, inorm=2, nthreads=1,
                            allow_overwriting_input=True)
        out = np.empty(s, dtype=np.float32 if a.dtype == np.complex64 else np.float64)
        # the columns' inverse transforms in place (each divided by its length), then the rows'
        _run_blocks(a.shape[1], lambda c: dfft.c2c(a[:, c], axes=(0,), forward=False, inorm=2, nthreads=1,
                                                   out=a[:, c]), workers)
        _run_blocks(s[0], lambda r: dfft.c2r(a[r], axes=(1,), lastsize=s[1], forward=False, inorm=2, nthreads=1,
                                             out=out[r], allow_overwriting_input=True), workers)
        return out

    return rfft2, irfft2


def scipy_transforms(workers: int) -> tuple[Any, Any]:
    """SciPy's real 2-D FFTs (their bits do not depend on ``workers``, measured to 1024^2)."""
    import scipy.fft as sfft  # noqa: PLC0415

    return (lambda a, s=None: sfft.rfft2(a, s=s, workers=workers),
            lambda a, s: sfft.irfft2(a, s=s, workers=workers))
