"""Reading quantities with units: exact values, clear errors."""

from __future__ import annotations

import math

import pytest

from fingerpad.errors import FingerpadError
from fingerpad.units import UNITS, format_quantity, parse_quantity, parse_range


@pytest.mark.parametrize(("text", "dimension", "plain"), [
    ("50um", "length", "5e-5"), ("200um", "length", "2e-4"), ("30 um", "length", "3e-5"),
    ("175µm", "length", "1.75e-4"), ("0.1mm", "length", "1e-4"), ("1.5e-3mm", "length", "1.5e-6"),
    ("80nm", "length", "8e-8"), ("2cm", "length", "0.02"), ("8.1kPa", "pressure", "8100"),
    ("0.3MPa", "pressure", "3e5"), ("2.4GPa", "pressure", "2.4e9"), ("-2mN", "force", "-0.002"),
    (".5um", "length", "5e-7"),
])
def test_a_prefixed_value_is_the_float_of_the_same_number_in_si(text, dimension, plain):
    # the same float bit for bit, not merely close: cache keys and file names follow the value
    assert parse_quantity(text, dimension) == float(plain)


def test_every_decimal_prefix_is_exact():
    """NUMBER + prefixed unit is the float literal NUMBERe<k>, for every power-of-ten unit."""
    for unit, (dimension, factor) in UNITS.items():
        if dimension == "angle":
            continue
        k = round(math.log10(factor))
        for number in ("1", "3", "7.3", "175", "0.3", "12.25"):
            assert parse_quantity(number + unit, dimension) == float(f"{number}e{k}"), (number, unit)


def test_angles_and_bare_numbers():
    assert parse_quantity("30deg", "angle") == math.radians(30)
    assert parse_quantity("0.5rad", "angle") == 0.5
    assert parse_quantity(2, "force") == 2.0
    assert parse_quantity("1e-3", "length") == 1e-3


@pytest.mark.parametrize(("text", "dimension", "needle"), [
    ("50uN", "length", "unknown unit"), ("2N", "length", "is a force, expected a length"),
    ("abc", "length", "cannot read"), ("1e400nm", "length", "not a finite number"),
    ("nan", "length", "cannot read"), (True, "length", "expected a number"),
])
def test_bad_quantities_are_clear_errors(text, dimension, needle):
    with pytest.raises(FingerpadError, match=needle):
        parse_quantity(text, dimension)


def test_ranges():
    assert parse_range("0.1N:4N:3", "force", log=True) == pytest.approx([0.1, math.sqrt(0.4), 4.0])
    assert parse_range("10kPa:30kPa:3", "pressure") == [1e4, 2e4, 3e4]
    assert parse_range("5um", "length") == [5e-6]
    for text, needle in [("4N:0.1N:3", "below START"), ("1N:2N:x", "integer"), ("1N:2N:0", "at least 1"),
                         ("0N:1N:3", "positive bounds"), ("1N:2N", "START:STOP:COUNT")]:
        with pytest.raises(FingerpadError, match=needle):
            parse_range(text, "force", log=True)


def test_format_reads_back():
    for value, dimension in [(5e-5, "length"), (8100.0, "pressure"), (0.002, "force")]:
        text = format_quantity(value, dimension, digits=12).replace(" ", "")
        assert parse_quantity(text, dimension) == pytest.approx(value, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# more: sizes, integers, positive values, linear ranges, formatting
# ---------------------------------------------------------------------------------------------


def test_linear_range_is_evenly_spaced():
    from fingerpad.units import parse_range as pr

    values = pr("1mm:2mm:5", "length")
    assert values == pytest.approx([1e-3, 1.25e-3, 1.5e-3, 1.75e-3, 2e-3], rel=1e-12)
    assert pr("1N:1N:1", "force") == [1.0]


def test_sizes_and_integers():
    from fingerpad.units import parse_int, parse_positive, parse_size

    assert parse_size("200um,100um") == (2e-4, 1e-4)
    assert parse_size("1mm") == (1e-3, 1e-3)
    for text in ("1mm,2mm,3mm", "0um", "-1mm"):
        with pytest.raises(FingerpadError, match="--size"):
            parse_size(text)
    assert parse_int("12", "--grid") == 12 and parse_int(7, "--grid") == 7
    for text in ("1.5", "x", "0"):
        with pytest.raises(FingerpadError, match="--grid"):
            parse_int(text, "--grid")
    assert parse_positive("3kPa", "pressure", name="--p") == 3e3
    with pytest.raises(FingerpadError, match="--p"):
        parse_positive("0kPa", "pressure", name="--p")


@pytest.mark.parametrize(("value", "dimension", "text"), [
    (5e-5, "length", "50 um"), (1.75e-4, "length", "175 um"), (2e-3, "length", "2 mm"),
    (8100.0, "pressure", "8.1 kPa"), (3e5, "pressure", "300 kPa"), (2.5e9, "pressure", "2.5 GPa"),
    (0.5, "force", "500 mN"), (2.0, "force", "2 N"),
])
def test_format_picks_a_readable_unit(value, dimension, text):
    assert format_quantity(value, dimension) == text


def test_per_cent_estimates_read_the_same_in_every_output():
    """One rule for an error estimate in per cent (the terminal's lines, predict's and a
    population's notes): two digits, '100' from 99.5 %, '>100' beyond, never '1.1e+02'."""
    from fingerpad.units import format_percent

    assert [format_percent(e) for e in (0.0123, 0.5, 0.996, 1.0, 1.1, 35.0)] == ["1.2", "50", "100", "100", ">100",
                                                                                  ">100"]
