"""The source's motion made the target's: only the expression, on the target's own features.

Not in the paper. Two photos of one person differ by the expression and by what the
landmark fitter scatters between them, and another person's expression carries that
person's own features. Both show up on the target as a drift from its identity, so
before the global and local stages:

1. **the source's motion is cleaned** (:func:`clean`): the motion of the points that
   no expression moves much (the face's frame: jaw line, brows, nose and the rigid
   points) is shrunk by the fitter's scatter, so that what the fitter scatters is not
   transferred and a real movement (a chin dropped by an open mouth, raised brows)
   keeps all but that much; and the part of the motion that differs between the face's
   two halves is shrunk alike, so that the source's lopsidedness is left behind but a
   wink is not;
2. **each organ is re-shaped as the target's** (:func:`organ_reference`): the local
   stage (Eqs. 1-2) makes an organ as high for its width as the organ it is given. The
   paper gives it the source's own organ, so that the target takes the source's nose,
   eyes and lips whenever the DB metric leans towards the local result; we give it the
   target's own organ moved by the source's motion as a share of the organ's width (the
   mouth's corners move by the same share of the target's mouth width, its lips keep
   their thickness and shape, it opens in proportion to the target's mouth).

Both run before the global warp, whichever it is (the paper's similarity or the RBF
transfer), and both are on by default (:attr:`exprclone.options.Options.retarget`; off,
the stages are the paper's). On 300 London Set pairs (``exprclone evaluate``, the
default against ``--retargets off``, pair by pair, the ERI's gate on in both) they bring the landmarks
closer to the target's real smile and the result closer to the target: for global warping
the mouth error by 0.0010 ± 0.0002 and the identity distance by 0.028 ± 0.002; for local
re-shaping by 0.0049 ± 0.0006 and 0.170 ± 0.005; for e+md by 0.0015 ± 0.0003 and 0.030 ±
0.003 (0.265 to 0.236). The same share of the mouth's width in the *global* stage (a wide
mouth widening more) made the mouth error worse (+0.0006 on 100 pairs), and so did keeping
the lips' thickness there (+0.0007): on the London Set, people with wide mouths widen
theirs less when they smile.
"""

from __future__ import annotations

import numpy as np

from ..landmarks import align
from ..landmarks.layout import Layout
from . import global_warp

#: motion of the face's frame (jaw line, brows, nose, rigid points) shrunk by this much, in
#: inter-ocular distances: between a London Set person's two photos these points move by
#: 0.01-0.03 (median per point), the fitter's scatter and little else. Chosen among 0.01,
#: 0.02 and 0.03 on 100 pairs: identity improved by 0.023, 0.032 and 0.033, and the eyes'
#: and the overall landmark errors improved at 0.02 and 0.03 alike.
FRAME_NOISE = 0.02
#: the lopsided part of the motion shrunk by this much (inter-ocular distances). Chosen
#: among 0.01, 0.02 and removing it all on 100 pairs: mouth error -0.0007, -0.0012 and
#: -0.0012; a wink (0.05 and more) keeps most of itself.
ASYMMETRY_NOISE = 0.02


def shrink(vectors: np.ndarray, amount: np.ndarray | float) -> np.ndarray:
    """Each vector shortened by ``amount``, and zero if it is shorter (soft thresholding).

    Donoho's soft threshold of a noisy signal, applied to the length of each vector:
    what lies within the noise is dropped, what stands out keeps its direction.

    Parameters
    ----------
    vectors : ndarray of shape (N, 2)
    amount : float or ndarray of shape (N,)

    Returns
    -------
    ndarray of shape (N, 2)

    Examples
    --------
    >>> shrink(np.array([[3.0, 4.0], [0.3, 0.4]]), 1.0).round(6).tolist()
    [[2.4, 3.2], [0.0, 0.0]]
    """
    length = np.linalg.norm(vectors, axis=1)
    keep = np.maximum(1.0 - np.asarray(amount) / np.maximum(length, 1e-12), 0.0)
    return vectors * keep[:, None]


