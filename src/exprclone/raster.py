"""Small raster helpers the stages share: luma, a polygon filled with sub-pixel corners, a mask eroded by a disc."""

from __future__ import annotations

import cv2
import numpy as np

#: weights of R, G and B in the luma (ITU-R BT.601).
LUMA = np.array([0.299, 0.587, 0.114], np.float32)
#: fractional bits of the corners given to OpenCV's polygon fill (1/16 pixel).
SUBPIXEL_BITS = 4


def luma(image: np.ndarray) -> np.ndarray:
    """BT.601 luma (:data:`LUMA`) of RGB pixels: an ``(H, W, 3)`` image or a ``(K, 3)`` list of pixels.

    A uint8 image gives uint8 luma (OpenCV's rounded fixed-point conversion); float pixels
    give float32 luma. Anything without a last axis of three channels is taken to be luma
    already and returned as it is.
    """
    if image.shape[-1] != 3:
        return image
    if image.dtype == np.uint8 and image.ndim == 3:
        return cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    return np.asarray(image, np.float32) @ LUMA


def fill_polygon(mask: np.ndarray, points: np.ndarray, value: float) -> np.ndarray:
    """Fill the polygon through ``points`` (``(K, 2)`` pixel x, y, in order) with ``value``, in place; returns ``mask``."""
    return cv2.fillPoly(mask, [np.round(np.asarray(points) * (1 << SUBPIXEL_BITS)).astype(np.int32)], value, shift=SUBPIXEL_BITS)


def erode(mask: np.ndarray, radius: int) -> np.ndarray:
    """The mask eroded by a disc of ``radius`` pixels: a feather's blur then ends inside the shape."""
    return cv2.erode(mask, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1)))
