"""The two findings of the layered skin (docs/model.md, section 6.5), numbers and figures.

(a) The skin modulus the friction-transition method recovers (docs/model.md, section 8: the
    transition pressure of the texture's cell read as that of a homogeneous skin) against the
    texture's scale, for a layered finger of published thickness: the default study's texture
    (caps R 100 um, h 20 um, hexagonal spacing 175 um) scaled uniformly from 17.5 um to 5.25 mm
    spacing, each cell solved with the layered kernel (BEM unit cell, transition pressure by
    geometric bisection to 0.2 %) and its transition pressure divided by the homogeneous cell's
    p_t / E*. The layer: stratum corneum t = 0.3 mm (thesis ch. 1.2: 0.2-0.35 mm), E_1 in
    {0.3, 1, 10} MPa; the tissue E_2 = 30.4 kPa (E_2* = 40 kPa, the pad's E_fp*); nu = 0.49.
    The pad's scale is the layered skin's effective modulus E1* / K(t / a) at the contact radius
    a of a 1 N touch (5.5 mm; Westergaard generalised, one wavenumber 1/a).
(b) Felt or pressed flat: a sinusoidal texture of amplitude h and wavelength lambda is pressed
    into full contact at p* = h / C(k) = E1* k h / (2 K(k t)), k = 2 pi / lambda (Westergaard
    generalised, exact: tests/contact/test_layered.py); pressed flat when p* <= the ridge
    pressure, 17-33 kPa. Map over lambda 1 um - 3 mm and h/lambda for the homogeneous skin
    (E_s 0.2-0.5 MPa) and the layered skins of (a).

    python benchmarks/layered_findings.py [--out DIR] [--grid 32] [--no-figures]

Deterministic: no random numbers, no timing enters a number; the figures are redrawn the same.
Markdown tables on stdout; figures layered_modulus_scale.png and layered_felt_map.png in DIR.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

import fingerpad as fp
from fingerpad.contact import HalfSpaceSolver, Layer
from fingerpad.contact.layered import effective_modulus

NU = 0.49
T_LAYER = 0.3e-3
T_BAND = (0.2e-3, 0.35e-3)
E2_STAR = 40e3
E2 = E2_STAR * (1 - NU**2)
E1_VALUES = (0.3e6, 1e6, 10e6)
SCALES = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0)  # x the default texture (spacing 175 um)
SPACING = 175e-6
PAD_RADIUS_1N = 5.53e-3  # Hertz contact radius of the default finger at 1 N (docs/model.md, finger.py)
RIDGE_PRESSURES = (17e3, 33e3)
E_S_THESIS = (0.2e6, 0.5e6)


def texture(scale: float, grid: int):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fp.make_texture("caps", radius=100e-6 * scale, height=20e-6 * scale, spacing=SPACING * scale,
                               lattice="hexagonal", grid=grid)


def transition_pressure(tex, modulus: float, layer: Layer | None, rtol: float = 2e-3) -> float:
    """Mean pressure (Pa) where the skin first touches the texture's base: doubling from 1e-5 E*,
    then geometric bisection to ``rtol``, warm-started."""
    solver = HalfSpaceSolver(tex, modulus, layer=layer, tol=1e-8)
    lo, res = 1e-5 * modulus, None
    while True:
        hi = 2 * lo
        r = solver.solve_pressure(hi, initial=res)
        if r.contact_state != "asperity":
            break
        lo, res = hi, r
        if hi > 10 * modulus:
            return math.inf
    while hi / lo > 1 + rtol:
        mid = math.sqrt(lo * hi)
        r = solver.solve_pressure(mid, initial=res)
        if r.contact_state != "asperity":
            hi = mid
        else:
            lo, res = mid, r
    return math.sqrt(lo * hi)


def finding_a(grid: int) -> dict:
    """Recovered E_s (Pa) per E_1 and scale; the homogeneous cell's p_t / E*."""
    unit = transition_pressure(texture(1.0, grid), 1.0, None)
    out = {"pt_over_e": unit, "spacing": [SPACING * s for s in SCALES], "recovered": {}, "westergaard": {}}
    for e1 in E1_VALUES:
        layer = Layer(T_LAYER, e1, NU, E2, NU)
        rec = []
        for s in SCALES:
            pt = transition_pressure(texture(s, grid), layer.reduced_modulus, layer)
            rec.append(pt / unit * (1 - NU**2))  # E_s a homogeneous skin would need, Pa
        out["recovered"][e1] = rec
        out["pad"] = out.get("pad", {})
        out["pad"][e1] = float(effective_modulus(layer, 1 / PAD_RADIUS_1N)) * (1 - NU**2)
    return out


