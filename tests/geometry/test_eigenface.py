"""Eigenface features (the DB metric's E of Eq. 7): the PCA fit, whitening, lighting invariance, saving."""

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


def test_axes_are_orthonormal_and_features_whitened():
    crops, labels, _ = faces(np.random.default_rng(0))
    basis = Eigenfaces.fit(crops, labels, n_components=6)
    assert basis.components.shape == (6, SIZE * SIZE) and basis.size == SIZE
    assert np.allclose(basis.components @ basis.components.T, np.eye(6), atol=1e-5)
    assert np.allclose(basis.features(crops).std(axis=0), 1.0, rtol=1e-4)


def test_lighting_changes_no_feature():
    crops, labels, _ = faces(np.random.default_rng(1))
    basis = Eigenfaces.fit(crops, labels, n_components=4)
    assert np.allclose(basis.features(crops), basis.features(1.7 * crops - 40), atol=1e-4)


def test_removing_each_persons_mean_makes_the_axes_span_expression_not_identity():
    crops, labels, smile = faces(np.random.default_rng(2))
    direction = (smile - smile.mean()).ravel() / np.linalg.norm(smile - smile.mean())
    by_person = Eigenfaces.fit(crops, labels, n_components=1).components[0]
    pooled = Eigenfaces.fit(crops, n_components=1).components[0]
    assert abs(by_person @ direction) > 0.95  # the paper's setting: the first axis is the expression
    assert abs(pooled @ direction) < 0.5  # without labels, identity (5x stronger) takes it


def test_a_saved_basis_loads_as_it_was(tmp_path):
    crops, labels, _ = faces(np.random.default_rng(3))
    basis = Eigenfaces.fit(crops, labels, n_components=5)
    basis.save(tmp_path / "b.npz")
    loaded = Eigenfaces.load(tmp_path / "b.npz")
    for field in ("mean", "components", "stddev"):
        assert np.array_equal(getattr(loaded, field), getattr(basis, field))
    assert loaded.size == basis.size and np.array_equal(loaded.features(crops), basis.features(crops))


def test_the_packaged_basis():
    basis = Eigenfaces.default()
    assert basis.components.shape == (16, eigenface.CROP_SIZE**2) and (basis.stddev > 0).all()


def test_train_on_photos_of_one_person(photo):
    """Photos with their landmarks in, a basis out: at most one axis fewer than photos."""
    shots = [photo("001"), photo("001", "smile"), photo("003")]
    basis = eigenface.train(shots, DLIB68)
    assert basis.components.shape == (2, eigenface.CROP_SIZE**2)
    crops = np.array([eigenface.crop(image, points, DLIB68) for image, points in shots])
    assert crops.shape == (3, eigenface.CROP_SIZE, eigenface.CROP_SIZE)
    # the eyes land where the crop frame puts them
    eyes = np.array([shots[0][1][list(e)].mean(0) for e in DLIB68.eyes])
    placed = eyes @ eigenface.crop_transform(shots[0][1], DLIB68)[:, :2].T + eigenface.crop_transform(shots[0][1], DLIB68)[:, 2]
    size = eigenface.CROP_SIZE
    assert placed == pytest.approx(
        np.array([[eigenface.EYE_LEFT, eigenface.EYE_HEIGHT], [eigenface.EYE_RIGHT, eigenface.EYE_HEIGHT]]) * size
    )
