"""The mouth interior: teeth, tongue and cavity taken from the source expression.

Not in the paper. Warping a closed neutral mouth open cannot create teeth: the lips are
stretched over where the teeth should be, and the paper's ERI and MD steps change
shading, not content. Where the final geometry opens the target's mouth and the source's
expression shows an open mouth, the inside of the target's inner lips is filled with the
source's mouth interior:

1. warped from the source's inner-lip polygon to the target's (a piecewise-affine warp
   over the lips and the polygon's centre);
2. matched to the target photo: its colour is scaled by the ratio of the two photos'
   eye whites (sclera), the one part of a face that, like teeth, is near white for
   everyone, so that the photo's exposure and colour cast carry over but not the
   source's skin tone;
3. blended inside the inner-lip polygon with a feathered edge that ends at the lip line,
   so the target's own lips stay the target's.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy.spatial import Delaunay

from . import warp
from .layout import Layout

#: inner-lip polygon area over the squared mouth width below which a mouth counts as closed.
MIN_OPENING = 0.015
#: feather of the blend, in mouth widths.
FEATHER = 0.015


def mouth_width(landmarks: np.ndarray, layout: Layout) -> float:
    """Distance between the outer mouth corners."""
    outer = layout.mouth_outer
    return float(np.linalg.norm(landmarks[outer[len(outer) // 2]] - landmarks[outer[0]]))


def opening(landmarks: np.ndarray, layout: Layout) -> float:
    """Area of the inner-lip polygon over the squared mouth width: 0 for a closed mouth."""
    inner = landmarks[list(layout.mouth_inner)]
    x, y = inner[:, 0], inner[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    return float(area / max(mouth_width(landmarks, layout), 1e-9) ** 2)


def sclera_colour(image: np.ndarray, landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Median RGB of the eye whites: the brightest quarter of the pixels inside both eyes."""
    mask = np.zeros(image.shape[:2], np.uint8)
    for eye in layout.eyes:
        cv2.fillPoly(mask, [np.round(landmarks[list(eye)]).astype(np.int32)], 1)
    pixels = image[mask > 0].astype(np.float32)
    if len(pixels) < 8:
        return np.full(3, 200.0, np.float32)
    luma = pixels @ np.array([0.299, 0.587, 0.114], np.float32)
    return np.median(pixels[luma >= np.percentile(luma, 75)], axis=0)


def fill_interior(
    image: np.ndarray,
    final: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    target_reference: np.ndarray,
    target_landmarks: np.ndarray,
    layout: Layout,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Paste the source's mouth interior inside the target's final inner lips.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The result so far (target photo in its final geometry).
    final : ndarray of shape (N, 2)
        Its landmarks.
    source : ndarray of shape (h, w, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    target_reference : ndarray of shape (H, W, 3), uint8
        The target's own photo, and ``target_landmarks`` its landmarks (for the tone match).
    layout : Layout

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
        Unchanged (the same array) when either mouth is closed.
    mask : ndarray of shape (H, W) or None
        Weight of the pasted interior, None when nothing was pasted.
    """
    if opening(final, layout) < MIN_OPENING or opening(source_landmarks, layout) < MIN_OPENING:
        return image, None
    mouth = list(layout.mouth_outer + layout.mouth_inner)
    inner = list(layout.mouth_inner)
    src = np.vstack([source_landmarks[mouth], source_landmarks[inner].mean(0)])
    dst = np.vstack([final[mouth], final[inner].mean(0)])
    width = mouth_width(final, layout)
    lo = np.maximum(np.floor(dst.min(0) - width * 0.1), 0).astype(int)
    hi = np.minimum(np.ceil(dst.max(0) + width * 0.1), (image.shape[1], image.shape[0])).astype(int)
    local = dst - lo
    triangles = Delaunay(local).simplices
    patch = warp.warp(source, src, local, triangles, (hi[1] - lo[1], hi[0] - lo[0])).astype(np.float32)
    gain = np.clip(sclera_colour(target_reference, target_landmarks, layout) / sclera_colour(source, source_landmarks, layout), 0.5, 2.0)
    patch *= gain

    polygon = np.zeros(patch.shape[:2], np.float32)
    cv2.fillPoly(polygon, [np.round(local[len(layout.mouth_outer) : len(mouth)] * 16).astype(np.int32)], 1.0, shift=4)
    sigma = max(FEATHER * width, 0.5)
    # shrink by a feather before blurring, and cut at the polygon: the fade ends at the
    # lip line and never reaches the lips
    k = max(1, int(round(sigma)))
    mask = cv2.erode(polygon, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1)))
    mask = cv2.GaussianBlur(mask, (0, 0), sigma) * polygon

    out = image.copy()
    box = (slice(lo[1], hi[1]), slice(lo[0], hi[0]))
    region = out[box].astype(np.float32)
    out[box] = np.clip(region + mask[..., None] * (patch - region) + 0.5, 0, 255).astype(np.uint8)
    full = np.zeros(image.shape[:2], np.float32)
    full[box] = mask
    return out, full
