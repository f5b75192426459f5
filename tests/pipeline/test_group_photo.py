"""The issue's group photo: six London people at face widths from 120 to 400 pixels, all given the built-in smile.

Every face reads as a smile to the expression judge (trained on sixteen other people), every face's region is the
single-face clone of that region cut out, and each face's change is, within JPEG-level noise, the change its clone makes
on its own London photo at the same scale (its own light, whatever stands around it)."""

import cv2
import numpy as np
import pytest
from conftest import LONDON, need_full_data

import exprclone.expressions
from exprclone.evaluation.groups import face_of, make
from exprclone.evaluation.judge import SMILING, SmileJudge
from exprclone.landmarks.backends import default_detector
from exprclone.pipeline import group

PEOPLE = ("039", "041", "043", "044", "045", "062")
WIDTHS = (120, 176, 232, 288, 344, 400)
#: the judge learns from the first sixteen London people (as tests/evaluation/test_judge.py), none of them in the photo.
TRAINING = 16
#: JPEG at quality 95 keeps a photo within about 40 dB of itself: the noise a region may differ by.
JPEG_PSNR = 40.0


def psnr(a, b):
    error = float(np.mean((np.asarray(a, float) - b) ** 2))
    return 10 * np.log10(255**2 / max(error, 1e-12))


@pytest.fixture(scope="module")
def made():
    image, people = make(need_full_data(LONDON), PEOPLE, WIDTHS, (1800, 1400))
    return image, people, exprclone.expressions.clone(image, "smile")


@pytest.fixture(scope="module")
def judge(photo):
    people = sorted(p.name[:3] for p in need_full_data(LONDON / "neutral_front").glob("*_03.jpg"))[:TRAINING]
    assert not set(people) & set(PEOPLE)
    return SmileJudge.train([photo(p)[1] for p in people], [photo(p, "smile")[1] for p in people])


def own_core(face, shape):
    """The pixels of a face's core (:func:`exprclone.pipeline.group.core_radius`), of its region."""
    x0, y0, x1, y1 = face.region
    ys, xs = np.mgrid[y0:y1, x0:x1]
    return group.core_radius(face.result.landmarks["target_neutral"] + (x0, y0), ys, xs) <= 1


def test_every_face_is_cloned_and_the_rest_is_the_input(made):
    image, _, result = made
    assert [f.number for f in result.face_results if f.result is not None] == [1, 2, 3, 4, 5, 6]
    outside = np.ones(image.shape[:2], bool)
    for face in result.face_results:
        x0, y0, x1, y1 = face.region
        outside[y0:y1, x0:x1] = False
    assert np.array_equal(result.image[outside], image[outside])


def test_every_face_smiles_for_the_judge(made, judge):
    image, _, result = made
    fit = default_detector().fit
    before = [judge(fit(image, face.box)) for face in result.face_results]
    after = [judge(fit(result.image, face.box)) for face in result.face_results]
    assert max(before) < SMILING <= min(after), (before, after)


def test_each_region_is_the_clone_of_its_face_cut_out(made):
    """Over its core, and wherever the photo takes its clone whole (its weight 1: away from the region's edges and from
    the other faces), each region is the clone of its face cut out. (Near the edges the clone's change fades out: the
    face's outline moves with its smile, and the clone of the cut-out moves what lies beside it, another face's hair.)"""
    image, _, result = made
    found = [group.Found(f.number, f.box, f.result.landmarks["target_neutral"] + f.region[:2]) for f in result.face_results]
    weights = group.weights(found, found, [f.region for f in result.face_results], image.shape)
    for face, weight in zip(result.face_results, weights):
        x0, y0, x1, y1 = face.region
        alone = exprclone.expressions.clone(image[y0:y1, x0:x1].copy(), "smile", target_landmarks=face.result.landmarks["target_neutral"])
        core = own_core(face, image.shape)
        ours = result.image[y0:y1, x0:x1]
        assert np.abs(ours[core].astype(int) - alone.image[core]).max() <= 1
        whole = weight >= 1
        assert whole.mean() > 0.3 and np.array_equal(ours[whole], alone.image[whole])


def test_each_face_changes_as_on_its_own_photo_at_the_same_scale(made):
    """The clone's change over each face (its core within its outline: beyond it lies the background, another one, which
    the outline's motion with the smile uncovers), against the change the same clone makes on the person's London photo
    scaled as in the group: another background, another crop, the same light on the face."""
    image, people, result = made
    for face in result.face_results:
        left, top, right, bottom = face.box
        (person,) = [p for p in people if left <= p.landmarks[30][0] <= right and top <= p.landmarks[30][1] <= bottom]
        photo, _ = face_of(LONDON, person.face_id)
        scaled = cv2.resize(photo, None, fx=person.scale, fy=person.scale, interpolation=cv2.INTER_AREA)
        x0, y0, x1, y1 = face.region
        ox, oy = int(person.offset[0]), int(person.offset[1])
        u0, v0, u1, v1 = max(0, x0 - ox), max(0, y0 - oy), min(scaled.shape[1], x1 - ox), min(scaled.shape[0], y1 - oy)
        own = scaled[v0:v1, u0:u1].copy()
        points = face.result.landmarks["target_neutral"] + (x0 - ox - u0, y0 - oy - v0)
        alone = exprclone.expressions.clone(own, "smile", target_landmarks=points)
        part = (slice(v0 + oy - y0, v1 + oy - y0), slice(u0 + ox - x0, u1 + ox - x0))
        outline = np.zeros(own.shape[:2], np.uint8)
        cv2.fillConvexPoly(outline, cv2.convexHull(np.round(points).astype(np.int32)), 1)
        core = own_core(face, image.shape)[part] & (outline > 0)
        ours = result.image[y0:y1, x0:x1][part].astype(float) - image[y0:y1, x0:x1][part]
        theirs = alone.image.astype(float) - own
        assert psnr(ours[core], theirs[core]) > JPEG_PSNR, person.face_id
