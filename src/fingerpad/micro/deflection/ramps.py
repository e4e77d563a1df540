"""The section solves of the gain tables: one normal-load ramp per section, then one shear ramp
per pressure level -- serially, or the ramps of several sections and levels at once in a process
pool (issue 23: ``predict --direction`` spent its time in six independent shear ramps).

Why the pool cannot change a number: every task builds its own solver from the same inputs (the
solver keeps no state between solves other than its fixed sparsity pattern), a shear ramp starts
from the very state the shared normal-load ramp converged to (sent to the worker bit for bit),
and each ramp is one process's sequential computation. The worker count, the order in which
tasks finish and the machine's load therefore decide only when a ramp is done, never what it
gives; the tables are bit-identical to the serial path (``workers=1``), which is tested.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...contact.greens import fft_threads_parked
from ...errors import FingerpadError
from ...units import parse_int
from .mesh import SectionGeometry, build_mesh
from .path import follow_load, follow_shear
from .pressure_ramp import PressureRamp, to_ramp
from .section import Section
from .settings import DeflectionSettings, SectionMaterials
from .solve import FrictionLaw, SectionSolver


@dataclass(frozen=True)
class SectionJob:
    """One section to solve at the nominal pressures ``pressures`` (Pa), friction law shape
    ``tau0`` (Pa), ``alpha`` (-)."""

    section: Section
    materials: SectionMaterials
    pressures: tuple[float, ...]
    tau0: float
    alpha: float
    settings: DeflectionSettings
    linear: bool = False

    def solver(self) -> tuple[SectionSolver, float, float]:
        """(solver, r, E_m): the dimensionless solver (lengths in r, stresses in E_m)."""
        if self.materials.texture_modulus is None:
            raise FingerpadError("a rigid texture does not deflect: its gain is exactly 1 (no section to solve)")
        em = float(self.materials.texture_modulus)
        sec, s = self.section, self.settings
        r = sec.half_width
        geom = SectionGeometry(sec.profile, sec.height / r, sec.period / r, s.base_thickness * sec.period / r)
        mesh = build_mesh(geom, resolution=int(s.resolution))
        law = FrictionLaw(s.friction, self.tau0 / em, self.alpha)
        solver = SectionSolver(mesh, self.materials.texture_poisson, self.materials.skin_plane_modulus / em, law,
                               linear=self.linear, fold_penalty=s.fold_penalty)
        return solver, r, em

    def loads(self, r: float, em: float) -> np.ndarray:
        """The dimensionless section loads P / (E_m r) of the (sorted) pressure levels."""
        return np.asarray(self.pressures, dtype=float) * self.section.load_per_pressure / (em * r)


def press(job: SectionJob) -> Any:
    """The normal-load ramp of ``job`` at zero shear through all its levels (:func:`.path.follow_load`)."""
    solver, r, em = job.solver()
    return follow_load(solver, job.loads(r, em))


def shear(job: SectionJob, k: int, start: Any) -> Any:
    """The shear ramp of ``job``'s level ``k`` from its pressed state ``start``, as a
    :class:`.pressure_ramp.PressureRamp` (SI units)."""

    solver, r, em = job.solver()
    s = job.settings
    ramp = follow_shear(solver, start, s.mu_max, check_stability=s.check_stability, max_steps=int(s.max_steps),
                        time_limit=s.time_limit)
    out = to_ramp(solver, ramp, job.pressures[k], start.load * em * r, r, em)
    out.incomplete = bool(ramp.timed_out)
    return out


def unpressed(job: SectionJob, ramp0: Any) -> list[Any]:
    """Empty ramps for the levels the normal-load ramp did not reach (they say why)."""

    return [PressureRamp(float(pk), float(pk * job.section.load_per_pressure), *([np.zeros(0)] * 9),
                         math.nan, math.nan, False, f"not pressed on: {ramp0.stopped}")
            for pk in job.pressures[len(ramp0.states):]]


def default_workers(tasks: int) -> int:
    """Worker processes for ``tasks`` ramps: the cores this process may use (at most ``tasks``),
    ``FINGERPAD_DEFLECTION_WORKERS`` if set; 1 (serial) inside a daemonic process, which may not
    start children (e.g. a multiprocessing pool's worker), and off the main thread (a Dask
    worker's task, a server's job): those already run their work side by side.

    Other threads beside the main one (a progress bar's refresh thread) do not make it serial:
    the pool then starts its workers from a fork server instead of forking this process
    (:func:`_context`). Before, such a thread made every command's ramps serial (issue 23: the
    progress bar of ``predict --direction`` has one)."""
    if multiprocessing.current_process().daemon or threading.current_thread() is not threading.main_thread():
        return 1
    text = os.environ.get("FINGERPAD_DEFLECTION_WORKERS", "").strip()
    if text:
        n = parse_int(text, "FINGERPAD_DEFLECTION_WORKERS")
    else:
        n = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(n, tasks))


def solve_sections(jobs: Sequence[SectionJob], workers: int | None = None,
                   progress: Callable[[str], None] | None = None,
                   on_free_core: Callable[[], None] | None = None) -> list[list[Any]]:
    """The ramps (:class:`.pressure_ramp.PressureRamp`, one per level in the job's order) of every job.

    Parameters
    ----------
    jobs
        The sections to solve; each job's ``pressures`` must be increasing.
    workers
        Processes: 1 solves in this process, in order; None: :func:`default_workers`. The
        numbers are the same whatever the count (see the module's docstring).
    progress
        Called with a short message when a stage starts (serial) or ends (pool).
    on_free_core
        Called once, in this process, when the pool first has a worker with no ramp left to take
        while others still run (never in serial): work of the caller's own that would otherwise
        wait for the last ramp runs on that core (``predict --direction`` imports what writes
        its outputs there, issue 23). It must not raise: an error there is the caller's.
    """
    jobs = list(jobs)
    for job in jobs:
        if list(job.pressures) != sorted(job.pressures):
            raise FingerpadError("section job: pressure levels must be increasing")
    n = default_workers(sum(len(j.pressures) for j in jobs)) if workers is None else max(1, int(workers))
    if n == 1 or not jobs:
        return [_serial(job, progress) for job in jobs]
    return _pooled(jobs, n, progress, on_free_core)


def _serial(job: SectionJob, progress: Callable[[str], None] | None) -> list[Any]:
    if progress:
        progress(f"pressing the skin on ({len(job.pressures)} pressure levels)")
    ramp0 = press(job)
    out = []
    for k, start in enumerate(ramp0.states):
        if progress:
            progress(f"shear ramp {k + 1}/{len(ramp0.states)} at p = {job.pressures[k]:.4g} Pa")
        out.append(shear(job, k, start))
    return out + (unpressed(job, ramp0) if ramp0.stopped else [])


def _context() -> Any:
    """How the pool starts its workers: by forking this process where it has one thread (they
    inherit the imported package: no start-up import); where other threads run, from a fork
    server, a fresh single-threaded process that imports this module once and forks the workers
    (forking a threaded process can leave a lock held by another thread, a console's or stderr's,
    locked forever in the child); elsewhere (no fork), the platform's default."""
    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and threading.active_count() == 1:
        return multiprocessing.get_context("fork")
    if "forkserver" in methods:
        context = multiprocessing.get_context("forkserver")
        # the main module once in the server (its workers then skip importing it again: a script
        # must guard its work with `if __name__ == "__main__":`, as for any spawned pool), and
        # this module with the numerics
        context.set_forkserver_preload(["__main__", __name__])
        return context
    return multiprocessing.get_context()


def start_fork_server() -> None:
    """Start the fork server the pool may need now, so that its start (a fresh interpreter
    importing the numerics, ~0.3 s) runs beside the caller's own work instead of before the
    first ramp. Does nothing where there is no fork server, off the main thread and in a
    daemonic process (serial there)."""
    if "forkserver" not in multiprocessing.get_all_start_methods() or default_workers(2) == 1:
        return
    from multiprocessing import forkserver

    multiprocessing.get_context("forkserver").set_forkserver_preload(["__main__", __name__])
    forkserver.ensure_running()


def _pooled(jobs: list[SectionJob], workers: int, progress: Callable[[str], None] | None,
            on_free_core: Callable[[], None] | None = None) -> list[list[Any]]:
    context = _context()
    results: list[list[Any]] = [[] for _ in jobs]
    tails: list[list[Any]] = [[] for _ in jobs]
    if progress:
        progress(f"pressing {len(jobs)} section(s), then shearing in {workers} processes")
    # the pool forks its workers as tasks arrive: the FFTs' threads parked meanwhile (a fork once
    # hung in ducc0's fork handler; fft_threads_parked)
    with fft_threads_parked(), ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        # the normal-load ramps first (1-2 s each), then the shear ramps longest first (LPT),
        # as far as the inputs tell: a ramp's CPU time grows with the section's unknowns (its
        # Newton steps' sparse LU) and with the pressure (more steps, more failed ones), so the
        # estimate is unknowns x pressure. README ellipsoids (CPU s; across sections 2820
        # unknowns, along 832): across 11, 16, 27, along 1, 4, 14 at 14.5, 26.8, 49.6 kPa. Sorted
        # by slenderness first (before), the along 14 s ramp started last, at 27 s on one worker:
        # 40.7 s of ramps on 2 workers; by the estimate, 38.3 s (the best split of these six).
        # The order decides only when a ramp is done.
        pressed = [fut.result() for fut in [pool.submit(press, job) for job in jobs]]
        tasks = []
        for i, ramp0 in enumerate(pressed):
            results[i] = [None] * len(ramp0.states)
            tails[i] = unpressed(jobs[i], ramp0) if ramp0.stopped else []
            tasks += [(-float(start.v.size) * jobs[i].pressures[k], i, k, start)
                      for k, start in enumerate(ramp0.states)]
        tasks.sort(key=lambda t: t[:3])
        pending = {pool.submit(shear, jobs[i], k, start): (i, k) for _, i, k, start in tasks}
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                i, k = pending.pop(fut)
                results[i][k] = fut.result()
                if progress:
                    progress(f"shear ramp {len(tasks) - len(pending)}/{len(tasks)} done "
                             f"(p = {jobs[i].pressures[k] / 1e3:.3g} kPa)")
                if on_free_core is not None and 0 < len(pending) < workers:
                    # every ramp is taken and a worker waits: its core is free until the last
                    # ends (checked per ramp, so that two ending together still count)
                    on_free_core()
                    on_free_core = None
    return [r + t for r, t in zip(results, tails)]


__all__ = ["SectionJob", "default_workers", "press", "shear", "solve_sections", "start_fork_server"]
