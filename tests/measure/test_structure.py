"""Where the measurement code lives: one power-law type, the table helpers in their own module,
plotting free of measure/ imports."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

import fingerpad
from fingerpad import friction
from fingerpad import measure as m

SRC = Path(fingerpad.__file__).resolve().parent


def _runtime_imports(path: Path) -> set[str]:
    """Modules imported by ``path`` outside ``if TYPE_CHECKING:`` blocks (relative ones resolved
    against ``fingerpad.plotting``)."""
    found: set[str] = set()

    def visit(nodes):
        for node in nodes:
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
                continue
            if isinstance(node, ast.ImportFrom):
                base = "fingerpad.plotting".split(".")[: 2 - (node.level - 1)] if node.level else []
                found.add(".".join(base + ([node.module] if node.module else [])))
            elif isinstance(node, ast.Import):
                found.update(a.name for a in node.names)
            for child in ("body", "orelse", "finalbody", "handlers"):
                visit(getattr(node, child, []) or [])

    visit(ast.parse(path.read_text(encoding="utf-8")).body)
    return found


def test_plotting_imports_nothing_from_measure():
    for path in sorted((SRC / "plotting").glob("*.py")):
        bad = sorted(i for i in _runtime_imports(path) if i.startswith("fingerpad.measure"))
        assert not bad, f"{path.name} imports {bad}"


def test_one_power_law_type():
    assert friction.PowerLawFit is friction.PowerLaw is m.PowerLaw
    rng = np.random.default_rng(0)
    f = np.geomspace(0.1, 5, 30)
    mu = 0.5 * f ** -0.3 * np.exp(0.05 * rng.standard_normal(f.size))
    plain = friction.fit_power_law(f, mu)
    clustered = m.fit_power_law_clustered(f, mu)  # no recordings: the same least squares
    assert type(plain) is type(clustered) is friction.PowerLaw
    for name in ("k", "n", "k_stderr", "n_stderr", "dof", "df_level"):
        assert getattr(plain, name) == pytest.approx(getattr(clustered, name), rel=1e-9), name
    assert plain.k_ci == pytest.approx(clustered.k_ci) and plain.n_ci == pytest.approx(clustered.n_ci)
    # the same behaviour: scalar in, scalar out; the mean log level over loads
    assert plain(1.0) == pytest.approx(plain.k) and isinstance(clustered(2.0), float)
    value, se, df = plain.log_level(f)
    assert value == pytest.approx(math.log(plain.k) + (plain.n - 1) * np.mean(np.log(f)))
    assert se > 0 and df == plain.dof == 28
    # the confidence level is a parameter of both fits
    narrow = friction.fit_power_law(f, mu, level=0.5)
    assert narrow.level == 0.5 and narrow.n_ci[1] - narrow.n_ci[0] < plain.n_ci[1] - plain.n_ci[0]
    with pytest.raises(fingerpad.FingerpadError, match="level must lie in"):
        friction.fit_power_law(f, mu, level=1.0)


def test_table_helpers_in_their_own_module():
    from fingerpad.measure import strokes, tables

    for name in ("stroke_table", "bin_strokes", "load_bin_edges", "flag_outliers", "plausibility_warnings",
                 "cluster_column", "bin_index"):
        assert getattr(tables, name).__module__ == "fingerpad.measure.tables"
        assert not hasattr(strokes, name), name
    assert m.stroke_table is tables.stroke_table and m.measure_strokes is strokes.measure_strokes
