import cv2
import numpy as np
import pytest

from exprclone import eri, geometry, warp
from exprclone.layout import DLIB68


def test_same_photo_twice_gives_ratio_one(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = warp.build_mesh(lm, target.shape, DLIB68)
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    ratio = eri.expression_ratio(target, target, mask, geometry.interocular(lm, DLIB68))
    assert np.allclose(ratio, 1.0)
    assert np.array_equal(eri.apply_details(target, ratio), target)


def test_mask_is_one_on_the_cheeks_and_zero_off_the_face_and_in_the_eyes(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = warp.build_mesh(lm, target.shape, DLIB68)
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    cheek = ((lm[2] + lm[31]) / 2).round().astype(int)
    eye = lm[36:42].mean(0).round().astype(int)
    assert mask[cheek[1], cheek[0]] > 0.99
    assert mask[eye[1], eye[0]] < 0.3
    assert mask[5, 5] == 0 and mask[-5, -5] == 0
    assert 0 <= mask.min() and mask.max() <= 1


def test_dark_pixels_give_finite_clamped_ratios():
    black = np.zeros((64, 64, 3), np.uint8)
    white = np.full((64, 64, 3), 255, np.uint8)
    mask = np.ones((64, 64), np.float32)
    for a, b in ((black, white), (white, black), (black, black)):
        r = eri.expression_ratio(a, b, mask, 100.0)
        assert np.isfinite(r).all() and r.min() >= eri.CLAMP[0] and r.max() <= eri.CLAMP[1]


def test_local_shading_is_transferred_and_exposure_is_not(pair):
    (_, _, target), (_, _, lm) = pair
    iod = geometry.interocular(lm, DLIB68)
    x, y = ((lm[2] + lm[31]) / 2).round().astype(int)  # a cheek
    fold = (slice(y - 40, y + 40), slice(x - 40, x + 40))
    shaded = target.copy()
    shaded[fold] = (shaded[fold] * 0.8).astype(np.uint8)  # a fold darkens the cheek
    face = np.zeros(target.shape[:2], np.float32)
    face[int(lm[19, 1]) : int(lm[8, 1]), int(lm[0, 0]) : int(lm[16, 0])] = 1
    out = eri.apply_details(target, eri.expression_ratio(target, shaded, face, iod))
    patch = (slice(y - 20, y + 20), slice(x - 20, x + 20))
    assert out[patch].astype(float).mean() / target[patch].mean() == pytest.approx(0.8, abs=0.03)
    nose = (slice(int(lm[30, 1]) - 10, int(lm[30, 1]) + 10), slice(int(lm[30, 0]) - 10, int(lm[30, 0]) + 10))
    assert np.abs(out[nose].astype(float) - target[nose]).mean() < 1.5  # untouched elsewhere
    # the same darkening over the whole photo is exposure, not expression
    darker = (target * 0.8).astype(np.uint8)
    assert np.allclose(eri.expression_ratio(target, darker, face, iod), 1.0, atol=0.02)


def test_texture_confidence_trusts_skin_not_hair(pair):
    (_, _, target), (_, _, lm) = pair
    iod = geometry.interocular(lm, DLIB68)
    conf = eri.texture_confidence(eri.luminance(target), iod)
    cheek = ((lm[2] + lm[31]) / 2).round().astype(int)
    hair = np.array([lm[19, 0], lm[19, 1] - 0.3 * iod]).round().astype(int)  # 003 wears a fringe
    assert conf[cheek[1], cheek[0]] > 0.9
    assert conf[hair[1], hair[0]] < 0.2
    assert conf.min() >= 0 and conf.max() <= 1


def test_filters_on_the_shrunk_grid_match_full_resolution(pair, monkeypatch):
    """The ERI is smooth at FILTER_SIGMA, so computing it shrunk and enlarging it changes little."""
    (sn, se, target), (sn_lm, se_lm, lm) = pair
    mesh = warp.build_mesh(lm, target.shape, DLIB68)
    iod = geometry.interocular(lm, DLIB68)
    ctrl = [mesh.control_points(p, geometry.fit_similarity(lm[list(DLIB68.rigid)], p[list(DLIB68.rigid)])) for p in (sn_lm, se_lm)]
    box = (slice(300, 1200), slice(250, 1100))
    local = mesh.points - (box[1].start, box[0].start)
    shape = (box[0].stop - box[0].start, box[1].stop - box[1].start)
    neutral, expression = (warp.warp(im, c, local, mesh.triangles, shape) for im, c in zip((sn, se), ctrl))
    mask = eri.ratio_mask(shape, local[: mesh.n_landmarks], local[mesh.forehead], DLIB68)
    assert eri.filter_step(iod) >= 2
    shrunk = eri.expression_ratio(neutral, expression, mask, iod)
    monkeypatch.setattr(eri, "FILTER_PIXELS", np.inf)
    assert eri.filter_step(iod) == 1
    full = eri.expression_ratio(neutral, expression, mask, iod)
    assert shrunk.shape == full.shape == shape and shrunk.dtype == full.dtype == np.float32
    assert np.abs(full - 1).max() > 0.1  # there is something to compare
    err = np.abs(shrunk - full)
    assert err.max() < 0.01 and err.mean() < 2e-4


def test_apply_details_is_eq_9_rounded(pair):
    (_, _, target), _ = pair
    image = target[400:700, 400:800]
    rng = np.random.default_rng(0)
    ratio = rng.uniform(*eri.CLAMP, image.shape[:2]).astype(np.float32)
    importance = rng.uniform(1.0, 1.5, image.shape[:2]).astype(np.float32)
    want = image * (1 + importance * (ratio - 1))[..., None]
    got = eri.apply_details(image, ratio, importance)
    assert got.dtype == np.uint8 and got.shape == image.shape
    assert np.abs(got - np.clip(want, 0, 255)).max() <= 0.5 + 1e-3  # rounded to nearest, saturated
    assert (got[want > 255] == 255).all()


@pytest.mark.parametrize("shape", [(90, 120), (91, 127)])
def test_shrink_then_enlarge_keeps_a_smooth_image(shape):
    ys, xs = np.mgrid[: shape[0], : shape[1]].astype(np.float32)
    smooth = np.sin(xs / 15) + np.cos(ys / 11)
    small = eri.shrink(smooth, 3)
    assert small.shape == (shape[0] // 3, shape[1] // 3)
    assert np.isclose(small[0, 0], smooth[:3, :3].mean(), atol=1e-5)  # block means
    back = eri.enlarge(small, shape, 3)
    assert back.shape == shape
    assert np.abs(back - smooth)[3:-3, 3:-3].max() < 0.02  # bilinear error of a curve 11 pixels wide
    assert np.abs(back - smooth).max() < 0.3  # the edge, repeated


def test_luma_warped_instead_of_rgb_gives_nearly_the_same_ratio(pair):
    (sn, se, target), (sn_lm, se_lm, lm) = pair
    mesh = warp.build_mesh(lm, target.shape, DLIB68)
    iod = geometry.interocular(lm, DLIB68)
    ctrl = [mesh.control_points(p, geometry.fit_similarity(lm[list(DLIB68.rigid)], p[list(DLIB68.rigid)])) for p in (sn_lm, se_lm)]
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    rgb = [warp.warp(im, c, mesh.points, mesh.triangles) for im, c in zip((sn, se), ctrl)]
    luma = [warp.warp(cv2.cvtColor(im, cv2.COLOR_RGB2GRAY), c, mesh.points, mesh.triangles) for im, c in zip((sn, se), ctrl)]
    assert np.abs(eri.luminance(luma[0]) - eri.luminance(rgb[0])).max() <= 1.001 / 255
    err = np.abs(eri.expression_ratio(*luma, mask, iod) - eri.expression_ratio(*rgb, mask, iod))
    assert err.max() < 0.01 and err.mean() < 1e-4
