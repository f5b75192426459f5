"""Small raster helpers the stages share: luma, a polygon filled with sub-pixel corners, a mask eroded by a disc, an
image shrunk by whole blocks and enlarged back, pixels evenly sampled for a fit."""

from __future__ import annotations

import cv2
import numpy as np

#: weights of R, G and B in the luma (ITU-R BT.601).
LUMA = np.array([0.299, 0.587, 0.114], np.float32)
#: fractional bits of the corners given to OpenCV's polygon fill (1/16 pixel).
SUBPIXEL_BITS = 4
#: added to intensities in [0, 1] before a ratio or a logarithm of them, so that dark pixels give no NaN or infinity.
EPS = 0.02
#: a fit over an image's trusted pixels (a face's colour, the light's trend) takes at most this many of them, evenly
#: spread (:func:`evenly`; a fit's standard error at that count is under 1% of the spread it measures).
FIT_PIXELS = 16384


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


def dilate(mask: np.ndarray, radius: int) -> np.ndarray:
    """The mask dilated by a disc of ``radius`` pixels: the shape grown by ``radius`` all round."""
    return cv2.dilate(mask, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1)))


def shrink(image: np.ndarray, step: int) -> np.ndarray:
    """``image`` averaged over blocks of ``step x step`` pixels; a last partial block is left out.

    A whole number of blocks takes OpenCV's fast path of area averaging.
    """
    if step == 1:
        return image
    h, w = image.shape[0] // step, image.shape[1] // step
    return cv2.resize(image[: h * step, : w * step], (w, h), interpolation=cv2.INTER_AREA)


def enlarge(image: np.ndarray, shape: tuple[int, int], step: int, out: np.ndarray | None = None) -> np.ndarray:
    """Undo :func:`shrink` to ``shape`` (bilinear; the left-out edge repeats its neighbour), into ``out`` if given."""
    if step == 1 and out is None:
        return image
    out = np.empty(tuple(shape) + image.shape[2:], image.dtype) if out is None else out
    if step == 1:
        out[...] = image
        return out
    h, w = image.shape[0] * step, image.shape[1] * step
    cv2.resize(image, (w, h), dst=out[:h, :w], interpolation=cv2.INTER_LINEAR)  # in place: a padded copy costs 10 times the resize
    out[:h, w:] = out[:h, w - 1 : w]
    out[h:] = out[h - 1 : h]
    return out


def evenly(weight: np.ndarray) -> np.ndarray:
    """Flat indices of at most :data:`FIT_PIXELS` of the pixels of ``weight > 0.5``, evenly spread over them."""
    trusted = np.flatnonzero(weight > 0.5)
    return trusted[:: max(1, -(-len(trusted) // FIT_PIXELS))]
