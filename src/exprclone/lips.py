"""The inner-lip polygon kept valid.

Landmark fitters often put the inner lips of a closed mouth crossed over each other
(the lower inner lip a pixel above the upper one), and now and then an inner lip
outside the outer one. Either folds the mesh over and makes the mouth opening a
self-intersecting polygon, so every landmark set is made valid first.
"""

from __future__ import annotations

import numpy as np

from . import geometry
from .layout import Layout


def uncross(landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks whose lips are stacked in order in every column of the mouth.

    In the face's own frame (so a tilted head works), for each column
    ``(upper outer, upper inner, lower inner, lower outer)`` of ``layout.lip_columns``:
    an inner lip point above its outer lip (or below, for the lower lip) is moved onto
    it, and a crossed inner pair moves to its midpoint: the mouth is closed there.
    Valid columns are left as they are.

    Parameters
    ----------
    landmarks : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)
    """
    out = np.array(landmarks, float)
    down = geometry.face_axes(out, layout)[1]
    for upper_outer, upper, lower, lower_outer in layout.lip_columns:
        for inner, outer, sign in ((upper, upper_outer, 1), (lower, lower_outer, -1)):
            depth = sign * (out[inner] - out[outer]) @ down  # how far inside the outer lip
            if depth < 0:
                out[inner] -= sign * depth * down
        if (out[lower] - out[upper]) @ down < 0:
            out[[upper, lower]] = (out[upper] + out[lower]) / 2
    return out
