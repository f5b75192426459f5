"""Similarity alignment of landmark sets and the face-aligned frame.

Landmarks are ``(N, 2)`` float arrays of pixel ``(x, y)`` coordinates. A transform is a
``(2, 3)`` matrix ``[[a, -b, tx], [b, a, ty]]`` acting on column vectors ``(x, y, 1)``.
"""

from __future__ import annotations

import numpy as np

from .layout import Layout


def fit_similarity(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Least-squares similarity (rotation, uniform scale, shift) taking ``src`` to ``dst``.

    Umeyama's closed form, without reflection.

    Parameters
    ----------
    src, dst : ndarray of shape (N, 2)
        Corresponding points, N >= 2.

    Returns
    -------
    ndarray of shape (2, 3)

    Examples
    --------
    >>> src = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> np.allclose(fit_similarity(src, 2 * src + 3), [[2, 0, 3], [0, 2, 3]])
    True
    """
    src = np.asarray(src, float)
    dst = np.asarray(dst, float)
    ms, md = src.mean(0), dst.mean(0)
    s, d = src - ms, dst - md
    # With complex numbers z = x + iy a similarity is z -> c z + t; c = <s, d> / <s, s>.
    zs = s[:, 0] + 1j * s[:, 1]
    zd = d[:, 0] + 1j * d[:, 1]
    c = np.vdot(zs, zd) / max(np.vdot(zs, zs).real, 1e-12)
    a, b = c.real, c.imag
    t = md - np.array([a * ms[0] - b * ms[1], b * ms[0] + a * ms[1]])
    return np.array([[a, -b, t[0]], [b, a, t[1]]])


def fit_rigid(src: np.ndarray, dst: np.ndarray, layout: Layout) -> np.ndarray:
    """The similarity taking one face's rigid landmarks (``layout.rigid``) to another's: head motion, or one face placed on another."""
    rigid = list(layout.rigid)
    return fit_similarity(np.asarray(src)[rigid], np.asarray(dst)[rigid])


def box(points: np.ndarray, shape: tuple[int, ...], margin: float = 0.0, *, closed: bool = True) -> tuple[slice, slice]:
    """``(rows, columns)`` of the pixels the points' bounding box covers, grown by ``margin`` pixels, inside the image.

    ``closed``: the pixel under the largest coordinate is included (the box ends at
    ``ceil(max + margin) + 1``); otherwise it ends at ``ceil(max + margin)``, as the ERI's
    face box and the mouth patch were first written (their outputs depend on the exact box).

    Examples
    --------
    >>> box(np.array([[2.5, 1.0], [4.0, 3.2]]), (10, 10))
    (slice(1, 5, None), slice(2, 5, None))
    >>> box(np.array([[2.5, 1.0], [4.0, 3.2]]), (10, 10), margin=3, closed=False)
    (slice(0, 7, None), slice(0, 7, None))
    """
    lo = np.maximum(np.floor(points.min(0) - margin).astype(int), 0)
    hi = np.minimum(np.ceil(points.max(0) + margin).astype(int) + int(closed), (shape[1], shape[0]))
    return slice(int(lo[1]), int(hi[1])), slice(int(lo[0]), int(hi[0]))


def apply(transform: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply a ``(2, 3)`` transform to ``(N, 2)`` points."""
    points = np.asarray(points, float)
    return points @ transform[:, :2].T + transform[:, 2]


def interocular(landmarks: np.ndarray, layout: Layout) -> float:
    """Distance between the two outer eye corners: the face's unit of length."""
    i, j = layout.eye_corners
    return float(np.linalg.norm(landmarks[j] - landmarks[i]))


def face_axes(landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Rows: the face's unit "right" axis (along the eye line) and its "down" axis.

    Returns
    -------
    ndarray of shape (2, 2)
        Multiplying image vectors by its transpose gives face-frame coordinates, so a
        tilted head is handled as if it were upright.
    """
    i, j = layout.eye_corners
    right = landmarks[j] - landmarks[i]
    right = right / max(np.linalg.norm(right), 1e-12)
    return np.array([right, [-right[1], right[0]]])
