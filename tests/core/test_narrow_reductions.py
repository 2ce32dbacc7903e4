"""Reductions over a few columns or corners, worked out a column at a time for speed
(core/arrays/reduce.py, core/arrays/geometry2d.py's corner extremes): the same values as numpy's, to the bit."""

import numpy as np
import pytest

from seamless_ao.core.arrays.geometry2d import corner_max, corner_min
from seamless_ao.core.arrays.reduce import column_max, column_min, row_all, row_any, row_length, row_max


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int64])
def test_narrow_reductions_are_numpys_along_each_axis_nan_and_all(dtype):
    values = (np.random.default_rng(3).normal(size=(1000, 3)) * 100).astype(dtype)
    if dtype != np.int64:
        values[7, 1] = np.nan                                # numpy's answer in that row and column is NaN
        values[9] = [-0.0, 0.0, -0.0]
    for ours, numpys in ((column_min, lambda v: v.min(axis=0)), (column_max, lambda v: v.max(axis=0)),
                         (row_max, lambda v: v.max(axis=1))):
        got, expected = ours(values), numpys(values)
        assert got.dtype == expected.dtype and got.shape == expected.shape
        assert np.array_equal(got.view(np.uint8), expected.view(np.uint8)), ours.__name__


@pytest.mark.parametrize("columns", [1, 2, 3])
def test_row_all_and_any_are_numpys(columns):
    values = np.random.default_rng(columns).random((1000, columns)) < 0.6
    given = values.copy()
    for ours, numpys in ((row_all, lambda v: v.all(axis=1)), (row_any, lambda v: v.any(axis=1))):
        got, expected = ours(values), numpys(values)
        assert got.dtype == expected.dtype and np.array_equal(got, expected), ours.__name__
        assert 0 < got.sum() < len(got) and np.array_equal(values, given)       # the input left as it was
        assert np.array_equal(ours(values[:0]), numpys(values[:0]))


@pytest.mark.parametrize("shape", [(1000, 3, 2), (1000, 2, 3), (1000, 3), (1000, 2), (0, 3, 2)])
def test_corner_extremes_are_numpys_over_the_corners(shape):
    values = np.random.default_rng(5).normal(size=shape)
    if values.size:
        values[3, 1] = np.nan
    for ours, numpys in ((corner_min, lambda v: v.min(axis=1)), (corner_max, lambda v: v.max(axis=1))):
        got, expected = ours(values), numpys(values)
        assert got.shape == expected.shape and np.array_equal(got, expected, equal_nan=True), ours.__name__


@pytest.mark.parametrize("scale", [1e-150, 1.0, 1e150])
def test_row_length_is_numpys_norm_to_the_bit(scale):
    vectors = np.random.default_rng(7).normal(size=(1000, 3)) * scale
    assert np.array_equal(row_length(vectors).view(np.uint64), np.linalg.norm(vectors, axis=1).view(np.uint64))

