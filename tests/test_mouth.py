"""The mouth interior pasted from the source's open smile."""

import cv2
import numpy as np
import pytest

import exprclone
from exprclone import mouth
from exprclone.layout import DLIB68

INNER = list(DLIB68.mouth_inner)


def polygon_mask(shape, points, shrink=0):
    mask = np.zeros(shape[:2], np.uint8)
    cv2.fillPoly(mask, [np.round(points).astype(np.int32)], 1)
    if shrink:
        mask = cv2.erode(mask, np.ones((2 * shrink + 1, 2 * shrink + 1), np.uint8))
    return mask.astype(bool)


@pytest.fixture(scope="module")
def open_pair(photo):
    """Source 126 smiles with her teeth; target 100's neutral mouth is closed."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("100")
    assert mouth.opening(se_lm, DLIB68) > 3 * mouth.MIN_OPENING and mouth.opening(tn_lm, DLIB68) < mouth.MIN_OPENING
    on = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm))
    off = exprclone.clone(sn, se, tn, method="e+md", landmarks=(sn_lm, se_lm, tn_lm), mouth=False)
    return on, off, se, se_lm, tn, tn_lm


def test_opened_mouth_shows_the_source_teeth(open_pair):
    on, off, se, se_lm, tn, tn_lm = open_pair
    assert on.mouth_mask is not None and off.mouth_mask is None
    polygon = polygon_mask(on.image.shape, on.landmarks["final"][INNER])
    inside = on.mouth_mask > 0.95  # where the paste is whole; the rest is the feathered edge
    assert inside.sum() > 0.5 * polygon.sum() and not (inside & ~polygon).any()
    source_inside = polygon_mask(se.shape, se_lm[INNER], shrink=4)
    gain = np.clip(mouth.sclera_colour(tn, tn_lm, DLIB68) / mouth.sclera_colour(se, se_lm, DLIB68), 0.5, 2.0)
    expected = se[source_inside].astype(float).mean(0) * gain  # the source interior, tone-matched
    pasted = np.abs(on.image[inside].astype(float).mean(0) - expected).mean()
    stretched = np.abs(off.image[inside].astype(float).mean(0) - expected).mean()
    assert stretched > 5 * pasted, (pasted, stretched)  # "far better than the stretched lips"
    # teeth are bright: the mouth interior is now brighter than the stretched lips were
    assert on.image[inside].mean() > off.image[inside].mean() + 20


def test_the_target_lips_stay_the_target(open_pair):
    on, off, *_ = open_pair
    grown = polygon_mask(on.image.shape, on.landmarks["final"][INNER])
    grown = cv2.dilate(grown.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    assert np.array_equal(on.image[~grown], off.image[~grown])


def test_closed_mouth_source_changes_nothing(photo):
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("003"), photo("003", "smile"), photo("100")
    assert mouth.opening(se_lm, DLIB68) < mouth.MIN_OPENING
    lms = (sn_lm, se_lm, tn_lm)
    on = exprclone.clone(sn, se, tn, method="elastic+eri", landmarks=lms)
    off = exprclone.clone(sn, se, tn, method="elastic+eri", landmarks=lms, mouth=False)
    assert on.mouth_mask is None and np.array_equal(on.image, off.image)


def test_geometric_methods_never_paste(open_pair, photo):
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("100")
    r = exprclone.clone(sn, se, tn, method="global", landmarks=(sn_lm, se_lm, tn_lm))
    assert r.mouth_mask is None
