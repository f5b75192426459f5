"""Checks at the door: the inputs of the core, refused with one :class:`ExprCloneError` each.

The core's stages take what these functions let through and check nothing more. Every
outer layer (command line, server, batch) calls the same checks, so a bad input is
worded the same way everywhere.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from .errors import ExprCloneError
from .layout import Layout
from .options import GLOBAL_WARPS, IMAGE_WARPS, STRENGTH_RANGE, Options

#: the smallest distance between the outer eye corners, in pixels: every stage measures the face in this unit.
MIN_INTEROCULAR = 8.0
#: how far from the eyes' midpoint a landmark may lie, in eye distances (a chin lies about 1.5 away).
MAX_REACH = 4.0
#: the smallest ratio of the landmarks' narrower spread to their wider one (a face is no line).
MIN_SPREAD = 0.2


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
    >>> from exprclone.layout import DLIB68
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


def parse_lambda(value: float | str) -> float | str:
    """lambda_k as a command line, a form or a manifest gives it: ``"auto"`` or a number >= 0, as a number or as text
    (:func:`check_lambda`), else ExprCloneError about ``lambda``.

    Examples
    --------
    >>> parse_lambda("auto"), parse_lambda("0.5"), parse_lambda("inf"), parse_lambda(2)
    ('auto', 0.5, inf, 2)
    """
    if isinstance(value, str) and value != "auto":
        try:
            value = float(value)
        except ValueError:
            raise ExprCloneError("lambda", f"must be 'auto' or a number >= 0, got {value!r}") from None
    return check_lambda(value)


def options_from(options: Options | None, keywords: Mapping[str, Any]) -> Options:
    """The :class:`~exprclone.options.Options` of a call: ``options``, or the same given as keywords (``strength=0.5``).

    Raises
    ------
    ExprCloneError
        About a keyword that is not an option, or given beside ``options``.
    """
    names = [f.name for f in dataclasses.fields(Options)]
    unknown = sorted(set(keywords) - set(names))
    if unknown:
        raise ExprCloneError(unknown[0], f"not an option; choose from {', '.join(names)}")
    if options is None:
        return Options(**keywords)
    if keywords:
        raise ExprCloneError(sorted(keywords)[0], "given twice: as a keyword and in options")
    return options


def check_choices(options: Options, regions: tuple[str, ...]) -> Options:
    """The options that need no photo (warps, strength, regions, retargeting) checked, or ExprCloneError about the
    first bad one; ``global_landmarks`` is left as it is (:func:`check_options` checks it against a target photo).

    Parameters
    ----------
    options : Options
        ``only`` may also be one comma-separated string of region names.
    regions : tuple of str
        The regions ``only`` may name (:attr:`exprclone.layout.Layout.regions`).

    Returns
    -------
    Options
        With ``strength`` a float, ``only`` a tuple of region names or None, ``retarget`` a bool.
    """
    o = options
    for subject, value, allowed in (("global_warp", o.global_warp, GLOBAL_WARPS), ("image_warp", o.image_warp, IMAGE_WARPS)):
        if value not in allowed:
            raise ExprCloneError(subject, f"unknown {subject.replace('_', ' ')} {value!r}; choose one of: {', '.join(allowed)}")
    low, high = STRENGTH_RANGE
    if isinstance(o.strength, bool) or not isinstance(o.strength, (int, float)) or not low <= o.strength <= high:
        raise ExprCloneError("strength", f"must be a number from {low:g} to {high:g}, got {o.strength!r}")
    if not isinstance(o.retarget, (bool, np.bool_)):
        raise ExprCloneError("retarget", f"must be True or False, got {o.retarget!r}")
    return dataclasses.replace(o, strength=float(o.strength), only=check_regions(o.only, regions), retarget=bool(o.retarget))


def check_options(options: Options, n_points: int, target_shape: tuple[int, ...], regions: tuple[str, ...]) -> Options:
    """The options of a clone onto a target photo of ``target_shape`` (:func:`check_choices`, and ``global_landmarks``
    inside that photo), or ExprCloneError about the first bad one.

    Parameters
    ----------
    options : Options
    n_points : int
        Landmarks per face (for ``global_landmarks``).
    target_shape : tuple of int
        The target photo's shape: ``global_landmarks`` must lie inside it.
    regions : tuple of str
        As for :func:`check_choices`.

    Returns
    -------
    Options
    """
    checked = check_choices(options, regions)
    if checked.global_landmarks is None:
        return checked
    given = check_points(checked.global_landmarks, target_shape, n_points, "global_landmarks")
    if checked.global_warp != GLOBAL_WARPS[0]:
        raise ExprCloneError("global_landmarks", f"given landmarks replace the global warp; drop global_warp={checked.global_warp!r}")
    return dataclasses.replace(checked, global_landmarks=given)


def check_regions(only: tuple[str, ...] | str | None, regions: tuple[str, ...]) -> tuple[str, ...] | None:
    """``only`` as a tuple of known region names without repeats (a comma-separated string is split), or None for all
    (also when it names every region: the whole face)."""
    if only is None:
        return None
    names = tuple(n.strip() for n in only.split(",")) if isinstance(only, str) else tuple(only)
    bad = [n for n in names if n not in regions]
    if not names or bad:
        raise ExprCloneError("only", f"unknown region {bad[0] if bad else ''!r}; choose from: {', '.join(regions)}")
    return None if set(names) == set(regions) else tuple(dict.fromkeys(names))
