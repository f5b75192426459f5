import numpy as np
import pytest

from exprclone import lips
from exprclone.layout import DLIB68


def test_crossed_inner_lips_close_and_open_ones_stay(pair):
    _, (_, se, tn) = pair
    crossed = tn.copy()
    crossed[[61, 62, 63], 1] += 3
    crossed[[67, 66, 65], 1] -= 3
    fixed = lips.uncross(crossed, DLIB68)
    for upper, lower in DLIB68.lip_pairs:
        assert fixed[upper, 1] <= fixed[lower, 1] + 1e-9
    others = [i for i in range(68) if i not in (61, 62, 63, 65, 66, 67)]
    assert np.array_equal(fixed[others], crossed[others])
    opened = tn.copy()
    opened[[61, 62, 63], 1] -= 5
    assert np.array_equal(lips.uncross(opened, DLIB68), opened)


def test_inner_lips_never_outside_the_outer_lips(pair):
    _, (_, se, tn) = pair
    wild = tn.copy()
    wild[62, 1] = tn[51, 1] - 6  # upper inner lip above the upper outer lip
    wild[66, 1] = tn[57, 1] + 4  # lower inner lip below the lower outer lip
    fixed = lips.uncross(wild, DLIB68)
    for top, upper, lower, bottom in DLIB68.lip_columns:
        assert fixed[top, 1] <= fixed[upper, 1] + 1e-9 <= fixed[lower, 1] + 2e-9 <= fixed[bottom, 1] + 3e-9
    assert fixed[62, 1] == pytest.approx(tn[51, 1], abs=0.05) and fixed[66, 1] == pytest.approx(tn[57, 1], abs=0.05)
    assert np.array_equal(lips.uncross(se, DLIB68)[48:60], se[48:60])  # the outer lips never move
