"""Reductions over a few columns or corners, worked out a column at a time for speed
(core/arrays/reduce.py, core/arrays/geometry2d.py's corner extremes): the same values as numpy's, to the bit."""

import numpy as np
import pytest

from seamless_ao.core.arrays.geometry2d import corner_max, corner_min
from seamless_ao.core.arrays.reduce import column_max, column_min, row_length, row_max


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


def test_put_pairs_writes_what_numpy_assignment_writes_repeats_and_rounding_included():
    """Pairs scattered as single 8-byte items equal numpy's row assignment bit for bit: float64 pairs rounded
    to float32, repeated indices (the last pair kept), a (t, 3) index with (t, 3, 2) pairs (a mesh's corners),
    NaN and -0.0; a target that is not C-contiguous (n, 2) float32 is refused."""
    from seamless_ao.core.arrays.reduce import put_pairs
    rng = np.random.default_rng(3)
    index = rng.integers(0, 50, (40, 3))                             # repeats certain: 120 writes into 50
    pairs = rng.normal(0, 1, (40, 3, 2)) * 10.0 ** rng.integers(-8, 8, (40, 3, 1))
    pairs[0, 0] = (np.nan, -0.0)
    expected = np.full((50, 2), 7.0, dtype=np.float32)
    expected[index.ravel()] = pairs.reshape(-1, 2)
    target = np.full((50, 2), 7.0, dtype=np.float32)
    put_pairs(target, index, pairs)
    assert np.array_equal(target.view(np.uint32), expected.view(np.uint32))
    for wrong in (np.zeros((50, 2)), np.zeros((50, 3), dtype=np.float32), np.zeros((2, 50), dtype=np.float32).T):
        with pytest.raises(ValueError):
            put_pairs(wrong, index, pairs)
