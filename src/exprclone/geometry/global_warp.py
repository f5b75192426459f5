"""Global warping (the paper's GI, after Liu et al. 2001 and Wolberg), and the RBF transfer of Seol and Lewis.

The target's expression landmarks are its neutral landmarks plus the source's
neutral-to-expression motion, brought into the target's frame: "the feature positions in
the target expression image are moved 'relatively' according to the movements of their
corresponding feature positions in the source person's face" (Sec. II). Two ways:

- by one similarity transform between the two neutral faces (:func:`global_landmarks`,
  the paper's GI);
- by the local Jacobian of a radial-basis-function map between them
  (:func:`rbf_landmarks`): the 2-D reading of Seol and Lewis, on whose results the
  paper puts its elastic model in Figs. 19-20. A wider mouth, or a longer face, gets
  motion scaled to it.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from scipy.interpolate import RBFInterpolator

from ..landmarks import align
from ..landmarks.layout import Layout

#: the RBF map's kernel: the thin-plate spline ``r**2 log r`` with an affine part. It has
#: no shape parameter (the map does not depend on the faces' size in pixels), it
#: reproduces an affine correspondence exactly (so a target that is the source scaled
#: and rotated gets the similarity transfer), and of all maps through the points it
#: bends least (Bookstein 1989).
RBF_KERNEL: Final = "thin_plate_spline"
#: the RBF map's smoothing, coordinates in inter-ocular distances. Exact interpolation
#: is impossible (uncrossed inner lips of a closed mouth coincide), and near it the
#: Jacobian at the inner lips stretches a motion 5 times or squashes it 20 times
#: (between a closed and a parted mouth). ``python tools/rbf_smoothing.py``: on 300
#: random pairs of the London Set's neutral faces, 0.15 is the least smoothing of
#: {1e-4, 0.001, 0.01, 0.05, 0.1, 0.15, 0.2, 0.3, 1} whose Jacobians all stretch and
#: squash by at most 2 (singular values 0.50 to 1.77); it predicts a landmark left out
#: of the fit within 0.015 inter-ocular distances on average (0.010 near interpolation,
#: 0.046 for an affine map).
RBF_SMOOTHING = 0.15
#: step of the central differences that give the RBF map's Jacobian, in inter-ocular distances.
JACOBIAN_STEP = 1e-4


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
    return align.apply(align.fit_rigid(expression, neutral, layout), expression)


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
    >>> from exprclone.landmarks.layout import DLIB68
    >>> rng = np.random.default_rng(0)
    >>> s = rng.uniform(0, 100, (68, 2))
    >>> t = 2 * s + 5  # the target is the source, twice as large
    >>> moved = s.copy(); moved[48] += (0, 3)
    >>> bool(np.allclose(global_landmarks(s, moved, t, DLIB68)[48], t[48] + (0, 6), atol=0.2))
    True
    """
    motion = remove_head_motion(source_neutral, source_expression, layout) - source_neutral
    linear = align.fit_similarity(source_neutral, target_neutral)[:, :2]
    return target_neutral + motion @ linear.T


def rbf_jacobians(source_neutral: np.ndarray, target_neutral: np.ndarray, layout: Layout) -> np.ndarray:
    """The Jacobian, at each source landmark, of the RBF map from the source's neutral face to the target's.

    The map ``f`` (kernel :data:`RBF_KERNEL`, smoothing :data:`RBF_SMOOTHING`) takes the
    source's neutral landmarks to the target's, each face centred and measured in its
    own inter-ocular distances; its Jacobian (central differences) is brought back to
    pixels by the ratio of the two faces' inter-ocular distances. It depends on the two
    neutral faces only.

    Parameters
    ----------
    source_neutral, target_neutral : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (N, 2, 2)
        ``J[i] @ m`` is a source motion ``m`` at landmark ``i`` in the target's frame.

    References
    ----------
    Y. Seol and J. Lewis, "Spacetime expression cloning for blendshapes", ACM Trans.
    Graphics 31(2), 2012 (the paper's [15]). F. L. Bookstein, "Principal warps:
    thin-plate splines and the decomposition of deformations", IEEE PAMI 11(6), 1989.
    """
    s_unit, t_unit = align.interocular(source_neutral, layout), align.interocular(target_neutral, layout)
    s = (source_neutral - source_neutral.mean(0)) / s_unit
    t = (target_neutral - target_neutral.mean(0)) / t_unit
    f = RBFInterpolator(s, t, kernel=RBF_KERNEL, smoothing=RBF_SMOOTHING)
    columns = [(f(s + JACOBIAN_STEP * e) - f(s - JACOBIAN_STEP * e)) / (2 * JACOBIAN_STEP) for e in np.eye(2)]
    return np.stack(columns, axis=-1) * (t_unit / s_unit)


def rbf_landmarks(
    source_neutral: np.ndarray,
    source_expression: np.ndarray,
    target_neutral: np.ndarray,
    layout: Layout,
    jacobians: np.ndarray | None = None,
) -> np.ndarray:
    """Landmarks of the target's expression by the RBF transfer (Seol and Lewis, in 2-D).

    ``A_gl[i] = T[i] + J[i] (S_exp[i] - S_neu[i])``: each landmark's motion (head motion
    removed, :func:`remove_head_motion`) is carried by the local Jacobian ``J[i]`` of the
    RBF correspondence between the two neutral faces (:func:`rbf_jacobians`), Seol and
    Lewis's movement matching, instead of by one global similarity.

    Parameters
    ----------
    source_neutral, source_expression, target_neutral : ndarray of shape (N, 2)
    layout : Layout
    jacobians : ndarray of shape (N, 2, 2), optional
        :func:`rbf_jacobians` of the two neutral faces, if already computed.

    Returns
    -------
    ndarray of shape (N, 2)

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> rng = np.random.default_rng(0)
    >>> s = rng.uniform(0, 100, (68, 2))
    >>> t = 2 * s + 5  # the target is the source, twice as large: the similarity transfer
    >>> moved = s.copy(); moved[48] += (0, 3)
    >>> bool(np.allclose(rbf_landmarks(s, moved, t, DLIB68), global_landmarks(s, moved, t, DLIB68)))
    True
    """
    if jacobians is None:
        jacobians = rbf_jacobians(source_neutral, target_neutral, layout)
    motion = remove_head_motion(source_neutral, source_expression, layout) - source_neutral
    return target_neutral + np.einsum("nij,nj->ni", jacobians, motion)
