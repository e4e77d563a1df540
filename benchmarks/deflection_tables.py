"""Regenerate the numbers of docs/deflection.md, "What it predicts against Paper C's 'up to 2x'"
and "Through the coupling", from the current code (one command, markdown out).

Settings (as the docs state them): texture and skin E = 0.3 MPa, nu 0.49; the package friction
law with the default finger's tau0 = 8.1 kPa, alpha = 0.1; lattice 300 um x 300 um; ellipsoids
b = 3a; pressure levels 2, 6.3 and 20 kPa (``directional_gain`` over 2-20 kPa, three levels);
resolution 6 (``--resolution``); circular ridges of width 90 um and height 45 um at a 300 um
spacing. Perpendicular = sliding across the ellipsoids' long axis (the short-axis section),
parallel = along it (:func:`~fingerpad.micro.deflection.section.principal_directions`). The
ratio is G_perp(p, mu) / G_par(p, mu) from the gain tables (a ``*`` marks a shear level past the
largest one a ramp reached in either direction: the gain is held there).

Then (``--mesh-check``, slow) the slender section at 6.3 kPa at resolution 9, and "Through the
coupling": ``predict`` (BEM cell, default finger, loads 0.1-4 N) with ``--direction`` for the
slender and the medium ellipsoids: the local shear level (the fixed point at the pad-centre
pressure 1.5 F / A_fr), the real-area ratio and mu_perp / mu_par per load (also without the
asperity-scale hysteresis factor, to separate the area's share), and the hysteresis factors.

    python benchmarks/deflection_tables.py [--resolution 6] [--slenderness] [--mesh-check] [--no-coupling]
        [--grid N] [--cache DIR]

Solved sections are cached by content (a fresh temporary folder unless ``--cache``), so a
second run with the same folder only reads them.
"""

from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np

from fingerpad.materials import Materials
from fingerpad.micro.deflection import DeflectionSettings, EllipsoidGeometry, RidgeGeometry, directional_gain
from fingerpad.micro.deflection.section import principal_directions

UM = 1e-6
MATS = Materials(skin_modulus=0.3e6, skin_poisson=0.49, material_modulus=0.3e6, material_poisson=0.49)
TAU0, ALPHA = 8.1e3, 0.1
P_RANGE = (2e3, 2e4)
MUS = (0.3, 0.6, 1.0, 1.5)
LATTICE = 300 * UM


def ellipsoid(a: float, h: float) -> EllipsoidGeometry:
    return EllipsoidGeometry(a * UM, 3 * a * UM, h * UM, LATTICE, LATTICE)


def gains(geometry, settings: DeflectionSettings, cache: str) -> dict:
    """Gain curves across (perpendicular) and along (parallel) the long axis, with timings."""
    par, perp = principal_directions(geometry)
    out = {}
    for name, direction in (("perp", perp), ("par", par)):
        t0 = time.perf_counter()
        out[name] = directional_gain(geometry, MATS, direction, P_RANGE, tau0=TAU0, alpha=ALPHA, settings=settings,
                                     cache=cache)
        out[name + "_s"] = time.perf_counter() - t0
    return out


def ratio_row(g: dict, p: float) -> list[str]:
    cells = []
    for mu in MUS:
        r = float(g["perp"](p, mu) / g["par"](p, mu))
        sat = bool(g["perp"].saturated(p, mu) or g["par"].saturated(p, mu))
        cells.append(f"{r:.2f}{'*' if sat else ''}")
    return cells


def ramp_at(curve, p: float):
    if not curve.ramps:
        return None
    k = int(np.argmin(np.abs(np.log(curve.pressures) - np.log(p))))
    return curve.ramps[k]


def describe(curve, label: str) -> str:
    """One line per pressure level: reach, stop, buckling, fold onset, limit point."""
    if curve.is_identity:
        return f"  {label}: identity (G = 1, nothing to solve)"
    lines = []
    for r in curve.ramps:
        lines.append(f"  {label} {r.pressure / 1e3:5.2f} kPa: mu reached {r.mu_reached:.3g}, buckled {r.buckled}, "
                     f"fold onset mu {r.fold_onset_mu:.3g}, limit mu {r.limit_mu:.3g}, "
                     f"stopped: {r.stopped or '-'}")
    return "\n".join(lines)


