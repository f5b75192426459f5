"""Thin-plate-spline image warping (Bookstein 1989): smooth where the mesh warp has kinks.

The piecewise-affine warp of :mod:`exprclone.warp` is continuous but its derivative jumps
at every triangle edge: a straight line across the face (a wrinkle, the edge of a lip)
bends at each edge it crosses. The thin-plate spline through the same control points
is the map of least bending energy: smooth everywhere, exact at the control points.

The output-to-source map ``g`` is fitted on the control points (output positions to
source positions) and evaluated on two grids only: a coarse one over the whole image,
and a finer one over the face, where it bends most (:data:`GRID_STEP`); the maps in
between are interpolated (bicubic) and the photo sampled with one ``cv2.remap``. The
spline is smooth at the grids' scales, so this costs little accuracy and most of the
time of evaluating it at every pixel.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import cv2
import numpy as np
from scipy.interpolate import RBFInterpolator

#: pixels between the grid nodes where the spline is evaluated over the whole image, and
#: over the face (the box of the control points that move, grown by :data:`FACE_MARGIN`),
#: where it bends most. ``python tools/tps_grid.py``: on 20 London smiles cloned at 1350
#: pixels, the map interpolated between these nodes (bicubic) is at most 0.57 pixel from
#: the spline itself (median 0.02), in 1.6 times the mesh warp's time; one grid of 16
#: pixels everywhere, as fast, was 2.5 pixels off near the inner lips, and (32, 4) 0.24
#: pixel off in 3.1 times the mesh warp's time.
GRID_STEP = (32, 8)
#: the fine grid reaches this share of the face box's size beyond it.
FACE_MARGIN = 0.1
#: control points whose output positions are closer than this (pixels) are one point, at
#: their mean source position: the inner lips of a closed mouth and the point between
#: them coincide, and a spline cannot take one place to several (or nearly one place to
#: places far apart without a spike).
MERGE_DISTANCE = 1.0


def merged(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Control points with output positions closer than :data:`MERGE_DISTANCE` merged (:data:`MERGE_DISTANCE`'s note).

    Examples
    --------
    >>> src, dst = np.array([[0.0, 0], [0, 4], [9, 9]]), np.array([[0.0, 0], [0, 0.2], [9, 9]])
    >>> [a.tolist() for a in merged(src, dst)]
    [[[0.0, 2.0], [9.0, 9.0]], [[0.0, 0.1], [9.0, 9.0]]]
    """
    label = np.arange(len(dst))
    for i in range(len(dst)):
        close = np.flatnonzero(np.linalg.norm(dst - dst[i], axis=1) < MERGE_DISTANCE)
        label[close] = label[close].min()
    groups = np.unique(label)
    return (np.array([a[label == g].mean(axis=0) for g in groups]) for a in (src, dst))


def upsampled(spline: Callable[[np.ndarray], np.ndarray], origin: tuple[int, int], shape: tuple[int, int], step: int) -> np.ndarray:
    """``spline`` over the ``shape`` pixels from ``origin`` (x, y): evaluated every ``step`` pixels, bicubic in between.

    ``cv2.resize`` by ``step`` puts node ``j`` at pixel ``(j + 0.5) step - 0.5`` of its
    output; two nodes more on each side than the pixels need keep its edge (where it
    repeats the last node) out of the result, which is cropped from it.
    """
    (x0, y0), (h, w) = origin, shape
    ny, nx = -(-h // step) + 4, -(-w // step) + 4
    xs, ys = x0 + (np.arange(nx) - 1.5) * step - 0.5, y0 + (np.arange(ny) - 1.5) * step - 0.5
    nodes = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
    coarse = spline(nodes).reshape(ny, nx, 2).astype(np.float32)
    fine = cv2.resize(coarse, (nx * step, ny * step), interpolation=cv2.INTER_CUBIC)
    return fine[2 * step : 2 * step + h, 2 * step : 2 * step + w]


def inverse_maps(src: np.ndarray, dst: np.ndarray, out_shape: tuple[int, int], moving: int | None = None) -> np.ndarray:
    """The spline's map from each output pixel to its source position, ``(H, W, 2)`` float32 (for ``cv2.remap``).

    Parameters
    ----------
    src, dst : ndarray of shape (N, 2)
        Control points in the source image and in the output, not all on one line.
    out_shape : (H, W)
    moving : int, optional
        The first ``moving`` control points are the face's (:data:`GRID_STEP`); all by default.
    """
    h, w = out_shape
    src, dst = np.asarray(src, float), np.asarray(dst, float)
    face = dst[:moving]
    src, dst = merged(src, dst)
    # the spline of the displacement, fitted in units of the control points' spread: the
    # kernel's scale does not matter to a thin-plate spline, but the linear system is better conditioned
    centre, unit = dst.mean(axis=0), max(float(dst.std()), 1.0)
    fit = RBFInterpolator((dst - centre) / unit, src - dst, kernel="thin_plate_spline")
    spline = lambda points: fit((points - centre) / unit)  # noqa: E731
    shift = upsampled(spline, (0, 0), (h, w), GRID_STEP[0])
    margin = FACE_MARGIN * (face.max(axis=0) - face.min(axis=0))
    lo = np.clip(np.floor(face.min(axis=0) - margin), 0, (w, h)).astype(int)
    hi = np.clip(np.ceil(face.max(axis=0) + margin), 0, (w, h)).astype(int)
    if (hi > lo).all():
        shift[lo[1] : hi[1], lo[0] : hi[0]] = upsampled(spline, tuple(lo), (hi[1] - lo[1], hi[0] - lo[0]), GRID_STEP[1])
    return cv2.add(shift, pixel_grid(h, w))


@functools.lru_cache(maxsize=4)
def pixel_grid(h: int, w: int) -> np.ndarray:
    """The ``(x, y)`` of every pixel, ``(h, w, 2)`` float32 (cached, read-only)."""
    grid = np.stack(np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32)), axis=-1)
    grid.flags.writeable = False
    return grid


def warp(
    image: np.ndarray, src: np.ndarray, dst: np.ndarray, out_shape: tuple[int, int] | None = None, moving: int | None = None
) -> np.ndarray:
    """Warp ``image`` by the thin-plate spline that takes control points ``src`` to ``dst``.

    Parameters
    ----------
    image : ndarray of shape (H, W, C) or (H, W)
    src, dst : ndarray of shape (N, 2)
        Control points in ``image`` and in the output.
    out_shape : (H, W), optional
        Output size; the input's by default.
    moving : int, optional
        The first ``moving`` control points are the face's (:func:`inverse_maps`).

    Returns
    -------
    ndarray
        Same dtype and channels as ``image``; where the map leaves the image, its edge is repeated.

    Examples
    --------
    >>> img = np.arange(64 * 64, dtype=np.uint8).reshape(64, 64)
    >>> pts = np.array([[0.0, 0], [63, 0], [0, 63], [63, 63], [30, 30]])
    >>> bool((warp(img, pts, pts) == img).all())
    True
    """
    out_shape = tuple(image.shape[:2] if out_shape is None else out_shape)
    return cv2.remap(image, inverse_maps(src, dst, out_shape, moving), None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
