"""The mouth interior pasted from the source's open smile."""

import cv2
import numpy as np
import pytest
from scipy.spatial import Delaunay

import exprclone
from exprclone.drive.driver import closed_mouth_frame, strongest_frames
from exprclone.imaging import piecewise, raster
from exprclone.io.video import read_frames
from exprclone.landmarks import blendshapes, lips
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68
from exprclone.mouth import measure, paste, tone

INNER = list(DLIB68.mouth_inner)


def polygon_mask(shape, points, shrink=0):
    mask = np.zeros(shape[:2], np.uint8)
    cv2.fillPoly(mask, [np.round(points).astype(np.int32)], 1)
    if shrink:
        mask = cv2.erode(mask, np.ones((2 * shrink + 1, 2 * shrink + 1), np.uint8))
    return mask.astype(bool)


@pytest.fixture(scope="module")
def open_pair(photo):
    """Source 126 smiles with her teeth; target 100's neutral mouth is closed, and the clone opens it wide (the full set's photos)."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126", original=True), photo("126", "smile", original=True), photo("100")
    assert measure.opening(se_lm, DLIB68) > 3 * measure.OPENING[1] and measure.opening(tn_lm, DLIB68) < measure.OPENING[1]
    on = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
    off = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm), mouth=False)
    return on, off, se, se_lm, tn, tn_lm


def test_opened_mouth_shows_the_source_teeth(open_pair, photo):
    on, off, se, se_lm, tn, tn_lm = open_pair
    assert on.mouth_mask is not None and off.mouth_mask is None
    final = on.landmarks["final"]
    polygon = polygon_mask(on.image.shape, final[INNER])
    inside = on.mouth_mask > 0.95  # where the paste is whole; the rest is the feathered edge
    # whole wherever the feather (eroded by one sigma, then blurred) cannot reach: four sigmas in
    sigma = paste.FEATHER * measure.mouth_width(final, DLIB68)
    core = polygon_mask(on.image.shape, final[INNER], shrink=int(np.ceil(4 * sigma)))
    assert core.any() and (inside | ~core).all() and not (inside & ~polygon).any()
    # there it is the source's interior as it lands there (lips and the opening's centre), tone-matched
    sn, sn_lm = photo("126", original=True)
    s_exp = lips.uncross(se_lm, DLIB68)
    points = list(DLIB68.mouth_outer + DLIB68.mouth_inner)
    src, dst = (np.vstack([p[points], p[INNER].mean(0)]) for p in (s_exp, final))
    landed = piecewise.warp(se, src, dst, Delaunay(dst).simplices, on.image.shape[:2]).astype(float)
    reference = tone.Reference.measure(tn, lips.uncross(tn_lm, DLIB68), DLIB68, (sn, lips.uncross(sn_lm, DLIB68)))
    expected = landed[inside].mean(0) * tone.tone_gain(se, s_exp, reference, DLIB68, landed[polygon])
    pasted = np.abs(on.image[inside].astype(float).mean(0) - expected).mean()
    stretched = np.abs(off.image[inside].astype(float).mean(0) - expected).mean()
    assert stretched > 5 * pasted, (pasted, stretched)  # "far better than the stretched lips"
    # teeth are bright: the mouth interior is now brighter than the stretched lips were
    assert on.image[inside].mean() > off.image[inside].mean() + 20
    source_inside = polygon_mask(se.shape, se_lm[INNER], shrink=4)
    # but not flat white: the source's teeth are unclipped, and so are the pasted ones
    # (her eye whites read darker than the target's, and the tone match would have glared)
    assert (se[source_inside].max(1) == 255).mean() < 0.01
    assert (on.image[inside].max(1) == 255).mean() < 0.02


@pytest.fixture(scope="module")
def grain_pair(photo):
    """Source 107 shows her teeth; target 005's mouth is closed.

    Returns ``fill(degrade)``: the paste into the result without it, with the target
    photo and that result both degraded alike (as cloning onto a degraded photo would
    be); the paste into the untouched result; where the paste is whole (away from its
    feathered edge); the target photo and its landmarks.
    """
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("107"), photo("107", "smile"), photo("005")
    off = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm), mouth=False)
    source_lm, target_lm = lips.uncross(se_lm, DLIB68), lips.uncross(tn_lm, DLIB68)  # as the pipeline passes them

    def fill(degrade):
        def measure():
            return tone.Reference.measure(degrade(tn), target_lm, DLIB68)

        image, final = degrade(off.image), off.landmarks["final"]
        made = paste.patch(image.shape, final, se, source_lm, measure, DLIB68)
        return paste.blend(image, made, lambda: paste.source_grain(se, source_lm, measure(), final, DLIB68))

    sharp, weight = fill(lambda im: im)
    whole = cv2.erode((weight > 0.99).astype(np.uint8), np.ones((7, 7), np.uint8)).astype(bool)
    return fill, sharp, whole, tn, tn_lm


def high_frequency(image, region):
    """Mean squared difference of the luma from its Gaussian blur (sigma 1.5 px) in ``region``."""
    luma = raster.luma(image.astype(np.float32))
    return float(np.mean((luma - cv2.GaussianBlur(luma, (0, 0), 1.5))[region] ** 2))


def test_pasted_interior_is_as_soft_as_a_low_resolution_target(grain_pair):
    fill, sharp, whole, tn, tn_lm = grain_pair
    h, w = tn.shape[:2]

    def low_res(im):  # a quarter of the resolution, brought back to the size
        return cv2.resize(cv2.resize(im, (w // 4, h // 4), interpolation=cv2.INTER_AREA), (w, h), interpolation=cv2.INTER_LINEAR)

    soft, _ = fill(low_res)
    face = np.zeros((h, w), bool)
    (x0, y0), (x1, y1) = tn_lm.min(0).astype(int), tn_lm.max(0).astype(int)
    face[y0:y1, x0:x1] = True
    target_loss = high_frequency(low_res(tn), face) / high_frequency(tn, face)
    pasted_loss = high_frequency(soft, whole) / high_frequency(sharp, whole)
    assert whole.sum() > 500
    # unmatched, the paste would keep the sharp source's detail (a loss of 1): it must
    # lose about what the target lost, closer to it than to 1 and not much beyond it
    assert target_loss / 2 < pasted_loss < np.sqrt(target_loss), (pasted_loss, target_loss)


def test_pasted_interior_is_as_noisy_as_a_noisy_target_and_reproducible(grain_pair):
    fill, sharp, whole, *_ = grain_pair
    rng = np.random.default_rng(3)
    grainy, _ = fill(lambda im: np.clip(im + rng.normal(0, 8.0, im.shape), 0, 255).astype(np.uint8))
    unclipped = whole & (sharp.min(2) > 10) & (sharp.max(2) < 245)
    added = (grainy.astype(float) - sharp)[unclipped].std(axis=0)
    assert unclipped.sum() > 500
    assert added == pytest.approx([8.0, 8.0, 8.0], rel=0.15)  # the target's noise, not the clean source's
    assert np.array_equal(fill(lambda im: im)[0], sharp)  # seeded: the same inputs, the same image


def test_the_target_lips_stay_the_target(open_pair):
    """The paste reaches onto the lips by :data:`exprclone.mouth.paste.REACH` of the mouth's width, no further, and
    never beyond the outer lips."""
    on, off, *_ = open_pair
    final = on.landmarks["final"]
    reach = int(np.ceil(paste.REACH * measure.mouth_width(final, DLIB68))) + 1
    grown = polygon_mask(on.image.shape, final[INNER]).astype(np.uint8)
    grown = cv2.dilate(grown, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1,) * 2)).astype(bool)
    outer = polygon_mask(on.image.shape, final[list(DLIB68.mouth_outer)])
    kept = ~(grown & outer)
    assert np.array_equal(on.image[kept], off.image[kept])
    assert (on.mouth_mask[~polygon_mask(on.image.shape, final[INNER])] > 0.5).any()  # it does reach the lips


def test_closed_mouth_source_changes_nothing(photo, monkeypatch):
    """A source's closed mouth pastes nothing, and the photos are not measured for a paste (a fifth of e+md's work); an
    open one's are, once."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("003"), photo("003", "smile"), photo("001")
    assert measure.opening(se_lm, DLIB68) < measure.OPENING[0]
    lms = (sn_lm, se_lm, tn_lm)
    measured = []
    real = tone.Reference.measure
    monkeypatch.setattr(tone.Reference, "measure", lambda *a, **k: measured.append(1) or real(*a, **k))
    on = exprclone.clone(sn, se, tn, method="elastic+eri", landmarks=lms)
    assert measured == []
    off = exprclone.clone(sn, se, tn, method="elastic+eri", landmarks=lms, mouth=False)
    assert on.mouth_mask is None and np.array_equal(on.image, off.image)
    (sn, sn_lm), (se, se_lm) = photo("126"), photo("126", "smile")
    opened = exprclone.clone(sn, se, tn, method="elastic+eri", landmarks=(sn_lm, se_lm, tn_lm))
    assert opened.mouth_mask is not None and measured == [1]