def table(resolution: int, cache: str) -> dict:
    settings = DeflectionSettings(resolution=resolution)
    rows = [
        ("15 x 45 x 15 (skin near full contact)", ellipsoid(15, 15), (2e3,)),
        ("30 x 90 x 30", ellipsoid(30, 30), (2e3, P_RANGE[0] * 10**0.5)),
        ("45 x 135 x 45", ellipsoid(45, 45), (2e3, P_RANGE[0] * 10**0.5)),
        ("45 x 135 x 90 (h = 2a)", ellipsoid(45, 90), (2e3, P_RANGE[0] * 10**0.5)),
    ]
    print(f"## Ratio perpendicular / parallel of the gain (resolution {resolution})\n")
    print("| asperity a x b x h (um) | p (kPa) | mu = 0.3 | 0.6 | 1.0 | 1.5 |")
    print("|---|---|---|---|---|---|")
    solved = {}
    notes = []
    for label, geo, ps in rows:
        g = gains(geo, settings, cache)
        solved[label] = g
        notes.append(f"{label}: perpendicular {g['perp_s']:.0f} s, parallel {g['par_s']:.0f} s\n"
                     + describe(g["perp"], "perp") + "\n" + describe(g["par"], "par "))
        for p in ps:
            print(f"| {label} | {p / 1e3:.2g} | " + " | ".join(ratio_row(g, p)) + " |")
    ridge = RidgeGeometry(90 * UM, 45 * UM, LATTICE)
    g = gains(ridge, settings, cache)
    solved["ridges"] = g
    notes.append(f"circular ridges: across {g['perp_s']:.0f} s\n" + describe(g["perp"], "across") + "\n"
                 + describe(g["par"], "along "))
    per_level = np.array([[float(g["perp"](p, mu) / g["par"](p, mu)) for mu in MUS] for p in g["perp"].pressures])
    sat = [any(bool(g["perp"].saturated(p, mu)) for p in g["perp"].pressures) for mu in MUS]
    print("| circular ridges w 90, h 45 (across / along) | 2-20 | "
          + " | ".join(f"{lo:.2f}-{hi:.2f}{'*' if s else ''}"
                       for lo, hi, s in zip(per_level.min(0), per_level.max(0), sat)) + " |")
    print("\n(* past the largest shear a ramp reached: the gain is held.)\n")
    print("Ramps:\n" + "\n".join(notes) + "\n")
    slender = solved["45 x 135 x 90 (h = 2a)"]
    p_mid = P_RANGE[0] * 10**0.5
    print("Slender section (45 x 135 x 90) gains G = L(mu)/L(0):")
    for p in (2e3, p_mid, P_RANGE[1]):
        perp = [float(slender["perp"](p, mu)) for mu in MUS]
        par = [float(slender["par"](p, mu)) for mu in MUS]
        rp, rl = ramp_at(slender["perp"], p), ramp_at(slender["par"], p)
        print(f"  p = {p / 1e3:.3g} kPa: across {' / '.join(f'{v:.3f}' for v in perp)}; "
              f"along {' / '.join(f'{v:.3f}' for v in par)} (mu = {', '.join(map(str, MUS))}); "
              f"across: buckled {rp.buckled}, fold onset mu {rp.fold_onset_mu:.3g}, limit mu {rp.limit_mu:.3g}, "
              f"reached {rp.mu_reached:.3g}; along: buckled {rl.buckled}, reached {rl.mu_reached:.3g}")
    print()
    return solved


