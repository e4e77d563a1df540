"""Column specs of recordings: units to SI, header units, aliases, spec files, file-name templates."""

from __future__ import annotations

import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError


@pytest.mark.parametrize("unit, dimension, factor", [
    ("", "force", 1.0), ("N", "force", 1.0), ("mN", "force", 1e-3), ("uN", "force", 1e-6), ("cN", "force", 1e-2),
    ("gf", "force", 9.80665e-3), ("kgf", "force", 9.80665), ("lbf", "force", 4.4482216152605),
    ("ozf", "force", 4.4482216152605 / 16), ("newtons", "force", 1.0), ("Millinewton", "force", 1e-3),
    ("mm", "length", 1e-3), ("um", "length", 1e-6), ("metres", "length", 1.0),
    ("ms", "time", 1e-3), ("min", "time", 60.0), ("h", "time", 3600.0),
    ("mm/s", "velocity", 1e-3), ("m/min", "velocity", 1 / 60), ("um/ms", "velocity", 1e-3),
])
def test_unit_factors(unit, dimension, factor):
    assert m.unit_factor(unit, dimension) == pytest.approx(factor, rel=1e-14)


@pytest.mark.parametrize("unit, dimension, message", [
    ("g", "force", r"unknown force unit 'g' \(grams-force: write gf\)"),
    ("mm", "force", r"unknown force unit 'mm'"),
    ("N", "length", r"unknown length unit 'N'"),
    ("fortnight", "time", r"unknown time unit 'fortnight'"),
    ("mm", "velocity", r"unknown velocity unit 'mm' \(write LENGTH/TIME, e.g. mm/s\)"),
    ("mm/fortnight", "velocity", r"unknown time unit 'fortnight'"),
])
def test_unknown_units_named(unit, dimension, message):
    with pytest.raises(FingerpadError, match=r"^col Fn: " + message):
        m.unit_factor(unit, dimension, where="col Fn")


@pytest.mark.parametrize("unit, factor", [("seconds", 1.0), ("milliseconds", 1e-3), ("Second", 1.0)])
def test_spelled_out_time_units(unit, factor):
    assert m.unit_factor(unit, "time") == pytest.approx(factor)


def test_spec_refusals():
    for kwargs, message in ((dict(columns={"load": "Fz"}), "unknown quantity 'load' in the column mapping"),
                            (dict(units={"normal": "mm"}), "unit of normal: unknown force unit 'mm'"),
                            (dict(nan_policy="ignore"), "nan_policy must be 'raise' or 'drop'"),
                            (dict(skip_rows=-1), "skip_rows must be a non-negative integer"),
                            (dict(decimal=";"), "decimal must be '.' or ','"),
                            (dict(delimiter="::"), "delimiter must be one character"),
                            (dict(pattern="{participant"), "unbalanced braces")):
        with pytest.raises(FingerpadError, match=message):
            m.ColumnSpec(**kwargs)


def test_with_options_merges_mappings():
    spec = m.ColumnSpec(columns={"normal": "Fz"}, units={"normal": "mN"})
    merged = spec.with_options(columns={"friction": "Fx"}, units={"normal": "N", "friction": ""}, delimiter=None,
                               skip_rows=2)
    assert merged.columns == {"normal": "Fz", "friction": "Fx"}
    assert merged.units == {"normal": "N"}  # an empty value does not replace
    assert merged.skip_rows == 2 and merged.delimiter is None
    assert spec.skip_rows == 0, "the original is unchanged"


def test_spec_file(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_text('[columns]\nnormal = "Fz"\nfriction = "Fx"\n[units]\nnormal = "mN"\ntime = "ms"\n'
                    '[files]\ndelimiter = "tab"\ndecimal = ","\nskip_rows = 3\ninvert_normal = true\n'
                    'pattern = "{participant}_{sample}_{direction}_{repetition}.csv"\nnan_policy = "drop"\n')
    spec = m.load_spec(path)
    assert spec.columns == {"normal": "Fz", "friction": "Fx"} and spec.units == {"normal": "mN", "time": "ms"}
    assert (spec.delimiter, spec.decimal, spec.skip_rows, spec.invert_normal, spec.nan_policy) == \
        ("\t", ",", 3, True, "drop")


@pytest.mark.parametrize("content, message", [
    ("[colums]\nnormal = 'Fz'\n", r"unknown section\(s\) colums"),
    ("[files]\nskip = 3\n", r"unknown key\(s\) skip in \[files\]"),
    ("[columns]\nnormal = 3\n", r"\[columns\] must map quantities to strings"),
    ("[units]\nnormal = 'stone'\n", r"spec\.toml: unit of normal: unknown force unit 'stone'"),
    ("[columns\n", r"^column spec '.*spec\.toml': Expected '\]'"),
])
def test_bad_spec_files_named(tmp_path, content, message):
    path = tmp_path / "spec.toml"
    path.write_text(content)
    with pytest.raises(FingerpadError, match=message):
        m.load_spec(path)
    with pytest.raises(FingerpadError, match=r"^cannot read column spec '.*none\.toml': no such file$"):
        m.load_spec(tmp_path / "none.toml")


@pytest.mark.parametrize("path, template, expected", [
    ("P01_glass_2.csv", "{participant}_{sample}_{repetition}.*", {"participant": "P01", "sample": "glass",
                                                                   "repetition": "2"}),
    ("data/P01/bumps_1.xlsx", "{participant}/{sample}_{repetition}.xlsx", {"participant": "P01", "sample": "bumps",
                                                                           "repetition": "1"}),
    ("S3-P7-flat-fwd.csv", "S{session}-{participant}-{sample}-{direction}.csv",
     {"session": "3", "participant": "P7", "sample": "flat", "direction": "fwd"}),
    ("P1_ab12_3.csv", "{participant}_{sample:[a-z]+\\d+}_{repetition:\\d+}.csv",
     {"participant": "P1", "sample": "ab12", "repetition": "3"}),
    ("P1_x_y_2.csv", "{participant}_{note}_{sample}_{repetition}.csv",
     {"participant": "P1", "sample": "y", "repetition": "2"}),  # unknown fields are matched and left out
    ("readme.txt", "{participant}_{sample}_{repetition}.*", None),
])
def test_file_name_templates(path, template, expected):
    assert m.parse_filename(path, template) == expected


def test_template_refusals():
    with pytest.raises(FingerpadError, match=r"field \{sample\} appears twice"):
        m.template_regex("{sample}_{sample}.csv")
    with pytest.raises(FingerpadError, match="invalid"):
        m.template_regex("{sample:[}.csv")
    # literal dots and brackets are literal, * is the only wildcard
    rx = m.template_regex("{participant}.(1)*")
    assert rx.fullmatch("P1.(1)anything") and not rx.fullmatch("P1x(1)")
