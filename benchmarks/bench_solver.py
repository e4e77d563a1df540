"""Benchmark of fingerpad's contact solver against tamaas and ContactMechanics.

Run::

    make bench                                              # everything below, default sizes
    .venv/bin/python benchmarks/bench_solver.py --quick     # 256^2/512^2, no peers' 2048^2
    .venv/bin/python benchmarks/bench_solver.py --sections command --grids 1024 --reps 5

Sections (``--sections``, comma-separated; default all):

``command``
    The issue-12 cell: one spherical cap (R 50 um, h 10 um) in a periodic 100 um cell, E* 0.3 MPa,
    tol 1e-8, at ``mid`` = 15 kPa (35 % contact) and ``full`` = 100 kPa (98 %), on 1024^2 and
    2048^2. Timed in the same run:

    * the whole ``fingerpad solve`` command (a child process: interpreter start-up, imports,
      texture, solve, output), median of ``--reps`` runs;
    * the solver alone in this process (median of ``--reps``), with its transforms counted:
      ``pairs/it`` = float64 rfft2+irfft2 pairs per fine iteration (coarse levels weighted by
      their size), ``cost/it`` = solver seconds / (iterations x one float64 pair on that grid),
      the pair timed here before and after the cases;
    * tamaas 2.9 ``PolonskyKeerRey`` (``benchmarks/_peer_tamaas.py``, a child process; model +
      solver construction + solve, imports excluded) and ContactMechanics 1.8
      ``NonSmoothContactSystem.minimize_proxy`` (``benchmarks/_peer_contactmechanics.py``, also
      a child process; system construction + solve). Ratios = peer seconds / fingerpad *command*
      seconds (so fingerpad carries its start-up, the peers do not). Contact fractions are
      compared and every field's residual is evaluated with fingerpad's own KKT criterion.

``sweep``
    Cold solves across contact fractions 1-99 % (``--sweep-grid``), preconditioned (default)
    against the plain Polonsky-Keer iteration (``precondition=False``), with and without the
    coarse-to-fine start: iterations and seconds.

``curve``
    A psi(p) load curve of the same cell, 50 log-spaced pressures 100 Pa - 100 kPa,
    warm-started (``fingerpad.micro.loadcurve.load_curve``): total iterations and seconds, and the
    ratio to one cold solve at 15 kPa.

``maps``
    Measured-like, non-periodic maps (zero-padded Love kernel): a 512^2 AFM-like map (self-affine,
    Hurst 0.8, 20 um, 80 nm rms) and a 200 x 296 optical-profilometer-like map (1.0 x 1.48 mm,
    self-affine plus a tilt, 1.5 um rms), generated with fixed seeds on a larger grid and cut
    (not periodic). Iterations, seconds and cost per iteration in padded float64 pairs,
    preconditioned against plain.

``memory``
    One 4096^2 cell at the mid load in a child process; its peak resident set size (os.wait4).

Output: Markdown tables on stdout, JSON in ``out/bench/solver.json``. Progress on stderr. The
development machine is shared: compare ratios measured in the same run, not seconds.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import scipy

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "solver.json"
FINGERPAD = str(Path(sys.executable).with_name("fingerpad"))

RADIUS, HEIGHT, SPACING = 50e-6, 10e-6, 100e-6  # m
MODULUS = 0.3e6  # Pa, reduced modulus E*
LOADS = {"mid": 15e3, "full": 100e3}  # Pa
TOL = 1e-8
try:  # the previous solver: plain Polonsky-Keer iteration with its compiled loops where Numba imports
    import numba  # noqa: F401

    PREVIOUS: dict[str, Any] = {"precondition": False, "kernels": "numba"}
except ImportError:
    PREVIOUS = {"precondition": False}


def _version(dist: str) -> str | None:
    from importlib.metadata import PackageNotFoundError, version  # noqa: PLC0415

    try:
        return version(dist)
    except PackageNotFoundError:
        return None


def _engine() -> str:
    from fingerpad.contact.greens import Backend  # noqa: PLC0415

    return Backend().fft


FFT_ENGINE = _engine()


def log(msg: str) -> None:
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def cell(grid: int):
    from fingerpad.textures import spherical_caps  # noqa: PLC0415

    return spherical_caps(radius=RADIUS, height=HEIGHT, spacing=SPACING, lattice="square", grid=grid)


def median_time(fn, reps: int) -> tuple[float, Any]:
    times, out = [], None
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def fft_pair(shape: tuple[int, int], reps: int = 7) -> float:
    """Median seconds of one float64 rfft2 + irfft2 pair with the solver's own FFT engine and
    threads (fingerpad.contact.greens.Backend: ducc0 when installed, else SciPy), after warm-up."""
    from fingerpad.contact.greens import Backend  # noqa: PLC0415

    be = Backend()
    a = np.random.default_rng(0).standard_normal(shape)
    for _ in range(2):
        be.irfft2(be.rfft2(a), shape)
    return median_time(lambda: be.irfft2(be.rfft2(a), shape), reps)[0]


@contextlib.contextmanager
def count_transforms(fine_size: int):
    """Count the solver's transforms: float64 ones in fine-grid pairs (weighted by size), float32 apart."""
    from fingerpad.contact import greens  # noqa: PLC0415

    c = {"f64": 0.0, "f32": 0.0}
    init0 = greens.Backend.__init__

    def init(self, *args, **kw):
        init0(self, *args, **kw)
        f0, i0 = self.rfft2, self.irfft2

        def rf(a, s=None):
            size = math.prod(s) if s is not None else a.size
            c["f64" if a.dtype == np.float64 else "f32"] += 0.5 * size / fine_size
            return f0(a, s)

        def irf(a, s):
            c["f64" if a.dtype == np.complex128 else "f32"] += 0.5 * math.prod(s) / fine_size
            return i0(a, s)

        self.rfft2, self.irfft2 = rf, irf

    greens.Backend.__init__ = init
    try:
        yield c
    finally:
        greens.Backend.__init__ = init0