def print_a(a: dict) -> None:
    print(f"homogeneous cell: p_t / E* = {a['pt_over_e']:.4g}\n")
    head = " | ".join(f"E_1 = {e / 1e6:g} MPa" for e in E1_VALUES)
    print(f"| texture spacing | {head} |")
    print("|---|" + "---|" * len(E1_VALUES))
    for i, lam in enumerate(a["spacing"]):
        cells = " | ".join(f"{a['recovered'][e][i] / 1e6:.3g} MPa" for e in E1_VALUES)
        print(f"| {lam * 1e6:.4g} um | {cells} |")
    cells = " | ".join(f"{a['pad'][e] / 1e3:.3g} kPa" for e in E1_VALUES)
    print(f"| pad (a = {PAD_RADIUS_1N * 1e3:.3g} mm) | {cells} |\n")


def flat_threshold(lam: np.ndarray, e_star: np.ndarray, p: float) -> np.ndarray:
    """h / lambda below which a sinusoid is pressed flat at pressure p: p* = pi E*_eff h / lambda."""
    return p / (math.pi * e_star)


def skins() -> list[tuple[str, Layer | None, float]]:
    """(label, layer, E_s of the homogeneous skin) of map (b)."""
    out: list[tuple[str, Layer | None, float]] = [
        (f"homogeneous E_s {E_S_THESIS[0] / 1e6:g} MPa", None, E_S_THESIS[0]),
        (f"homogeneous E_s {E_S_THESIS[1] / 1e6:g} MPa", None, E_S_THESIS[1])]
    for e1 in E1_VALUES:
        out.append((f"layered E_1 {e1 / 1e6:g} MPa", Layer(T_LAYER, e1, NU, E2, NU), e1))
    return out


def finding_b() -> tuple[np.ndarray, dict]:
    lam = np.geomspace(1e-6, 3e-3, 200)
    thresholds = {}
    for label, layer, e in skins():
        e_star = np.full(lam.shape, e / (1 - NU**2)) if layer is None else effective_modulus(layer, 2 * np.pi / lam)
        thresholds[label] = [flat_threshold(lam, e_star, p) for p in RIDGE_PRESSURES]
    return lam, thresholds


def print_b(lam: np.ndarray, thresholds: dict) -> None:
    picks = [2e-6, 20e-6, 0.2e-3, 0.45e-3, 2e-3]
    head = " | ".join(f"{x * 1e6:g} um" for x in picks)
    print(f"| h/lambda pressed flat below (17 / 33 kPa) | {head} |")
    print("|---|" + "---|" * len(picks))
    for label, (lo, hi) in thresholds.items():
        cells = " | ".join(f"{np.interp(math.log(x), np.log(lam), lo):.2g} / {np.interp(math.log(x), np.log(lam), hi):.2g}"
                           for x in picks)
        print(f"| {label} | {cells} |")
    print()


