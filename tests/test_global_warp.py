import numpy as np

from exprclone import geometry, global_warp
from exprclone.layout import DLIB68


def test_no_motion_gives_the_target(pair_points):
    (sn, _, tn), _ = pair_points
    assert np.allclose(global_warp.global_landmarks(sn, sn, tn, DLIB68), tn)


def test_head_motion_alone_is_not_an_expression(pair_points):
    (sn, _, tn), _ = pair_points
    turned = geometry.apply(np.array([[0.98, -0.17, 30.0], [0.17, 0.98, -12.0]]), sn)
    assert np.allclose(global_warp.global_landmarks(sn, turned, tn, DLIB68), tn, atol=1e-6)


def test_motion_is_scaled_and_rotated_into_the_target(pair_points):
    (sn, se, _), _ = pair_points
    t = np.array([[0.0, -1.5, 900.0], [1.5, 0.0, 100.0]])  # target = source turned 90 degrees, 1.5x
    tn = geometry.apply(t, sn)
    motion = global_warp.remove_head_motion(sn, se, DLIB68) - sn
    assert np.allclose(global_warp.global_landmarks(sn, se, tn, DLIB68) - tn, motion @ t[:, :2].T, atol=1e-6)


def test_real_smile_widens_the_target_mouth(pair_points):
    (sn, se, tn), _ = pair_points
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    width = lambda p: np.linalg.norm(p[54] - p[48])  # noqa: E731
    assert width(se) / width(sn) > 1.05  # the source really smiles
    assert width(gl) / width(tn) > 1.05
