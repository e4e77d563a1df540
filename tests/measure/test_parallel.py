"""The fits that do not depend on one another, run by forked worker processes: the same result,
bit for bit, as one process's."""

from __future__ import annotations

import os

import numpy as np
import pandas as pd
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError
from fingerpad.measure.parallel import forked_map, resolve_workers


def _pid_and_product(i: int) -> tuple[int, int, float]:
    rng = np.random.default_rng(i)
    a = rng.standard_normal((40, 40))
    return i, os.getpid(), float((a @ a.T).sum())


def test_forked_map_keeps_the_order_and_the_bits_of_a_loop_here():
    here = [_pid_and_product(i) for i in range(12)]
    there = forked_map(_pid_and_product, range(12), workers=2, chunksize=5)
    assert [(i, x) for i, _, x in there] == [(i, x) for i, _, x in here]
    assert {pid for _, pid, _ in there} - {os.getpid()}, "computed by workers"
    # a closure over data of this process (the workers inherit it, nothing of it is pickled)
    table = {i: str(i) * 3 for i in range(5)}
    assert forked_map(lambda i: table[i], range(5), workers=2) == [table[i] for i in range(5)]


def _fails_on_three(i: int) -> int:
    if i == 3:
        raise FingerpadError("three")
    return i


def test_forked_map_raises_a_worker_s_error_here():
    with pytest.raises(FingerpadError, match="three"):
        forked_map(_fails_on_three, range(6), workers=2)


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_workers_must_be_a_whole_number_or_none(bad):
    with pytest.raises(FingerpadError, match="workers must be a whole number >= 1 or None"):
        resolve_workers(bad, 10)
    assert resolve_workers(None, 1) == 1 and resolve_workers(5, 3) == 3


def test_analysis_on_two_workers_is_the_same_as_in_one_process(small_study_dir, study_small):
    """analyse_study(workers=2): every table of the result, the fits and the transition tests
    equal those computed in one process (the study_small fixture), bit for bit."""
    result = m.analyse_study(m.load_study([small_study_dir]), m.AnalysisOptions(reference="flat", n_null=199),
                             textures=m.read_textures(small_study_dir / "samples.csv"), workers=2)
    for name in ("conditions", "participants", "fits", "bins", "sensitivity", "population_fits",
                 "population_curves", "strokes"):
        pd.testing.assert_frame_equal(getattr(result, name), getattr(study_small, name), check_exact=True,
                                      obj=name)
    # repr: a float's shortest round-trip digits (equal reprs, equal bits), and NaN equal to NaN
    assert repr(result.modulus_fits) == repr(study_small.modulus_fits)
    assert repr(result.breakpoints) == repr(study_small.breakpoints)
    assert {k: t.table.tobytes() for k, t in result.tables.items()} == \
        {k: t.table.tobytes() for k, t in study_small.tables.items()}
    assert {f.model for f in result.modulus_fits.values()} == {"bem"}  # the tables keep the model's name


def test_forks_happen_with_ducc0_s_pool_shrunk_to_this_thread():
    """ducc0 joins its pool's threads inside fork(); the suite once hung there for good. While
    workers fork, the pool holds only the calling thread (nothing to join), and it is restored
    after; gc is frozen meanwhile (copy on write)."""
    import gc

    ducc0 = pytest.importorskip("ducc0")
    import ducc0.misc as dm

    from fingerpad.measure.parallel import fork_ready

    ducc0.fft.r2c(np.ones((8, 8)), nthreads=1)  # the pool exists
    before = dm.thread_pool_size()
    dm.resize_thread_pool(2)
    try:
        with fork_ready():
            assert dm.thread_pool_size() == 1 and gc.get_freeze_count() > 0
            seen = forked_map(lambda x: x + 1, range(4), workers=2)
        assert dm.thread_pool_size() == 2 and seen == [1, 2, 3, 4]
    finally:
        dm.resize_thread_pool(before)


def _blas_threads(_item: int) -> tuple[int, list[int]]:
    from threadpoolctl import threadpool_info

    return os.getpid(), [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_workers_run_blas_on_one_thread_for_good():
    """Each worker puts BLAS on one thread once (one_blas_thread), and it stays so for every
    later task of that worker; the calling process keeps its own setting."""
    from threadpoolctl import threadpool_info

    from fingerpad.measure import parallel

    here = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
    out = forked_map(_blas_threads, range(6), workers=2)
    assert {pid for pid, _ in out} and os.getpid() not in {pid for pid, _ in out}
    assert all(threads and set(threads) == {1} for _, threads in out)
    assert [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"] == here
    assert parallel._ONE_BLAS_THREAD != [os.getpid()]  # nothing limited here
