"""Checks at the door: the inputs of the core, refused with one :class:`ExprCloneError` each.

The core's stages take what these functions let through and check nothing more. Every
outer layer (command line, server, batch) calls the same checks, so a bad input is
worded the same way everywhere.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from ..errors import ExprCloneError
from ..landmarks.layout import Layout
from ..options import Options, check_regions

#: the smallest distance between the outer eye corners, in pixels: every stage measures the face in this unit.
MIN_INTEROCULAR = 8.0
#: how far from the eyes' midpoint a landmark may lie, in eye distances (a chin lies about 1.5 away).
MAX_REACH = 4.0
#: the smallest ratio of the landmarks' narrower spread to their wider one (a face is no line).
MIN_SPREAD = 0.2


def check_image(image: np.ndarray, subject: str) -> np.ndarray:
    """An ``(H, W, 3)`` uint8 RGB image, or ExprCloneError about ``subject`` (a file's path given for its image: how to
    read it)."""
    if isinstance(image, (str, os.PathLike)):
        raise ExprCloneError(subject, f"a file's path ({os.fspath(image)}), not its image: read it with exprclone.io.images.load_image")
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ExprCloneError(subject, f"expected an (H, W, 3) uint8 RGB image, got shape {image.shape} dtype {image.dtype}")
    return image


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


def check_face(points: np.ndarray, layout: Layout, subject: str) -> np.ndarray:
    """Landmarks that make a face the stages can measure, or ExprCloneError about ``subject``.

    What the clone relies on: the outer eye corners apart (:data:`MIN_INTEROCULAR` pixels; every
    length is measured in eye distances, and the face's axes are set by the eye line), every
    point near the eyes (:data:`MAX_REACH` eye distances: the face's box bounds the work), and a
    face that is not flat (the smaller principal spread at least :data:`MIN_SPREAD` of the larger;
    collinear landmarks leave the mesh without triangles). Coinciding points are allowed: the
    lids of a closed eye and the lips of a closed mouth meet.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Landmarks (x, y) in pixels, finite (:func:`check_points`).
    layout : Layout
    subject : str

    Returns
    -------
    ndarray of shape (N, 2)
        ``points``, unchanged.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> check_face(np.zeros((68, 2)), DLIB68, "same.json")
    Traceback (most recent call last):
    ...
    exprclone.errors.ExprCloneError: same.json: not a face: the outer eye corners (points 36 and 45) are 0 pixels apart (at least 8)
    """
    i, j = layout.eye_corners
    iod = float(np.linalg.norm(points[j] - points[i]))
    if not iod >= MIN_INTEROCULAR:
        raise ExprCloneError(
            subject, f"not a face: the outer eye corners (points {i} and {j}) are {iod:.3g} pixels apart (at least {MIN_INTEROCULAR:g})"
        )
    reach = np.linalg.norm(points - (points[i] + points[j]) / 2, axis=1) / iod
    if reach.max() > MAX_REACH:
        k = int(reach.argmax())
        raise ExprCloneError(subject, f"not a face: point {k} lies {reach[k]:.3g} eye distances from the eyes (at most {MAX_REACH:g})")
    spread = np.linalg.svd(points - points.mean(0), compute_uv=False)
    if spread[1] < MIN_SPREAD * spread[0]:
        raise ExprCloneError(subject, "not a face: the landmarks lie (almost) on one line")
    return points


def check_for_target(options: Options, target_shape: tuple[int, ...]) -> Options:
    """The options of a clone onto a target photo of ``target_shape``: ``only``'s regions those of the options' layout,
    ``global_landmarks`` a face inside that photo (:func:`check_points`, :func:`check_face`); else ExprCloneError about
    the first bad one.

    Returns
    -------
    Options
        With ``global_landmarks`` as float64 points.
    """
    layout = options.landmarks_layout
    check_regions(options.only, "only", tuple(layout.regions))
    if options.global_landmarks is None:
        return options
    given = check_points(options.global_landmarks, target_shape, layout.n_points, "global_landmarks")
    return dataclasses.replace(options, global_landmarks=check_face(given, layout, "global_landmarks"))
