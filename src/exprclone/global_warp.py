"""Global warping (the paper's GI, after Liu et al. 2001 and Wolberg).

The target's expression landmarks are its neutral landmarks plus the source's
neutral-to-expression motion, brought into the target's frame by a similarity
transform: "the feature positions in the target expression image are moved
'relatively' according to the movements of their corresponding feature positions in
the source person's face" (Sec. II).
"""

from __future__ import annotations

import numpy as np

from . import geometry
from .layout import Layout


def remove_head_motion(neutral: np.ndarray, expression: np.ndarray, layout: Layout) -> np.ndarray:
    """The expression landmarks moved into the neutral photo's frame.

    Two photos of one head are rarely pixel-aligned (the head shifts and tilts); a
    similarity fitted on the rigid landmarks (``layout.rigid``: nose bridge, eye corners,
    upper jaw) takes that rigid motion out, leaving the expression's own motion.

    Parameters
    ----------
    neutral, expression : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)
    """
    return geometry.apply(geometry.fit_rigid(expression, neutral, layout), expression)


def global_landmarks(source_neutral: np.ndarray, source_expression: np.ndarray, target_neutral: np.ndarray, layout: Layout) -> np.ndarray:
    """Landmarks of the globally warped target (GI).

    ``A_gl = T + R s (S_exp - S_neu)`` where ``R s`` is the rotation and scale of the
    least-squares similarity from the source's neutral landmarks to the target's, and
    ``S_exp`` has had the source's head motion removed (:func:`remove_head_motion`).

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2)

    Examples
    --------
    >>> from exprclone.layout import DLIB68
    >>> rng = np.random.default_rng(0)
    >>> s = rng.uniform(0, 100, (68, 2))
    >>> t = 2 * s + 5  # the target is the source, twice as large
    >>> moved = s.copy(); moved[48] += (0, 3)
    >>> bool(np.allclose(global_landmarks(s, moved, t, DLIB68)[48], t[48] + (0, 6), atol=0.2))
    True
    """
    motion = remove_head_motion(source_neutral, source_expression, layout) - source_neutral
    linear = geometry.fit_similarity(source_neutral, target_neutral)[:, :2]
    return target_neutral + motion @ linear.T
