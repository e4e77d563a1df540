"""Benchmark of fingerpad's periodic contact solver (``fingerpad.contact.HalfSpaceSolver``).

Run::

    make bench                                   # = .venv/bin/python benchmarks/bench_solver.py
    .venv/bin/python benchmarks/bench_solver.py --quick                 # 256², 512² only
    .venv/bin/python benchmarks/bench_solver.py --grids 256,512,1024 \\
        --peer-python /tmp/tv/bin/python --peer-grids 512,1024 --memory 4096

What is measured
----------------
A square lattice of spherical caps (radius 50 µm, cap height 10 µm, spacing 150 µm, i.e. a
150 µm x 150 µm periodic cell with one cap of base radius 30 µm, 12.6 % of the cell) pressed by
an elastic half-space of contact modulus E* = 1 MPa, on grids 256² ... 2048², at two mean
pressures fixed once for all grids (calibrated at 128²/256²; re-run with ``--calibrate``):

* ``mid``  = 19 kPa: contact fraction ~0.31 (the skin touches the caps *and* the flat base
  around them: the "transition" state, the hardest regime for the primal method);
* ``full`` = 200 kPa: contact fraction ~0.974 (near full contact; only small pockets at the
  cap feet stay open).

Both solvers are cold-started (no initial solution). Per case the table lists the formulation
that produced the answer (``auto`` mode), fine-grid iterations (the solver's coarse-grid solves --
the formulation probe and the coarse-to-fine levels -- are *not* counted in ``iterations`` but
*are* in the seconds; a primal run that
stalls and hands over to the dual counts both), solve seconds (``ContactResult.seconds``), the
wall time including the solver's construction, contact fraction, convergence flag and final
residual, and ``cost/it = seconds / (iterations * t_fft)``, where ``t_fft`` is the time of one
``scipy.fft.rfft2`` + ``irfft2`` pair with ``workers=os.cpu_count()`` on that grid, measured in
the same run (median of repetitions taken after a warm-up, before and after the grid's cases).
An ideal settled CCG iteration costs one FFT pair plus a few O(N) array passes, so cost/it is
a machine-independent measure of the per-iteration overhead (and of the coarse-grid share).

Convergence criterion (see the module docstring of ``fingerpad/contact/solver.py``): the relative
KKT residual, i.e. the RMS over the cell of the projected gradient -- gap error in contact and
overlap elsewhere for the primal (divided by the texture's peak-to-valley height), pressure
error off contact and tension in contact for the dual (divided by the mean pressure) -- must
fall below ``tol`` (default 1e-8, the solver default).

Comparison with ContactMechanics (optional)
-------------------------------------------
The same cells are solved with ContactMechanics' Polonsky-Keer constrained conjugate gradient
(``NonSmoothContactSystem.minimize_proxy(external_force=mean_pressure * Lx * Ly, ...)``) for the
same total force, with tolerances matched to ``tol`` (``pentol = tol * PV``,
``forcetol = tol * mean_pressure * pixel_area``; see ``benchmarks/_peer_contactmechanics.py``
for the unit and sign conventions). Reported: its seconds (system construction + solve), the
speed ratio CM/fingerpad (fingerpad also timed including its construction) and the difference
of the contact fractions. Two routes:

1. in-process: when ``import ContactMechanics`` works in the benchmark's interpreter, the peer
   worker's ``solve_case`` is called directly;
2. another interpreter: ``--peer-python /path/to/python`` (or the environment variable
   ``FINGERPAD_BENCH_PEER_PYTHON``) runs ``benchmarks/_peer_contactmechanics.py`` there via
   ``subprocess``; the heights travel as a ``.npy`` in a temporary directory and the results
   come back as JSON lines. Interpreter start-up and imports are excluded from its timing.

``--peer-python`` takes precedence over the in-process route. Without either the comparison is
skipped with a message. By default the peer solves the grids up to 1024² (``--peer-grids``).

Memory
------
``--memory 4096`` solves one 4096² cell at the mid load in a child process and reports the
child's peak resident set size (``os.wait4`` rusage of that child, cross-checked with
``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``, which covers all children waited for; the
memory run is done first so both agree). Target: < 4 GiB. If the default (coarse-to-fine)
solve fails, the failure is reported and the run is repeated with ``coarse_to_fine=False``
(``--memory-no-fallback`` to skip that); ``--memory-max-iter`` caps its iterations (the arrays
are all allocated in the first iterations, but a capped, unconverged primal solve hands over to
the dual, whose arrays then add up: a capped run is an upper estimate rather than the real
path); ``--memory-load full`` measures the near-full-contact (dual) path instead.

Output
------
Markdown tables on stdout; the same data as JSON in ``out/bench/solver.json`` (relative to
the repository root, outside version control; ``--out`` to change). Progress lines go to
stderr. Timings on a shared machine are noisy: compare the within-run ratios, not the seconds.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import inspect
import json
import os
import platform
import resource
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
import scipy.fft as sfft

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "solver.json"

RADIUS = 50e-6  # m
HEIGHT = 10e-6  # m
SPACING = 150e-6  # m
MODULUS = 1e6  # Pa, contact modulus E*
#: Mean pressures (Pa), found once with ``--calibrate`` at 128²/256² and reused on every grid.
LOADS = {"mid": 19e3, "full": 2e5}
TOL = 1e-8
PEER_ENV = "FINGERPAD_BENCH_PEER_PYTHON"


def log(msg: str) -> None:
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def texture(grid: int):
    from fingerpad.textures import spherical_caps  # noqa: PLC0415

    return spherical_caps(radius=RADIUS, height=HEIGHT, spacing=SPACING, lattice="square", grid=grid)


# ---------------------------------------------------------------------------------- FFT timing


def fft_pair_samples(n: int, reps: int, warmup: int = 2) -> list[float]:
    """Times of one rfft2 + irfft2 pair on an (n, n) float64 array, workers=os.cpu_count()."""
    w = os.cpu_count() or 1
    a = np.random.default_rng(0).standard_normal((n, n))
    for _ in range(warmup):
        sfft.irfft2(sfft.rfft2(a, workers=w), s=a.shape, workers=w)
    out = []
    for _ in range(reps):
        t0 = time.perf_counter()
        sfft.irfft2(sfft.rfft2(a, workers=w), s=a.shape, workers=w)
        out.append(time.perf_counter() - t0)
    return out


# ---------------------------------------------------------------------------------- our solver


def solve_ours(tex, mean_pressure: float, tol: float, max_iter: int, coarse_to_fine: bool = True) -> dict[str, Any]:
    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        solver = HalfSpaceSolver(tex, MODULUS, tol=tol, max_iter=max_iter, coarse_to_fine=coarse_to_fine)
        res = solver.solve_pressure(mean_pressure)
        wall = time.perf_counter() - t0
    return {
        "kernels": type(getattr(solver, "_kern", None)).__name__ if hasattr(solver, "_kern") else "n/a",
        "formulation": res.formulation,
        "iterations": int(res.iterations),
        "converged": bool(res.converged),
        "residual": float(res.residual),
        "contact_fraction": float(res.contact_fraction),
        "contact_state": res.contact_state,
        "mean_pressure_out": float(res.mean_pressure),
        "seconds": float(res.seconds),
        "wall_seconds": wall,
        "warnings": [str(w.message) for w in caught],
        "_pressure": res.pressure,
    }


# ---------------------------------------------------------------------------------- peer


class Peer:
    """ContactMechanics, in-process or in another interpreter; ``None``-like when unavailable."""

    def __init__(self, python: str | None) -> None:
        self.python = python
        self.mode = None
        self.info: dict[str, Any] = {}
        self.reason = ""
        if python:
            try:
                out = subprocess.run(
                    [python, str(HERE / "_peer_contactmechanics.py"), "--versions"],
                    capture_output=True, text=True, timeout=300, check=True,
                )
                self.info = json.loads(out.stdout.strip().splitlines()[-1])
                self.mode = "subprocess"
            except (OSError, subprocess.SubprocessError, ValueError, IndexError) as exc:
                detail = getattr(exc, "stderr", "") or ""
                self.reason = f"peer interpreter {python!r} cannot run ContactMechanics: {exc} {detail[-500:]}"
            return
        try:
            import ContactMechanics  # noqa: F401, PLC0415

            sys.path.insert(0, str(HERE))
            import _peer_contactmechanics as pcm  # noqa: PLC0415

            self._pcm = pcm
            self.info = pcm.versions()
            self.mode = "in-process"
        except ImportError as exc:
            self.reason = (
                f"ContactMechanics is not importable here ({exc}); pass --peer-python PATH "
                f"(or set {PEER_ENV}) to use an interpreter that has it"
            )

    def solve(self, heights: np.ndarray, size: tuple[float, float], pressures: list[float], tol: float) -> list[dict]:
        if self.mode == "in-process":
            return [self._pcm.solve_case(heights, size, MODULUS, p, tol, keep_pressure=True) for p in pressures]
        with tempfile.TemporaryDirectory(prefix="fingerpad-peer-") as tmp:
            np.save(Path(tmp) / "heights.npy", heights)
            job = {"heights": "heights.npy", "size": list(size), "modulus": MODULUS, "tol": tol,
                   "pressures": list(pressures)}
            (Path(tmp) / "job.json").write_text(json.dumps(job))
            t0 = time.perf_counter()
            out = subprocess.run(
                [self.python, str(HERE / "_peer_contactmechanics.py"), str(Path(tmp) / "job.json")],
                capture_output=True, text=True, check=False,
            )
            total = time.perf_counter() - t0
            if out.returncode != 0:
                raise RuntimeError(f"peer worker failed (rc {out.returncode}): {out.stderr[-2000:]}")
            rows = [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
            for r in rows:
                r["_pressure"] = np.load(Path(tmp) / r.pop("pressure_file"))
        for r in rows:
            r["process_seconds"] = total  # whole subprocess incl. start-up and imports, all loads
        return rows


# ---------------------------------------------------------------------------------- memory


def memory_child(grid: int, load: str, tol: float, max_iter: int, coarse_to_fine: bool) -> None:
    tex = texture(grid)
    r = solve_ours(tex, LOADS[load], tol, max_iter, coarse_to_fine=coarse_to_fine)
    r.pop("_pressure")
    print(json.dumps(r), flush=True)


def memory_run(grid: int, tol: float, max_iter: int, coarse_to_fine: bool = True, load: str = "mid") -> dict[str, Any]:
    """One solve of a grid² cell in a child process; its peak RSS from os.wait4."""
    cmd = [sys.executable, str(Path(__file__).resolve()), "--_memory-child", str(grid),
           "--memory-load", load, "--tol", repr(tol), "--max-iter", str(max_iter)]
    if not coarse_to_fine:
        cmd.append("--_no-c2f")
    t0 = time.perf_counter()
    with tempfile.TemporaryFile(mode="w+") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True)
        stdout = proc.stdout.read()
        proc.stdout.close()
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        stderr = err.read()
    wall = time.perf_counter() - t0
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss  # KiB on Linux
    lines = [ln for ln in stdout.splitlines() if ln.startswith("{")]
    result = json.loads(lines[-1]) if lines else {}
    peak_kib = usage.ru_maxrss
    out = {
        "grid": grid,
        "load": load,
        "mean_pressure": LOADS[load],
        "coarse_to_fine": coarse_to_fine,
        "max_iter": max_iter,
        "returncode": proc.returncode,
        "peak_rss_bytes": peak_kib * 1024,
        "peak_rss_gib": peak_kib / 2**20,
        "rusage_children_maxrss_gib": children / 2**20,
        "target_gib": 4.0,
        "within_target": peak_kib / 2**20 < 4.0,
        "process_wall_seconds": wall,
        "result": result,
    }
    if proc.returncode != 0:
        out["within_target"] = None
        tail = [ln for ln in stderr.strip().splitlines() if ln.strip()]
        out["error"] = tail[-1] if tail else f"exit code {proc.returncode}"
        out["stderr_tail"] = stderr[-3000:]
    return out


# ---------------------------------------------------------------------------------- calibration


def calibrate(grids: list[int], tol: float) -> None:
    """Contact fraction against mean pressure (scan), to choose the two loads."""
    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415

    print("| grid | p (kPa) | contact fraction | state | formulation | iterations |")
    print("|---:|---:|---:|---|---|---:|")
    for g in grids:
        s = HalfSpaceSolver(texture(g), MODULUS, tol=tol)
        for p in (5e3, 1e4, 1.5e4, 1.7e4, 1.8e4, 1.9e4, 2e4, 3e4, 5e4, 1e5, 1.5e5, 2e5, 3e5):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = s.solve_pressure(p)
            print(f"| {g} | {p / 1e3:g} | {r.contact_fraction:.4f} | {r.contact_state} | "
                  f"{r.formulation} | {r.iterations} |", flush=True)


# ---------------------------------------------------------------------------------- report


def fmt(x: Any, spec: str = ".3g") -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "**NO**"
    if isinstance(x, float):
        return format(x, spec)
    return str(x)


def markdown(report: dict[str, Any]) -> str:
    m = report["meta"]
    lines = [
        "## fingerpad HalfSpaceSolver benchmark",
        "",
        f"- {m['date']}, host `{m['host']}`, os.cpu_count() = **{m['cpu_count']}**, load average at "
        f"start {m['loadavg_start']}, Python {m['python']}, NumPy {m['numpy']}, SciPy {m['scipy']}",
        f"- cell: square lattice of spherical caps, radius {RADIUS * 1e6:g} µm, height {HEIGHT * 1e6:g} µm, "
        f"spacing {SPACING * 1e6:g} µm (periodic {SPACING * 1e6:g} µm cell); E* = {MODULUS / 1e6:g} MPa",
        f"- loads (fixed for all grids): mid = {LOADS['mid'] / 1e3:g} kPa, full = {LOADS['full'] / 1e3:g} kPa",
        f"- convergence: relative KKT residual < tol = {m['tol']:g} (RMS projected gradient / peak-to-valley "
        "height for the primal, / mean pressure for the dual); cold starts, coarse-to-fine on",
        "- `cost/it` = solve seconds / (fine-grid iterations × t_fft); t_fft = one scipy.fft rfft2+irfft2 "
        "pair, workers=os.cpu_count(), median in this run. Coarse-grid solves (formulation probe, "
        "coarse-to-fine levels) are in the seconds, not in the iterations.",
        f"- one-off warm-up before the cases (imports, FFT plans, compiled kernels): "
        f"{m.get('warmup_seconds', float('nan')):.1f} s, not in any case's time",
        "",
        "| grid | load | p (kPa) | formulation | iterations | converged | residual | contact fraction | state "
        "| solve s | wall s (incl. setup) | t_fft ms | cost/it | kernels |",
        "|---:|---|---:|---|---:|---|---:|---:|---|---:|---:|---:|---:|---|",
    ]
    for c in report["cases"]:
        lines.append(
            f"| {c['grid']}² | {c['load']} | {c['mean_pressure'] / 1e3:g} | {c['formulation']} | {c['iterations']} "
            f"| {fmt(c['converged'])} | {c['residual']:.2g} | {c['contact_fraction']:.5f} | {c['contact_state']} "
            f"| {c['seconds']:.3g} | {c['wall_seconds']:.3g} | {c['t_fft'] * 1e3:.3g} | {c['cost_per_iteration']:.3g} "
            f"| {c.get('kernels', 'n/a')} |"
        )
    abl = [c for c in report["cases"] if c.get("no_c2f")]
    if abl:
        lines += [
            "",
            "### Diagnostic: coarse-to-fine off (`coarse_to_fine=False`, same tol, cold start)",
            "",
            "`coarse_to_fine=False` also drops the solver's coarse-grid solves (formulation probe, "
            "coarse-to-fine start), so `auto` starts with the primal and hands over only on a stall.",
            "",
            "| grid | load | c2f on: formulation, iterations, s | c2f off: formulation, iterations, s "
            "| c2f off cost/it | speed-up from turning c2f off | Δcf |",
            "|---:|---|---|---|---:|---:|---:|",
        ]
        for c in abl:
            a = c["no_c2f"]
            lines.append(
                f"| {c['grid']}² | {c['load']} | {c['formulation']}, {c['iterations']}, {c['seconds']:.3g} "
                f"| {a['formulation']}, {a['iterations']}, {a['seconds']:.3g}{'' if a['converged'] else ' (NOT converged)'} "
                f"| {a['seconds'] / (max(a['iterations'], 1) * c['t_fft']):.3g} | {c['seconds'] / a['seconds']:.3g} "
                f"| {a['contact_fraction'] - c['contact_fraction']:+.1e} |"
            )
    p = report["peer"]
    lines.append("")
    lines.append("### ContactMechanics comparison")
    lines.append("")
    if p.get("mode") is None:
        lines.append(f"Skipped: {p.get('reason', 'not requested')}")
    else:
        info = p.get("info", {})
        lines += [
            f"- route: {p['mode']}; ContactMechanics {info.get('ContactMechanics')}, SurfaceTopography "
            f"{info.get('SurfaceTopography')}, NumPy {info.get('numpy')} ({info.get('executable', '')})",
            "- CM solver: `NonSmoothContactSystem.minimize_proxy` (Polonsky-Keer CCG), external_force = p·Lx·Ly; "
            f"tolerances matched to tol = {m['tol']:g}: pentol = tol·PV, forcetol = tol·p·pixel area "
            "(absolute max-norm criteria, so CM's stop is at least as strict as ours)",
            "- seconds on both sides include the construction of the solver/system (not texture generation, "
            "imports or interpreter start-up); speed ratio = CM s / fingerpad s (> 1: fingerpad faster)",
            "",
            "| grid | load | fingerpad s | CM s | CM / fingerpad | CM iterations | CM converged "
            "| cf fingerpad | cf CM | Δcf | pressure-field rel. diff |",
            "|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|",
        ]
        for c in report["cases"]:
            q = c.get("peer")
            if not q:
                continue
            lines.append(
                f"| {c['grid']}² | {c['load']} | {c['wall_seconds']:.3g} | {q['seconds']:.3g} "
                f"| {q['speed_ratio']:.3g} | {q['iterations']} | {fmt(q['converged'])} "
                f"| {c['contact_fraction']:.5f} | {q['contact_fraction']:.5f} | {q['delta_contact_fraction']:+.1e} "
                f"| {fmt(q.get('pressure_rel_diff'), '.1e')} |"
            )
        v = p.get("verification")
        if v:
            lines += [
                "",
                f"Verification ({v['grid']}² {v['load']}, matching tol {m['tol']:g}): |Δcf| = "
                f"{v['abs_delta_contact_fraction']:.1e} ({v['pixels']} pixels) → "
                f"{'agrees to ≤ 1e-4' if v['agrees'] else '**differs by more than 1e-4**'}",
            ]
    runs = report.get("memory")
    lines += ["", "### Memory", ""]
    if not runs:
        lines.append("Not run (use `--memory 4096`).")
    else:
        lines += [
            "| grid | load | coarse_to_fine | peak RSS (GiB) | target | within | outcome | iterations (cap) "
            "| converged | contact fraction | solve s |",
            "|---:|---|---|---:|---:|---|---|---:|---|---:|---:|",
        ]
        for mem in runs:
            r = mem.get("result", {})
            outcome = f"**FAILED**: {mem['error']}" if "error" in mem else "ok"
            lines.append(
                f"| {mem['grid']}² | {mem.get('load', 'mid')} ({mem['mean_pressure'] / 1e3:g} kPa) | {mem['coarse_to_fine']} "
                f"| {mem['peak_rss_gib']:.3f} | < 4 | {fmt(mem['within_target'])} | {outcome} "
                f"| {r.get('iterations', '–')} ({mem['max_iter']}) | {fmt(r.get('converged'))} "
                f"| {fmt(r.get('contact_fraction'), '.5f')} | {fmt(r.get('seconds'), '.3g')} |"
            )
        lines += [
            "",
            "Peak RSS of each child from os.wait4; getrusage(RUSAGE_CHILDREN).ru_maxrss after the last run = "
            f"{runs[-1]['rusage_children_maxrss_gib']:.3f} GiB (maximum over all children); child wall times "
            + ", ".join(f"{m['process_wall_seconds']:.3g} s" for m in runs) + " (incl. start-up).",
        ]
    return "\n".join(lines)


# ---------------------------------------------------------------------------------- main


def parse_grids(s: str) -> list[int]:
    return [int(x) for x in s.split(",") if x.strip()]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grids", type=parse_grids, default=[256, 512, 1024, 2048], help="comma-separated grid sizes")
    ap.add_argument("--quick", action="store_true", help="grids 256,512 only")
    ap.add_argument("--loads", default="mid,full", help="subset of: mid,full")
    ap.add_argument("--tol", type=float, default=TOL)
    ap.add_argument("--max-iter", type=int, default=5000)
    ap.add_argument("--fft-reps", type=int, default=7, help="FFT-pair repetitions per measurement")
    ap.add_argument("--peer-python", default=os.environ.get(PEER_ENV),
                    help=f"interpreter with ContactMechanics (default: ${PEER_ENV}, else try importing it here)")
    ap.add_argument("--peer-grids", type=parse_grids, default=None,
                    help="grids solved with ContactMechanics too (default: the benchmark grids up to 1024)")
    ap.add_argument("--no-peer", action="store_true", help="skip the ContactMechanics comparison")
    ap.add_argument("--memory", type=int, default=None, metavar="N", help="peak-RSS run of one N² cell (mid load)")
    ap.add_argument("--memory-max-iter", type=int, default=None,
                    help="iteration cap of the memory run (default: --max-iter); a capped primal hands over to the dual, so the peak is then an upper estimate")
    ap.add_argument("--ablate-c2f", action="store_true",
                    help="also solve every case with coarse_to_fine=False (diagnostic table)")
    ap.add_argument("--calibrate", action="store_true", help="print contact fraction vs pressure at 128², 256² and exit")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--memory-load", choices=sorted(LOADS), default="mid", help="load of the memory run")
    ap.add_argument("--memory-no-fallback", action="store_true",
                    help="do not retry a failed memory run with coarse_to_fine=False")
    ap.add_argument("--_memory-child", type=int, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--_no-c2f", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)

    if args._memory_child:
        memory_child(args._memory_child, args.memory_load, args.tol, args.max_iter, not args._no_c2f)
        return 0
    if args.calibrate:
        calibrate([128, 256], args.tol)
        return 0

    grids = [256, 512] if args.quick else args.grids
    loads = [x.strip() for x in args.loads.split(",") if x.strip()]
    for ld in loads:
        if ld not in LOADS:
            ap.error(f"unknown load {ld!r}")
    peer_grids = args.peer_grids if args.peer_grids is not None else [g for g in grids if g <= 1024]

    report: dict[str, Any] = {
        "meta": {
            "date": _dt.datetime.now().isoformat(timespec="seconds"),
            "host": platform.node(),
            "platform": platform.platform(),
            "cpu_count": os.cpu_count(),
            "loadavg_start": ", ".join(f"{x:.2f}" for x in os.getloadavg()),
            "python": platform.python_version(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "tol": args.tol,
            "max_iter": args.max_iter,
            "criterion": "relative KKT residual (RMS projected gradient / PV for primal, / mean pressure for dual)",
            "texture": {"kind": "spherical_caps", "lattice": "square", "radius": RADIUS, "height": HEIGHT,
                        "spacing": SPACING},
            "modulus": MODULUS,
            "loads": {k: LOADS[k] for k in loads},
            "fft": "scipy.fft rfft2+irfft2, workers=os.cpu_count(), median of repetitions after warm-up",
        },
        "cases": [],
        "peer": {},
        "memory": None,
    }
    log(f"os.cpu_count() = {os.cpu_count()}, grids {grids}, loads {loads}, tol {args.tol:g}")

    # Memory first: RUSAGE_CHILDREN is the maximum over every child waited for so far.
    if args.memory:
        cap = args.memory_max_iter or args.max_iter
        runs = []
        for c2f in (True, False):
            log(f"memory run: {args.memory}² at {LOADS[args.memory_load] / 1e3:g} kPa, coarse_to_fine={c2f}, "
                f"max_iter={cap}, in a child process ...")
            mem = memory_run(args.memory, args.tol, cap, coarse_to_fine=c2f, load=args.memory_load)
            runs.append(mem)
            log(f"memory run done: peak RSS {mem['peak_rss_gib']:.3f} GiB, "
                f"{mem['result'].get('iterations')} iterations, {mem['process_wall_seconds']:.1f} s"
                + (f"; FAILED: {mem['error']}" if "error" in mem else ""))
            if "error" not in mem or args.memory_no_fallback:
                break
        report["memory"] = runs

    peer = Peer(None) if args.no_peer else Peer(args.peer_python)
    if args.no_peer:
        peer.mode, peer.reason = None, "--no-peer"
    report["peer"] = {"mode": peer.mode, "reason": peer.reason, "info": peer.info, "grids": peer_grids}
    if peer.mode is None:
        log(f"ContactMechanics comparison skipped: {peer.reason}")
    else:
        log(f"ContactMechanics comparison: {peer.mode} route, grids {peer_grids}")

    # Warm-up: imports, FFT plans, the solver's code paths and (where the solver has them) its
    # compiled kernels, loaded once per process: one-off costs excluded from the cases, as the
    # peer's imports are.
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(sys.stderr):
        solve_ours(texture(64), LOADS["mid"], args.tol, args.max_iter)
        from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415

        if "kernels" in inspect.signature(HalfSpaceSolver).parameters:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                for ld in loads:
                    try:
                        HalfSpaceSolver(texture(64), MODULUS, tol=args.tol, kernels="numba").solve_pressure(LOADS[ld])
                    except Exception as exc:  # noqa: BLE001 - no Numba: nothing to warm up
                        log(f"warm-up of compiled kernels skipped: {exc}")
                        break
    report["meta"]["warmup_seconds"] = time.perf_counter() - t0
    log(f"warm-up (imports, FFT plans, compiled kernels) {report['meta']['warmup_seconds']:.1f} s")

    for g in grids:
        tex = texture(g)
        samples = fft_pair_samples(g, args.fft_reps)
        rows = []
        for ld in loads:
            p = LOADS[ld]
            r = solve_ours(tex, p, args.tol, args.max_iter)
            rows.append((ld, p, r))
            log(f"{g}² {ld} ({p / 1e3:g} kPa): {r['formulation']}, {r['iterations']} it, "
                f"converged={r['converged']}, cf={r['contact_fraction']:.5f}, {r['seconds']:.2f} s "
                f"(wall {r['wall_seconds']:.2f} s)")
            if args.ablate_c2f:
                a = solve_ours(tex, p, args.tol, args.max_iter, coarse_to_fine=False)
                a.pop("_pressure")
                r["no_c2f"] = a
                log(f"{g}² {ld} coarse_to_fine=False: {a['formulation']}, {a['iterations']} it, "
                    f"converged={a['converged']}, cf={a['contact_fraction']:.5f}, {a['seconds']:.2f} s")
        peer_rows = None
        if peer.mode is not None and g in peer_grids:
            try:
                peer_rows = peer.solve(tex.heights, tuple(tex.size), [p for _, p, _ in rows], args.tol)
                for (ld, _, _), q in zip(rows, peer_rows):
                    log(f"{g}² {ld} ContactMechanics: {q['iterations']} it, converged={q['converged']}, "
                        f"cf={q['contact_fraction']:.5f}, {q['seconds']:.2f} s")
            except Exception as exc:  # noqa: BLE001 - report and continue
                log(f"ContactMechanics failed on {g}²: {exc}")
                report["peer"].setdefault("errors", []).append(f"{g}: {exc}")
        samples += fft_pair_samples(g, args.fft_reps)
        t_fft = statistics.median(samples)
        log(f"{g}² t_fft = {t_fft * 1e3:.3g} ms (median of {len(samples)}; min {min(samples) * 1e3:.3g}, "
            f"max {max(samples) * 1e3:.3g})")
        for i, (ld, p, r) in enumerate(rows):
            pressure = r.pop("_pressure")
            case = {"grid": g, "load": ld, "mean_pressure": p, **r, "t_fft": t_fft,
                    "t_fft_samples": samples,
                    "cost_per_iteration": r["seconds"] / (max(r["iterations"], 1) * t_fft)}
            if peer_rows is not None and i < len(peer_rows):
                q = dict(peer_rows[i])
                pq = q.pop("_pressure", None)
                if pq is not None:
                    q["pressure_rel_diff"] = float(np.linalg.norm(pq - pressure) / np.linalg.norm(pressure))
                q["speed_ratio"] = q["seconds"] / r["wall_seconds"]
                q["delta_contact_fraction"] = q["contact_fraction"] - r["contact_fraction"]
                case["peer"] = q
            report["cases"].append(case)
            del pressure

    # Verification: the first mid-load case solved by both (else any compared case).
    compared = [c for c in report["cases"] if c.get("peer")]
    if compared:
        v = next((c for c in compared if c["load"] == "mid"), compared[0])
        d = abs(v["peer"]["delta_contact_fraction"])
        report["peer"]["verification"] = {
            "grid": v["grid"], "load": v["load"], "tol": args.tol, "abs_delta_contact_fraction": d,
            "pixels": round(d * v["grid"] ** 2), "agrees": d <= 1e-4,
        }

    text = markdown(report)
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2, default=float) + "\n")
    log(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
