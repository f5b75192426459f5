import cv2
import numpy as np
import pytest
from changes import lock_of_hair

from exprclone.details import coarse, eri, gate
from exprclone.imaging import piecewise, raster
from exprclone.landmarks import align
from exprclone.landmarks.layout import DLIB68
from exprclone.testing.lighting import relit


def expression_ratio(neutral_warped, expression_warped, mask, iod, target=None, exempt=None):
    """The ERI's luma ratio of two photos already in one geometry (:func:`ratio_and_tint`)."""
    return ratio_and_tint(neutral_warped, expression_warped, mask, iod, target, exempt)[..., eri.RATIO]


def ratio_and_tint(neutral_warped, expression_warped, mask, iod, target=None, exempt=None, still=None):
    """The ERI and its tint of two photos already in one geometry, ``(H, W, 3)``, made by the production path's own
    functions on the grid shrunk by :func:`eri.filter_step` (:func:`exprclone.details.stage.ratio_image` makes the same
    from photos shrunk in their own frames and warped): the neutral photo's channels (:func:`eri.neutral_channels`), the
    target's skin trust, then :func:`eri.ratio_on_grid` (``still``: the face the expression leaves still)."""
    step = min(eri.filter_step(iod), *mask.shape)
    neutral, expression = (coarse.grid_pixels(image, iod, step) for image in (neutral_warped, expression_warped))
    small_mask, sigma = raster.shrink(mask, step), eri.FILTER_SIGMA * iod / step
    face = small_mask * eri.texture(neutral[..., coarse.ENERGY], neutral[..., coarse.LUMA], sigma)
    channels, hue = eri.neutral_channels(neutral, face, sigma)
    trust = None if target is None else gate.trust(gate.colour(coarse.grid_pixels(target, iod, step, detail=False), sigma), face)
    lips = None if exempt is None else raster.shrink(exempt, step)
    resting = None if still is None else raster.shrink(still, step)
    small = eri.ratio_on_grid(channels, expression, trust, small_mask, iod / step, lips, hue, step > 1, resting)
    return raster.enlarge(small, mask.shape, step)


