"""Is a pulled-in transition's extrapolation right beyond the texture it was measured on?
(docs/model.md 6.6.1, "The pulled-in transition on other textures").

For each case (a texture generated at every grid, the default finger's skin on PE and a work of
adhesion whose base is pulled in on coarse grids,
:attr:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.pulled_in`; the exponential law at the
resolved range, the cells a prediction prepares):

* the grid's own transition on each grid, and whether it was pulled in;
* the least-squares fit ``p* + a dx^q1 + b dx^q2`` of the four finest pulled-in grids for every
  pair of orders from {1/2, 1, 3/2, 2, 3} (one degree of freedom: the residual says how well the
  pair fits), the assumed pair (1, 3/2) and the three best;
* the transition a prediction reports at each grid and its estimate
  (:func:`fingerpad.micro.pull_in.extrapolated_states` from the grid, its half, quarter and
  eighth; where the grid was not pulled in, its own with the adhesive cell's estimate, the change
  from the half grid over ``2^(1/2) - 1``), which rule made it, and how far it lies from the
  reference: the transition reported on the finest grid given (beyond those a prediction takes),
  and, for Johnson's adhesive sinusoid, from the closed form (the maximum of
  ``p / p* = sin^2(pi a / lambda) - alpha sqrt(tan(pi a / lambda))``, where it jumps into full
  contact).

    python benchmarks/pull_in_orders.py [--cases caps-w0.3,sinusoid-0.3,...] [--grids 32,64,128,256]
                                        [--out out/bench/pull_in_orders.json]

Cells are cached in the unit-cell cache (``FINGERPAD_CACHE``): a second run reads them. Grids 32
to 256 of the five caps cases take some 10 min of CPU; a grid 512 of a hexagonal cell 20-40 min.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import time
import warnings
from pathlib import Path

import numpy as np

ORDERS = (0.5, 1.0, 1.5, 2.0, 3.0)
ASSUMED = (1.0, 1.5)
#: The default finger on PE: skin 0.3 MPa / 0.49 on 0.5 GPa / 0.4.
SKIN = (0.3e6, 0.49, 0.5e9, 0.4)


def johnson_limit(alpha: float, pstar: float) -> float:
    """The pressure (Pa) at which Johnson's adhesive sinusoid jumps into full contact on loading:
    the maximum over the contact width of ``p* (sin^2 t - alpha sqrt(tan t))``."""
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(lambda t: -(math.sin(t) ** 2 - alpha * math.sqrt(math.tan(t))),
                          bounds=(1e-9, math.pi / 2 - 1e-9), method="bounded", options={"xatol": 1e-12})
    return -float(res.fun) * pstar


def cases(modulus: float) -> dict[str, dict]:
    """The cases by name: ``make(nx)`` builds the texture, ``w`` J/m^2, ``exact`` Pa or None."""
    from fingerpad.textures import sinusoid, spherical_caps

    def caps(radius, height, spacing, lattice):
        return lambda n: spherical_caps(radius=radius, height=height, spacing=spacing, lattice=lattice, grid=n)

    out = {
        "caps-w0.3": {"make": caps(100e-6, 20e-6, 175e-6, "hexagonal"), "w": 0.3,
                      "what": "caps R 100 h 20 um, hexagonal 175 um (the default cell)"},
        "caps-w0.15": {"make": caps(100e-6, 20e-6, 175e-6, "hexagonal"), "w": 0.15,
                       "what": "the default cell at w 0.15"},
        "caps-w0.2": {"make": caps(100e-6, 20e-6, 175e-6, "hexagonal"), "w": 0.2,
                      "what": "the default cell at w 0.2"},
        "square-w0.3": {"make": caps(100e-6, 20e-6, 175e-6, "square"), "w": 0.3,
                        "what": "caps R 100 h 20 um, square 175 um"},
        "tall-w0.3": {"make": caps(100e-6, 30e-6, 250e-6, "hexagonal"), "w": 0.3,
                      "what": "caps R 100 h 30 um, hexagonal 250 um (taller, sparser)"},
    }
    lam, h = 200e-6, 10e-6  # one wavelength of a sinusoid of amplitude h (peak-to-valley 2h)
    pstar = math.pi * modulus * h / lam
    for alpha in (0.3, 0.45):
        w = alpha**2 * math.pi**2 * h**2 * modulus / (2 * lam)  # Johnson's alpha (docs/model.md 6.6)
        out[f"sinusoid-{alpha:g}"] = {
            "make": (lambda n: sinusoid(amplitude=h, wavelength=lam, grid=n)), "w": w,
            "exact": johnson_limit(alpha, pstar),
            "what": f"sinusoid lambda 200 um, h 10 um, alpha {alpha:g} (Johnson)"}
    return out


def fit(dx: np.ndarray, p: np.ndarray, orders: tuple[float, float]) -> tuple[float, float]:
    """Least squares ``p = p* + a dx^q1 + b dx^q2``: ``(p*, rms residual)`` (Pa)."""
    a = np.column_stack([np.ones_like(dx), dx ** orders[0], dx ** orders[1]])
    coef, *_ = np.linalg.lstsq(a, p, rcond=None)
    return float(coef[0]), float(np.sqrt(np.mean((a @ coef - p) ** 2)))


def measure(name: str, case: dict, grids: list[int], modulus: float) -> dict:
    from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
    from fingerpad.micro.pull_in import (_asymptotic, _converges_faster, _fading, extrapolated_states,
                                            order_factor)

    need = sorted({g // 2**i for g in grids for i in range(4) if g // 2**i >= 16})
    cells, seconds = {}, {}
    for n in need:
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # coarse grids on purpose
            cells[n] = AdhesiveUnitCell(case["make"](n), modulus, work_of_adhesion=case["w"]).prepare()
        seconds[n] = time.perf_counter() - t0
        print(f"  {name} grid {n}: own transition {cells[n].own_state_pressure('transition'):.1f} Pa, "
              f"pulled in {cells[n].pulled_in} (gap {cells[n].pull_in_ranges:.2f} ranges), {seconds[n]:.1f} s",
              flush=True)
    own = {n: cells[n].own_state_pressure("transition") for n in need}
    length = float(case["make"](grids[-1]).size[0])
    fit_grids = [g for g in grids if cells[g].pulled_in][-4:]
    dx = np.array([length / g for g in fit_grids])
    pv = np.array([own[g] for g in fit_grids])
    fits = sorted(((q, *fit(dx, pv, q)) for q in itertools.combinations(ORDERS, 2)), key=lambda r: r[2]) \
        if len(fit_grids) == 4 else []
    reported = {}
    for g in grids:
        chain = [cells.get(g // 2**i) for i in range(4)]
        out = extrapolated_states(*chain)
        half = own.get(g // 2)
        plain = abs(own[g] / half - 1.0) * order_factor(AdhesiveUnitCell) if half else math.nan
        p, pc, err = out["transition"] if out else (own[g], half or math.nan, plain)
        chained = []  # the grids' own transitions the rule reads, finest first
        for c in chain:
            if c is None or not c.pulled_in:
                break
            chained.append(own[int(c.texture.shape[0])])
        rule = ("own, not pulled in" if not out else
                "fold: own" if len(chained) >= 3 and _converges_faster(chained[:3])
                else "four grids" if len(chained) == 4 and _asymptotic(chained) else
                "four grids, safeguard" if len(chained) == 4 else f"{len(chained)} grids")
        if out and _fading(cells[g], cells[g // 2]):
            rule += ", fading"
        reported[g] = {"pressure": p, "compared": pc, "estimate": err, "extrapolated": bool(out), "rule": rule}
    # the reference: the finest grid's reported transition (a grid beyond those a prediction takes)
    reference = reported[grids[-1]]["pressure"]
    for g, v in reported.items():
        v["off_reference"] = abs(v["pressure"] / reference - 1.0) if g != grids[-1] else None
        v["off_exact"] = abs(v["pressure"] / case["exact"] - 1.0) if case.get("exact") else None
    return {"case": name, "what": case["what"], "work_of_adhesion": case["w"], "exact": case.get("exact"),
            "own": {str(n): own[n] for n in need}, "pulled_in": {str(n): cells[n].pulled_in for n in need},
            "gap_ranges": {str(n): cells[n].pull_in_ranges for n in need},
            "seconds": {str(n): seconds[n] for n in need}, "fit_grids": fit_grids,
            "fits": [{"orders": list(q), "limit": ps, "rms": r} for q, ps, r in fits],
            "reference_grid": grids[-1], "reference": reference,
            "reported": {str(g): v for g, v in reported.items()}}


def table(rows: list[dict]) -> str:
    """The cases as text, at most 80 columns."""
    lines = []
    for r in rows:
        lines.append(f"{r['case']}: {r['what']}")
        ref = (f"  w {r['work_of_adhesion']:.4g} J/m2; reference: the report on {r['reference_grid']}, "
               f"{r['reference'] / 1e3:.2f} kPa")
        if r["reported"][str(r["reference_grid"])]["rule"] == "own, not pulled in":
            ref += " (touched: a lower bound)"
        lines.append(ref)
        if r["exact"]:
            lines.append(f"  exact (Johnson): {r['exact'] / 1e3:.2f} kPa")
        lines.append("  grid   own  gap/rho  reported  estimate  off ref  rule")
        for n, own in r["own"].items():
            v = r["reported"].get(n)
            row = f"  {n:>4} {own / 1e3:5.2f}  {r['gap_ranges'][n]:7.2f}"
            if v is not None:
                off = "" if v["off_reference"] is None else f"{100 * v['off_reference']:6.1f} %"
                flag = "!" if v["off_reference"] is not None and v["off_reference"] > v["estimate"] else " "
                row += (f"  {v['pressure'] / 1e3:8.2f}  {100 * v['estimate']:6.1f} %  {off:>8}{flag} "
                        f"{v['rule']}")
            lines.append(row.rstrip())
        if r["fits"]:
            ours = next(f for f in r["fits"] if tuple(f["orders"]) == ASSUMED)
            grids = f"{r['fit_grids'][0]}-{r['fit_grids'][-1]}"
            lines.append(f"  fit of {grids}: (1, 3/2) {ours['limit'] / 1e3:.2f} kPa, rms {ours['rms']:.0f} Pa, "
                         f"rank {r['fits'].index(ours) + 1}/10; best:")
            lines.append("    " + "; ".join(f"({f['orders'][0]:g}, {f['orders'][1]:g}) {f['limit'] / 1e3:.2f} kPa "
                                            f"{f['rms']:.0f} Pa" for f in r["fits"][:3]))
    lines.append("(kPa; gap/rho: the base's gap before the jump in ranges; '!': off the reference")
    lines.append(" by more than the estimate)")
    return "\n".join(lines)


def main() -> None:
    from fingerpad.materials import reduced_modulus

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="caps-w0.3,caps-w0.15,tall-w0.3,square-w0.3,sinusoid-0.3,sinusoid-0.45",
                        help="comma-separated case names")
    parser.add_argument("--grids", default="32,64,128,256",
                        help="grids reported (points along x); their halves to an eighth are prepared too")
    parser.add_argument("--out", default="out/bench/pull_in_orders.json")
    args = parser.parse_args()
    modulus = reduced_modulus(*SKIN)
    known = cases(modulus)
    names = [c for c in args.cases.split(",") if c]
    unknown = [c for c in names if c not in known]
    if unknown:
        raise SystemExit(f"error: unknown case {unknown[0]!r} (known: {', '.join(known)})")
    grids = sorted(int(g) for g in args.grids.split(","))
    rows = []
    for name in names:
        rows.append(measure(name, known[name], grids, modulus))
        print(table(rows[-1:]), flush=True)
    load = os.getloadavg()
    print(f"\nload average {load[0]:.2f}, {load[1]:.2f}, {load[2]:.2f}")
    print(table(rows))
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rows": rows, "load_average": load}, indent=1))


if __name__ == "__main__":
    main()