def frame_points(layout: Layout) -> list[int]:
    """The points no expression moves much: jaw line, brows, nose and ``layout.rigid``."""
    return sorted(set(layout.jaw).union(*layout.brows, layout.nose, layout.rigid))


def clean(neutral: np.ndarray, expression: np.ndarray, layout: Layout, still: np.ndarray | None = None) -> np.ndarray:
    """The expression landmarks in the neutral photo's frame, their motion cleaned.

    The head's motion is removed (:func:`exprclone.geometry.global_warp.remove_head_motion`);
    then, in the face's own frame, the motion is split into the part mirrored by the
    other half of the face and the lopsided rest, the rest is shrunk by
    :data:`ASYMMETRY_NOISE` (:func:`shrink`), and the motion of the face's frame
    (:func:`frame_points`) by :data:`FRAME_NOISE`. The mouth's and the eyelids' own
    symmetric motion is kept whole.

    Parameters
    ----------
    neutral, expression : ndarray of shape (N, 2)
        The source's landmarks in its two photos.
    layout : Layout
    still : ndarray of shape (N, 2), optional
        ``expression`` with the head's motion already removed, when the caller has it.

    Returns
    -------
    ndarray of shape (N, 2)
    """
    motion = (global_warp.remove_head_motion(neutral, expression, layout) if still is None else still) - neutral
    iod = align.interocular(neutral, layout)
    axes = align.face_axes(neutral, layout)
    local = motion @ axes.T
    mirrored = local[list(layout.mirror)] * (-1.0, 1.0)  # the other half's motion, reflected
    symmetric = (local + mirrored) / 2
    local = symmetric + shrink(local - symmetric, ASYMMETRY_NOISE * iod)
    noise = np.zeros(len(local))
    noise[frame_points(layout)] = FRAME_NOISE * iod
    # the shrinking moved the rigid points a little: what of that is the head's is taken out again
    return global_warp.remove_head_motion(neutral, neutral + shrink(local @ axes, noise), layout)


def organ_reference(source_neutral: np.ndarray, source_expression: np.ndarray, target_neutral: np.ndarray, layout: Layout) -> np.ndarray:
    """The target's organs moved by the source's motion in proportion to their size: what local re-shaping aims at.

    For each organ of ``layout.organs``, in each face's own frame, the target's neutral
    points plus the source's motion of that organ times ``W_t / W_s``, the ratio of the
    two neutral organs' widths. The local stage (:func:`exprclone.geometry.local_warp.local_landmarks`)
    then gives the target's organ the height-to-width ratio of the target's own organ so
    moved, instead of the source's organ.

    Parameters
    ----------
    source_neutral : ndarray of shape (N, 2)
    source_expression : ndarray of shape (N, 2)
        In the source's neutral frame (:func:`clean`).
    target_neutral : ndarray of shape (N, 2)
    layout : Layout

    Returns
    -------
    ndarray of shape (N, 2)
        In the target's frame; the points of no organ are the target's neutral ones.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> s = np.random.default_rng(0).uniform(0, 100, (68, 2))
    >>> moved = s.copy(); moved[48] += (0, 3)
    >>> bool(np.allclose(organ_reference(s, moved, 2 * s, DLIB68)[48], 2 * s[48] + (0, 6)))
    True
    """
    axes_s, axes_t = align.face_axes(source_neutral, layout), align.face_axes(target_neutral, layout)
    out = np.array(target_neutral, float)
    for organ in layout.organs.values():
        idx = list(organ)
        neutral, moved, target = (
            p[idx] @ a.T for p, a in ((source_neutral, axes_s), (source_expression, axes_s), (target_neutral, axes_t))
        )
        width = np.ptp(target[:, 0]) / max(np.ptp(neutral[:, 0]), 1e-12)
        out[idx] = (target + (moved - neutral) * width) @ axes_t
    return out