def test_closed_lips_the_fitter_left_apart_paste_nothing(photo):
    """Source 005's smile is closed, but the fitted inner lips enclose some of her full lips."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("005"), photo("005", "smile"), photo("006")
    lms = (sn_lm, se_lm, tn_lm)
    on = exprclone.clone(sn, se, tn, method="global+eri", landmarks=lms)
    off = exprclone.clone(sn, se, tn, method="global+eri", landmarks=lms, mouth=False)
    # both polygons have area: only what the source shows between its lips says "closed"
    assert measure.opening(lips.uncross(se_lm, DLIB68), DLIB68) > measure.OPENING[0]
    assert measure.opening(on.landmarks["final"], DLIB68) > measure.OPENING[0]
    teeth, cavity = measure.interior(se, lips.uncross(se_lm, DLIB68), DLIB68)
    assert teeth.sum() + cavity.sum() < measure.INTERIOR[0] * measure.mouth_width(se_lm, DLIB68) ** 2
    assert on.mouth_mask is None and np.array_equal(on.image, off.image)


def test_a_squinting_source_has_its_eye_whites_read_on_its_neutral_photo(photo):
    (sn, sn_lm), (se, se_lm) = photo("013"), photo("013", "smile")
    # her smile onto her own neutral photo: the right gain is the change of exposure
    # between the two, which the studio wall in the corner shows (the smile is 6% darker)
    wall = sn[10:110, 10:110].reshape(-1, 3).mean(0) / se[10:110, 10:110].reshape(-1, 3).mean(0)
    squinting = tone.tone_gain(se, se_lm, tone.Reference.measure(sn, sn_lm, DLIB68), DLIB68)
    read_open = tone.tone_gain(se, se_lm, tone.Reference.measure(sn, sn_lm, DLIB68, (sn, sn_lm)), DLIB68)
    # read on the squint, the teeth glare: the squinting eyes weigh less than open ones
    # and her skin is a second cue, but the gain is still 40% too strong or more
    assert np.abs(np.log(squinting / wall)).min() > 0.3, squinting
    # her face flushes as she smiles, so it tells the exposure only to about 10%
    assert np.abs(np.log(read_open / wall)).max() < 0.15, (read_open, wall)


def test_geometric_methods_never_paste(open_pair, photo):
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("001")
    r = exprclone.clone(sn, se, tn, method="global", landmarks=(sn_lm, se_lm, tn_lm))
    assert r.mouth_mask is None


def test_teeth_fade_out_as_the_source_shows_less(open_pair):
    """No popping in a video: as the source's teeth are covered bit by bit, the paste fades, never jumps."""
    on, _, se, se_lm, tn, tn_lm = open_pair
    inner, outer = (np.zeros(se.shape[:2], np.uint8) for _ in range(2))
    cv2.fillPoly(inner, [np.round(se_lm[INNER]).astype(np.int32)], 1)
    cv2.fillPoly(outer, [np.round(se_lm[list(DLIB68.mouth_outer)]).astype(np.int32)], 1)
    lip_colour = np.median(se[(outer > 0) & (inner == 0)], axis=0)
    left, right = se_lm[INNER, 0].min(), se_lm[INNER, 0].max()
    reference = tone.Reference.measure(tn, tn_lm, DLIB68)
    amounts, shown = [], []
    for edge in np.linspace(left, right, 61):
        covered = se.copy()
        covered[(inner > 0) & (np.arange(se.shape[1]) < edge)[None, :]] = lip_colour
        teeth, cavity = measure.interior(covered, lips.uncross(se_lm, DLIB68), DLIB68)
        shown.append((teeth.sum() + cavity.sum()) / measure.mouth_width(se_lm, DLIB68) ** 2)
        made = paste.patch(on.image.shape, on.landmarks["final"], covered, se_lm, lambda: reference, DLIB68)
        amounts.append(0.0 if made is None else float(made.mask.sum()))
    amounts, shown = np.array(amounts), np.array(shown)
    assert shown[0] > measure.INTERIOR[1] and amounts[-1] == 0  # from all teeth to none
    assert np.abs(np.diff(amounts)).max() < 0.3 * amounts[0]  # each step covers a little, each step fades a little


