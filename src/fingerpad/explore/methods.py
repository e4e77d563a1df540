"""The "methods and references" panel: which equations each plot shows and where they come from.

Equation numbers are those of docs/model.md (Eqs. 2.1-3.10 as in the thesis, 3.11-3.14 the
project's completion of the coupling).
"""

from __future__ import annotations

__all__ = ["METHODS_MARKDOWN"]

METHODS_MARKDOWN = """
### Methods

Every number in the explorer is computed by the fingerpad library exactly as
`fingerpad predict` computes it (the export *study TOML* reproduces the view). Equation numbers are
those of the project's model description, `docs/model.md`.

| plot | what it shows | equations |
|---|---|---|
| contact areas | gross area `A_g` of the pad, ridge area `A_fr` inside it, real area `A_re` on the texture | 2.5-2.7 (macro), ch. 2.2.2 ridge models (meso), 3.7 and 3.11 (coupling) |
| friction, mu / mu_ref | `mu = F_f / F`, adhesion on `A_re` plus hysteresis; the flat reference has `A_re = A_fr` | 2.1-2.4, 3.12 |
| state bands, critical loads | state at the pad centre: asperity, transition (skin touches the texture's base), full contact; `F_crit`: centre pressure `1.5 F / A_fr` reaches the cell's transition pressure | 3.13, 3.14 (Eq. 3.6 for the Hertz cell) |
| psi(p) | real-to-nominal area of the unit cell at mean pressure `p`: BEM nodes (half-space solver) interpolated in log p; per-asperity Hertz | 3.1-3.3 (Hertz), docs/solver.md (BEM) |
| height, pressure and contact maps | the unit cell and one contact solve at the chosen mean pressure (skin: elastic half-space of modulus E1*) | 3.4 (E1*), docs/solver.md |
| contact zones | zones of the ridge-contact disc at the zone load, pad pressure along a radius and the local psi | 3.7, 3.13 |
| design map | critical load and mu / mu_ref over a parameter sweep | as above, per design |

* **Micro modulus.** `1/E1* = (1 - nu_s^2)/E_s + (1 - nu_m^2)/E_m` (Eq. 3.4), skin modulus `E_s` of
  the finger, material modulus `E_m` of the counter-surface (rigid: second term dropped).
* **BEM unit cell.** Frictionless, non-adhesive normal contact of an elastic half-space with the
  periodic cell, constrained conjugate gradient (Polonsky and Keer 1999); psi(p) depends on
  `p / E1*` only. The grid is doubled until the estimated relative error of `A_re / A_fr` is below
  the accuracy (2 % by default). Cells are cached on disk, so a design seen before runs no solve.
* **Hertz cell.** Each spherical cap in Hertz contact with the skin; hexagonal lattices as the square
  spacing of the same asperity density (docs/model.md, section 10).
* **Pad pressure.** `p(r) = 1.5 p_mean sqrt(1 - r^2/a_fr^2)`, `p_mean = F / A_fr` (Eq. 3.7) on an
  equivalent disc of area `A_fr`.

### References

* D. A. Sergachev, *Surface engineering of tactile friction*, PhD thesis, University of Twente,
  Enschede, 2021. DOI 10.3990/1.9789036551786 (the model: chapters 2 and 3).
* D. Sergachev, D. Matthews, E. van der Heide, Design of bidirectional frictional behaviour for
  tactile contact using ellipsoidal asperity micro-textures, *Friction* 10(5):762-771, 2022.
* B. M. Dzidek, M. J. Adams, J. W. Andrews, Z. Zhang, S. A. Johnson, Contact mechanics of the
  human finger pad under compressive loads, *J. R. Soc. Interface* 14(127):20160935, 2017
  (gross area with stiffening, Eqs. 2.6-2.7).
* J. A. Greenwood, D. Tabor, The friction of hard sliders on lubricated rubber: the importance of
  deformation losses, *Proc. Phys. Soc.* 71:989-1001, 1958 (hysteresis, Eq. 2.4).
* H. M. Westergaard, Bearing pressures and cracks, *J. Appl. Mech.* 6:A49-A53, 1939 (sinusoidal
  ridges).
* K. L. Johnson, J. A. Greenwood, J. G. Higginson, The contact of elastic regular wavy surfaces,
  *Int. J. Mech. Sci.* 27(6):383-396, 1985 (bisinusoidal textures).
* K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985 (Hertz contact).
* I. A. Polonsky, L. M. Keer, A numerical method for solving rough contact problems based on the
  multi-level multi-summation and conjugate gradient techniques, *Wear* 231(2):206-219, 1999.
* A. E. H. Love, The stress produced in a semi-infinite solid by pressure on part of the boundary,
  *Phil. Trans. R. Soc. A* 228:377-420, 1929 (finite-patch kernel).

The project's documents: `docs/model.md` (the model, every equation), `docs/solver.md` (the
half-space solver), `docs/explorer.md` (this explorer).
"""
