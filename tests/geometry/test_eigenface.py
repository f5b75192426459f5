"""Eigenface features (the DB metric's E of Eq. 7): the PCA fit of the organs' patches, its unit, lighting invariance, saving."""

import numpy as np
import pytest

from exprclone.geometry import eigenface
from exprclone.geometry.eigenface import Eigenfaces
from exprclone.landmarks.layout import DLIB68

SIZE = 16


def faces(rng, people=4, per_person=12, identity=5.0, expression=1.0):
    """Synthetic crops: each person a fixed pattern, each photo that plus some amount of one expression pattern."""
    who = rng.normal(size=(people, SIZE, SIZE)) * identity
    smile = rng.normal(size=(SIZE, SIZE))
    amounts = rng.uniform(-1, 1, (people, per_person))
    crops = who[:, None] + expression * amounts[..., None, None] * smile + 0.05 * rng.normal(size=(people, per_person, SIZE, SIZE))
    labels = np.repeat(np.arange(people), per_person)
    return crops.reshape(-1, SIZE, SIZE) + 100, labels, smile


def test_axes_are_orthonormal_and_the_unit_is_two_photos_of_one_person_apart():
    crops, labels, _ = faces(np.random.default_rng(0))
    basis = Eigenfaces.fit(crops, labels, n_components=6)
    assert basis.components.shape == (6, len(basis.mean)) and basis.size == SIZE
    assert np.allclose(basis.components @ basis.components.T, np.eye(6), atol=1e-5)
    # the unit: over every pair of one person's photos, root-mean-square distance, each person counted once
    e = basis.features(crops)
    per_person = [np.mean([np.sum((a - b) ** 2) for i, a in enumerate(e[labels == g]) for b in e[labels == g][i + 1 :]]) for g in range(4)]
    assert basis.unit == pytest.approx(np.sqrt(np.mean(per_person)), rel=1e-4)


def test_features_are_the_organs_patches_alone():
    crops, labels, _ = faces(np.random.default_rng(4))
    basis = Eigenfaces.fit(crops, labels, n_components=4)
    outside = np.ones((SIZE, SIZE), bool)
    for x0, y0, x1, y1 in basis.boxes:
        outside[y0:y1, x0:x1] = False
    changed = crops.copy()
    changed[:, outside] = 0  # whatever lies off the organs
    assert outside.any() and np.allclose(basis.features(changed), basis.features(crops), atol=1e-4)


def test_lighting_changes_no_feature():
    crops, labels, _ = faces(np.random.default_rng(1))
    basis = Eigenfaces.fit(crops, labels, n_components=4)
    assert np.allclose(basis.features(crops), basis.features(1.7 * crops - 40), atol=1e-4)


def test_removing_each_persons_mean_makes_the_axes_span_expression_not_identity():
    crops, labels, smile = faces(np.random.default_rng(2))
    by_person = Eigenfaces.fit(crops, labels, n_components=1)
    direction = by_person.patches(smile[None])[0]  # the expression's pattern on the patches, zero mean, unit norm
    pooled = Eigenfaces.fit(crops, n_components=1).components[0]
    assert abs(by_person.components[0] @ direction) > 0.95  # the paper's setting: the first axis is the expression
    assert abs(pooled @ direction) < 0.5  # without labels, identity (5x stronger) takes it


def test_a_saved_basis_loads_as_it_was(tmp_path):
    crops, labels, _ = faces(np.random.default_rng(3))
    basis = Eigenfaces.fit(crops, labels, n_components=5)
    basis.save(tmp_path / "b.npz")
    loaded = Eigenfaces.load(tmp_path / "b.npz")
    assert np.array_equal(loaded.mean, basis.mean) and np.array_equal(loaded.boxes, basis.boxes)
    assert loaded.size == basis.size and loaded.unit == basis.unit
    # the axes are stored as float16: the features move by a small part of the unit
    assert np.abs(loaded.features(crops) - basis.features(crops)).max() < 1e-3 * basis.unit


def test_the_packaged_basis():
    basis = Eigenfaces.default()
    pixels = sum((x1 - x0) * (y1 - y0) for x0, y0, x1, y1 in basis.boxes)
    assert basis.size == eigenface.FEATURE_SIZE and basis.components.shape == (eigenface.COMPONENTS, pixels) and basis.unit > 0


def test_train_on_photos_of_one_person(photo):
    """Photos with their landmarks in, a basis out: at most one axis fewer than photos."""
    shots = [photo("001"), photo("001", "smile"), photo("003")]
    basis = eigenface.train(shots, DLIB68)
    assert basis.components.shape[0] == 2 and basis.size == eigenface.FEATURE_SIZE
    # the eyes land where the crop frame puts them, FEATURE_IOD pixels apart
    t = eigenface.crop_transform(shots[0][1], DLIB68, eigenface.FEATURE_SIZE)
    eyes = np.array([shots[0][1][list(e)].mean(0) for e in DLIB68.eyes]) @ t[:, :2].T + t[:, 2]
    size = eigenface.FEATURE_SIZE
    assert eyes == pytest.approx(np.array([[eigenface.EYE_LEFT, eigenface.EYE_HEIGHT], [eigenface.EYE_RIGHT, eigenface.EYE_HEIGHT]]) * size)
    assert eyes[1, 0] - eyes[0, 0] == pytest.approx(eigenface.FEATURE_IOD, abs=0.5)