#: an orange light, channel by channel: skin under the GRID studio's lamps keeps about a
#: third of its blue and three quarters of its green, beside the London studio's.
ORANGE = np.array([1.0, 0.75, 0.4])


def test_an_orange_light_on_the_source_leaves_the_result_unchanged(open_pair, photo):
    """The source's two photos taken under an orange light: the paste matches the target's light, not the source's."""
    on, _, se, se_lm, tn, tn_lm = open_pair
    (sn, sn_lm) = photo("126", original=True)

    def orange(image):
        return np.round(image * ORANGE).astype(np.uint8)

    lit = exprclone.clone(orange(sn), orange(se), tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
    # the source's teeth are still seen as teeth (an orange light saturates teeth and lips alike)
    assert lit.mouth_mask is not None and np.allclose(lit.mouth_mask, on.mouth_mask)
    inside = on.mouth_mask > 0.95
    difference = lit.image[inside].astype(float) - on.image[inside]
    assert np.abs(orange(se).astype(float).mean((0, 1)) - se.mean((0, 1))).max() > 50  # the light is strong
    assert np.abs(difference.mean(0)).max() < 2, difference.mean(0)  # the same colour, to a grey level or two
    assert np.percentile(np.abs(difference), 99) <= 4
    # the ERI is a ratio of the source's two photos' luma, in which their light cancels
    outside = on.mouth_mask == 0
    assert np.abs(lit.image[outside].astype(float) - on.image[outside]).mean() < 0.5


#: MediaPipe's face mesh: its inner-lip contour, and its mouth corners.
MESH_INNER = (78, 95, 88, 178, 87, 14, 317, 402, 318, 324, 308, 415, 310, 311, 312, 13, 82, 81, 80, 191)
MESH_CORNERS = (61, 291)


def mesh_opening(image):
    """The inner-lip area over the squared mouth width as MediaPipe's face mesh reads the photo (as the blendshape
    judge reads it)."""
    points = blendshapes.shared().mesh.detect_mesh(image, "clone")
    x, y = points[list(MESH_INNER)].T
    return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1))) / np.sum(np.subtract(*points[list(MESH_CORNERS)]) ** 2)