def figures(a: dict, lam: np.ndarray, thresholds: dict, out: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    paths = []
    fig, ax = plt.subplots(figsize=(7, 4.5))
    scale = np.geomspace(10e-6, 20e-3, 200)
    colours = ("C0", "C1", "C3")
    for e1, c in zip(E1_VALUES, colours, strict=True):
        ax.plot(np.array(a["spacing"]) * 1e3, np.array(a["recovered"][e1]) / 1e6, "o", color=c,
                label=f"BEM cell, E_1 = {e1 / 1e6:g} MPa")
        for t, style in ((T_LAYER, "-"), (T_BAND[0], ":"), (T_BAND[1], ":")):
            layer = Layer(t, e1, NU, E2, NU)
            ax.plot(scale * 1e3, effective_modulus(layer, 2 * np.pi / scale) * (1 - NU**2) / 1e6, style, color=c,
                    lw=1 if style == ":" else 1.5)
        ax.plot([2 * math.pi * PAD_RADIUS_1N * 1e3], [a["pad"][e1] / 1e6], "s", color=c, mfc="none")
    ax.axhspan(E_S_THESIS[0] / 1e6, E_S_THESIS[1] / 1e6, color="0.85", zorder=0, label="thesis E_s 0.2-0.5 MPa")
    ax.axhline(E2 / 1e6, color="0.4", lw=0.8, ls="--", label="tissue E_2 (E_2* = 40 kPa)")
    ax.axvspan(0.4, 0.5, color="0.93", zorder=0)
    ax.text(0.45, 14, "ridges", ha="center", fontsize=8)
    ax.set(xscale="log", yscale="log", ylim=(0.02, 20), xlabel="texture scale: spacing or wavelength (mm)",
           ylabel="recovered skin modulus E_s (MPa)",
           title=f"Layered finger, t = {T_LAYER * 1e3:g} mm (dotted 0.2 / 0.35 mm): lines E*_eff(2 pi / lambda), "
                 "squares the pad at 1 N", )
    ax.title.set_fontsize(8)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    paths.append(out / "layered_modulus_scale.png")
    fig.savefig(paths[-1], dpi=120, metadata={"Software": None})
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    # the two homogeneous skins share a grey and differ by line style (one grey for both left the
    # legend unable to tell them apart)
    styles = {"homogeneous E_s 0.2": ("0.3", "--"), "homogeneous E_s 0.5": ("0.3", ":"),
              "layered E_1 0.3": ("C0", "-"), "layered E_1 1 ": ("C1", "-"), "layered E_1 10": ("C3", "-")}
    for label, (lo, hi) in thresholds.items():
        colour, style = next((v for k, v in styles.items() if label.startswith(k)), ("k", "-"))
        ax.fill_between(lam * 1e6, lo, hi, color=colour, alpha=0.25)
        ax.plot(lam * 1e6, np.sqrt(lo * hi), color=colour, ls=style, lw=1.2, label=label)
    ax.text(3, 0.2, "felt (above the band)", fontsize=9)
    ax.text(300, 2e-4, "pressed flat (below)", fontsize=9)
    ax.axvspan(400, 500, color="0.93", zorder=0)
    ax.set(xscale="log", yscale="log", xlabel="texture wavelength lambda (um)",
           ylabel="amplitude / wavelength h / lambda", ylim=(1e-4, 1))
    ax.set_title("Sinusoid pressed flat at ridge pressures 17-33 kPa (band): p* = E*_eff(k) k h / 2", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    paths.append(out / "layered_felt_map.png")
    fig.savefig(paths[-1], dpi=120, metadata={"Software": None})
    plt.close(fig)
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="layered_findings", help="folder of the figures")
    parser.add_argument("--grid", type=int, default=32, help="grid of the unit cells along x (default 32)")
    parser.add_argument("--no-figures", action="store_true")
    args = parser.parse_args()
    a = finding_a(args.grid)
    print_a(a)
    lam, thresholds = finding_b()
    print_b(lam, thresholds)
    if not args.no_figures:
        for path in figures(a, lam, thresholds, Path(args.out)):
            print(f"wrote {path}")


if __name__ == "__main__":
    main()
