"""The deflection job (micro/deflection/job.py): deterministic results, the time limit as a safety
stop only, stiff textures pressed on, held gains marked, and texture families' deflection hook."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.micro.cache import CurveCache
from fingerpad.micro.deflection.gain import DeflectionSettings, SectionMaterials
from fingerpad.micro.deflection.job import run_deflection
from fingerpad.micro.deflection.section import EllipsoidGeometry
from fingerpad.textures import base as texture_base
from fingerpad.textures.base import Param, Texture, TextureFamily

SOFT = SectionMaterials(0.3e6, 0.49, 0.3e6, 0.49)
ELLIPSOIDS = {"semi_axis_x": "30um", "semi_axis_y": "60um", "height": "30um", "spacing_x": "250um",
              "spacing_y": "250um"}
#: the smallest settings that still shear a section (one level, coarse mesh, no eigenvalues)
TINY = DeflectionSettings(resolution=2, n_pressures=1, mu_max=0.3, check_stability=False)


def _run(settings=TINY, cache=False, materials=SOFT, directions=(0.0,), params=ELLIPSOIDS, texture="ellipsoids",
         pressure=(3e3, 3e3)):
    return run_deflection(texture, params, materials, directions, pressure, tau0=8.1e3, alpha=0.1, settings=settings,
                          cache=cache)


def _entries(folder) -> list:
    return [p for p in folder.rglob("*") if p.is_file()]


def test_a_ramp_cut_by_the_time_limit_is_marked_and_never_cached(tmp_path):
    cut = _run(dataclasses.replace(TINY, time_limit=1e-9), cache=str(tmp_path))
    ramp = cut.curves[0].ramps[0]
    assert ramp.incomplete and cut.incomplete and "INCOMPLETE" in ramp.stopped
    assert ramp.mu_reached < TINY.mu_max
    assert _entries(tmp_path) == []  # nothing stored: a faster machine would have got further
    assert any("INCOMPLETE" in line for line in cut.lines())
    assert cut.document()["incomplete"] is True and cut.document()["gain_table"][0]["incomplete"] is True
    ds = cut.dataset()
    assert int(ds.attrs["incomplete"]) == 1 and float(ds["incomplete"].values[0, 0]) == 1.0
    # the same ramp without the stop is a result: stored under a key that ignores the stop
    full = _run(cache=str(tmp_path))
    assert not full.incomplete and full.curves[0].ramps[0].mu_reached >= TINY.mu_max - 1e-9
    assert len(_entries(tmp_path)) >= 1
    again = _run(dataclasses.replace(TINY, time_limit=1e-9), cache=str(tmp_path))  # read back, complete
    assert not again.incomplete and again.curves[0].cache_key == full.curves[0].cache_key
    assert again.gain_table() == full.gain_table()


def test_deterministic_limits_give_identical_tables():
    settings = dataclasses.replace(TINY, mu_max=1.5, max_steps=3)
    one, two = _run(settings), _run(settings)
    r1, r2 = one.curves[0].ramps[0], two.curves[0].ramps[0]
    assert r1.stopped == r2.stopped == "too many shear steps" and not r1.incomplete
    assert 0 < r1.mu_reached < 1.5
    np.testing.assert_array_equal(r1.mu, r2.mu)
    np.testing.assert_array_equal(r1.gain, r2.gain)
    assert one.gain_table() == two.gain_table()
    assert one.lines() == two.lines()


@pytest.mark.parametrize("modulus", [1e9, 3e9])
def test_stiff_textures_are_pressed_on_and_sheared(modulus):
    """The 1 GPa ellipsoids of the issue never got pressed on (0 deg), 3 GPa in neither direction:
    now both directions run to the shear asked for and the computed gain is 1 to 1e-6."""
    stiff = SectionMaterials(modulus, 0.49, 0.3e6, 0.49)
    params = {"semi_axis_x": "45um", "semi_axis_y": "135um", "height": "90um", "spacing_x": "300um",
              "spacing_y": "300um"}
    res = _run(dataclasses.replace(TINY, resolution=3, mu_max=1.5), materials=stiff, directions=(0.0, 90.0),
               params=params, pressure=(2e3, 2e3))
    for curve in res.curves:
        assert not curve.is_identity
        ramp = curve.ramps[0]
        assert ramp.stopped is None and ramp.mu_reached >= 1.5 - 1e-9
        assert np.all(np.abs(ramp.gain - 1.0) < 1e-6)
        assert ramp.bend_dx[-1] > 0  # it did deflect, by a little
    assert not any(any(row["held"]) for row in res.gain_table())


def test_held_gains_are_marked_in_table_document_and_dataset():
    res = _run()  # mu_max 0.3: G(0.6), G(1), G(1.5) are the value at 0.3, held
    row = res.gain_table()[0]
    assert row["held"] == [False, True, True, True]
    line = next(ln for ln in res.lines() if ln.strip().startswith("3 "))
    assert line.count("*") == 3
    assert any(ln.strip().startswith("* held") for ln in res.lines())
    ds = res.dataset()
    np.testing.assert_array_equal(ds["table_gain_held"].values[0, 0], [0, 1, 1, 1])
    assert float(ds["table_gain"].values[0, 0, 0]) == pytest.approx(row["gain"][0])


def test_the_job_refuses_a_family_without_a_deflection_model_before_solving():
    with pytest.raises(FingerpadError, match="has no deflection model"):
        _run(texture="caps", params={"radius": "50um", "height": "10um", "spacing": "200um"})
    with pytest.raises(FingerpadError, match="overlap"):  # the texture's own check
        _run(params={**ELLIPSOIDS, "semi_axis_x": "200um"})


@pytest.mark.parametrize("settings", [dict(n_pressures=0), dict(n_pressures=2.5), dict(mu_max=-1.0),
                                      dict(mu_max=math.nan), dict(resolution=1), dict(time_limit=-1.0),
                                      dict(time_limit=0.0), dict(time_limit=math.nan), dict(max_steps=0)])
def test_settings_refuse_values_that_make_no_sense(settings):
    with pytest.raises(FingerpadError):
        DeflectionSettings(**settings)


def test_the_time_limit_is_not_part_of_the_key():
    assert DeflectionSettings(time_limit=5.0).key() == DeflectionSettings().key()
    assert DeflectionSettings(max_steps=10).key() != DeflectionSettings().key()


# --- a new compliant family is one file: its generator, its parameters and its deflection hook ---


def _domes(*, radius, height, spacing, grid=None) -> Texture:
    """Round half-ellipsoid domes on a square lattice (a test family)."""
    from fingerpad.errors import FingerpadError as Err

    if 2 * radius > spacing:
        raise Err("domes overlap: 2 radius exceeds the spacing")
    n = 16
    x = (np.arange(n) + 0.5) * spacing / n - spacing / 2
    xx, yy = np.meshgrid(x, x, indexing="ij")
    z = height * np.sqrt(np.maximum(1 - (xx**2 + yy**2) / radius**2, 0.0))
    return Texture(z, (spacing, spacing), periodic=True, name="domes",
                   params={"radius": radius, "height": height, "spacing": spacing}, family="domes")


DOMES = TextureFamily(
    name="domes", generator=_domes, summary="Round domes (test family).",
    params=(Param("radius", "length", "dome radius"), Param("height", "length", "dome height"),
            Param("spacing", "length", "lattice period")),
    deflection=lambda p: EllipsoidGeometry(p["radius"], p["radius"], p["height"], p["spacing"], p["spacing"]),
)


def test_a_new_family_with_a_deflection_hook_runs_through_the_job(monkeypatch):
    monkeypatch.setitem(texture_base._REGISTRY, "domes", DOMES)
    params = {"radius": "30um", "height": "30um", "spacing": "250um"}
    res = _run(texture="domes", params=params, directions=(0.0, 45.0))
    assert res.texture == "domes" and isinstance(res.geometry, EllipsoidGeometry)
    g0, g45 = (c.ramps[0] for c in res.curves)
    assert g0.mu_reached >= TINY.mu_max - 1e-9
    # a round dome on a square lattice: the same section in every direction (period at least 2r)
    assert res.curves[0].section.half_width == pytest.approx(res.curves[1].section.half_width)
    with pytest.raises(FingerpadError, match="domes overlap"):  # the family's own check
        _run(texture="domes", params={**params, "radius": "200um"})


def test_a_buckled_ramp_that_never_carried_shear_has_no_computed_gain():
    """A ramp toward +x from a buckled start first goes to negative shear; stopped there, it was
    read as a ramp toward -x that had reached |mu| (h/a = 3 at 20 kPa printed unmarked gains of
    1.30). The tip was moved toward +x: it reached mu 0, and every gain past it is held."""
    from fingerpad.micro.deflection.gain import GainCurve, PressureRamp

    mu = np.array([0.0, -0.1, -0.25])
    z = np.zeros(3)
    ramp = PressureRamp(2e4, 1.0, mu, np.array([1.0, 1.2, 1.3]), np.array([1.0, 1.2, 1.3]),
                        np.array([0.0, 1e-6, 2e-6]), z, z, z, z, z, math.nan, math.nan, True, "lost convergence")
    assert ramp.mu_reached == 0.0
    curve = GainCurve(np.array([2e4]), [ramp])
    assert float(curve(2e4, 0.3)) == 1.0 and bool(curve.saturated(2e4, 0.3))
    mirrored = dataclasses.replace(ramp, mu=-mu, tip_dx=-ramp.tip_dx)  # the same ramp toward -x
    assert mirrored.mu_reached == 0.0


def test_the_ramps_in_worker_processes_give_the_serial_numbers_bit_for_bit(tmp_path):
    # two sections (across and along) at two levels: six tasks (two normal ramps, four shear
    # ramps) in two processes against all of them in this one; and a section shared by two
    # directions (0 and 180 deg) solved once, without a cache, to the same numbers as alone
    settings = dataclasses.replace(TINY, n_pressures=2)
    serial = run_deflection("ellipsoids", ELLIPSOIDS, SOFT, (0.0, 90.0), (3e3, 6e3), tau0=8.1e3, alpha=0.1,
                            settings=settings, cache=False, workers=1)
    pooled = run_deflection("ellipsoids", ELLIPSOIDS, SOFT, (0.0, 90.0, 180.0), (3e3, 6e3), tau0=8.1e3, alpha=0.1,
                            settings=settings, cache=str(tmp_path), workers=2)
    assert len(pooled.curves[0].ramps) == 2 and pooled.curves[0].ramps[0].mu.size > 3
    for a, b in zip(serial.curves + serial.curves[:1], pooled.curves, strict=True):
        for ra, rb in zip(a.ramps, b.ramps, strict=True):
            for name in ("mu", "gain", "contact_length", "tip_dx", "bend_dx", "min_eigenvalue", "fold_nodes"):
                assert np.array_equal(getattr(ra, name), getattr(rb, name), equal_nan=True), name
            assert ra.stopped == rb.stopped and all(np.array_equal(x, y) for x, y in zip(ra.surfaces, rb.surfaces))
    assert serial.gain_table() == [row for row in pooled.gain_table() if row["direction_deg"] != 180.0]
    # the directions 0 and 180 share their section: one solve, one cache entry per section
    assert pooled.curves[0].cache_key == pooled.curves[2].cache_key
    assert len([p for p in _entries(tmp_path) if p.suffix == ".json"]) == 2


def test_a_thread_beside_the_main_one_keeps_the_pool_and_its_numbers(tmp_path, monkeypatch):
    """A progress bar's refresh thread made every command's ramps serial (issue 23): with another
    thread running, the ramps still go to worker processes, started from a fork server (forking
    a threaded process is unsafe), with the serial numbers bit for bit; off the main thread (a
    Dask task, a server's job) they stay serial."""
    import threading

    from fingerpad.micro.deflection import ramps

    monkeypatch.setenv("FINGERPAD_DEFLECTION_WORKERS", "2")
    settings = dataclasses.replace(TINY, n_pressures=2)
    serial = run_deflection("ellipsoids", ELLIPSOIDS, SOFT, (0.0,), (3e3, 6e3), tau0=8.1e3, alpha=0.1,
                            settings=settings, cache=False, workers=1)
    stop = threading.Event()
    beside = threading.Thread(target=stop.wait, daemon=True)
    beside.start()
    try:
        assert ramps.default_workers(6) == 2
        assert ramps._context().get_start_method() == "forkserver"
        pooled = run_deflection("ellipsoids", ELLIPSOIDS, SOFT, (0.0,), (3e3, 6e3), tau0=8.1e3, alpha=0.1,
                                settings=settings, cache=False)
        off_main: list[int] = []
        worker = threading.Thread(target=lambda: off_main.append(ramps.default_workers(6)))
        worker.start()
        worker.join()
        assert off_main == [1]
    finally:
        stop.set()
        beside.join()
    for ra, rb in zip(serial.curves[0].ramps, pooled.curves[0].ramps, strict=True):
        for name in ("mu", "gain", "contact_length", "tip_dx", "bend_dx"):
            assert np.array_equal(getattr(ra, name), getattr(rb, name), equal_nan=True), name
    assert serial.gain_table() == pooled.gain_table()


def test_the_pool_hands_its_first_free_core_to_the_caller_once():
    """``on_free_core`` (issue 23: ``predict --direction`` imports what writes its outputs there)
    runs once, in this process, when every ramp is taken and a worker waits while another ramp
    still runs; the serial path never calls it, nor does a cached section. Progress counts the
    shear ramps."""
    import os

    from fingerpad.micro.deflection import directional_gains, texture_geometry
    from fingerpad.textures import ellipsoids

    geometry = texture_geometry(ellipsoids(**ELLIPSOIDS, grid=128))
    settings = dataclasses.replace(TINY, n_pressures=2)
    for workers in (2, 1):
        messages: list[str] = []
        calls: list[tuple[int, str]] = []
        curves = directional_gains(geometry, SOFT, (0.0, 90.0), (3e3, 6e3), tau0=8.1e3, alpha=0.1, settings=settings,
                                   cache=False, workers=workers, progress=messages.append,
                                   on_free_core=lambda: calls.append((os.getpid(), messages[-1])))
        assert len(curves) == 2 and all(len(c.ramps) == 2 for c in curves)
        if workers == 1:
            assert calls == []
            continue
        done = [m for m in messages if m.startswith("shear ramp ")]
        assert [m.split()[2] for m in done] == ["1/4", "2/4", "3/4", "4/4"]
        # once, here, when the third of four ramps ended on two workers (the fourth may have
        # ended with it: the ramps are counted one by one)
        assert calls == [(os.getpid(), done[2])]
