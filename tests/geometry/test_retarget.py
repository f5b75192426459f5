"""The source's motion cleaned, and the organs the local stage aims at (retarget.py)."""

import numpy as np
import pytest

from exprclone.geometry import global_warp, local_warp, retarget
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68

RIGID = list(DLIB68.rigid)
MOUTH = list(DLIB68.mouth_outer + DLIB68.mouth_inner)
#: the target is the source turned by 20 degrees, 1.7 times as large, and moved
SCALED = np.array([[1.7 * np.cos(0.35), -1.7 * np.sin(0.35), 300.0], [1.7 * np.sin(0.35), 1.7 * np.cos(0.35), -40.0]])


def test_a_scaled_target_gets_the_motion_scaled_alike(pair_points):
    (sn, se, _), _ = pair_points
    tn = align.apply(SCALED, sn)
    cleaned = retarget.clean(sn, se, DLIB68)
    motion = (cleaned - sn) @ SCALED[:, :2].T  # the source's (cleaned) motion, turned and scaled
    assert np.abs(motion).max() > 20  # a real smile: there is motion to scale
    assert np.allclose(global_warp.global_landmarks(sn, cleaned, tn, DLIB68) - tn, motion, atol=1e-6)
    organs = sorted(set().union(*DLIB68.organs.values()))
    reference = retarget.organ_reference(sn, cleaned, tn, DLIB68)
    assert np.allclose(reference[organs] - tn[organs], motion[organs], atol=1e-6)
    # so the local stage has nothing to re-shape: the target's organs already move as the source's
    gl = global_warp.global_landmarks(sn, cleaned, tn, DLIB68)
    assert np.allclose(local_warp.local_landmarks(gl, reference, DLIB68), gl, atol=1e-6)


def test_rigid_points_stay_rigid_and_the_smile_stays(pair_points):
    (sn, se, _), _ = pair_points
    iod = align.interocular(sn, DLIB68)
    raw = global_warp.remove_head_motion(sn, se, DLIB68) - sn
    cleaned = retarget.clean(sn, se, DLIB68) - sn
    rigid_raw, rigid_cleaned = (np.linalg.norm(m[RIGID], axis=1) / iod for m in (raw, cleaned))
    assert rigid_raw.max() > 2 * retarget.FRAME_NOISE  # the fitter scattered them
    # and that scatter is not transferred: each moves less, and together less than half as much
    assert (rigid_cleaned < rigid_raw).all() and np.linalg.norm(rigid_cleaned) < 0.5 * np.linalg.norm(rigid_raw)
    # the mouth's own motion is kept: the corners move as far apart, and the lips as far
    width = lambda m: np.linalg.norm((sn + m)[54] - (sn + m)[48])  # noqa: E731
    assert width(raw) > 1.05 * width(0 * raw)
    assert width(cleaned) == pytest.approx(width(raw), rel=0.02)
    # up to the head's motion taken out again, the mouth loses only what is lopsided
    centred = lambda m: m[MOUTH] - m[MOUTH].mean(0)  # noqa: E731
    assert np.linalg.norm(centred(cleaned) - centred(raw), axis=1).max() < retarget.ASYMMETRY_NOISE * iod


def test_a_wink_is_kept_and_a_head_turn_is_not_an_expression(pair_points):
    (sn, _, _), _ = pair_points
    iod = align.interocular(sn, DLIB68)
    down = align.face_axes(sn, DLIB68)[1]
    wink = sn.copy()
    wink[[37, 38]] += 0.08 * iod * down  # the right upper lid closes
    cleaned = retarget.clean(sn, wink, DLIB68) - sn
    lid = cleaned[[37, 38]] @ down
    # half of a one-sided motion is lopsided: it loses ASYMMETRY_NOISE, and the other eye gains the rest
    assert lid == pytest.approx(0.08 * iod - retarget.ASYMMETRY_NOISE * iod, rel=1e-6)
    assert np.allclose(cleaned[[44, 43]] @ down, retarget.ASYMMETRY_NOISE * iod, rtol=1e-6)
    turned = align.apply(np.array([[0.98, -0.17, 30.0], [0.17, 0.98, -12.0]]), sn)
    assert np.allclose(retarget.clean(sn, turned, DLIB68), sn, atol=1e-6)


def test_the_target_keeps_its_own_organs(pair_points):
    """Without motion the local stage aims at the target's own organs, not the source's."""
    (sn, se, tn), _ = pair_points
    assert np.allclose(retarget.organ_reference(sn, sn, tn, DLIB68), tn, rtol=0, atol=1e-9)
    # a source whose nose does not move leaves the target's nose as it is, whatever its shape
    cleaned = retarget.clean(sn, se, DLIB68)
    nose = list(DLIB68.nose)
    still = cleaned.copy()
    still[nose] = sn[nose]
    assert np.allclose(retarget.organ_reference(sn, still, tn, DLIB68)[nose], tn[nose])
    assert not np.allclose(retarget.organ_reference(sn, cleaned, tn, DLIB68)[MOUTH], tn[MOUTH])


def test_mirror_table_is_a_reflection():
    mirror = np.array(DLIB68.mirror)
    assert sorted(mirror) == list(range(DLIB68.n_points)) and np.array_equal(mirror[mirror], np.arange(DLIB68.n_points))
    # a symmetric face, reflected by the table, is itself
    x = np.linspace(-1, 1, DLIB68.n_points)
    face = np.column_stack([x - x[mirror], np.arange(DLIB68.n_points) + np.arange(DLIB68.n_points)[mirror]])
    assert np.allclose(face[mirror] * (-1, 1), face)
