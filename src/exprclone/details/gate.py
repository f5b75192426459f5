"""Only expression shading (ours, not in the paper): where the expression ratio image counts.

An expression changes the shading of the skin it moves, not the material there. So the
ERI (:mod:`exprclone.details.eri`) is faded out

* where the expression does not move the skin (:func:`moved`): the source's motion,
  spread over the face by the mesh;
* where either source photo, or the target, shows no skin, or the source's photos
  differ in what is there (:func:`skin`): hair against skin, a highlight, glasses, the
  background, told by a chromaticity unlike the face's own skin, or by a change of it
  that shading does not make. The lips are the face too (:func:`lips`).

This gate is always on, whatever the options (``retarget`` changes the shape stages
only): what it removes is not expression.
"""

from __future__ import annotations

import functools

import cv2
import numpy as np
from scipy import special

from ..imaging import order, piecewise, raster
from ..landmarks.layout import Layout

#: source motion (inter-ocular distances) at which the ratio starts to count, and counts fully
#: (:func:`moved`); the lower end is the landmark fitter's scatter on the eyes (0.01), the upper
#: one the motion that gives a muscle area of the MD model its full strength (0.04).
MOTION_RANGE = (0.01, 0.04)
#: the source's motion is spread over the face by a Gaussian of this sigma (inter-ocular distances).
MOTION_SPREAD = 0.1
#: the face's colour is fitted on this share of its pixels, those nearest its median.
CORE = 0.7
#: a colour (or a change of chromaticity) this many robust standard deviations from the
#: face's starts to fade the ratio, and ends it: the three-sigma rule, not tuned. Of a
#: Gaussian spread of skin colours, 1% (chromaticity) to 3% (with the luma) lies beyond 3,
#: a hundredth of that beyond 5.
OUTLIER_RANGE = (3.0, 5.0)
#: a colour model (or the median change of hue) takes at least this many trusted pixels.
MIN_PIXELS = 8


def moved(labelling: piecewise.Labelling, motion: np.ndarray, iod: float, shrink: int = 8) -> np.ndarray:
    """Where the expression moves the skin, in [0, 1] (``(H, W)`` float32, the labelling's size).

    Each triangle of the mesh takes the mean of its corners' motion; the result is
    blurred by :data:`MOTION_SPREAD` and mapped linearly from 0 at ``MOTION_RANGE[0]``
    to 1 at ``MOTION_RANGE[1]``. An expression's shading (folds, a cheek's lift, crow's
    feet) lies where it moves the skin; where it does not (the forehead of a smile, the
    nose), what differs between the source's photos is the light, the hair, a
    highlight. On 300 London Set pairs (measured on the first version of the gate)
    this took 0.020 off the identity
    distance of e+md and left its mouth's landmark error as it was.

    Parameters
    ----------
    labelling : warp.Labelling
        The mesh's triangles in this frame (the ERI's warps label its grid so, :class:`exprclone.imaging.piecewise.Labelling`).
    motion : ndarray of shape (P,)
        How far each control point moves in the source's expression, in inter-ocular distances.
    iod : float
        Inter-ocular distance in this frame.
    shrink : int
        It is smooth at the scale of the spread: the triangles' values are averaged over blocks of this many pixels
        a side, blurred there and enlarged.
    """
    labels, triangles = labelling.labels, labelling.triangles
    table = np.zeros(256 if labels.dtype == np.uint8 else len(triangles) + 1, np.float32)
    table[1 : len(triangles) + 1] = motion[triangles].mean(1)
    drawn = cv2.LUT(labels, table) if labels.dtype == np.uint8 else table[labels]
    shrink = max(1, min(shrink, *labels.shape))
    out = cv2.GaussianBlur(raster.shrink(drawn, shrink), (0, 0), max(MOTION_SPREAD * iod / shrink, 0.5))
    lo, hi = MOTION_RANGE
    return np.clip((raster.enlarge(out, labels.shape, shrink) - lo) / (hi - lo), 0.0, 1.0)


def colour(rgb: np.ndarray, sigma: float) -> np.ndarray:
    """``(log(R/G), log(B/G), log(Y))`` of ``rgb`` (``(h, w, 3)`` float in [0, 1]) smoothed by a Gaussian of ``sigma`` pixels.

    The first two, the chromaticity, shading leaves unchanged (it scales the three
    channels alike) and a change of material changes; the third, the luma, tells dark
    hair from skin of much the same hue.
    """
    blurred = cv2.GaussianBlur(np.ascontiguousarray(rgb[..., :3], np.float32), (0, 0), max(sigma, 0.5)) + raster.EPS
    return np.dstack([np.log(blurred[..., [0, 2]] / blurred[..., 1:2]), np.log(blurred @ raster.LUMA)])


#: a robust Gaussian (:func:`robust_gaussian`): its centre and inverse covariance, None when too few pixels were trusted.
Fit = tuple[np.ndarray, np.ndarray] | None


def robust_gaussian(values: np.ndarray, trusted: np.ndarray) -> Fit:
    """Centre and inverse covariance of the k-vectors ``values`` (``(h, w, k)``) over the pixels ``trusted`` (flat indices).

    The centre is their median, the covariance that of the :data:`CORE` share nearest to
    it (hair, lips and a highlight on the face must not widen what counts as skin),
    divided by the share of a Gaussian's variance left in that core (its second moment
    there, ``P(chi2_{k+2} < q) / P(chi2_k < q)`` at the core's radius ``q``). None when
    fewer than :data:`MIN_PIXELS` pixels are trusted.
    """
    face = values[np.unravel_index(trusted, values.shape[:2])]
    if len(face) < MIN_PIXELS:
        return None
    k = values.shape[-1]
    centre = order.median(face, 0)
    near = np.linalg.norm(face - centre, axis=1)
    core = face[near <= order.percentile(near, 100 * CORE)]
    return centre, np.linalg.inv(np.atleast_2d(np.cov(core.T)) / core_variance(k) + 1e-8 * np.eye(k))


