"""Shape-normalised composites on the sample people: the frame, the warp to a shape, the average, the pasted interior."""

import numpy as np
import pytest

from exprclone.expressions import composite
from exprclone.expressions.composite import Face
from exprclone.landmarks import align
from exprclone.landmarks.backends import default_detector
from exprclone.landmarks.layout import DLIB68

PEOPLE = ("001", "003", "126")


@pytest.fixture(scope="module")
def pairs(request):
    photo = request.getfixturevalue("photo")
    return [(Face(*photo(p)), Face(*photo(p, "smile"))) for p in PEOPLE]


@pytest.fixture(scope="module")
def built(pairs):
    return composite.build(pairs)


def iod(points):
    return align.interocular(points, DLIB68)


def test_the_reference_is_levelled_scaled_and_centred(pairs):
    frame = composite.reference([n.points for n, _ in pairs])
    left, right = frame[list(DLIB68.eye_corners)]
    assert np.isclose(iod(frame), composite.IOD) and abs(left[1] - right[1]) < 1e-9
    h, w = composite.SIZE
    assert np.isclose((left[0] + right[0]) / 2, w / 2) and (frame >= 0).all() and (frame[:, 0] < w).all() and (frame[:, 1] < h).all()


def test_a_photo_warped_to_a_shape_has_that_shape(pairs, built):
    warped = composite.to_shape(pairs[1][0], built.neutral.points).astype(np.uint8)
    found = default_detector().detect(warped)
    assert np.linalg.norm(found - built.neutral.points, axis=1).mean() < 0.03 * composite.IOD


def test_a_composite_is_a_face_of_the_average_shape(built, pairs):
    """Its landmarks are the people's aligned mean, and a detector finds them there; both composites share one frame."""
    found = default_detector().detect(built.neutral.image)
    assert np.linalg.norm(found - built.neutral.points, axis=1).mean() < 0.03 * composite.IOD
    rigid = list(DLIB68.rigid)
    assert np.abs(built.expression.points[rigid] - built.neutral.points[rigid]).max() < 0.03 * composite.IOD
    widths = [np.linalg.norm(p[54] - p[48]) / iod(p) for p in (built.neutral.points, built.expression.points)]
    assert widths[1] > widths[0]  # they smile


def test_the_interior_is_the_donors_inside_the_inner_lips_and_nothing_outside(pairs):
    built, donor = composite.build(pairs[2:]), pairs[0][1]  # 126's open smile, 001's mouth
    pasted = composite.with_interior(built.expression, donor)
    mask = composite.interior_mask(built.expression.points, composite.SIZE)
    assert np.array_equal(pasted.image[mask == 0], built.expression.image[mask == 0])
    warped = composite.to_shape(donor, built.expression.points)
    inside = mask > 0.9
    assert inside.sum() > 100
    near = np.abs(pasted.image[inside] - warped[inside])
    assert (near <= 0.1 * np.abs(built.expression.image[inside] - warped[inside]) + 1).all()