def test_same_photo_twice_gives_ratio_one(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    ratio = expression_ratio(target, target, mask, align.interocular(lm, DLIB68))
    assert np.allclose(ratio, 1.0)
    assert np.array_equal(eri.apply_details(target, ratio), target)


def test_mask_is_one_on_the_cheeks_and_zero_off_the_face_and_in_the_eyes(pair):
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
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
        r = expression_ratio(a, b, mask, 100.0)
        assert np.isfinite(r).all() and r.min() >= eri.CLAMP[0] and r.max() <= eri.CLAMP[1]


def test_local_shading_is_transferred_and_exposure_is_not(pair):
    (_, _, target), (_, _, lm) = pair
    iod = align.interocular(lm, DLIB68)
    x, y = ((lm[2] + lm[31]) / 2).round().astype(int)  # a cheek
    fold = (slice(y - 40, y + 40), slice(x - 40, x + 40))
    shaded = target.copy()
    shaded[fold] = (shaded[fold] * 0.8).astype(np.uint8)  # a fold darkens the cheek
    face = np.zeros(target.shape[:2], np.float32)
    face[int(lm[19, 1]) : int(lm[8, 1]), int(lm[0, 0]) : int(lm[16, 0])] = 1
    out = eri.apply_details(target, expression_ratio(target, shaded, face, iod))
    patch = (slice(y - 20, y + 20), slice(x - 20, x + 20))
    assert out[patch].astype(float).mean() / target[patch].mean() == pytest.approx(0.8, abs=0.03)
    nose = (slice(int(lm[30, 1]) - 10, int(lm[30, 1]) + 10), slice(int(lm[30, 0]) - 10, int(lm[30, 0]) + 10))
    assert np.abs(out[nose].astype(float) - target[nose]).mean() < 1.5  # untouched elsewhere
    # the same darkening over the whole photo is exposure, not expression
    darker = (target * 0.8).astype(np.uint8)
    assert np.allclose(expression_ratio(target, darker, face, iod), 1.0, atol=0.02)


def test_the_texture_test_trusts_skin_not_hair(pair):
    (_, _, target), (_, _, lm) = pair
    iod = align.interocular(lm, DLIB68)
    energy, luma = coarse.detail_energy(eri.luminance(target), iod), eri.luminance(target)
    conf = eri.texture(energy, luma, eri.FILTER_SIGMA * iod)
    cheek = ((lm[2] + lm[31]) / 2).round().astype(int)
    hair = np.array([lm[19, 0], lm[19, 1] - 0.3 * iod]).round().astype(int)  # 003 wears a fringe
    assert conf[cheek[1], cheek[0]] > 0.9
    assert conf[hair[1], hair[0]] < 0.2
    assert conf.min() >= 0 and conf.max() <= 1


def test_filters_on_the_shrunk_grid_match_full_resolution(pair, monkeypatch):
    """The ERI is smooth at FILTER_SIGMA, so computing it shrunk and enlarging it changes little."""
    (sn, se, target), (sn_lm, se_lm, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    iod = align.interocular(lm, DLIB68)
    ctrl = [mesh.control_points(p, align.fit_similarity(lm[list(DLIB68.rigid)], p[list(DLIB68.rigid)])) for p in (sn_lm, se_lm)]
    box = (slice(300, 1200), slice(250, 1100))
    local = mesh.points - (box[1].start, box[0].start)
    shape = (box[0].stop - box[0].start, box[1].stop - box[1].start)
    neutral, expression = (piecewise.warp(im, c, local, mesh.triangles, shape) for im, c in zip((sn, se), ctrl))
    mask = eri.ratio_mask(shape, local[: mesh.n_landmarks], local[mesh.forehead], DLIB68)
    assert eri.filter_step(iod) >= 2
    shrunk = expression_ratio(neutral, expression, mask, iod)
    with monkeypatch.context() as m:  # the grid's own blur not taken off the filter (eri.GRID_VARIANCE)
        m.setattr(eri, "GRID_VARIANCE", 0.0)
        blurred = expression_ratio(neutral, expression, mask, iod)
    monkeypatch.setattr(eri, "FILTER_PIXELS", np.inf)
    assert eri.filter_step(iod) == 1
    full = expression_ratio(neutral, expression, mask, iod)
    assert shrunk.shape == full.shape == shape and shrunk.dtype == full.dtype == np.float32
    assert np.abs(full - 1).max() > 0.1  # there is something to compare
    err = np.abs(shrunk - full)
    # the grid is about 50 pixels to an inter-ocular distance (FILTER_PIXELS): measured 0.023 at most, 1.5e-4 on average
    assert err.max() < 0.03 and err.mean() < 3e-4
    assert err.mean() < 0.8 * np.abs(blurred - full).mean()  # measured 0.69: the correction brings the grid nearer


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
    small = raster.shrink(smooth, 3)
    assert small.shape == (shape[0] // 3, shape[1] // 3)
    assert np.isclose(small[0, 0], smooth[:3, :3].mean(), atol=1e-5)  # block means
    back = raster.enlarge(small, shape, 3)
    assert back.shape == shape
    assert np.abs(back - smooth)[3:-3, 3:-3].max() < 0.02  # bilinear error of a curve 11 pixels wide
    assert np.abs(back - smooth).max() < 0.3  # the edge, repeated
    h, w = small.shape[0] * 3, small.shape[1] * 3
    assert (back[h:] == back[h - 1]).all() and (back[:, w:] == back[:, w - 1 : w]).all()  # the left-out edge, exactly
    colour = raster.enlarge(np.dstack([small, 2 * small]), shape, 3)
    assert colour.shape == (*shape, 2)  # each channel alike (OpenCV's paths for 1 and 2 channels round apart by an ulp)
    assert np.allclose(colour[..., 0], back, atol=1e-6) and np.allclose(colour[..., 1], 2 * back, atol=1e-6)


def face_frame(pair):
    """The target photo of ``pair`` (003), its landmarks, its ratio mask and inter-ocular distance."""
    (_, _, target), (_, _, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    return target, lm, eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68), align.interocular(lm, DLIB68)


def test_a_light_that_moved_across_the_face_is_not_expression(pair):
    target, lm, mask, iod = face_frame(pair)
    lit = relit(target, lm)  # 30% brighter from ear to ear
    ratio = expression_ratio(target, lit, mask, iod)
    assert np.abs(ratio - 1).max() < 0.01
    # a median ratio of 1 would have left the tilt: +-15% across the face
    trusted = mask > 0.5
    raw = (eri.luminance(lit) + raster.EPS) / (eri.luminance(target) + raster.EPS)
    assert np.percentile(raw[trusted] / np.median(raw[trusted]), [2, 98]) @ [-1, 1] > 0.15


def test_hair_over_the_skin_is_not_expression_and_shading_is(pair):
    target, lm, mask, iod = face_frame(pair)
    left, right = (lm[2] + lm[31]) / 2, (lm[14] + lm[35]) / 2  # the cheeks
    hair = (70, 50, 38)  # dark brown
    neutral = lock_of_hair(target, left, 0.12 * iod, hair)  # a lock of hair on one cheek...
    expression = lock_of_hair(target, right, 0.12 * iod, hair)  # ...that moved to the other
    x, y = lm[8] + (0, -0.25 * iod)  # and the chin darkened by a fold, as shading does
    fold = (slice(int(y - 0.1 * iod), int(y + 0.1 * iod)), slice(int(x - 0.1 * iod), int(x + 0.1 * iod)))
    expression[fold] = (expression[fold] * 0.8 + 0.5).astype(np.uint8)
    ratio = expression_ratio(neutral, expression, mask, iod, target)
    for centre in (left, right):
        near = np.hypot(*(np.mgrid[: target.shape[0], : target.shape[1]][::-1] - centre[:, None, None])) < 0.2 * iod
        assert np.abs(ratio[near] - 1).max() < 0.01, centre
    core = (slice(fold[0].start + 15, fold[0].stop - 15), slice(fold[1].start + 15, fold[1].stop - 15))
    assert np.median(ratio[core]) == pytest.approx(0.8, abs=0.03)


def test_moved_is_where_the_expression_moves_the_skin(pair):
    (_, _, target), (sn, se, lm) = pair
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    iod = align.interocular(lm, DLIB68)
    motion = np.zeros(len(mesh.points))
    mouth = list(DLIB68.mouth_outer + DLIB68.mouth_inner)
    motion[mouth] = 0.1  # a smile: only the mouth moves
    labelling = piecewise.Labelling.of(mesh.points, mesh.triangles, target.shape[:2])
    region = gate.moved(labelling, motion, iod)
    at = lambda p: region[int(p[1]), int(p[0])]  # noqa: E731
    assert at(lm[mouth].mean(0)) == 1.0 and at((lm[48] + lm[31]) / 2) > 0.9  # the mouth, the fold beside it
    assert at(lm[27] + (0, -0.5 * iod)) == 0.0 and at(lm[39]) < 0.2  # not the forehead, hardly the eyes
    assert region.min() >= 0 and region.max() <= 1
    assert not gate.moved(labelling, 0 * motion, iod).any()


def test_colour_tells_a_change_of_material_from_shading(pair):
    """A smooth patch of another colour (a lens, a coloured light, the background) is not shading, however smooth."""
    target, lm, mask, iod = face_frame(pair)
    left, right = (lm[2] + lm[31]) / 2, (lm[14] + lm[35]) / 2
    expression = target.copy()
    for centre, colour in ((left, (120, 150, 170)), (right, (90, 90, 90))):  # a bluish lens, a grey shadow of a frame
        disc = np.zeros(target.shape[:2], np.float32)
        cv2.circle(disc, tuple(int(v) for v in centre), int(0.12 * iod), 1.0, -1)
        disc = cv2.GaussianBlur(disc, (0, 0), 2)[..., None]
        expression = np.clip(expression * (1 - disc) + np.array(colour, np.float32) * disc + 0.5, 0, 255).astype(np.uint8)
    ratio = expression_ratio(target, expression, mask, iod)
    yy, xx = np.mgrid[: target.shape[0], : target.shape[1]]
    for centre in (left, right):
        inner = np.hypot(xx - centre[0], yy - centre[1]) < 0.12 * iod - 2 * eri.FILTER_SIGMA * iod  # away from its soft edge
        assert np.abs(ratio[inner] - 1).max() < 0.01, centre
        # the same patch in the skin's own colour, darker, would have been shading
        shade = target.copy()
        core = np.hypot(xx - centre[0], yy - centre[1]) < 0.12 * iod
        shade[core] = (shade[core] * 0.6 + 0.5).astype(np.uint8)
        # clamped to CLAMP[0]; the darkened skin's texture confidence (its relative contrast rises as its luma falls)
        # fades that by up to 15%: at least 80% of it is transferred
        assert np.median(expression_ratio(target, shade, mask, iod)[inner]) < 1 - 0.8 * (1 - eri.CLAMP[0]), centre


def test_the_target_is_shaded_only_on_its_skin(pair):
    """Where the target shows hair (003's fringe), it takes no ratio, whatever the source's skin did there."""
    target, lm, mask, iod = face_frame(pair)
    x, y = ((lm[2] + lm[31]) / 2).astype(int)
    cheek = target[y - 32 : y + 32, x - 32 : x + 32]
    # the source: 003 with skin (its cheek, tiled) where 003 wears a fringe
    fringe = (slice(int(lm[19, 1] - 0.45 * iod), int(lm[19, 1] - 0.1 * iod)), slice(int(lm[18, 0]), int(lm[25, 0])))
    source = target.copy()
    h, w = source[fringe].shape[:2]
    source[fringe] = np.tile(cheek, (h // 64 + 1, w // 64 + 1, 1))[:h, :w]
    # and the expression shades that skin: folds across it 0.1 iod wide (a raised brow's wrinkles), 30% darker; a
    # darkening even over the whole band would be read as a light that changed (:func:`eri.light_trend`)
    shaded = source.copy()
    rows = np.arange(fringe[0].start, fringe[0].stop)
    folds = np.where((rows - rows[0]) // int(0.1 * iod) % 2 == 0, 0.7, 1.0)[:, None, None]
    shaded[fringe] = (shaded[fringe] * folds + 0.5).astype(np.uint8)
    band = (slice(fringe[0].start + 30, fringe[0].stop - 30), slice(fringe[1].start + 30, fringe[1].stop - 30))
    without, with_target = (expression_ratio(source, shaded, mask, iod, t) for t in (None, target))
    assert without[band].min() < 0.9  # the source's skin was shaded there
    # but the target shows hair there: dark, all around (skin shows through its parting)
    sigma = eri.FILTER_SIGMA * iod
    dark = (cv2.GaussianBlur(eri.luminance(target), (0, 0), sigma) < 0.5 * eri.luminance(cheek).mean()).astype(np.uint8)
    reach = int(sigma)
    hair = cv2.erode(dark, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1, 2 * reach + 1)))[band] > 0
    assert hair.mean() > 0.5 and np.abs(with_target[band][hair] - 1).max() < 0.01


def cheek_patch(target, lm, iod):
    """A soft disc on the right cheek, where a smile's fold darkens the skin, ``(H, W)`` float32 in [0, 1]."""
    patch = np.zeros(target.shape[:2], np.float32)
    centre = ((lm[2] + lm[31]) / 2 + lm[48]) / 2
    cv2.circle(patch, tuple(int(v) for v in centre), int(0.18 * iod), 1.0, -1)
    return cv2.GaussianBlur(patch, (0, 0), 0.05 * iod)


def shaded(image, patch, gains):
    """``image`` multiplied by ``gains`` (R, G, B) inside ``patch``, 1 outside."""
    factor = 1 + patch[..., None] * (np.array(gains, np.float32) - 1)
    return np.clip(image * factor + 0.5, 0, 255).astype(np.uint8)


def test_a_warm_shadow_gives_a_warm_tint_and_a_grey_one_none(pair):
    """The tint carries how the source's chromaticity changes as its skin darkens: a fold darkened more in G and B
    than in R (as real skin's shadows are) gives a positive log R/G shift there, one darkened alike none; the luma
    ratio is much the same in both."""
    (_, _, target), (_, _, lm) = pair
    iod = align.interocular(lm, DLIB68)
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    patch = cheek_patch(target, lm, iod)
    inside = patch > 0.9
    warm_gains = np.float32([0.91, 0.87, 0.86])  # as the London Set's real smiles darken and warm a fold
    skin = np.median(target[inside], axis=0).astype(np.float32)
    grey_gain = float(skin * warm_gains @ raster.LUMA / (skin @ raster.LUMA))  # the warm shadow's luma, on this skin
    warm, grey = (ratio_and_tint(target, shaded(target, patch, g), mask, iod) for g in (warm_gains, (grey_gain,) * 3))
    assert abs(np.median(warm[..., 0][inside]) - np.median(grey[..., 0][inside])) < 0.01
    assert np.median(warm[..., 1][inside]) > 0.02 and np.median(warm[..., 2][inside]) < 0.0  # redder, less blue
    assert np.abs(grey[..., 1:][inside]).max() < 0.01


def test_a_change_of_white_balance_is_no_tint(pair):
    """A colour cast over the whole expression photo (the light's colour, white balance) is taken out of the tint,
    measured where the expression leaves the skin still; a grey fold stays grey."""
    (_, _, target), (_, _, lm) = pair
    iod = align.interocular(lm, DLIB68)
    mesh = piecewise.build_mesh(lm, target.shape, DLIB68)
    mask = eri.ratio_mask(target.shape[:2], lm, mesh.points[mesh.forehead], DLIB68)
    patch = cheek_patch(target, lm, iod)
    rows = np.arange(target.shape[0], dtype=np.float32)[:, None]
    moved = np.broadcast_to(np.clip((rows - lm[28, 1]) / (0.3 * iod), 0, 1), patch.shape)  # below the nose's bridge
    cast = shaded(shaded(target, np.ones_like(patch), (1.06, 1.0, 0.94)), patch, (0.82, 0.82, 0.82))
    made = ratio_and_tint(target, cast, mask * moved, iod, still=mask * (1 - moved))
    assert np.abs(made[..., 1:][patch > 0.9]).max() < 0.01
    assert np.median(made[..., 0][patch > 0.9]) < 0.9  # the fold is there


def test_the_tint_shifts_chromaticity_and_keeps_the_lumas_gain():
    skin = np.full((8, 8, 3), (200, 150, 120), np.uint8)
    gain, tint = np.full((8, 8), 0.8, np.float32), np.tile(np.float32([0.05, -0.03]), (8, 8, 1))
    out = eri.apply_details(skin, gain, 1.0, tint).astype(np.float64)
    luma = out[0, 0] @ raster.LUMA / (np.float64(skin[0, 0]) @ raster.LUMA)
    assert abs(luma - 0.8) < 0.01
    before, after = np.log(skin[0, 0] / skin[0, 0, 1]), np.log(out[0, 0] / out[0, 0, 1])
    assert np.allclose(after[[0, 2]] - before[[0, 2]], [0.05, -0.03], atol=0.01)
    assert np.array_equal(eri.apply_details(skin, gain, 0.0, tint), skin)  # M = 0: neither shading nor tint
