"""The inner-lip polygon kept valid.

Landmark fitters often put the inner lips of a closed mouth crossed over each other
(the lower inner lip a pixel above the upper one). Crossed lips fold the mesh over
where the mouth should be a closed slit, so every landmark set is uncrossed first.
"""

from __future__ import annotations

import numpy as np

from . import geometry
from .layout import Layout


def uncross(landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks whose upper inner lip never lies below the facing lower inner lip.

    Where a pair ``(upper, lower)`` of ``layout.lip_pairs`` is crossed (in the face's
    own frame, so a tilted head works), both points move to their midpoint: the
    mouth is closed there. Uncrossed pairs are left as they are.

    Parameters
    ----------
    landmarks : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)
    """
    out = np.array(landmarks, float)
    down = geometry.face_axes(out, layout)[1]
    for upper, lower in layout.lip_pairs:
        if (out[lower] - out[upper]) @ down < 0:
            out[[upper, lower]] = (out[upper] + out[lower]) / 2
    return out