@functools.cache
def core_variance(k: int) -> float:
    """The share of a k-dimensional Gaussian's variance left in its :data:`CORE` share nearest the centre.

    The chi-squared CDF and quantile as ``scipy.stats.chi2`` computes them (``chdtr``; twice ``gammaincinv`` at half
    the degrees of freedom), from ``scipy.special``: importing ``scipy.stats`` cost every command 0.7 s at start-up.

    >>> from scipy.stats import chi2
    >>> bool(core_variance(3) == chi2.cdf(chi2.ppf(CORE, 3), 5) / CORE)
    True
    """
    return special.chdtr(k + 2, 2 * special.gammaincinv(k / 2, CORE)) / CORE


def fade_out(values: np.ndarray, centre: np.ndarray, inverse: np.ndarray) -> np.ndarray:
    """1 where the Mahalanobis distance from ``centre`` is below ``OUTLIER_RANGE[0]``, 0 above ``OUTLIER_RANGE[1]``.

    ``values`` is an ``(h, w, k)`` image of k-vectors, ``centre`` ``(k,)``, ``inverse`` ``(k, k)``; the quadratic form
    is taken in float32 by OpenCV (several times faster than numpy's einsum on an image).
    """
    d = np.ascontiguousarray(values - centre.astype(np.float32), np.float32)
    squared = cv2.transform(cv2.multiply(cv2.transform(d, inverse.astype(np.float32)), d), np.ones((1, len(centre)), np.float32))
    dist = np.sqrt(np.maximum(squared, 0.0))
    lo, hi = OUTLIER_RANGE
    return np.clip((hi - dist) / (hi - lo), 0.0, 1.0).astype(np.float32)


def trust(colour: np.ndarray, face: np.ndarray) -> np.ndarray:
    """How much each pixel of a neutral photo shows its face's skin, in [0, 1] (``(h, w)`` float32).

    Its colour (:func:`colour`) is compared with the face's own, a Gaussian fitted over
    the pixels ``face`` (``(h, w)`` weights) trusts (:func:`robust_gaussian`, :func:`fade_out`): hair,
    brows, lips, eyes, teeth, a highlight and the background lie far from it in most
    people. All three colour components count: the luma tells dark hair from skin of
    much the same hue. 1 everywhere when too few pixels are trusted.
    """
    fit = robust_gaussian(colour, raster.evenly(face))
    return np.ones(colour.shape[:2], np.float32) if fit is None else fade_out(colour, *fit)


def skin(
    expression: np.ndarray,
    neutral_chroma: np.ndarray,
    neutral_trust: np.ndarray,
    weight: np.ndarray,
    exempt: np.ndarray | None = None,
    hue: Fit = None,
) -> np.ndarray:
    """Trust that a pixel is the same skin in the source's two photos and the target, in [0, 1].

    The neutral photos (the source's, and the target) are compared with their faces'
    own colours once, on their own grids (:func:`trust`), and come in warped,
    ``neutral_trust``. The expression photo is compared here with its face's colour by
    its chromaticity alone, as the expression shades it. The change of chromaticity
    between the source's photos is compared with the spread of the neutral one's
    (``hue``), its median taken out (a change of the light's colour): skin whose hue
    changed as much as skin differs from what is not skin did not change by shading.

    Parameters
    ----------
    expression : ndarray of shape (h, w, 3)
        The colour (:func:`colour`) of the source's expression photo in the target's
        final geometry, on the shrunk grid.
    neutral_chroma : ndarray of shape (h, w, 2)
        The chromaticity of the source's neutral photo (the first two of its colour), warped alike.
    neutral_trust : ndarray of shape (h, w)
        :func:`trust` of the neutral photos, warped alike, multiplied.
    weight : ndarray of shape (h, w)
        The trusted face: the expression's model and the change's median are taken there.
    exempt : ndarray of shape (h, w), optional
        Face that is trusted whatever its colour (:func:`lips`).
    hue : Fit
        The neutral photo's chromaticity, fitted over its face (:func:`robust_gaussian`); None leaves the change untested.

    Returns
    -------
    ndarray of shape (h, w), float32
    """
    out, trusted = neutral_trust.astype(np.float32), raster.evenly(weight)
    chroma = expression[..., :2]
    fit = robust_gaussian(chroma, trusted)
    if fit is not None:
        out *= fade_out(chroma, *fit)
    if hue is not None and len(trusted) >= MIN_PIXELS:
        change = chroma - neutral_chroma
        out *= fade_out(change, order.median(change[np.unravel_index(trusted, change.shape[:2])], 0), hue[1])
    return out if exempt is None else np.maximum(out, exempt)


def lips(shape: tuple[int, int], landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """1 inside the outer lips, 0 elsewhere (``(H, W)`` float32): face that is not skin-coloured.

    The expression stretches the lips and shades them, so their ratio is kept though
    their colour is not skin's (:func:`skin`); what opens between them is left out by
    :func:`exprclone.details.eri.ratio_mask`. On 300 London Set pairs (with an earlier version of the colour
    test), leaving the lips out made e+md's mouth error on broad smiles worse by 0.0008 ±
    0.0004 and its identity distance better by 0.003.
    """
    out = np.zeros(shape, np.float32)
    return raster.fill_polygon(out, landmarks[list(layout.mouth_outer)], 1.0)
