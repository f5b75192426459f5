"""Eigenface feature vectors (Turk and Pentland), the features of the DB metric.

A face is described by the PCA coefficients of an aligned, grey, contrast-normalised
crop. The crop frame is fixed by the two eye centres only, so that differences of
expression (mouth, brows) are kept rather than aligned away.

The default basis, ``data/eigenfaces.npz``, was trained by ``tools/train_eigenfaces.py``
on the 144 photos (neutral and smiling) of the Face Research Lab London Set
(DeBruine and Jones 2017, CC BY 4.0). A user may train one on their own folder.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from importlib import resources

import cv2
import numpy as np

from ..imaging import raster
from ..landmarks import align
from ..landmarks.layout import Layout

#: side of the square face crop, in pixels.
CROP_SIZE = 64
#: where the eye centres land in the crop, as fractions of its side.
EYE_LEFT, EYE_RIGHT, EYE_HEIGHT = 0.3, 0.7, 0.32


def crop_transform(landmarks: np.ndarray, layout: Layout, size: int = CROP_SIZE) -> np.ndarray:
    """Similarity ``(2, 3)`` from image pixels to the crop frame, set by the eye centres."""
    eyes = np.array([landmarks[list(e)].mean(0) for e in layout.eyes])
    target = np.array([[EYE_LEFT, EYE_HEIGHT], [EYE_RIGHT, EYE_HEIGHT]]) * size
    return align.fit_similarity(eyes, target)


def normalise(crops: np.ndarray) -> np.ndarray:
    """Flatten ``(n, S, S)`` grey crops to zero mean and unit norm each (lighting invariance)."""
    flat = crops.reshape(len(crops), -1).astype(np.float64)
    flat = flat - flat.mean(axis=1, keepdims=True)
    return flat / np.maximum(np.linalg.norm(flat, axis=1, keepdims=True), 1e-12)


def downscaled(image: np.ndarray, transform: np.ndarray) -> tuple[np.ndarray, float]:
    """A grey copy of ``image`` shrunk close to the crop's scale, and its scale factor.

    Sampling a 1350-pixel photo straight into a 64-pixel crop would alias; shrinking
    first with area averaging keeps the crop a faithful low-pass view.
    """
    grey = raster.luma(image)
    scale = min(1.0, 2.0 * float(np.hypot(*transform[:, 0])))
    if scale < 1.0:
        grey = cv2.resize(grey, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    return grey, scale


def crop(image: np.ndarray, landmarks: np.ndarray, layout: Layout, size: int = CROP_SIZE) -> np.ndarray:
    """The aligned grey face crop of an image, ``(size, size)`` float32."""
    t = crop_transform(landmarks, layout, size)
    grey, scale = downscaled(image, t)
    t_small = t.copy()
    t_small[:, :2] /= scale
    return cv2.warpAffine(grey, t_small, (size, size), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE).astype(np.float32)


@dataclass(frozen=True)
class Eigenfaces:
    """A PCA basis of normalised face crops.

    Attributes
    ----------
    mean : ndarray of shape (D,)
    components : ndarray of shape (K, D)
        Orthonormal principal axes, strongest first.
    stddev : ndarray of shape (K,)
        Standard deviation of the training photos' coefficients on each axis.
    size : int
        Crop side; ``D = size * size``.
    """

    mean: np.ndarray
    components: np.ndarray
    stddev: np.ndarray
    size: int

    @classmethod
    def fit(cls, crops: np.ndarray, people: Sequence[str] | np.ndarray | None = None, n_components: int = 16) -> "Eigenfaces":
        """PCA of ``(n, S, S)`` crops, keeping ``n_components`` axes.

        The paper trains on "images with different expressions of one person", so that
        the axes span expression rather than identity. With photos of several people,
        ``people`` (one label per crop) says whose each crop is, and each person's mean
        crop is removed before the PCA, which keeps that property.
        """
        flat = normalise(crops)
        mean = flat.mean(axis=0)
        labels = np.zeros(len(flat), int) if people is None else np.unique(np.asarray(people), return_inverse=True)[1]
        centred = flat.copy()
        for g in np.unique(labels):
            centred[labels == g] -= flat[labels == g].mean(axis=0)
        _, _, vt = np.linalg.svd(centred, full_matrices=False)
        components = vt[:n_components]
        stddev = ((flat - mean) @ components.T).std(axis=0)
        return cls(mean.astype(np.float32), components.astype(np.float32), stddev.astype(np.float32), crops.shape[1])

    def features(self, crops: np.ndarray) -> np.ndarray:
        """Eigenface feature vectors ``E`` of ``(n, S, S)`` crops, ``(n, K)``.

        Coefficients are whitened (divided by :attr:`stddev`), so Euclidean distances
        between features are Mahalanobis distances in face space: the expected squared
        distance between two training faces is ``2 K``.

        The product is NumPy's own (einsum), not BLAS's: OpenBLAS shares a product of this size between threads, which
        on a busy machine wait for a core (a DB search of 13 candidates took 150 ms instead of 13 on two loaded cores).
        """
        return np.einsum("ij,kj->ik", normalise(crops) - self.mean, self.components.astype(np.float64)) / self.stddev

    def save(self, path: str | os.PathLike[str]) -> None:
        np.savez_compressed(path, mean=self.mean, components=self.components, stddev=self.stddev, size=self.size)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "Eigenfaces":
        with np.load(path) as f:
            return cls(f["mean"], f["components"], f["stddev"], int(f["size"]))

    @classmethod
    def default(cls) -> "Eigenfaces":
        """The basis shipped with the package (see the module docstring)."""
        with resources.as_file(resources.files("exprclone") / "data" / "eigenfaces.npz") as path:
            return cls.load(path)


def train(
    faces: Iterable[tuple[np.ndarray, np.ndarray]], layout: Layout, people: list[str] | None = None, n_components: int = 16
) -> Eigenfaces:
    """Fit a basis on the aligned crops (:func:`crop`) of faces.

    Parameters
    ----------
    faces : iterable of (image, landmarks)
        ``(H, W, 3)`` uint8 RGB photos, one face each, with its ``(N, 2)`` landmarks.
        Without ``people`` they are taken to show one person with different
        expressions, as in the paper.
    layout : Layout
    people : list of str, optional
        Whose face each photo shows.
    n_components : int
        Axes kept; at most one fewer than the number of photos.
    """
    crops = np.asarray([crop(image, points, layout) for image, points in faces])
    return Eigenfaces.fit(crops, people, min(n_components, len(crops) - 1))


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once, shared by every call that passes none of its own."""
    return Eigenfaces.default()