def slenderness(resolution: int, cache: str) -> None:
    """The gain against slenderness h/a (a 45 um, b 135 um, lattice 300 um), pressure and mu:
    per row the gains across (perpendicular) and along (parallel) and their ratio; ``*``: held
    past the shear a ramp reached; ``B``: the section across is buckled under the normal load
    alone at that level (its ramp follows the branch folded toward the sliding direction)."""
    settings = DeflectionSettings(resolution=resolution)
    print(f"## Gain against slenderness (a x b = 45 x 135 um, resolution {resolution})\n")
    print("| h/a (h um) | p (kPa) | G across, mu = 0.3 / 0.6 / 1 / 1.5 | G along | ratio across/along | buckled |")
    print("|---|---|---|---|---|---|")
    notes = []
    for h in (45, 90, 135):
        t0 = time.perf_counter()
        g = gains(ellipsoid(45, h), settings, cache)
        notes.append(f"h = {h} um ({time.perf_counter() - t0:.0f} s):\n" + describe(g["perp"], "perp") + "\n"
                     + describe(g["par"], "par "))
        for p in g["perp"].pressures:
            def cells(c):
                return " / ".join(f"{float(c(p, mu)):.2f}{'*' if c.saturated(p, mu) else ''}" for mu in MUS)
            rp, rl = ramp_at(g["perp"], p), ramp_at(g["par"], p)
            buckled = ", ".join(n for n, r in (("across", rp), ("along", rl)) if r is not None and r.buckled) or "-"
            print(f"| {h / 45:g} ({h}) | {p / 1e3:.3g} | {cells(g['perp'])} | {cells(g['par'])} | "
                  + " / ".join(ratio_row(g, p)) + f" | {buckled} |")
    print("\n(* past the largest shear a ramp reached: the gain is held.)\n")
    print("Ramps:\n" + "\n".join(notes) + "\n")


def mesh_check(cache: str) -> None:
    p = P_RANGE[0] * 10**0.5
    settings = DeflectionSettings(resolution=9, n_pressures=1)
    geo = ellipsoid(45, 90)
    par, perp = principal_directions(geo)
    t0 = time.perf_counter()
    g = {name: directional_gain(geo, MATS, d, (p, p), tau0=TAU0, alpha=ALPHA, settings=settings, cache=cache)
         for name, d in (("perp", perp), ("par", par))}
    across = [float(g["perp"](p, mu)) for mu in MUS]
    along = [float(g["par"](p, mu)) for mu in MUS]
    ratio = [a / b for a, b in zip(across, along)]
    print(f"## Mesh check: slender section at {p / 1e3:.3g} kPa, resolution 9 ({time.perf_counter() - t0:.0f} s)\n")
    print(f"gains across {' / '.join(f'{v:.2f}' for v in across)}, along {' / '.join(f'{v:.2f}' for v in along)}, "
          f"ratios {' / '.join(f'{v:.2f}' for v in ratio)} (mu = {', '.join(map(str, MUS))})")
    print(describe(g["perp"], "across") + "\n" + describe(g["par"], "along ") + "\n")


