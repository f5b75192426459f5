"""Changes of light that are no expression, made to a photo: grey, relit from one side, another white balance.

A source pair should be one session in one light; these are what a pair from elsewhere brings (issue 57). The tests
(the ERI's, the role check's) and the tools that measure what such a change does (``tools/role_check.py``,
``tools/relight.py``) make them alike.
"""

from __future__ import annotations

import cv2
import numpy as np

from exprclone.imaging import raster

#: the relight's change from the face's middle to each ear: +-15% (30% from one ear to the other).
SIDE_LIGHT = 0.15
#: another white balance: a warm light (R up, B down) and a cool one, as R, G, B gains.
WARM, COOL = (1.08, 1.0, 0.9), (0.9, 1.0, 1.1)
#: the noise of :func:`noisy`, in grey levels: a change no eye sees.
NOISE = 1.0


def grey(image: np.ndarray) -> np.ndarray:
    """The photo made grey: its luma (:func:`exprclone.imaging.raster.luma`) in all three channels."""
    return np.repeat(raster.luma(image)[..., None], 3, axis=2)


def relit(image: np.ndarray, landmarks: np.ndarray, sign: int = 1) -> np.ndarray:
    """The photo lit :data:`SIDE_LIGHT` more on one side of the face and as much less on the other, linearly from one ear
    (dlib's landmark 0) to the other (16), the gain held beyond them; ``sign`` 1 brighter towards landmark 16."""
    x = np.arange(image.shape[1], dtype=np.float32)
    across = np.clip((x - landmarks[0, 0]) / (landmarks[16, 0] - landmarks[0, 0]), 0.0, 1.0)
    gain = 1.0 + sign * SIDE_LIGHT * (2.0 * across - 1.0)
    return np.clip(image * gain[None, :, None] + 0.5, 0, 255).astype(np.uint8)


def balanced(image: np.ndarray, gains: tuple[float, float, float]) -> np.ndarray:
    """The photo's R, G and B scaled by ``gains``: another white balance."""
    return np.clip(image * np.asarray(gains, np.float32) + 0.5, 0, 255).astype(np.uint8)


def changes(image: np.ndarray, landmarks: np.ndarray) -> dict[str, np.ndarray]:
    """Every change of light of the tools, by name: ``grey``, ``relit+``, ``relit-``, ``warm``, ``cool``."""
    return {
        "grey": grey(image),
        "relit+": relit(image, landmarks, 1),
        "relit-": relit(image, landmarks, -1),
        "warm": balanced(image, WARM),
        "cool": balanced(image, COOL),
    }


def noisy(image: np.ndarray, sigma: float = NOISE, seed: int = 0) -> np.ndarray:
    """The photo with Gaussian noise of ``sigma`` grey levels (seeded): no change of light, a reference for one."""
    noise = np.random.default_rng(seed).normal(0.0, sigma, image.shape)
    return np.clip(image + noise + 0.5, 0, 255).astype(np.uint8)


def face(shape: tuple[int, ...], landmarks: np.ndarray) -> np.ndarray:
    """Inside the face: the hull of the jaw and the brows (dlib's 0-26), bool ``(H, W)``."""
    mask = np.zeros(shape[:2], np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(landmarks[:27].astype(np.float32)).round().astype(np.int32), 1)
    return mask.astype(bool)


def change(a: np.ndarray, b: np.ndarray, mask: np.ndarray) -> tuple[float, float]:
    """The mean and the 95th percentile inside ``mask`` of how much ``b`` differs from ``a``, uint8 RGB: each pixel's
    absolute difference averaged over R, G and B (grey levels). A change of the luma counts as it is; a change of colour
    that keeps the luma (another white balance carried as a tint) counts too."""
    diff = np.abs(a.astype(np.float32) - b.astype(np.float32)).mean(axis=2)[mask]
    return float(diff.mean()), float(np.percentile(diff, 95))
