"""The mouth's state: how wide, how open, and what it shows between the lips (teeth, the dark cavity).

Not in the paper. Whether an expression opens the mouth, and whether the source's mouth
shows an interior worth pasting (:mod:`exprclone.mouth.paste`), is measured on the
landmarks and on the lips' own colours: landmark fitters often leave the inner lips of
full, closed lips apart, and what lies between them is then lips, not teeth.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..imaging import order, raster
from ..landmarks import align
from ..landmarks.layout import Layout

#: inner-lip polygon area over the squared mouth width (:func:`opening`): below the first
#: value a mouth is closed, above the second fully open; in between the paste fades in, so
#: that in a video the teeth appear as the lips part instead of popping in at once.
OPENING = (0.010, 0.020)
#: a pixel is tooth-coloured below this share of the lips' median saturation (and brighter
#: than the lips' median).
TOOTH_SATURATION = 0.6
#: a pixel is the mouth's cavity below this share of the lips' median luma.
CAVITY = 0.5
#: teeth and cavity between the lips (:func:`interior`), in squared mouth widths: below the
#: first value a source's mouth shows nothing, above the second it is fully open, and the
#: paste fades in between. On the London Set's 72 smiles and 72 neutral photos (detected
#: landmarks), closed mouths show at most 0.0052 (the shadow of the lip line, a lip
#: piercing) and smiles that show teeth 0.010 and more.
INTERIOR = (0.005, 0.010)


def mouth_width(landmarks: np.ndarray, layout: Layout) -> float:
    """Distance between the outer mouth corners."""
    i, j = layout.mouth_corners
    return float(np.linalg.norm(landmarks[j] - landmarks[i]))


def opening(landmarks: np.ndarray, layout: Layout) -> float:
    """Area of the inner-lip polygon over the squared mouth width: 0 for a closed mouth."""
    inner = landmarks[list(layout.mouth_inner)]
    x, y = inner[:, 0], inner[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    return float(area / max(mouth_width(landmarks, layout), 1e-9) ** 2)


def interior(image: np.ndarray, landmarks: np.ndarray, layout: Layout, gain: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The teeth and the dark cavity inside the inner lips, told from the lips around them.

    The lips (between the outer and the inner lip polygons) are the face's own
    reference, lit as the mouth is, so the rule holds for every skin tone and exposure:
    a pixel inside the inner-lip polygon is tooth-coloured when paler than the lips
    (saturation in HSV below :data:`TOOTH_SATURATION` times theirs, median) and
    brighter; it is cavity when darker than :data:`CAVITY` times their median luma.
    Lips, and a tongue, are neither. A coloured light saturates teeth and lips alike (an
    orange one drains their blue), and under a strong one teeth no longer look paler
    than lips; ``gain`` first takes the photo to another light (:func:`exprclone.mouth.tone.tone_gain`).

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    landmarks : ndarray of shape (N, 2)
    layout : Layout
    gain : ndarray of shape (3,), optional
        Per-channel gain applied to the photo's colours first.

    Returns
    -------
    teeth, cavity : ndarray of shape (H, W), bool
    """
    box, teeth_in_box, cavity_in_box = interior_in_box(image, landmarks, layout, gain)
    teeth = np.zeros(image.shape[:2], bool)
    cavity = teeth.copy()
    teeth[box], cavity[box] = teeth_in_box, cavity_in_box
    return teeth, cavity


def lips_in_box(
    image: np.ndarray, landmarks: np.ndarray, layout: Layout, gain: np.ndarray | None = None
) -> tuple[tuple[slice, slice], np.ndarray, np.ndarray, np.ndarray]:
    """The box of the outer lips, the photo in it (``gain`` applied to its colours first, as :func:`interior`'s), and in
    it the lips (between the outer and the inner lip polygons) and what the inner lips enclose, ``(h, w)`` bool each."""
    box = align.box(landmarks[list(layout.mouth_outer)], image.shape)
    crop, corner = image[box], (box[1].start, box[0].start)
    if gain is not None:
        crop = np.clip(crop * np.asarray(gain, np.float32) + 0.5, 0, 255).astype(np.uint8)
    inner: np.ndarray = np.zeros(crop.shape[:2], np.uint8)
    outer = np.zeros(crop.shape[:2], np.uint8)
    raster.fill_polygon(inner, landmarks[list(layout.mouth_inner)] - corner, 1)
    raster.fill_polygon(outer, landmarks[list(layout.mouth_outer)] - corner, 1)
    return box, crop, (outer > 0) & (inner == 0), inner > 0


def interior_in_box(
    image: np.ndarray, landmarks: np.ndarray, layout: Layout, gain: np.ndarray | None = None
) -> tuple[tuple[slice, slice], np.ndarray, np.ndarray]:
    """:func:`interior` in the box of the outer lips, where it may be found: the box, and the teeth and the cavity in it."""
    box, crop, lip, inner = lips_in_box(image, landmarks, layout, gain)
    if not lip.any() or not inner.any():
        return box, np.zeros_like(inner), np.zeros_like(inner)
    saturation = cv2.cvtColor(crop, cv2.COLOR_RGB2HSV)[..., 1].astype(np.float32)
    luma = raster.luma(crop.astype(np.float32))
    lip_luma = order.median(luma[lip])
    teeth = inner & (saturation < TOOTH_SATURATION * order.median(saturation[lip])) & (luma > lip_luma)
    return box, teeth, inner & (luma < CAVITY * lip_luma)


def fade_in(value: float, band: tuple[float, float]) -> float:
    """0 below ``band[0]``, 1 above ``band[1]``, linear in between.

    Examples
    --------
    >>> [fade_in(v, (1, 3)) for v in (0, 2, 5)]
    [0.0, 0.5, 1.0]
    """
    low, high = band
    return float(np.clip((value - low) / (high - low), 0.0, 1.0))
