import numpy as np

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
