import numpy as np
import pytest

from exprclone.geometry import global_warp
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68


def test_no_motion_gives_the_target(pair_points):
    (sn, _, tn), _ = pair_points
    assert np.allclose(global_warp.global_landmarks(sn, sn, tn, DLIB68), tn)


def test_head_motion_alone_is_not_an_expression(pair_points):
    (sn, _, tn), _ = pair_points
    turned = align.apply(np.array([[0.98, -0.17, 30.0], [0.17, 0.98, -12.0]]), sn)
    assert np.allclose(global_warp.global_landmarks(sn, turned, tn, DLIB68), tn, atol=1e-6)


def test_motion_is_scaled_and_rotated_into_the_target(pair_points):
    (sn, se, _), _ = pair_points
    t = np.array([[0.0, -1.5, 900.0], [1.5, 0.0, 100.0]])  # target = source turned 90 degrees, 1.5x
    tn = align.apply(t, sn)
    motion = global_warp.remove_head_motion(sn, se, DLIB68) - sn
    assert np.allclose(global_warp.global_landmarks(sn, se, tn, DLIB68) - tn, motion @ t[:, :2].T, atol=1e-6)


def test_real_smile_widens_the_target_mouth(pair_points):
    (sn, se, tn), _ = pair_points
    gl = global_warp.global_landmarks(sn, se, tn, DLIB68)
    width = lambda p: np.linalg.norm(p[54] - p[48])  # noqa: E731
    assert width(se) / width(sn) > 1.05  # the source really smiles
    assert width(gl) / width(tn) > 1.05


def test_rbf_transfer_with_no_motion_gives_the_target(pair_points):
    (sn, _, tn), _ = pair_points
    assert np.allclose(global_warp.rbf_landmarks(sn, sn, tn, DLIB68), tn, atol=1e-9)


def test_rbf_transfer_of_a_scaled_and_rotated_target_is_the_similarity_transfer(pair_points):
    (sn, se, _), _ = pair_points
    t = np.array([[0.0, -1.5, 900.0], [1.5, 0.0, 100.0]])  # target = source turned 90 degrees, 1.5x
    tn = align.apply(t, sn)
    assert np.allclose(global_warp.rbf_landmarks(sn, se, tn, DLIB68), global_warp.global_landmarks(sn, se, tn, DLIB68), atol=1e-6)
    assert np.allclose(global_warp.rbf_jacobians(sn, tn, DLIB68), t[:, :2], atol=1e-7)


def test_rbf_transfer_scales_the_motion_to_a_wider_mouth(pair_points):
    """A target that is the source with a mouth 30% wider, and a source whose mouth widens by 10%: the similarity
    transfer carries the motion as it is (scaled by the whole face), the RBF transfer widens it, though by less than
    the mouth is wider: the mouth corners, which move most, sit where the stretch of the mouth meets the unstretched
    cheeks, and the map's Jacobian there is close to 1 (about 9% wider here), and the map's smoothing takes some of it."""
    (sn, se, _), _ = pair_points
    mouth = list(DLIB68.mouth_outer + DLIB68.mouth_inner)
    tn = sn.copy()
    centre = sn[mouth].mean(0)
    tn[mouth, 0] = centre[0] + 1.3 * (sn[mouth, 0] - centre[0])
    sideways = np.zeros_like(sn)
    sideways[mouth, 0] = sn[mouth, 0] - centre[0]  # the mouth widening by its own width
    source_expression = sn + 0.1 * sideways
    similarity = global_warp.global_landmarks(sn, source_expression, tn, DLIB68) - tn
    rbf = global_warp.rbf_landmarks(sn, source_expression, tn, DLIB68) - tn
    widening = lambda motion: np.sum(motion[mouth, 0] * sideways[mouth, 0]) / np.sum(0.1 * sideways[mouth, 0] ** 2)  # noqa: E731
    assert widening(similarity) == pytest.approx(1.0, abs=0.02)
    assert widening(similarity) + 0.05 < widening(rbf) < 1.3
    mouth_jacobian = global_warp.rbf_jacobians(sn, tn, DLIB68)[mouth, 0, 0].mean()
    assert 1.15 < mouth_jacobian < 1.3  # inside the mouth, most of the 30%
    # the eyes, far from the mouth, are carried as by the similarity
    eyes = [i for eye in DLIB68.eyes for i in eye]
    assert np.allclose(global_warp.rbf_jacobians(sn, tn, DLIB68)[eyes], np.eye(2), atol=0.05)
