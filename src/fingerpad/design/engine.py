"""Running a sweep: its plan's tasks on Dask distributed, a LocalCluster by default, an existing
scheduler if given.

The client (the ``fingerpad sweep`` process) lays the store out, finds the chunks not yet done,
and makes the sweep's plan (:mod:`.plan`: one task per distinct unit cell, for its first point,
which solves the cell into the shared on-disk cache over what every point sharing it asks for;
one per chunk of points, after the cells its points use; no task for a chunk whose every point
is its cell's first point, written from those cells' results). :func:`execute_plan` submits the
tasks to an executor (:mod:`.executor`: Dask here, or in this process for tests) and writes
finished chunks into the store as they come back. Workers run one thread each, and BLAS and FFT
threads are capped at one inside them: the parallelism of a sweep is its workers.

To use more than one machine, start ``dask scheduler`` on one, ``dask worker tcp://HOST:8786
--nthreads 1`` on each (with fingerpad installed, and ``FINGERPAD_CACHE`` on a shared folder if
the cells should be shared), and give ``--scheduler tcp://HOST:8786`` (docs/sweeps.md).
"""

from __future__ import annotations

import contextlib
import math
import os
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError, one_line
from ..extras import require
from .evaluate import evaluate_chunk, prepare_cell
from .executor import Executor, _close_quietly
from .plan import SweepPlan, plan_sweep
from .spec import SweepSpec
from .store import SweepStore, check_store_path, pressure_grid

__all__ = ["SweepReport", "check_address", "check_workers", "connect", "execute_plan", "max_workers", "probe_scheduler",
           "run_sweep", "sweep_pressures"]

#: Local worker processes per core a sweep may start (``--workers``): one per core is the
#: default; more only share the cores, and each costs ~0.1-0.3 GB of memory.
MAX_WORKERS_PER_CORE = 4


def max_workers() -> int:
    """Most worker processes of a local cluster on this machine (:data:`MAX_WORKERS_PER_CORE`
    per core): their number changes how fast a sweep runs, never its results."""
    return MAX_WORKERS_PER_CORE * (os.cpu_count() or 1)


def check_workers(workers: Any, name: str = "--workers") -> int | None:
    """``workers`` (text or a number; ``None``: one per core) checked against :func:`max_workers`."""
    from ..units import parse_int

    if workers is None:
        return None
    return parse_int(workers, name, 1, max_workers())


#: Seconds to wait for an existing scheduler before giving up.
CONNECT_TIMEOUT = 5.0
#: Seconds without a worker on an existing scheduler before the sweep says it is waiting, and
#: between the reminders after that.
NO_WORKER_NOTICE = 5.0
NO_WORKER_REPEAT = 60.0


@dataclass
class SweepReport:
    """What a sweep did (for the progress line and the summary)."""

    points: int = 0
    done_before: int = 0
    computed: int = 0
    invalid: int = 0
    unconverged: int = 0
    cells: int = 0
    cells_solved: int = 0
    cache_hits: int = 0
    solves: int = 0  # unit-cell solves, by the cell tasks and by the points (range ends they add)
    failures: list[str] = field(default_factory=list)
    seconds: float = 0.0
    dashboard: str | None = None
    workers: int = 0
    #: Points of damaged chunks marked for recomputing, and what was damaged (``repair``).
    repaired: int = 0
    damage: str = ""


def sweep_pressures(spec: SweepSpec) -> np.ndarray:
    """The common pressure grid (Pa) of psi: the local pressures the exploration loads give on
    the base study's finger, over the range a prediction prepares (Eq. 3.7), 12 per decade."""
    from ..study.run import P_HIGH, P_LOW
    from ..study.spec import study_from_dict

    study = study_from_dict(spec.base)
    p = spec.loads / np.asarray(study.finger.ridge_area(spec.loads), float)
    return pressure_grid(P_LOW * float(p.min()), P_HIGH * float(p.max()))


def check_address(scheduler: str) -> str:
    """``scheduler`` as a Dask address (``tcp://HOST:PORT``, or ``HOST:PORT`` for tcp).

    Raises
    ------
    FingerpadError
        An address without a port, with an unknown scheme or a port out of range.
    """
    from distributed.comm.addressing import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    text = str(scheduler).strip()
    try:
        scheme, location = parse_address(text)
        get_backend(scheme)
        _, port = parse_host_port(location)
    except (ValueError, TypeError) as exc:
        raise FingerpadError(f"--scheduler {scheduler!r}: {exc} (expected tcp://HOST:PORT)") from None
    if not 0 < int(port) < 65536:
        raise FingerpadError(f"--scheduler {scheduler!r}: port {port} is out of range (1-65535)")
    return text if "://" in text else f"tcp://{text}"


