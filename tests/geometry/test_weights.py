"""Expression strength, per region and whole, and ``only``: what is transferred, how much, and where."""

import numpy as np
import pytest

import exprclone
from exprclone.landmarks.layout import DLIB68
from exprclone.landmarks.lips import uncross
from exprclone.mouth import measure
from exprclone.options import Options
from exprclone.pipeline import render
from exprclone.pipeline.cloner import Cloner

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
    faces, photo = cloner.faces, cloner.prepare(se, se_lm, ("global+eri",)).photo
    rendered = render.fi(faces, *render.geometry(faces, whole.landmarks["global"], cloner.transfer), "mesh")
    whole_eri, half_eri = (
        render.ratio(faces, rendered.control, photo, render.transfer(faces, Options(strength=s)), "mesh") for s in (1, 0.5)
    )
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


def hull_pixels(image, points, regions):
    """The pixels of ``image`` inside the convex hull of each of the region's parts (the eyes: each eye)."""
    import cv2

    mask = np.zeros(image.shape[:2], np.uint8)
    for part in regions:
        cv2.fillConvexPoly(mask, cv2.convexHull(np.round(points[list(part)]).astype(np.int32)), 1)
    return image[mask > 0].astype(int)


@pytest.mark.parametrize("region, parts", [("mouth", [DLIB68.regions["mouth"]]), ("eyes", list(DLIB68.eyes))])
def test_a_region_at_strength_zero_is_the_targets_own(pair, region, parts):
    """Its landmarks stay at the target's neutral ones and its pixels are the target's, by every method; the other regions
    still move as they do in the whole clone."""
    images, landmarks = pair
    prepared = exprclone.prepare(*images, exprclone.METHODS, landmarks=landmarks)
    whole, held = prepared.render(), prepared.render(**{f"strength_{region}": 0})
    idx = list(DLIB68.regions[region])
    others = [i for name, ids in DLIB68.regions.items() if name != region for i in ids]
    for method in exprclone.METHODS:
        neutral = held[method].landmarks["target_neutral"]
        assert np.abs(whole[method].landmarks["final"][idx] - neutral[idx]).max() > 1, method  # what it holds back
        assert np.array_equal(held[method].landmarks["final"][idx], neutral[idx]), method
        assert np.array_equal(held[method].landmarks["final"][others], whole[method].landmarks["final"][others]), method
        assert np.array_equal(hull_pixels(held[method].image, neutral, parts), hull_pixels(images[2], neutral, parts)), method
        assert np.abs(hull_pixels(whole[method].image, neutral, parts) - hull_pixels(images[2], neutral, parts)).mean() > 3, method


def test_the_mouth_opens_with_its_own_strength_and_the_eyes_keep_theirs(open_mouths):
    images, landmarks = open_mouths
    prepared = exprclone.prepare(*images, landmarks=landmarks)
    results = [prepared.render(strength=0.5, strength_mouth=float(s))["e+md"] for s in np.linspace(0, 2, 6)]
    opening = [measure.opening(r.landmarks["final"], DLIB68) for r in results]
    assert np.all(np.diff(opening) > 0), opening
    eyes = [r.landmarks["final"][list(DLIB68.regions["eyes"])] for r in results]
    assert all(np.array_equal(e, eyes[0]) for e in eyes)  # at the whole strength, 0.5, whatever the mouth's
    half = prepared.render(strength=0.5)["e+md"].landmarks["final"]
    assert np.array_equal(half[list(DLIB68.regions["eyes"])], eyes[0])


def test_only_is_a_case_of_the_regions_strengths(pair):
    """``only=mouth`` means the eyes' and brows' strengths at 0: the same image, bit for bit."""
    images, landmarks = pair
    prepared = exprclone.prepare(*images, ("e+md", "global"), landmarks=landmarks)
    by_only, by_strengths = prepared.render(only=("mouth",), strength=0.7), prepared.render(strength=0.7, strength_eyes=0, strength_brows=0)
    for method in by_only:
        assert np.array_equal(by_only[method].image, by_strengths[method].image), method


def test_shading_scales_the_details_alone(pair):
    """``strength_shading=0``: each ERI method gives its shape's image (FI), the ERI left out; 2 doubles the ERI's logarithm."""
    images, landmarks = pair
    prepared = exprclone.prepare(*images, ("global", "global+eri"), landmarks=landmarks)
    plain, none = prepared.render(mouth=False), prepared.render(mouth=False, strength_shading=0)
    assert np.array_equal(none["global+eri"].image, plain["global"].image)
    assert np.array_equal(none["global+eri"].landmarks["final"], plain["global+eri"].landmarks["final"])
    folds = np.abs(np.log(plain["global+eri"].eri)) > 0.05  # where the ERI darkens or lightens
    assert np.abs(plain["global+eri"].image.astype(int) - plain["global"].image)[folds].mean() > 3  # what shading 0 takes away
    double = prepared.render(strength_shading=2)["global+eri"].eri
    assert np.allclose(np.log(double), 2 * np.log(plain["global+eri"].eri), atol=1e-5)
