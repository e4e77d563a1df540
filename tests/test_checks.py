"""Input checks shared by the physics: every bad number is a FingerpadError naming the quantity."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.checks import as_areas, as_loads, nonnegative, positive, scalar_out
from fingerpad.errors import FingerpadError, describe_exception, one_line


@pytest.mark.parametrize("value", [1, 2.5, np.float32(3.0), np.int64(4)])
def test_positive_accepts_numbers(value):
    assert positive(value, "x") == float(value) and isinstance(positive(value, "x"), float)


@pytest.mark.parametrize("value", [0, -1.0, math.nan, math.inf, True, "1", None, [1.0]])
def test_positive_refuses(value):
    with pytest.raises(FingerpadError, match=r"^spacing must be a positive number, got "):
        positive(value, "spacing")


def test_nonnegative():
    assert nonnegative(0, "x") == 0.0
    for value in (-1e-300, math.nan, False):
        with pytest.raises(FingerpadError, match="must be a non-negative number"):
            nonnegative(value, "x")


def test_as_loads():
    np.testing.assert_array_equal(as_loads([0.0, 1.0]), [0.0, 1.0])
    assert as_loads(2).shape == ()
    with pytest.raises(FingerpadError, match="load must be positive, got a minimum of 0"):
        as_loads([0.0, 1.0], strict=True)
    with pytest.raises(FingerpadError, match="force must be non-negative, got a minimum of -2"):
        as_loads([-2.0, 1.0], "force")
    with pytest.raises(FingerpadError, match="load holds NaN or infinite values"):
        as_loads([1.0, math.inf])
    with pytest.raises(FingerpadError, match="load must be a number or an array of numbers"):
        as_loads("heavy")


def test_as_areas_and_scalar_out():
    with pytest.raises(FingerpadError, match="ridge area must be positive"):
        as_areas([1e-4, 0.0])
    assert isinstance(scalar_out(np.float64(2.0)), float)
    assert isinstance(scalar_out(np.array(2.0)), float)
    out = scalar_out(np.array([2.0]))
    assert isinstance(out, np.ndarray) and out.shape == (1,)


def test_error_messages_on_one_line():
    assert one_line("first\n  second \n\nthird") == "first second third"
    assert one_line("\n \n") == "unknown error"
    exc = FileNotFoundError(2, "No such file or directory", "/data/x.csv")
    assert describe_exception(exc) == "No such file or directory: /data/x.csv"
    assert describe_exception(PermissionError(13, "Permission denied")) == "Permission denied"
    assert describe_exception(FingerpadError("bad")) == "bad"
    assert issubclass(FingerpadError, ValueError)