async def _identity(address: str) -> Any:
    """Connect to ``address`` and ask its identity (the scheduler must answer, not just accept)."""
    from distributed.comm import connect as comm_connect
    from distributed.security import Security

    # the client's connection settings from the Dask configuration (TLS certificates, if any),
    # as the Client itself would use them
    args = Security().get_connection_args("client")
    comm = await comm_connect(address, timeout=CONNECT_TIMEOUT, **args)
    try:
        await comm.write({"op": "identity"})
        return await comm.read()
    finally:
        comm.abort()


def probe_scheduler(address: str, timeout: float = CONNECT_TIMEOUT) -> dict[str, Any]:
    """The identity of the Dask scheduler at ``address``, within ``timeout`` seconds overall.

    A peer that accepts the connection but never answers (not a scheduler, a stalled one) would
    hold the Client's handshake until it closes (minutes): the bound here covers the whole
    exchange, connection, handshake and answer.

    Raises
    ------
    FingerpadError
        Nothing answers as a scheduler within ``timeout`` s.
    """
    import asyncio

    try:
        answer = asyncio.run(asyncio.wait_for(_identity(address), timeout))
    except (OSError, TimeoutError, asyncio.TimeoutError) as exc:
        why = "no answer" if isinstance(exc, (TimeoutError, asyncio.TimeoutError)) and not str(exc) else \
            type(exc).__name__
        raise FingerpadError(f"--scheduler {address}: no Dask scheduler answers there within {timeout:g} s "
                             f"({why})") from None
    except Exception as exc:  # noqa: BLE001 - a peer speaking another protocol, TLS not configured
        raise FingerpadError(f"--scheduler {address}: cannot talk to a Dask scheduler there "
                             f"({type(exc).__name__}: {one_line(str(exc))})") from None
    if not isinstance(answer, dict) or answer.get("type") != "Scheduler":
        raise FingerpadError(f"--scheduler {address}: answers, but not as a Dask scheduler")
    return answer


def connect(scheduler: str | None, workers: int | None) -> tuple[Any, Any]:
    """A Dask client: to ``scheduler`` (answering within :data:`CONNECT_TIMEOUT` s), or to a new
    LocalCluster of ``workers`` single-threaded processes on 127.0.0.1 (default: one per core).

    The address is checked and the scheduler asked for its identity before a Client exists: a
    Client that fails while connecting cannot be closed by its caller and prints a traceback
    when it is collected, seconds after the error.
    """
    from distributed import Client, LocalCluster

    if scheduler is not None:
        address = check_address(scheduler)
        probe_scheduler(address)
        client = Client.__new__(Client)
        try:
            client.__init__(address, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except Exception as exc:  # noqa: BLE001 - it went away between the probe and the Client
            _close_quietly(client)
            raise FingerpadError(f"--scheduler {address}: the Dask scheduler stopped answering "
                                 f"({type(exc).__name__})") from None
        return client, None
    n = check_workers(workers, "workers") or os.cpu_count() or 1
    import importlib.util

    # Dask's dashboard is drawn with Bokeh: ask for it only where Bokeh is installed (looked up,
    # not imported: Bokeh belongs to the explorer's layer).
    dashboard: str | None = "127.0.0.1:0" if importlib.util.find_spec("bokeh") is not None else None
    with _worker_start(), _interrupt_deferred() as interrupted:
        # preload: each worker runs dask_setup below when it starts (a spawned one too)
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=dashboard, silence_logs=50, preload=[__name__])
    if interrupted:
        cluster.close()
        raise KeyboardInterrupt
    try:
        return Client(cluster, set_as_default=False), cluster
    except BaseException:
        cluster.close()
        raise


