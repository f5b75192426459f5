"""Local warping (the paper's LI): per-organ re-shaping, Eqs. (1)-(2).

Each organ of the globally warped landmarks is re-shaped so that its height-to-width
ratio equals the same organ's in the source expression; the other points stay where
they are (Sec. II, rules a and b).
"""

from __future__ import annotations

import numpy as np

from ..landmarks import align
from ..landmarks.layout import Layout


def reshape_organ(target: np.ndarray, source: np.ndarray) -> np.ndarray:
    """Eqs. (1)-(2) on one organ, in face-aligned coordinates.

    Eq. (1): every point's vertical distance to the horizontal middle line of the
    organ's bounding box becomes the source's distance times ``W_t / W_s``.
    Eq. (2): every horizontal distance to the vertical middle line becomes the source's
    times ``H_t / H_s``. We apply them in this order and measure ``H_t`` after Eq. (1),
    the only reading under which the paper's claim holds that the two together give the
    organ the source's height-to-width ratio; ``H_t / H_s`` then equals ``W_t / W_s``.
    The box keeps its centre and its width ``W_t``.

    Parameters
    ----------
    target : ndarray of shape (n, 2)
        The organ's points in the globally warped face (face frame).
    source : ndarray of shape (n, 2)
        The same points in the source expression (face frame).

    Returns
    -------
    ndarray of shape (n, 2)
    """
    t_lo, t_hi = target.min(0), target.max(0)
    s_lo, s_hi = source.min(0), source.max(0)
    t_mid, s_mid = (t_lo + t_hi) / 2, (s_lo + s_hi) / 2
    w_t, w_s = t_hi[0] - t_lo[0], max(s_hi[0] - s_lo[0], 1e-9)
    out = np.empty_like(target)
    out[:, 1] = t_mid[1] + (source[:, 1] - s_mid[1]) * (w_t / w_s)  # Eq. (1)
    # Eq. (2): H_t / H_s with H_t = H_s W_t / W_s, the height left by Eq. (1).
    out[:, 0] = t_mid[0] + (source[:, 0] - s_mid[0]) * (w_t / w_s)
    return out


def local_landmarks(global_pts: np.ndarray, source_expression: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks of the locally warped target (LI).

    Each organ of ``layout.organs`` is re-shaped by :func:`reshape_organ` in the face's
    own frame (axes from the eye line of each face), so a tilted head works.

    Parameters
    ----------
    global_pts : ndarray of shape (N, 2)
        Globally warped target landmarks.
    source_expression : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)
    """
    axes_t = align.face_axes(global_pts, layout)
    axes_s = align.face_axes(source_expression, layout)
    out = global_pts.copy()
    for organ in layout.organs.values():
        idx = list(organ)
        t = global_pts[idx] @ axes_t.T
        s = source_expression[idx] @ axes_s.T
        out[idx] = reshape_organ(t, s) @ axes_t
    return out