def coupling(cache: str, grid: str | None) -> None:
    from fingerpad.cli.predict import build_study
    from fingerpad.coupling import predict_curve
    from fingerpad.micro.deflection import DirectionalCell, texture_geometry
    from fingerpad.study.run import directional_settings, run_study

    print("## Through the coupling: predict --direction 0 (BEM cell, default finger, loads 0.1-4 N)\n")
    for label, h in (("slender 45 x 135 x 90", 90), ("medium 45 x 135 x 45", 45)):
        # the README command's study (default loads: 40 from 0.1 to 4 N), rows at five of them
        flags = {"--texture": "ellipsoids", "--model": "bem",
                 "--material-modulus": "0.3MPa", "--material-poisson": "0.49", "--direction": "0",
                 "--grid": grid, "--cache": cache}
        args = ["--semi-axis-x", "45um", "--semi-axis-y", "135um", "--height", f"{h}um",
                "--spacing-x", "300um", "--spacing-y", "300um"]
        t0 = time.perf_counter()
        study = build_study(ctx_args=args, flags=flags, finger_param=[], options={})
        pred = run_study(study)
        d = pred.directional
        loads = np.asarray(study.loads, float)
        finger = study.finger
        centre = 1.5 * loads / np.asarray(finger.ridge_area(loads), float)
        p_range = (float(centre.min()), float(centre.max()))
        geometry = texture_geometry(pred.texture)
        mats = Materials(finger.skin_modulus, finger.skin_poisson, study.material_modulus, study.material_poisson)
        local, plain = {}, {}
        for name, direction in (("perp", d["perpendicular_direction"]), ("par", d["parallel_direction"])):
            gain = directional_gain(geometry, mats, direction, p_range, tau0=finger.tau0, alpha=finger.alpha,
                                    settings=directional_settings(finger, pred.cell, centre), cache=cache)
            cell = DirectionalCell(pred.cell, gain, finger.tau0, finger.alpha)
            local[name] = cell.local_shear(centre)
            plain[name] = predict_curve(loads, finger, cell).mu  # without the hysteresis direction factor
        print(f"### {label} ({time.perf_counter() - t0:.0f} s; BEM grid {list(pred.cell.texture.shape)}; "
              f"pad-centre pressures {p_range[0] / 1e3:.3g}-{p_range[1] / 1e3:.3g} kPa)\n")
        print("| F (N) | p centre (kPa) | local mu perp | local mu par | G perp | G par | A_re perp/par "
              "| mu perp | mu par | mu perp/par | same, hysteresis factor 1 | hysteresis term (factor 1) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        fac = d["hysteresis_factor"]["perpendicular"]
        # the hysteresis term of Eq. 2.4 before the direction factor: mu = mu_plain + (factor - 1) mu_hys
        hys = (d["mu_perpendicular"] - plain["perp"]) / (fac - 1.0) if fac != 1.0 else np.full(loads.size, np.nan)
        area = d["area_ratio_perpendicular"] / d["area_ratio_parallel"]
        rows = np.unique(np.linspace(0, loads.size - 1, 5).round().astype(int))
        for i in rows:
            f = loads[i]
            print(f"| {f:.3g} | {centre[i] / 1e3:.3g} | {local['perp'].mu[i]:.3f} | {local['par'].mu[i]:.3f} | "
                  f"{local['perp'].gain[i]:.3f}{'*' if local['perp'].saturated[i] else ''} | "
                  f"{local['par'].gain[i]:.3f}{'*' if local['par'].saturated[i] else ''} | {area[i]:.3f} | "
                  f"{d['mu_perpendicular'][i]:.4f} | {d['mu_parallel'][i]:.4f} | "
                  f"{d['mu_perpendicular_over_parallel'][i]:.3f} | {plain['perp'][i] / plain['par'][i]:.3f} | {hys[i]:.4f} |")
        print(f"\nhysteresis factors: {', '.join(f'{k} {v:.3f}' for k, v in d['hysteresis_factor'].items())}; "
              f"notes: {'; '.join(pred.notes) or '-'}\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=int, default=6)
    ap.add_argument("--mesh-check", action="store_true", help="also the resolution-9 check (slow)")
    ap.add_argument("--no-table", action="store_true")
    ap.add_argument("--slenderness", action="store_true", help="the gain against h/a = 1, 2, 3 table")
    ap.add_argument("--no-coupling", action="store_true")
    ap.add_argument("--grid", default=None, help="BEM grid of the coupling's predict (default: automatic)")
    ap.add_argument("--cache", default=None, help="cache folder (default: a fresh temporary one)")
    args = ap.parse_args()
    print(f"Settings: E_texture = E_skin = 0.3 MPa, nu 0.49, tau0 {TAU0 / 1e3:g} kPa, alpha {ALPHA:g}; lattice 300 um; "
          f"pressure levels {', '.join(f'{p / 1e3:.3g}' for p in np.geomspace(*P_RANGE, 3))} kPa; "
          f"{DeflectionSettings(resolution=args.resolution)}\n")
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        cache = args.cache or tmp
        if args.slenderness:
            slenderness(args.resolution, cache)
        if not args.no_table:
            table(args.resolution, cache)
        if args.mesh_check:
            mesh_check(cache)
        if not args.no_coupling:
            coupling(cache, args.grid)
    print(f"total {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
