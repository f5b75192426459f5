"""Checks at the door: the inputs of the core, refused with one :class:`ExprCloneError` each.

The core's stages take what these functions let through and check nothing more. Every
outer layer (command line, server, batch) calls the same checks, so a bad input is
worded the same way everywhere.
"""

from __future__ import annotations

import numpy as np

from .errors import ExprCloneError


def check_image(image: np.ndarray, subject: str) -> np.ndarray:
    """An ``(H, W, 3)`` uint8 RGB image, or ExprCloneError about ``subject``."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ExprCloneError(subject, f"expected an (H, W, 3) uint8 RGB image, got shape {image.shape} dtype {image.dtype}")
    return image


def check_lambda(lambda_k: float | str) -> float | str:
    """``"auto"`` or a number >= 0 (``inf`` allowed: the local result), or ExprCloneError about ``lambda``."""
    if lambda_k != "auto" and not (isinstance(lambda_k, (int, float)) and lambda_k >= 0):
        raise ExprCloneError("lambda", f"must be 'auto' or a number >= 0, got {lambda_k!r}")
    return lambda_k


def check_finite(points: np.ndarray, subject: str) -> None:
    """ExprCloneError naming the first point with a NaN or infinite coordinate."""
    bad = ~np.isfinite(points).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        x, y = points[i]
        raise ExprCloneError(subject, f"point {i} has a non-finite coordinate ({x:g}, {y:g})")


def check_points(points: np.ndarray, image_shape: tuple[int, ...], n_points: int, subject: str) -> np.ndarray:
    """Landmarks checked for count, finiteness and position inside the image.

    Parameters
    ----------
    points : array_like of shape (n_points, 2)
        Landmarks (x, y) in pixels.
    image_shape : tuple of int
        Shape ``(H, W, ...)`` of the photo; points must lie in ``[0, W - 1] x [0, H - 1]``.
    n_points : int
        Number of landmarks expected.
    subject : str
        What the landmarks are (a role such as ``target_neutral``, or a file path).

    Returns
    -------
    ndarray of shape (n_points, 2), float64

    Raises
    ------
    ExprCloneError
        Wrong shape or count, a NaN or infinite value, or a point outside the image.
    """
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 2 or len(points) != n_points:
        found = f"{len(points)} landmarks" if points.ndim == 2 and points.shape[1] == 2 else f"an array of shape {points.shape}"
        raise ExprCloneError(subject, f"found {found}, expected {n_points} (x, y) pairs")
    check_finite(points, subject)
    h, w = image_shape[:2]
    outside = (points[:, 0] < 0) | (points[:, 0] > w - 1) | (points[:, 1] < 0) | (points[:, 1] > h - 1)
    if outside.any():
        i = int(np.flatnonzero(outside)[0])
        x, y = points[i]
        raise ExprCloneError(subject, f"landmark {i} at ({x:g}, {y:g}) is outside the {w}x{h} image")
    return points
