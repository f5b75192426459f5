"""Expression strength and ``only``: what is transferred, how much, and where."""

import numpy as np
import pytest

import exprclone
from exprclone.landmarks.layout import DLIB68
from exprclone.landmarks.lips import uncross
from exprclone.mouth import measure
from exprclone.pipeline.clone import Cloner

EYES_AND_BROWS = list(DLIB68.regions["eyes"] + DLIB68.regions["brows"])
MOUTH = list(DLIB68.regions["mouth"])


@pytest.fixture(scope="module")
def open_mouths(photo):
    """Source 126, whose smile shows its teeth, onto 082, whose neutral lips are parted (the London Set's widest)."""
    (sn, sn_lm), (se, se_lm), (tn, tn_lm) = photo("126"), photo("126", "smile"), photo("082")
    return (sn, se, tn), (sn_lm, se_lm, tn_lm)


def test_strength_zero_gives_the_target(open_mouths, pair):
    for images, landmarks in (open_mouths, pair):
        results = exprclone.clone_methods(*images, landmarks=landmarks, strength=0)
        for method, r in results.items():
            assert np.abs(r.image.astype(int) - images[2]).max() <= 1, method
            assert r.mouth_mask is None, method


def test_the_whole_strength_pastes_teeth_into_the_parted_lips(open_mouths):
    """What strength 0 has to hold back: at strength 1 the paste is there."""
    images, landmarks = open_mouths
    assert measure.opening(uncross(landmarks[2], DLIB68), DLIB68) > measure.OPENING[1]
    assert exprclone.clone(*images, landmarks=landmarks).mouth_mask.max() > 0.9


def test_the_mouth_opens_steadily_with_strength(open_mouths):
    images, landmarks = open_mouths
    strengths = np.linspace(0, 2, 9)
    results = [exprclone.clone(*images, landmarks=landmarks, strength=float(s)) for s in strengths]
    opening = [measure.opening(r.landmarks["final"], DLIB68) for r in results]
    pasted = [0.0 if r.mouth_mask is None else float(r.mouth_mask.sum()) for r in results]
    assert np.all(np.diff(opening) > 0), opening
    assert np.all(np.diff(pasted) >= 0) and pasted[0] == 0 and pasted[-1] > 0, pasted


def test_strength_scales_motion_and_the_eri_in_the_log_domain(pair):
    images, landmarks = pair
    whole = exprclone.clone(*images, landmarks=landmarks, method="global+eri")
    half = exprclone.clone(*images, landmarks=landmarks, method="global+eri", strength=0.5)
    neutral = whole.landmarks["target_neutral"]
    assert np.array_equal(half.landmarks["global"], whole.landmarks["global"])  # the stages run on the whole expression
    outside = [i for i in range(68) if i not in DLIB68.mouth_inner]  # inner lips are then made valid (lips.uncross)
    halfway = neutral + 0.5 * (whole.landmarks["global"] - neutral)
    assert np.allclose(half.landmarks["final"][outside], halfway[outside], atol=1e-9)
    assert half.options.strength == 0.5 and whole.options.strength == 1.0
    # the ERI, on one geometry: its logarithm halved
    (sn, se, tn), (sn_lm, se_lm, tn_lm) = images, landmarks
    cloner = Cloner(sn, sn_lm, tn, tn_lm)
    rendered, photo = cloner.fi(whole.landmarks["global"], cloner.transfer), cloner.prepare(se, se_lm, ("global+eri",)).photo
    whole_eri, half_eri = (cloner.ratio(rendered, photo, Cloner(sn, sn_lm, tn, tn_lm, strength=s).transfer) for s in (1, 0.5))
    assert whole_eri.box == half_eri.box and (whole_eri.eri != 1).mean() > 0.05
    assert np.allclose(np.log(half_eri.eri), 0.5 * np.log(whole_eri.eri), atol=1e-5)
    assert np.abs(whole_eri.tint).max() > 0.005 and np.allclose(half_eri.tint, 0.5 * whole_eri.tint, atol=1e-6)  # its tint too


def test_only_the_mouth_leaves_the_eyes_and_brows_where_they_are(pair):
    images, landmarks = pair
    whole = exprclone.clone(*images, landmarks=landmarks, method="elastic", lambda_k=1.0)
    mouth_only = exprclone.clone(*images, landmarks=landmarks, method="elastic", lambda_k=1.0, only=("mouth",))
    neutral = whole.landmarks["target_neutral"]
    moved = np.linalg.norm(whole.landmarks["final"] - neutral, axis=1)
    assert moved[EYES_AND_BROWS].max() > 1  # the whole transfer moves them
    assert np.array_equal(mouth_only.landmarks["final"][EYES_AND_BROWS], neutral[EYES_AND_BROWS])
    assert np.allclose(mouth_only.landmarks["final"][MOUTH], whole.landmarks["final"][MOUTH])
    # the chin follows the mouth, the top of the nose stays with the eyes
    share = np.linalg.norm(mouth_only.landmarks["final"] - neutral, axis=1) / np.maximum(moved, 1e-9)
    assert share[8] > 0.8 and share[27] < 0.2, (share[8], share[27])


def test_only_the_eyes_and_brows_changes_nothing_around_the_mouth(pair):
    images, landmarks = pair
    r = exprclone.clone(*images, landmarks=landmarks, method="e+md", only="eyes,brows")
    neutral = r.landmarks["target_neutral"]
    assert np.array_equal(r.landmarks["final"][MOUTH], neutral[MOUTH]) and r.mouth_mask is None
    assert np.linalg.norm(r.landmarks["final"][EYES_AND_BROWS] - neutral[EYES_AND_BROWS], axis=1).max() > 1


def test_every_region_is_the_whole_face(pair):
    images, landmarks = pair
    whole = exprclone.clone(*images, landmarks=landmarks)
    every = exprclone.clone(*images, landmarks=landmarks, only=("brows", "mouth", "eyes"))
    assert np.array_equal(every.image, whole.image) and every.options.only is None


def test_a_cloner_with_strength_drives_every_frame_with_it(pair):
    (sn, se, tn), (sn_lm, se_lm, tn_lm) = pair
    cloner = Cloner(sn, sn_lm, tn, tn_lm, strength=0)
    r = cloner.changed(lambda_k=0.0).clone_methods(se, se_lm, ("e+md",))["e+md"]
    assert np.abs(r.image.astype(int) - tn).max() <= 1
