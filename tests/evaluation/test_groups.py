"""The group photos made of London people: each face as wide as asked, where its record says, whole, and no face over
another."""

import cv2
import numpy as np
import pytest

from exprclone import data as samples
from exprclone.evaluation.groups import face_of, make, row_heights

WIDTHS = (100, 260, 180)


@pytest.fixture(scope="module")
def made():
    return make(samples.london(), samples.PEOPLE, WIDTHS, (900, 800), seed=1, tilts=(0, 12, -20))


def test_each_face_is_as_wide_as_asked_and_none_covers_another(made):
    _, people = made
    assert [p.face_id for p in people] == list(samples.PEOPLE)
    assert np.allclose([p.width for p in people], WIDTHS, rtol=0.01)
    boxes = [np.r_[p.landmarks.min(0), p.landmarks.max(0)] for p in people]
    for a in range(3):
        for b in range(a + 1, 3):
            apart = np.minimum(boxes[a][2:], boxes[b][2:]) < np.maximum(boxes[a][:2], boxes[b][:2])
            assert apart.any()
    assert people[0].landmarks[:, 1].mean() < min(p.landmarks[:, 1].mean() for p in people[1:])  # the smallest behind


def test_the_face_is_the_persons_own_photo_where_the_record_puts_it(made):
    image, people = made
    person = people[1]  # turned by 12 degrees
    photo, points = face_of(samples.london(), person.face_id)
    matrix = cv2.getRotationMatrix2D(tuple(float(v) for v in points[36:48].mean(0)), 12, 1.0)
    turned = cv2.warpAffine(photo, matrix, photo.shape[1::-1])
    small = cv2.resize(turned, None, fx=person.scale, fy=person.scale, interpolation=cv2.INTER_AREA)
    eye = person.landmarks[36:42].mean(0).round().astype(int)  # the subject's right eye, and around it
    own = ((np.asarray(points[36:42]).mean(0) @ matrix[:, :2].T + matrix[:, 2] + 0.5) * person.scale - 0.5).round().astype(int)
    patch = image[eye[1] - 15 : eye[1] + 15, eye[0] - 25 : eye[0] + 25].astype(int)
    mine = small[own[1] - 15 : own[1] + 15, own[0] - 25 : own[0] + 25].astype(int)
    assert np.abs(patch - mine).mean() < 4


def test_a_photo_too_low_for_its_rows_is_refused():
    assert row_heights([[100], [200]], 700)[1] > row_heights([[100], [200]], 700)[0]
    with pytest.raises(ValueError, match="too low"):
        row_heights([[100], [300]], 600)
