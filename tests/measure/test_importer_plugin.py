"""A tribometer format is added by adding one file to ``fingerpad/measure/importers/``.

The test writes a small importer module (a JSON format of its own, ``.tribo``) into a
temporary folder that joins the importers package's search path, and reads a recording
through the ordinary entry points: nothing else is edited or registered.
"""

from __future__ import annotations

import json
import sys
import textwrap

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError
from fingerpad.measure import importers

PLUGIN = textwrap.dedent('''
    """A toy tribometer format: one JSON object, channel name -> list of samples."""

    import json

    import numpy as np

    from fingerpad.errors import FingerpadError
    from fingerpad.measure.importers import Importer, RawTable


    def read_tribo(path, spec):
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except ValueError as exc:
            raise FingerpadError(f"{path}: not a .tribo file ({exc})") from None
        header = list(data)
        columns = [np.asarray(data[name], dtype=float) for name in header]
        return RawTable(header=header, columns=columns, rows=np.arange(1, columns[0].size + 1), row_word="sample")


    IMPORTER = Importer(name="tribo", suffixes=(".tribo",), read_table=read_tribo)
''')


@pytest.fixture()
def plugin(tmp_path, monkeypatch):
    """The importers package with one more file in it (a folder on its search path)."""
    folder = tmp_path / "plugins"
    folder.mkdir()
    (folder / "tribo.py").write_text(PLUGIN, encoding="utf-8")
    monkeypatch.setattr(importers, "__path__", [*importers.__path__, str(folder)])
    monkeypatch.setattr(importers, "_IMPORTERS", None)  # found afresh, with the new file
    monkeypatch.delitem(sys.modules, "fingerpad.measure.importers.tribo", raising=False)
    yield folder
    sys.modules.pop("fingerpad.measure.importers.tribo", None)


def _recording_json(path, mu=0.45, load=1.2, n_strokes=6, fs=200.0):
    """Reciprocating strokes: friction force in mN (the unit in the channel name)."""
    v = np.concatenate([np.r_[np.zeros(20), (1 if j % 2 == 0 else -1) * 0.02 * np.sin(np.linspace(0, np.pi, 200))]
                        for j in range(n_strokes)] + [np.zeros(20)])
    rng = np.random.default_rng(0)
    fn = load * (1 + 0.005 * rng.standard_normal(v.size))
    ft = -np.tanh(v / 1e-3) * mu * fn
    data = {"time [s]": (np.arange(v.size) / fs).tolist(), "Fn [N]": fn.tolist(), "Ft [mN]": (1e3 * ft).tolist(),
            "x [mm]": (1e3 * np.cumsum(v) / fs).tolist()}
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def test_new_format_is_one_file(plugin, tmp_path):
    assert ".tribo" not in [s for imp in importers.importers() if imp.name != "tribo" for s in imp.suffixes]
    assert ".tribo" in m.supported_suffixes()
    path = _recording_json(tmp_path / "P1_flat_1.tribo")
    rec = m.read_recording(path, participant="P1", sample="flat")
    assert rec.friction.max() == pytest.approx(0.45 * 1.2, rel=0.02)  # mN -> N from the channel name
    strokes = m.measure_strokes(rec)
    assert len(strokes) == 6 and strokes["mu"].to_numpy() == pytest.approx(0.45, rel=0.02)
    # found in a folder by its suffix and file-name template, like every built-in format
    study = m.load_study([tmp_path])
    assert [(r.participant, r.sample) for r in study] == [("P1", "flat")]
    # the importer's own error, naming the file
    (tmp_path / "bad.tribo").write_text("{not json", encoding="utf-8")
    with pytest.raises(FingerpadError, match="not a .tribo file"):
        m.read_recording(tmp_path / "bad.tribo")


def test_without_the_file_the_format_is_unknown(tmp_path, monkeypatch):
    monkeypatch.setattr(importers, "_IMPORTERS", None)
    path = _recording_json(tmp_path / "P1_flat_1.tribo")
    assert ".tribo" not in m.supported_suffixes()
    with pytest.raises(FingerpadError, match="cannot read .tribo files"):
        m.read_recording(path)
