"""Medians and percentiles of large arrays, exactly NumPy's, in a fraction of the time.

NumPy partitions an array around one rank with a vectorised selection (x86-simd-sort),
but around several (a median's two middle values, a percentile's neighbours and the
ends, its NaN check) with the older introselect, ten times slower on a face's 250,000
noise values. Both functions here partition the array around one rank first, which
leaves its values the same, then ask NumPy's own function: the same result, bit for
bit (a median or a percentile depends on the values alone, not on their order). The
median asks it of its one or two middle values alone (the lower of two is the largest
below the rank partitioned around), as they would be averaged in the whole array.
"""

from __future__ import annotations

import numpy as np


def median(values: np.ndarray, axis: int | None = None) -> np.ndarray:
    """``np.median(values, axis)``, faster: of all the values, or (``axis=0``) of each column of a 2-D array.

    Examples
    --------
    >>> x = np.random.default_rng(0).normal(size=(1001, 2)).astype(np.float32)
    >>> bool(median(x) == np.median(x)), bool((median(x, 0) == np.median(x, 0)).all())
    (True, True)
    >>> median(np.array([1.0, 4.0, 2.0, 3.0]))
    np.float64(2.5)
    """
    values = np.asarray(values)
    if axis is not None:
        if axis != 0 or values.ndim != 2:
            raise ValueError("a median along an axis is of the columns of a 2-D array (axis 0)")
        if not len(values):
            return np.median(values, 0)
        return np.array([median(column) for column in values.T], np.median(values[:1], 0).dtype)
    flat = values.reshape(-1)
    n, k = len(flat), len(flat) // 2
    if not n:
        return np.median(flat)
    part = np.partition(flat, k)
    if part.dtype.kind in "fc" and np.isnan(part[k:].max()):  # any NaN lies above the rank: NumPy's median is NaN
        return np.median(part)
    return np.median(part[k : k + 1] if n % 2 else np.array([part[:k].max(), part[k]], part.dtype))


def percentile(values: np.ndarray, q: float) -> np.floating:
    """``np.percentile(values, q)`` of all the values (linear interpolation, ``q`` one number), faster.

    Examples
    --------
    >>> x = np.random.default_rng(0).normal(size=1001).astype(np.float32)
    >>> bool(percentile(x, 98) == np.percentile(x, 98))
    True
    """
    flat = np.asarray(values).reshape(-1)
    if len(flat) < 2:
        return np.percentile(flat, q)
    above = min(int(np.floor(q / 100 * (len(flat) - 1))) + 1, len(flat) - 1)  # the upper of the two values it blends
    return np.percentile(np.partition(flat, above), q)
