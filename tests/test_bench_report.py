"""``benchmarks/report.py``: issue 34's table prints the `analyse` row of every panel shape."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _report_module():
    spec = importlib.util.spec_from_file_location("bench_report", ROOT / "benchmarks" / "report.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    return module


def test_issue34_table_has_a_row_per_analysed_panel_shape(tmp_path: Path) -> None:
    """A report of bench_analyse.py with three shapes gives three `analyse` rows, each with its
    own wording and time, and no 'not measured' line for the analysis."""
    rows = [{"row": f"`analyse`, {p} people x {t + 1} samples x 3 recordings, every figure",
             "script": "bench_analyse.py", "today": "-", "now": f"{w} s wall, {c} s CPU (CPU/wall 1.50)",
             "ratio": None, "goal": "<= 15 s", "met": w <= 15, "load": "1.0"}
            for p, t, w, c in ((10, 4, 14.5, 26.0), (3, 1, 3.1, 4.0), (20, 8, 61.0, 118.0))]
    (tmp_path / "analyse.json").write_text(json.dumps({"issue34": rows}))
    report = _report_module()
    table = report.table34(report.collect(tmp_path, "issue34"))
    lines = [line for line in table.splitlines() if "bench_analyse.py" in line]
    assert len(lines) == 3
    for (p, t, w), line in zip(((10, 5, 14.5), (3, 2, 3.1), (20, 9, 61.0)), lines):
        assert f"{p} people x {t} samples" in line and f"{w} s wall" in line
    assert "| yes |" in lines[0] and "| **no** |" in lines[2]