def kkt_residual(tex, pressure: np.ndarray) -> float:
    """fingerpad's primal KKT residual of any pressure field (RMS gap error / PV)."""
    from fingerpad.contact.greens import Backend, compliance_operator  # noqa: PLC0415

    u = compliance_operator(Backend(), tex, MODULUS)(pressure)
    d = u - tex.heights
    contact = pressure > 0
    lam = float(d[contact].mean()) if tex.periodic else 0.0
    g = d - lam
    err = np.where(contact, g, np.minimum(g, 0.0))
    return float(np.sqrt(np.mean(err**2)) / tex.peak_to_valley)


# ----------------------------------------------------------------------------------- fingerpad


def solve_inprocess(tex, p: float, **kw) -> Any:
    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return HalfSpaceSolver(tex, MODULUS, tol=TOL, **kw).solve_pressure(p)


def run_command(grid: int, p: float, fft: str | None = None) -> dict[str, Any]:
    cmd = [FINGERPAD, "solve", "--texture", "caps", "--radius", f"{RADIUS * 1e6:g}um", "--height",
           f"{HEIGHT * 1e6:g}um", "--spacing", f"{SPACING * 1e6:g}um", "--modulus", f"{MODULUS / 1e6:g}MPa",
           "--grid", str(grid), "--pressure", f"{p:g}Pa", "--tol", f"{TOL:g}", "--json", "-"]
    env = dict(os.environ, FINGERPAD_FFT=fft) if fft else None
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, check=False, env=env)
    wall = time.perf_counter() - t0
    if out.returncode != 0:
        raise RuntimeError(f"fingerpad solve failed ({out.returncode}): {out.stderr[-1000:]}")
    r = json.loads(out.stdout)["results"][0]
    return {"wall": wall, "seconds": r["seconds"], "iterations": r["iterations"],
            "contact_fraction": r["contact_fraction"], "converged": r["converged"], "command": " ".join(cmd[1:])}


# ----------------------------------------------------------------------------------- peers


