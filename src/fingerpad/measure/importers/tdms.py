"""LabVIEW TDMS files (``.tdms``) read with npTDMS.

The channels of one group become the columns (the group named by the spec's ``sheet``, else
the first group with two or more channels). A channel's ``unit_string`` property gives its
unit. Without a time channel, the waveform properties (``wf_increment``, ``wf_start_offset``)
of the channels give one, in seconds. Rows in messages are sample numbers (1-based). The
``.tdms_index`` files LabVIEW writes beside the data are not recordings.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import FingerpadError
from ...extras import load
from . import Importer, RawTable

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def read_tdms_table(path: Path, spec: "ColumnSpec") -> RawTable:
    TdmsFile = load("nptdms", f"{path}: reading LabVIEW files").TdmsFile
    try:
        tdms = TdmsFile.read(str(path))
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except Exception as exc:  # npTDMS raises ValueError, struct.error, ... for a bad file
        raise FingerpadError(f"{path}: cannot read as a LabVIEW TDMS file ({type(exc).__name__}: {exc})") from None
    groups = tdms.groups()
    names = [g.name for g in groups]
    if spec.sheet is not None:
        if spec.sheet not in names:
            raise FingerpadError(f"{path}: no group {spec.sheet!r} (groups: {', '.join(names) or 'none'})")
        group = tdms[spec.sheet]
    else:
        group = next((g for g in groups if len(g.channels()) >= 2), None)
        if group is None:
            raise FingerpadError(f"{path}: no group with two or more channels (groups: {', '.join(names) or 'none'})")
    channels = [c for c in group.channels() if c.data.dtype.kind in "fiub"]
    if not channels:
        raise FingerpadError(f"{path}: group {group.name!r} has no numeric channels")
    n = len(channels[0])
    short = [c.name for c in channels if len(c) != n]
    if short:
        raise FingerpadError(f"{path}: channels of group {group.name!r} differ in length "
                             f"({channels[0].name}: {n}; {', '.join(short)} differ)")
    header = [c.name for c in channels]
    columns = [np.asarray(c[:], dtype=float) for c in channels]
    units = [str(c.properties.get("unit_string", "") or "") for c in channels]
    keys = {h.strip().lower() for h in header}
    if not keys & {"time", "t", "timestamp", "time_s"} and "wf_increment" in channels[0].properties:
        try:
            columns.insert(0, np.asarray(channels[0].time_track(), dtype=float))
            header.insert(0, "time")
            units.insert(0, "s")
        except (KeyError, ValueError, TypeError):
            pass  # no usable waveform timing: the recording has no time column
    return RawTable(header=header, columns=columns, rows=np.arange(1, n + 1), units=units, row_word="sample")


IMPORTER = Importer(name="tdms", suffixes=(".tdms",), read_table=read_tdms_table)
