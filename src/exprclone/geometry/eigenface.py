"""Eigenface feature vectors (Turk and Pentland), the features ``E`` of the DB metric (Eq. 7).

A face is described by the PCA coefficients of its organs: the patches (:data:`BOXES`) of the brows and eyes, the nose
and the mouth of a grey crop aligned on the two eye centres alone (:func:`crop_transform`, so that the differences of
expression are kept rather than aligned away), with :data:`FEATURE_IOD` pixels between them (:data:`FEATURE_SIZE`):
there, the organs' changes the elastic model balances are several pixels. The patches' pixels are brought to zero
mean and unit norm together (:func:`normalise`: a change of exposure changes no feature), and projected on the basis's
orthonormal axes; distances between features are Euclidean, in the basis's :attr:`Eigenfaces.unit`.

The paper trains its basis on "images with different expressions of one person" (12 in its experiments): its axes span
expression. With photos of several people, each person's mean is removed before the PCA (:meth:`Eigenfaces.fit`),
which keeps that property. The default basis, ``data/eigenfaces.npz``, was trained by ``tools/train_eigenfaces.py`` on
the 144 photos (each person's neutral face and smile) of the Face Research Lab London Set (DeBruine and Jones 2017, CC
BY 4.0), :data:`COMPONENTS` axes; a user may train one on a folder of one person's photos, as the paper does
(``--eigenfaces``). GRID's clips (many frames of a few speakers) are not in it: their faces have 65-77 pixels between
the eyes, about half the features' scale, and they speak rather than smile.

:func:`crop` at :data:`CROP_SIZE` is also the role check's first look at a face (:mod:`exprclone.pipeline.role_check`).
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

#: side of the role check's square face crop, in pixels.
CROP_SIZE = 64
#: where the eye centres land in a crop, as fractions of its side.
EYE_LEFT, EYE_RIGHT, EYE_HEIGHT = 0.3, 0.7, 0.32
#: pixels between the eye centres in the features' crop: an organ's change of 0.013 inter-ocular distances (the mouth's
#: between GI and LI, at the least) is 1.7 of them, the nose's 0.08 ten; a London photo has about 210.
FEATURE_IOD = 128
#: side of the features' crop.
FEATURE_SIZE = round(FEATURE_IOD / (EYE_RIGHT - EYE_LEFT))
#: the organs' patches in the features' crop, ``(x0, y0, x1, y1)`` as fractions of its side: the brows and eyes, the
#: nose below them, the mouth. Every organ of the London Set's 144 photos lies inside its patch with 0.1 inter-ocular
#: distances to spare (brows 0.09-0.92 across and 0.12-0.31 down, eyes down to 0.36, nose 0.38-0.63 across, mouth
#: 0.28-0.73 across and 0.61-0.92 down).
BOXES = ((0.05, 0.075, 0.955, 0.395), (0.335, 0.395, 0.67, 0.57), (0.235, 0.57, 0.765, 0.955))
#: axes of the shipped basis: beyond 24, eight more add under 2% of a held-out person's smile (its change from their
#: neutral face captured: 28% with 16 axes, 31% with 24, 33% with 32, learnt without them); 24 axes of the patches'
#: 56,652 pixels take 2.7 MB as float16.
COMPONENTS = 24


def crop_transform(landmarks: np.ndarray, layout: Layout, size: int = CROP_SIZE) -> np.ndarray:
    """Similarity ``(2, 3)`` from image pixels to a crop of side ``size``, set by the eye centres."""
    eyes = np.array([landmarks[list(e)].mean(0) for e in layout.eyes])
    target = np.array([[EYE_LEFT, EYE_HEIGHT], [EYE_RIGHT, EYE_HEIGHT]]) * size
    return align.fit_similarity(eyes, target)


def normalise(crops: np.ndarray) -> np.ndarray:
    """Flatten ``(n, ...)`` grey crops (or their patches) to zero mean and unit norm each (lighting invariance)."""
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


def boxes_in_pixels(size: int) -> np.ndarray:
    """:data:`BOXES` in the pixels of a crop of side ``size``, ``(R, 4)`` int."""
    return np.rint(np.asarray(BOXES) * size).astype(int)


def unit_of(features: np.ndarray, labels: np.ndarray) -> float:
    """The root-mean-square distance between two photos of one person, over the people with two or more: of
    ``(n, K)`` features, ``labels`` saying whose each is. Over every pair of one person's ``m`` photos the mean squared
    distance is ``2 m / (m - 1)`` times their mean squared distance to their mean; each person counts once."""
    spread = []
    for g in np.unique(labels):
        own = features[labels == g]
        if len(own) > 1:
            spread.append(2 * len(own) / (len(own) - 1) * ((own - own.mean(0)) ** 2).sum(1).mean())
    return float(np.sqrt(np.mean(spread)))


@dataclass(frozen=True)
class Eigenfaces:
    """A PCA basis of the organs' patches of face crops.

    Attributes
    ----------
    mean : ndarray of shape (D,)
    components : ndarray of shape (K, D)
        Orthonormal principal axes, strongest first.
    unit : float
        The root-mean-square distance between the features of two photos of one training person (:func:`unit_of`):
        the DB metric's unit of distance.
    size : int
        Crop side.
    boxes : ndarray of shape (R, 4)
        The patches ``(x0, y0, x1, y1)`` in the crop's pixels; ``D`` is their pixels' count.
    """

    mean: np.ndarray
    components: np.ndarray
    unit: float
    size: int
    boxes: np.ndarray

    def patches(self, crops: np.ndarray) -> np.ndarray:
        """The patches' pixels of ``(n, S, S)`` crops, normalised (:func:`normalise`), ``(n, D)``."""
        return normalise(np.concatenate([crops[:, y0:y1, x0:x1].reshape(len(crops), -1) for x0, y0, x1, y1 in self.boxes], 1))

    @classmethod
    def fit(cls, crops: np.ndarray, people: Sequence[str] | np.ndarray | None = None, n_components: int = COMPONENTS) -> "Eigenfaces":
        """PCA of ``(n, S, S)`` crops' patches (:data:`BOXES`), keeping ``n_components`` axes.

        The paper trains on "images with different expressions of one person", so that
        the axes span expression rather than identity. With photos of several people,
        ``people`` (one label per crop) says whose each crop is, and each person's mean
        crop is removed before the PCA, which keeps that property. Without, all are one person's.
        """
        size = crops.shape[1]
        shell = cls(np.zeros(0, np.float32), np.zeros((0, 0), np.float32), 1.0, size, boxes_in_pixels(size))
        flat = shell.patches(crops)
        labels = np.zeros(len(flat), int) if people is None else np.unique(np.asarray(people), return_inverse=True)[1]
        centred = flat.copy()
        for g in np.unique(labels):
            centred[labels == g] -= flat[labels == g].mean(axis=0)
        _, _, vt = np.linalg.svd(centred, full_matrices=False)
        components = vt[:n_components].astype(np.float32)
        unit = unit_of(flat @ components.T.astype(np.float64), labels)
        return cls(flat.mean(axis=0).astype(np.float32), components, unit, size, shell.boxes)

    def features(self, crops: np.ndarray) -> np.ndarray:
        """Eigenface feature vectors ``E`` of ``(n, S, S)`` crops, ``(n, K)``: the patches' coordinates on the axes.

        The product is NumPy's own (einsum), not BLAS's: OpenBLAS shares a product of this size between threads, which
        on a busy machine wait for a core (a DB search of 13 candidates took 150 ms instead of 13 on two loaded cores).
        """
        return np.einsum("ij,kj->ik", (self.patches(crops) - self.mean).astype(np.float32), self.components).astype(np.float64)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the basis as a ``.npz``, its axes as float16 (their features change by under 1e-3 of the unit)."""
        np.savez_compressed(
            path, mean=self.mean, components=self.components.astype(np.float16), unit=self.unit, size=self.size, boxes=self.boxes
        )

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "Eigenfaces":
        with np.load(path) as f:
            return cls(f["mean"], f["components"].astype(np.float32), float(f["unit"]), int(f["size"]), f["boxes"])

    @classmethod
    def default(cls) -> "Eigenfaces":
        """The basis shipped with the package (see the module docstring)."""
        with resources.as_file(resources.files("exprclone") / "data" / "eigenfaces.npz") as path:
            return cls.load(path)


def train(
    faces: Iterable[tuple[np.ndarray, np.ndarray]], layout: Layout, people: list[str] | None = None, n_components: int = COMPONENTS
) -> Eigenfaces:
    """Fit a basis on the features' crops (:func:`crop` at :data:`FEATURE_SIZE`) of faces.

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
    crops = np.asarray([crop(image, points, layout, FEATURE_SIZE) for image, points in faces])
    return Eigenfaces.fit(crops, people, min(n_components, len(crops) - 1))


@functools.cache
def default_eigenfaces() -> Eigenfaces:
    """The eigenface basis shipped with the package, loaded once, shared by every call that passes none of its own."""
    return Eigenfaces.default()