@pytest.fixture(scope="module")
def speech(grid_mpg, photo):
    """The GRID speaker bbaf2n's most closed frame and most open one (as ``exprclone video`` and
    ``tools/grid_sources.py`` take them), with their landmarks, and target 001's neutral photo with its."""
    frames = list(read_frames(grid_mpg))
    points = np.array([default_detector().detect(frame, f"{grid_mpg.name} frame {k}") for k, frame in enumerate(frames)])
    usable = np.ones(len(frames), bool)
    opening = np.array([measure.opening(p, DLIB68) for p in points])
    closed, (opened,) = closed_mouth_frame(points, usable, DLIB68), strongest_frames(opening, usable, 1, 5)
    return (frames[closed], points[closed]), (frames[opened], points[opened]), photo("001")


def test_a_speaking_mouth_reads_as_open_as_its_landmarks(speech, monkeypatch):
    """A GRID speaker's open mouth onto a London face: the paste covers the whole opening, its feather on the lips (on
    the inner-lip line it weighs more than half), so the face mesh reads the clone's lips parted wider than when the
    paste faded out inside the line and left a band of the target's lips stretched over the opening."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = speech

    def cloned():
        return exprclone.clone(sn, se, tn, method="e+md", retarget=False, landmarks=(sn_lm, se_lm, tn_lm))

    reaching = cloned()
    final = reaching.landmarks["final"]
    assert measure.opening(final, DLIB68) > 3 * measure.OPENING[1]  # the clone's landmarks open the mouth
    inside = polygon_mask(tn.shape, final[INNER])
    line = inside & ~polygon_mask(tn.shape, final[INNER], shrink=1)
    assert np.median(reaching.mouth_mask[line]) > 0.5
    monkeypatch.setattr(paste, "REACH", 0.0)
    stopping = cloned()
    assert np.median(stopping.mouth_mask[line]) < 0.5  # the paste as it was: faded out at the line
    assert mesh_opening(reaching.image) > mesh_opening(stopping.image)
