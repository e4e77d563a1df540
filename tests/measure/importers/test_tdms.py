"""LabVIEW .tdms recordings written by npTDMS: channel units, waveform timing, groups."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError

from .sample import FORCE_UNITS, FRICTION, N_ROWS, NORMAL, POSITION_MM, TIME, check_si

nptdms = pytest.importorskip("nptdms")


def write(path, unit: str, *, with_time: bool = True, group: str = "run", extra_groups=()):
    chans = []
    if with_time:
        chans.append(nptdms.ChannelObject(group, "time", TIME, properties={"unit_string": "s"}))
    waveform = {} if with_time else {"wf_increment": 0.01, "wf_start_offset": 0.0}
    for name, values, u in (("Fn", NORMAL, unit), ("Ft", FRICTION, unit), ("x", POSITION_MM, "mm")):
        chans.append(nptdms.ChannelObject(group, name, values, properties={"unit_string": u, **waveform}))
    with nptdms.TdmsWriter(str(path)) as w:
        for g, objects in extra_groups:
            w.write_segment([nptdms.GroupObject(g), *objects])
        w.write_segment([nptdms.GroupObject(group), *chans])


@pytest.mark.parametrize("unit", list(FORCE_UNITS))
def test_tdms_sample_in_si(tmp_path, unit):
    path = tmp_path / "run.tdms"
    write(path, unit)
    table = m.read_table(path, m.ColumnSpec())
    assert table.header == ["time", "Fn", "Ft", "x"]
    assert table.units == ["s", unit, unit, "mm"]
    assert table.row_word == "sample"
    check_si(m.read_recording(path), unit)


def test_time_channel_in_spelled_out_seconds(tmp_path):
    path = tmp_path / "run.tdms"
    chans = [nptdms.ChannelObject("run", "time", TIME, properties={"unit_string": "seconds"}),
             nptdms.ChannelObject("run", "Fn", NORMAL, properties={"unit_string": "newtons"}),
             nptdms.ChannelObject("run", "Ft", FRICTION, properties={"unit_string": "newtons"}),
             nptdms.ChannelObject("run", "x", POSITION_MM, properties={"unit_string": "millimetres"})]
    with nptdms.TdmsWriter(str(path)) as w:
        w.write_segment([nptdms.GroupObject("run"), *chans])
    check_si(m.read_recording(path), "N")


def test_spelled_out_force_and_length_units(tmp_path):
    path = tmp_path / "run.tdms"
    chans = [nptdms.ChannelObject("run", "time", TIME, properties={"unit_string": "s"}),
             nptdms.ChannelObject("run", "Fn", NORMAL, properties={"unit_string": "millinewtons"}),
             nptdms.ChannelObject("run", "Ft", FRICTION, properties={"unit_string": "millinewtons"}),
             nptdms.ChannelObject("run", "x", POSITION_MM, properties={"unit_string": "millimetres"})]
    with nptdms.TdmsWriter(str(path)) as w:
        w.write_segment([nptdms.GroupObject("run"), *chans])
    check_si(m.read_recording(path), "mN")


def test_time_from_waveform_properties(tmp_path):
    path = tmp_path / "run.tdms"
    write(path, "mN", with_time=False)
    table = m.read_table(path, m.ColumnSpec())
    assert table.header[0] == "time" and table.units[0] == "s"
    check_si(m.read_recording(path), "mN")


def test_group_by_name_and_first_useful_group(tmp_path):
    path = tmp_path / "run.tdms"
    notes = [nptdms.ChannelObject("notes", "temperature", np.array([21.5]))]
    write(path, "N", group="trial", extra_groups=[("notes", notes)])
    # the first group with two or more channels is taken
    check_si(m.read_recording(path), "N")
    check_si(m.read_recording(path, m.ColumnSpec(sheet="trial")), "N")
    with pytest.raises(FingerpadError, match=r"no group 'nope' \(groups: notes, trial\)"):
        m.read_table(path, m.ColumnSpec(sheet="nope"))


def test_channels_of_different_length_refused(tmp_path):
    path = tmp_path / "run.tdms"
    chans = [nptdms.ChannelObject("run", "Fn", NORMAL), nptdms.ChannelObject("run", "Ft", FRICTION[:-2])]
    with nptdms.TdmsWriter(str(path)) as w:
        w.write_segment([nptdms.GroupObject("run"), *chans])
    with pytest.raises(FingerpadError, match=rf"differ in length \(Fn: {N_ROWS}; Ft differ\)"):
        m.read_table(path, m.ColumnSpec())


def test_no_useful_group_refused(tmp_path):
    path = tmp_path / "run.tdms"
    with nptdms.TdmsWriter(str(path)) as w:
        w.write_segment([nptdms.GroupObject("only"), nptdms.ChannelObject("only", "Fn", NORMAL)])
    with pytest.raises(FingerpadError, match="no group with two or more channels"):
        m.read_table(path, m.ColumnSpec())


def test_garbage_refused(tmp_path):
    path = tmp_path / "bad.tdms"
    path.write_bytes(b"a spreadsheet saved with the wrong suffix" * 3)
    with pytest.raises(FingerpadError, match=r"bad\.tdms: cannot read as a LabVIEW TDMS file"):
        m.read_table(path, m.ColumnSpec())
    # the right lead-in with nothing readable after it: still one user error naming the file
    path.write_bytes(b"TDSm" + b"\xff" * 60)
    with pytest.raises(FingerpadError, match=r"bad\.tdms: "):
        m.read_table(path, m.ColumnSpec())