def run_tamaas(tex, pressures: list[float], python: str) -> list[dict[str, Any]]:
    with tempfile.TemporaryDirectory(prefix="fingerpad-tamaas-") as tmp:
        np.save(Path(tmp) / "h.npy", tex.heights)
        job = {"heights": "h.npy", "size": list(tex.size), "modulus": MODULUS, "tol": TOL, "pressures": pressures}
        (Path(tmp) / "job.json").write_text(json.dumps(job))
        out = subprocess.run([python, str(HERE / "_peer_tamaas.py"), str(Path(tmp) / "job.json")],
                             capture_output=True, text=True, check=False)
        if out.returncode != 0:
            raise RuntimeError(f"tamaas worker failed: {out.stderr[-1500:]}")
        # tamaas writes its "iteration cost error" lines to stderr: the last one is the count
        its = [int(ln.split()[0]) for ln in out.stderr.splitlines() if ln.split() and ln.split()[0].isdigit()]
        finals = [its[i] for i in range(len(its)) if i + 1 == len(its) or its[i + 1] == 0]
        rows = []
        for k, line in enumerate(ln for ln in out.stdout.splitlines() if ln.startswith("RESULT ")):
            r = json.loads(line[7:])
            r["iterations"] = finals[k] if k < len(finals) else None
            r["_pressure"] = np.load(Path(tmp) / r.pop("pressure_file"))
            rows.append(r)
        return rows