@contextlib.contextmanager
def _worker_start() -> Iterator[None]:
    """Start the local workers by forking this process (Linux), not by spawning fresh interpreters.

    A spawned worker imports Python, Dask and the numerics anew; a forked one inherits them,
    with the prediction modules imported here first (:data:`~.evaluate.POINT_MODULES`, what a
    point imports: ~0.2 s of each worker's first point before, issue 23). Measured for issue 23 (2 workers, 2 cores,
    load average 12): start 3.3-3.9 s -> 0.5-0.9 s, closing 1.2-1.7 s -> 0.03-0.1 s, the
    workers' first imports 0.7-1.2 s -> 0.01 s. Elsewhere (macOS, Windows: fork is unsafe or
    absent there) Dask's default, spawn, stays; so it does with a GPU device
    (``FINGERPAD_DEVICE``): this process has initialised CUDA, which a forked child cannot use.
    A worker the nanny restarts later spawns.
    """
    import sys

    from ..contact.device import device_setting

    if not sys.platform.startswith("linux") or device_setting()[0] != "cpu":
        yield
        return
    import importlib
    import warnings

    import dask

    from .evaluate import POINT_MODULES

    for name in POINT_MODULES:  # what every worker imports for its first point
        importlib.import_module(name)
    from ..contact.greens import fft_threads_parked
    from ..contact.solver import preload_compiled_kernels

    # and the compiled loops the unit cells run on (kernels="compiled"), loaded once here
    preload_compiled_kernels()

    # the FFTs' threads parked while the workers fork (a fork once hung in ducc0's fork handler)
    with dask.config.set({"distributed.worker.multiprocessing-method": "fork"}), warnings.catch_warnings(), \
            fft_threads_parked():
        # Python >= 3.12 warns about forking a process with threads (the cluster's event loop):
        # the child runs only multiprocessing's start of a Dask worker
        warnings.filterwarnings("ignore", message=".*fork.*", category=DeprecationWarning)
        yield


def dask_setup(worker: Any) -> None:
    """Run by every worker of a local cluster when it starts (Dask's preload): Ctrl-C is the
    client's to handle. A terminal sends it to the whole process group, workers included, and
    each worker (and its nanny's process) printed a KeyboardInterrupt traceback, ~40 lines,
    before the client's one ``interrupted:`` line; the client closes the cluster, which stops
    them."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextlib.contextmanager
def _interrupt_deferred() -> Iterator[list[int]]:
    """While the local workers are started: Ctrl-C is noted in the list yielded (the caller
    stops once they are up), and the forked workers inherit a handler that only notes it
    (:func:`dask_setup` then makes them ignore it), so that none of them is born able to print
    a traceback for it."""
    import signal
    import threading

    caught: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield caught
        return
    before = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield caught
    finally:
        signal.signal(signal.SIGINT, before)


def run_sweep(
    spec: SweepSpec,
    store_path: str | Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    overwrite: bool = False,
    repair: bool = False,
    progress: Callable[[SweepReport], None] | None = None,
    notice: Callable[[str], None] | None = None,
) -> SweepReport:
    """Run the sweep into ``store_path`` (resuming it if it holds the same sweep).

    A store of this sweep is checked first (every chunk read): a damaged one is refused unless
    ``repair``, which recomputes the points of its damaged chunks and rewrites its metadata.
    When every point is done already, no cluster is started. With an existing ``scheduler``
    that has no worker yet, ``notice`` is told so after :data:`NO_WORKER_NOTICE` s, and again
    every minute, while the sweep waits for one. The tasks are those of the sweep's plan
    (:func:`~.plan.plan_sweep`), run by :func:`execute_plan` on Dask
    (:class:`~.executor.DaskExecutor`).

    Raises
    ------
    FingerpadError
        A store of another sweep without ``overwrite``, a damaged store without ``repair``,
        ``repair`` without a store, a store another sweep is writing
        (:class:`~fingerpad.locks.OutputBusy`), a scheduler that does not answer, a bad
        ``FINGERPAD_FFT`` setting.
    MissingExtraError
        Dask or Zarr not installed (the ``sweep`` extra).
    """
    require("sweep")
    from .. import locks
    from ..contact.greens import check_setup

    # A bad device or FFT setting would make every point's solve fail (each chunk then fails with
    # a SetupError, see evaluate_point): check it here, once, before any work (LocalCluster
    # workers inherit this environment; those of an existing scheduler have their own).
    check_setup()
    workers = check_workers(workers, "workers")
    if scheduler is not None:
        scheduler = check_address(scheduler)
    # One sweep writes a store at a time: a second is refused, naming the first (fingerpad.locks).
    key = locks.hold(store_path, "--out", os.fspath(store_path))
    try:
        return _run_sweep(spec, store_path, workers, scheduler, overwrite, repair, progress, notice)
    finally:
        locks.release(key)


def _run_sweep(spec: SweepSpec, store_path: str | Path, workers: int | None, scheduler: str | None,
               overwrite: bool, repair: bool, progress: Callable[[SweepReport], None] | None,
               notice: Callable[[str], None] | None) -> SweepReport:
    """:func:`run_sweep` once the store is this process's to write."""
    from .executor import DaskExecutor

    t_start = time.perf_counter()
    pressures = sweep_pressures(spec)
    store = SweepStore(store_path, spec, pressures)
    report = SweepReport(points=spec.size)
    if check_store_path(store_path, spec, overwrite, repair) == "resume":
        # Checked before any cluster starts: a damaged store is said at once, and a finished
        # sweep costs no cluster (9-16 s to start one on two cores, to do nothing).
        damage = store.check()
        if damage:
            if not repair:
                raise FingerpadError(damage.message())
            report.repaired = store.repair(damage)
            report.damage = damage.describe()
        done = store.done()
        if done.all():
            report.done_before = int(done.size)
            report.seconds = time.perf_counter() - t_start
            return report
    client, cluster = connect(scheduler, workers)
    executor = DaskExecutor(client, cluster)
    try:
        if cluster is None:
            _wait_for_a_worker(client, scheduler or "", notice)
            t_start = time.perf_counter()  # the rate of the summary counts computing, not waiting
        # (no client.run of limit_threads first: every task caps its own threads, and that round
        # trip to each worker held the first task back)
        report.workers = executor.workers
        report.dashboard = executor.dashboard if cluster is not None or scheduler else None
        resume = store.check_existing(overwrite) == "resume"
        plan = plan_sweep(spec, store.done() if resume else None)
        # The store is laid out once the tasks are submitted, while the workers compute: its
        # template (xarray, which imports dask.array, and zarr) took 1-4 s in this process, during
        # which the workers sat idle (profiled for issue 23).
        execute_plan(plan, executor, store, spec.loads, pressures, report, t_start=t_start, progress=progress,
                     population=spec.population_payload(), before_results=lambda: store.create(overwrite=overwrite))
    finally:
        executor.close()
    report.seconds = time.perf_counter() - t_start
    return report