def tamaas_available(python: str) -> str | None:
    out = subprocess.run([python, str(HERE / "_peer_tamaas.py"), "--versions"], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return json.loads(out.stdout.split("RESULT ", 1)[1]).get("tamaas")


def cm_version(python: str) -> str | None:
    out = subprocess.run([python, str(HERE / "_peer_contactmechanics.py"), "--versions"], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return json.loads(out.stdout.strip().splitlines()[-1]).get("ContactMechanics")


def run_cm(tex, pressures: list[float], python: str) -> list[dict[str, Any]]:
    """ContactMechanics in a child process (its threads and imports stay out of this one)."""
    with tempfile.TemporaryDirectory(prefix="fingerpad-cm-") as tmp:
        np.save(Path(tmp) / "h.npy", tex.heights)
        job = {"heights": "h.npy", "size": list(tex.size), "modulus": MODULUS, "tol": TOL, "pressures": pressures}
        (Path(tmp) / "job.json").write_text(json.dumps(job))
        out = subprocess.run([python, str(HERE / "_peer_contactmechanics.py"), str(Path(tmp) / "job.json")],
                             capture_output=True, text=True, check=False)
        if out.returncode != 0:
            raise RuntimeError(f"ContactMechanics worker failed: {out.stderr[-1500:]}")
        rows = [json.loads(ln) for ln in out.stdout.splitlines() if ln.startswith("{")]
        for r in rows:
            r["_pressure"] = np.load(Path(tmp) / r.pop("pressure_file"))
        return rows


# ----------------------------------------------------------------------------------- sections


def section_command(args, report) -> None:
    cm = None if args.no_cm else cm_version(args.cm_python)
    tm_version = None if args.no_tamaas else tamaas_available(args.tamaas_python)
    report["meta"]["tamaas"] = tm_version
    report["meta"]["ContactMechanics"] = cm
    rows = []
    for g in args.grids:
        tex = cell(g)
        t_fft = [fft_pair(tex.shape)]
        for load in args.loads:
            p = LOADS[load]
            log(f"command {g}^2 {load}: fingerpad solve x{args.reps} ...")
            cmds = [run_command(g, p) for _ in range(args.reps)]
            wall = statistics.median(c["wall"] for c in cmds)
            # the same command where the optional ducc0 is not installed (SciPy's FFT)
            wall_scipy = (statistics.median(run_command(g, p, fft="scipy")["wall"] for _ in range(args.reps))
                          if FFT_ENGINE == "ducc0" else wall)
            solve_s, res = median_time(lambda: solve_inprocess(tex, p), args.reps)
            with count_transforms(tex.heights.size) as cnt:
                solve_inprocess(tex, p)
            if not args.no_previous:
                prev_s, prev = median_time(lambda: solve_inprocess(tex, p, **PREVIOUS), 1)
                row_prev = {"seconds": prev_s, "iterations": prev.iterations, "formulation": prev.formulation,
                            "contact_fraction": prev.contact_fraction}
                log(f"  previous solver (plain Polonsky-Keer): {prev_s:.2f} s, {prev.iterations} it")
            else:
                row_prev = None
            row = {"grid": g, "load": load, "pressure": p, "iterations": res.iterations,
                   "contact_fraction": res.contact_fraction, "converged": res.converged,
                   "residual_ours_metric": kkt_residual(tex, res.pressure), "command_wall": wall,
                   "command_wall_scipy_fft": wall_scipy,
                   "command_walls": [c["wall"] for c in cmds], "command_solver_seconds": [c["seconds"] for c in cmds],
                   "solver_seconds": solve_s, "f64_pairs": cnt["f64"], "f32_pairs": cnt["f32"],
                   "command": cmds[0]["command"], "previous": row_prev}
            log(f"  fingerpad: command {wall:.2f} s (SciPy FFT {wall_scipy:.2f} s), solver {solve_s:.2f} s, {res.iterations} it, "
                f"cf {res.contact_fraction:.5f}, {cnt['f64']:.1f} f64 + {cnt['f32']:.1f} f32 pairs")
            if tm_version and g in args.peer_grids:
                log(f"  tamaas {g}^2 {load} ...")
                q = run_tamaas(tex, [p], args.tamaas_python)[0]
                pq = q.pop("_pressure")
                q["residual_ours_metric"] = kkt_residual(tex, pq)
                row["tamaas"] = q
                log(f"  tamaas: {q['seconds']:.2f} s, {q['iterations']} it, cf {q['contact_fraction']:.5f}")
            if cm and g in args.cm_grids:
                log(f"  ContactMechanics {g}^2 {load} ...")
                q = run_cm(tex, [p], args.cm_python)[0]
                pq = q.pop("_pressure")
                q["residual_ours_metric"] = kkt_residual(tex, pq)
                row["cm"] = q
                log(f"  CM: {q['seconds']:.2f} s, {q['iterations']} it, cf {q['contact_fraction']:.5f}")
            rows.append(row)
        t_fft.append(fft_pair(tex.shape))
        for row in rows:
            if row["grid"] == g:
                row["t_fft"] = statistics.median(t_fft)
                row["cost_per_iteration"] = row["solver_seconds"] / (max(row["iterations"], 1) * row["t_fft"])
                row["f64_pairs_per_iteration"] = row["f64_pairs"] / max(row["iterations"], 1)
    report["command"] = rows


def section_sweep(args, report) -> None:
    g = args.sweep_grid
    tex = cell(g)
    loads = [200.0, 1e3, 5e3, 15e3, 40e3, 100e3, 200e3]
    variants = {"PCG + coarse-to-fine (default)": {}, "PCG, cold": {"coarse_to_fine": False},
                "plain Polonsky-Keer (previous auto)": PREVIOUS}
    rows = []
    for p in loads:
        row = {"grid": g, "pressure": p}
        for name, kw in variants.items():
            s, r = median_time(lambda: solve_inprocess(tex, p, **kw), args.reps)
            row[name] = {"iterations": r.iterations, "seconds": s, "formulation": r.formulation,
                         "contact_fraction": r.contact_fraction, "converged": r.converged}
        log(f"sweep {g}^2 {p:g} Pa: cf {row[next(iter(variants))]['contact_fraction']:.4f} "
            + ", ".join(f"{k.split(' ')[0]}{'' if not v else ''} {row[k]['iterations']} it {row[k]['seconds']:.2f} s"
                        for k, v in variants.items()))
        rows.append(row)
    report["sweep"] = {"variants": list(variants), "rows": rows}


def section_curve(args, report) -> None:
    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415
    from fingerpad.micro.loadcurve import load_curve  # noqa: PLC0415

    g = args.curve_grid
    tex = cell(g)
    pressures = np.geomspace(100.0, 100e3, 50)
    one, r1 = median_time(lambda: solve_inprocess(tex, 15e3), args.reps)

    def curve():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return load_curve(HalfSpaceSolver(tex, MODULUS, tol=TOL), pressures, keep_fields=False)

    secs, c = median_time(curve, max(1, args.reps // 2))
    out = {"grid": g, "points": len(pressures), "seconds": secs, "iterations": int(c.iterations.sum()),
           "max_iterations": int(c.iterations.max()), "all_converged": bool(c.converged.all()),
           "one_solve_seconds": one, "one_solve_iterations": r1.iterations, "ratio_to_one_solve": secs / one}
    if not args.no_previous:
        def curve_prev():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return load_curve(HalfSpaceSolver(tex, MODULUS, tol=TOL, **PREVIOUS), pressures,
                                  keep_fields=False)

        ps, pc = median_time(curve_prev, 1)
        one_p, r1p = median_time(lambda: solve_inprocess(tex, 15e3, **PREVIOUS), 1)
        out["previous"] = {"seconds": ps, "iterations": int(pc.iterations.sum()), "one_solve_seconds": one_p,
                           "one_solve_iterations": r1p.iterations, "all_converged": bool(pc.converged.all())}
        log(f"curve, previous solver: {ps:.2f} s, {out['previous']['iterations']} it")
    log(f"curve {g}^2 x50: {secs:.2f} s, {out['iterations']} it (one cold solve {one:.2f} s, {r1.iterations} it)")
    report["curve"] = out


def rough_map(shape: tuple[int, int], size: tuple[float, float], rms: float, hurst: float, seed: int,
              tilt: float = 0.0):
    """A self-affine map cut from a periodic one twice the size (so it is not periodic)."""
    from fingerpad.textures import Texture  # noqa: PLC0415

    rng = np.random.default_rng(seed)
    nx, ny = 2 * shape[0], 2 * shape[1]
    qx = np.fft.fftfreq(nx)[:, None]
    qy = np.fft.rfftfreq(ny)[None, :]
    q = np.sqrt(qx**2 + (qy * ny / nx) ** 2) * nx
    spec = np.where(q >= 1, np.maximum(q, 1.0) ** (-(1 + hurst)), 0.0)
    noise = rng.standard_normal(spec.shape) + 1j * rng.standard_normal(spec.shape)
    z = np.fft.irfft2(spec * noise, s=(nx, ny))[: shape[0], : shape[1]]
    z = (z - z.mean()) * rms / z.std()
    if tilt:
        z = z + tilt * np.linspace(-0.5, 0.5, shape[0])[:, None] * rms
    return Texture(z - z.min(), size, periodic=False)


def section_maps(args, report) -> None:
    maps = {
        "AFM-like 512x512 (20 um, 80 nm rms, H 0.8)": (rough_map((512, 512), (20e-6, 20e-6), 80e-9, 0.8, 11), 0.05),
        "optical-like 200x296 (1.0 x 1.48 mm, 1.5 um rms, tilt)": (
            rough_map((200, 296), (1.0e-3, 1.48e-3), 1.5e-6, 0.7, 12, tilt=1.0), 0.05),
    }
    rows = []
    for name, (tex, frac) in maps.items():
        # mean pressure scale E* rms slope-ish: a few % of E* PV / L
        p = frac * MODULUS * tex.peak_to_valley / max(tex.size)
        fshape = (2 * tex.shape[0], 2 * tex.shape[1])
        t_pad = fft_pair(fshape)
        row = {"map": name, "shape": list(tex.shape), "pressure": p, "t_fft_padded": t_pad}
        for label, kw in (("preconditioned", {}), ("plain", {"precondition": False})):
            s, r = median_time(lambda: solve_inprocess(tex, p, **kw), args.reps)
            row[label] = {"iterations": r.iterations, "seconds": s, "contact_fraction": r.contact_fraction,
                          "converged": r.converged, "cost_per_iteration": s / (max(r.iterations, 1) * t_pad)}
        log(f"map {name}: cf {row['preconditioned']['contact_fraction']:.4f}, "
            f"PCG {row['preconditioned']['iterations']} it {row['preconditioned']['seconds']:.2f} s, "
            f"plain {row['plain']['iterations']} it {row['plain']['seconds']:.2f} s")
        rows.append(row)
    report["maps"] = rows


def memory_child(grid: int) -> None:
    tex = cell(grid)
    t0 = time.perf_counter()
    r = solve_inprocess(tex, LOADS["mid"])
    print(json.dumps({"iterations": r.iterations, "converged": r.converged, "contact_fraction": r.contact_fraction,
                      "seconds": time.perf_counter() - t0}), flush=True)


def section_memory(args, report) -> None:
    g = args.memory
    cmd = [sys.executable, str(Path(__file__).resolve()), "--_memory-child", str(g)]
    log(f"memory: {g}^2 mid load in a child process ...")
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    stdout = proc.stdout.read()
    proc.stdout.close()
    _, status, usage = os.wait4(proc.pid, 0)
    lines = [ln for ln in stdout.splitlines() if ln.startswith("{")]
    out = {"grid": g, "returncode": os.waitstatus_to_exitcode(status), "peak_rss_gib": usage.ru_maxrss / 2**20,
           "result": json.loads(lines[-1]) if lines else {}}
    log(f"memory: peak RSS {out['peak_rss_gib']:.3f} GiB")
    report["memory"] = out


# ----------------------------------------------------------------------------------- report


def markdown(rep: dict[str, Any]) -> str:
    m = rep["meta"]
    L = ["## fingerpad contact solver benchmark", "",
         f"- {m['date']}, host `{m['host']}`, {m['cpu_count']} cores, load average at start {m['loadavg']}; "
         f"Python {m['python']}, NumPy {m['numpy']}, SciPy {m['scipy']}, FFT engine {m.get('fft')} "
         f"(ducc0 {m.get('ducc0')}); tamaas {m.get('tamaas')}, "
         f"ContactMechanics {m.get('ContactMechanics')}",
         f"- cell: one spherical cap R {RADIUS * 1e6:g} um, h {HEIGHT * 1e6:g} um in a periodic {SPACING * 1e6:g} um cell, "
         f"E* {MODULUS / 1e6:g} MPa, tol {TOL:g}; mid = {LOADS['mid'] / 1e3:g} kPa, full = {LOADS['full'] / 1e3:g} kPa", ""]
    if "command" in rep:
        L += ["### Whole command against the peers", "",
              "| grid | load | iterations | f64 pairs/it | f32 pairs/it | solver s | cost/it | command s | command s, SciPy FFT "
              "| tamaas s (it) | tamaas / command | CM s (it) | CM / command | cf | Δcf tamaas | Δcf CM | residual ours / tamaas / CM |",
              "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for r in rep["command"]:
            t, c = r.get("tamaas"), r.get("cm")
            L.append(
                f"| {r['grid']}² | {r['load']} | {r['iterations']} | {r['f64_pairs_per_iteration']:.2f} "
                f"| {r['f32_pairs'] / max(r['iterations'], 1):.2f} | {r['solver_seconds']:.2f} | {r['cost_per_iteration']:.2f} "
                f"| {r['command_wall']:.2f} | {r.get('command_wall_scipy_fft', float('nan')):.2f} | {t['seconds'] if t else float('nan'):.1f} ({t.get('iterations') if t else '–'}) "
                f"| {t['seconds'] / r['command_wall'] if t else float('nan'):.1f}x "
                f"| {c['seconds'] if c else float('nan'):.1f} ({c.get('iterations') if c else '–'}) "
                f"| {c['seconds'] / r['command_wall'] if c else float('nan'):.1f}x "
                f"| {r['contact_fraction']:.5f} | {t['contact_fraction'] - r['contact_fraction'] if t else float('nan'):+.1e} "
                f"| {c['contact_fraction'] - r['contact_fraction'] if c else float('nan'):+.1e} "
                f"| {r['residual_ours_metric']:.1e} / {t['residual_ours_metric'] if t else float('nan'):.1e} / "
                f"{c['residual_ours_metric'] if c else float('nan'):.1e} |")
        L += ["", "| grid | load | previous solver (plain PK, in-process) s | iterations | this solver s | speed-up |",
              "|---:|---|---:|---:|---:|---:|"]
        for r in rep["command"]:
            q = r.get("previous")
            if q:
                L.append(f"| {r['grid']}² | {r['load']} | {q['seconds']:.2f} | {q['iterations']} | {r['solver_seconds']:.2f} "
                         f"| {q['seconds'] / r['solver_seconds']:.1f}x |")
        L += ["", "f64 pairs/it: float64 rfft2+irfft2 pairs per fine iteration, coarse levels weighted by size; "
              "f32: the single-precision preconditioner and curvature transforms, same units; cost/it = solver "
              "seconds / (iterations x one float64 pair of the solver's FFT engine, timed in the same run); command s: "
              "median wall time of the whole `fingerpad solve` child process (with FINGERPAD_FFT=scipy: where the "
              "optional ducc0 is not installed); ratios use the default command; peers: construction + solve, imports excluded; residual: "
              "RMS gap error / PV of each returned field, by fingerpad's criterion.", ""]
    if "sweep" in rep:
        v = rep["sweep"]["variants"]
        L += [f"### Contact fractions 1-99 % ({rep['sweep']['rows'][0]['grid']}², cold solves)", "",
              "| p (kPa) | contact fraction | " + " | ".join(f"{k}: it, s" for k in v) + " |",
              "|---:|---:|" + "---:|" * len(v)]
        for r in rep["sweep"]["rows"]:
            L.append(f"| {r['pressure'] / 1e3:g} | {r[v[0]]['contact_fraction']:.4f} | "
                     + " | ".join(f"{r[k]['iterations']}, {r[k]['seconds']:.2f}" + ("" if r[k]["converged"] else " (NOT conv.)")
                                  for k in v) + " |")
        L.append("")
    if "curve" in rep:
        c = rep["curve"]
        L += ["### Load curve (warm starts)", "",
              f"{c['points']} pressures 0.1-100 kPa on {c['grid']}²: {c['seconds']:.2f} s, {c['iterations']} iterations in all "
              f"(at most {c['max_iterations']} per point, all converged: {c['all_converged']}); one cold solve at 15 kPa: "
              f"{c['one_solve_seconds']:.2f} s, {c['one_solve_iterations']} iterations; the curve costs "
              f"{c['ratio_to_one_solve']:.1f} cold solves."]
        if c.get("previous"):
            q = c["previous"]
            L += ["", f"Previous solver (plain Polonsky-Keer, `precondition=False`), same curve: {q['seconds']:.2f} s, "
                  f"{q['iterations']} iterations (all converged: {q['all_converged']}); one cold solve "
                  f"{q['one_solve_seconds']:.2f} s, {q['one_solve_iterations']} iterations."]
        L.append("")
    if "maps" in rep:
        L += ["### Measured-like (non-periodic) maps", "",
              "| map | contact fraction | PCG it | PCG s | PCG cost/it | plain it | plain s | plain cost/it |",
              "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for r in rep["maps"]:
            a, b = r["preconditioned"], r["plain"]
            L.append(f"| {r['map']} | {a['contact_fraction']:.4f} | {a['iterations']} | {a['seconds']:.2f} "
                     f"| {a['cost_per_iteration']:.2f} | {b['iterations']} | {b['seconds']:.2f} | {b['cost_per_iteration']:.2f} |")
        L += ["", "cost/it in float64 pairs of the zero-padded (2nx x 2ny) transform.", ""]
    if "memory" in rep:
        mm = rep["memory"]
        L += ["### Memory", "", f"{mm['grid']}² at 15 kPa: peak RSS **{mm['peak_rss_gib']:.2f} GiB** "
              f"(child process, os.wait4), {mm['result'].get('iterations')} iterations, "
              f"converged {mm['result'].get('converged')}, {mm['result'].get('seconds', float('nan')):.1f} s.", ""]
    return "\n".join(L)


#: Issue 23's figure for the whole command against tamaas at 1024^2 (the code before it).
TODAY_TAMAAS_RATIO = 15.9


def issue23_rows(rep: dict[str, Any]) -> list[dict[str, Any]]:
    """The rows of issue 23's table this benchmark measures (read by ``benchmarks/report.py``):
    the whole command against tamaas in the same run, 1024^2."""
    rows = []
    for r in rep.get("command", []):
        t = r.get("tamaas")
        if r["grid"] != 1024 or not t:
            continue
        ratio = t["seconds"] / r["command_wall"]
        rows.append({"row": f"whole `solve` command, 1024² one-cap cell ({r['load']}), against tamaas 2.9 in the same run",
                     "script": "bench_solver.py", "today": f"{TODAY_TAMAAS_RATIO:g}x",
                     "now": f"{ratio:.1f}x (command {r['command_wall']:.2f} s, solver {r['solver_seconds']:.2f} s, "
                            f"tamaas {t['seconds']:.1f} s)",
                     "ratio": ratio, "ratio_of": "tamaas seconds / command seconds, same run", "goal": ">= 25x",
                     "met": ratio >= 25, "load": rep["meta"]["loadavg"]})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sections", default="command,sweep,curve,maps,memory")
    ap.add_argument("--grids", default="1024,2048")
    ap.add_argument("--loads", default="mid,full")
    ap.add_argument("--peer-grids", default=None, help="grids solved by tamaas (default: --grids)")
    ap.add_argument("--cm-grids", default=None, help="grids solved by ContactMechanics (default: --grids)")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--sweep-grid", type=int, default=1024)
    ap.add_argument("--curve-grid", type=int, default=1024)
    ap.add_argument("--memory", type=int, default=4096)
    ap.add_argument("--tamaas-python", default=sys.executable, help="interpreter with tamaas (default: this one)")
    ap.add_argument("--cm-python", default=sys.executable, help="interpreter with ContactMechanics (default: this one)")
    ap.add_argument("--no-tamaas", action="store_true")
    ap.add_argument("--no-cm", action="store_true")
    ap.add_argument("--no-previous", action="store_true",
                    help="skip the previous solver (precondition=False) in the command and curve sections")
    ap.add_argument("--quick", action="store_true", help="256^2/512^2, sweep and curve at 256^2, memory 1024^2")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--_memory-child", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args._memory_child:
        memory_child(args._memory_child)
        return 0
    if args.quick:
        args.grids, args.sweep_grid, args.curve_grid, args.memory = "256,512", 256, 256, 1024
    grids = [int(x) for x in args.grids.split(",") if x]
    args.grids = grids
    args.peer_grids = [int(x) for x in args.peer_grids.split(",")] if args.peer_grids else grids
    args.cm_grids = [int(x) for x in args.cm_grids.split(",")] if args.cm_grids else grids
    args.loads = [x for x in args.loads.split(",") if x]
    for ld in args.loads:
        if ld not in LOADS:
            ap.error(f"unknown load {ld!r}")
    report: dict[str, Any] = {"meta": {
        "date": _dt.datetime.now().isoformat(timespec="seconds"), "host": platform.node(),
        "cpu_count": os.cpu_count(), "loadavg": ", ".join(f"{x:.2f}" for x in os.getloadavg()),
        "python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__, "tol": TOL,
        "fft": FFT_ENGINE, "ducc0": _version("ducc0")}}
    # warm-up: imports, FFT plans and the previous solver's compiled loops (their ~0.5 s cache
    # load), excluded as the peers' imports are
    solve_inprocess(cell(64), LOADS["mid"])
    if not args.no_previous:
        solve_inprocess(cell(64), LOADS["mid"], **PREVIOUS)
        solve_inprocess(cell(64), LOADS["full"], **PREVIOUS)
    sections = [s.strip() for s in args.sections.split(",") if s.strip()]
    if "memory" in sections:  # first: a child's peak RSS, measured before this process grows
        section_memory(args, report)
    for name in ("command", "sweep", "curve", "maps"):
        if name in sections:
            globals()[f"section_{name}"](args, report)
    report["issue23"] = issue23_rows(report)
    text = markdown(report)
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2, default=float) + "\n")
    log(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