def execute_plan(plan: SweepPlan, executor: Executor, store: SweepStore, loads: np.ndarray, pressures: np.ndarray,
                 report: SweepReport, *, t_start: float | None = None,
                 progress: Callable[[SweepReport], None] | None = None,
                 population: dict[str, Any] | None = None,
                 before_results: Callable[[], None] | None = None) -> SweepReport:
    """Run ``plan``'s tasks on ``executor`` and write each chunk into ``store`` as it comes back.

    The cell tasks are submitted first (:func:`~.evaluate.prepare_cell`), then one task per chunk
    that needs one, after the cells it uses (:func:`~.evaluate.evaluate_chunk`); the chunks of
    first points alone are written here from their cells' results. A chunk whose task, or one of
    whose cells, failed is named in ``report.failures``; the others go on. ``before_results``
    runs once every task is submitted, before any result is written (the store is laid out
    there). ``population``: the members of :meth:`~.spec.SweepSpec.population_payload`, sent to
    every worker once.
    """
    t_start = time.perf_counter() if t_start is None else t_start
    report.done_before = plan.done_before
    report.cells = len(plan.cells)
    loads_, ps = np.asarray(loads, float).tolist(), np.asarray(pressures, float).tolist()
    shared = executor.broadcast(population) if population is not None else None
    # A cell task prepares the cell for every point that shares it (a modulus axis) before any
    # of them is predicted: the chunks then only read it, in whatever order they run. It predicts
    # its first point in full and returns that result, which the point's chunk takes as it is:
    # each such point is predicted once, not twice (the second time from the cache: ~a quarter
    # of a point at grid 48, profiled for issue 23).
    cell_tasks = {key: executor.submit(prepare_cell, task.data, loads_, ps, shared, task.index, list(task.sharing),
                                       name=task.name)
                  for key, task in plan.cells.items()}
    # Chunks whose every point is the first point of its cell (every point of a sweep over the
    # texture's shape) need no task of their own: they are written here from their cells'
    # results as those come in. Their task only passed those results on, from worker to worker
    # and back here, and queued behind the cell tasks (issue 23, 2 workers against 1).
    chunk_tasks = [(executor.submit(_after, list(chunk.items), loads_, ps, shared,
                                    after=[cell_tasks[k] for k in chunk.cells]), n)
                   for n, chunk in plan.chunk_tasks()]
    if before_results is not None:
        before_results()
    if progress is not None:
        progress(report)  # the start: the store is laid out and the workers are there
    waiting = plan.written_from_cells()
    left = {n: set(plan.chunks[n].cells) for ns in waiting.values() for n in ns}
    key_at = plan.first_points()
    # tasks by identity: a Dask future compares by its key, an in-process task by value
    cell_of = {id(handle): key for key, handle in cell_tasks.items()}
    chunk_of = {id(handle): n for handle, n in chunk_tasks}
    cells: dict[str, Any] = {}  # the results of the cells whose chunks are written here
    failed: dict[str, BaseException] = {}
    for done in executor.as_completed([*cell_tasks.values(), *(handle for handle, _ in chunk_tasks)]):
        key = cell_of.get(id(done.handle))
        if key is None:
            chunk = plan.chunks[chunk_of[id(done.handle)]]
            if done.error is not None:
                report.failures.append(f"chunk {chunk.label}: {done.error!r}")
            else:
                _record(store, chunk.region, done.result, report, t_start, progress)
            continue
        if done.error is not None:
            failed[key] = done.error
        else:
            solves = int(done.result["solves"])
            report.cells_solved += int(solves > 0)
            report.cache_hits += int(solves == 0)
            report.solves += solves
            if key in waiting:
                cells[key] = done.result
        for n in waiting.pop(key, []):
            left[n].discard(key)
            if left[n]:
                continue  # other cells of this chunk are still running
            chunk = plan.chunks[n]
            error = next((failed[k] for k in chunk.cells if k in failed), None)
            if error is not None:  # what the chunk's task would have failed with
                report.failures.append(f"chunk {chunk.label}: {error!r}")
                continue
            # as evaluate_chunk takes a point its cell task predicted (the solves were counted
            # with the cell)
            _record(store, chunk.region, [(idx, {**cells.pop(key_at[idx])["result"], "solves": 0})
                                          for idx, _ in chunk.items], report, t_start, progress)
    return report


def _record(store: SweepStore, region: tuple[slice, ...], results: list[Any], report: SweepReport, t_start: float,
            progress: Callable[[SweepReport], None] | None) -> None:
    """Write one chunk's results into the store and count them in ``report``."""
    store.write(region, results)
    report.computed += len(results)
    report.solves += sum(int(r.get("solves", 0)) for _, r in results)
    report.invalid += sum(1 for _, r in results if not r["valid"])
    report.unconverged += sum(1 for _, r in results if r["valid"] and not r["converged"])
    report.seconds = time.perf_counter() - t_start
    if progress is not None:
        progress(report)


def _wait_for_a_worker(client: Any, address: str, notice: Callable[[str], None] | None) -> None:
    """Wait until the scheduler has a worker, saying so after :data:`NO_WORKER_NOTICE` s and then
    every :data:`NO_WORKER_REPEAT` s: a sweep waiting for workers must not look like a hang."""
    from dask.distributed import TimeoutError as DaskTimeout

    waited, step = 0.0, NO_WORKER_NOTICE
    while not client.scheduler_info().get("workers"):
        try:
            client.wait_for_workers(1, timeout=step)
            return
        except (DaskTimeout, TimeoutError):
            waited += step
        if notice is not None:
            notice(f"no Dask worker has joined the scheduler at {address} after {waited:.0f} s; waiting for one "
                   f"(start workers with `dask worker {address} --nthreads 1`; Ctrl-C stops)")
        step = NO_WORKER_REPEAT


def _after(deps: list[Any], items: list[Any], loads: list[float], pressures: list[float],
           population: dict[str, Any] | None = None) -> list[Any]:
    """A chunk's points, run once the cells they use are in the cache (``deps`` are their
    results: the points the cell tasks predicted are taken from them)."""
    known = {tuple(d["index"]): d["result"] for d in deps if d.get("index") is not None and "result" in d}
    return evaluate_chunk(items, loads, pressures, population, known)


def eta(report: SweepReport) -> float:
    """Seconds left, from the rate so far (NaN before the first chunk)."""
    left = report.points - report.done_before - report.computed
    if report.computed == 0:
        return math.nan
    return report.seconds / report.computed * left
