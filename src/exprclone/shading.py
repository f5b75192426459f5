"""Only expression shading (ours, not in the paper): where the expression ratio image counts.

An expression changes the shading of the skin it moves, not the material there. So the
ERI (:mod:`exprclone.eri`) is faded out

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
from dataclasses import dataclass

import cv2
import numpy as np
from scipy import stats

from . import raster, warp
from .layout import Layout

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


def moved(labelling: warp.Labelling, motion: np.ndarray, iod: float, shrink: int = 8) -> np.ndarray:
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
        The mesh's triangles in this frame (the ERI's warps label its grid so, :class:`exprclone.warp.Labelling`).
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
    centre = np.median(face, 0)
    near = np.linalg.norm(face - centre, axis=1)
    core = face[near <= np.percentile(near, 100 * CORE)]
    return centre, np.linalg.inv(np.atleast_2d(np.cov(core.T)) / core_variance(k) + 1e-8 * np.eye(k))


@functools.cache
def core_variance(k: int) -> float:
    """The share of a k-dimensional Gaussian's variance left in its :data:`CORE` share nearest the centre."""
    return stats.chi2.cdf(stats.chi2.ppf(CORE, k), k + 2) / CORE


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


@dataclass(frozen=True)
class Fits:
    """The colour models of the photos that do not change between expressions (:func:`skin`): fitted once per pair of faces.

    Attributes
    ----------
    neutral, target : Fit
        The source's neutral photo's colour and the target's, in three dimensions (:func:`colour`).
    hue : Fit
        The neutral photo's chromaticity alone (its first two), the spread a change of hue is compared with.
    """

    neutral: Fit
    target: Fit
    hue: Fit

    @classmethod
    def measure(cls, neutral: np.ndarray, neutral_face: np.ndarray, target: np.ndarray | None, target_face: np.ndarray) -> Fits:
        """The models of the ``neutral`` and ``target`` colours (:func:`colour`), each over its own face (``(h, w)`` weights)."""
        on_neutral = raster.evenly(neutral_face)
        fit_target = None if target is None else robust_gaussian(target, raster.evenly(target_face))
        return cls(robust_gaussian(neutral, on_neutral), fit_target, robust_gaussian(neutral[..., :2], on_neutral))


def skin(colours: tuple[np.ndarray, ...], weight: np.ndarray, exempt: np.ndarray | None = None, fits: Fits | None = None) -> np.ndarray:
    """Trust that a pixel is the same skin in all of the photos whose ``colours`` are given, in [0, 1].

    Each photo's colour (:func:`colour`) is compared with its face's own, a Gaussian
    (:func:`robust_gaussian`): hair, brows, lips, eyes, teeth, a highlight and the
    background lie far from it in most people. The expression photo is compared by its
    chromaticity alone, as the expression shades it; the neutral photos by their luma
    too, which tells dark hair from skin of much the same hue. The change of
    chromaticity between the source's photos is compared with the spread of the neutral
    one's, its median taken out (a change of the light's colour): skin whose hue changed
    as much as skin differs from what is not skin did not change by shading.

    Parameters
    ----------
    colours : tuple of ndarray of shape (h, w, 3)
        The colours of the source's neutral and expression photos warped alike, then of
        any other neutral photo in the same geometry (the target), on the shrunk grid.
    weight : ndarray of shape (h, w)
        The trusted face; the expression's model is fitted there, and so are the others unless ``fits`` gives them.
    exempt : ndarray of shape (h, w), optional
        Face that is trusted whatever its colour (:func:`lips`).
    fits : Fits, optional
        The neutral photos' models, fitted once on their own faces (:meth:`Fits.measure`).

    Returns
    -------
    ndarray of shape (h, w), float32
    """
    out, trusted = np.ones(weight.shape, np.float32), raster.evenly(weight)
    if fits is None:
        fits = Fits.measure(colours[0], weight, colours[2] if len(colours) > 2 else None, weight)
    models = (fits.neutral, robust_gaussian(colours[1][..., :2], trusted)) + ((fits.target,) if len(colours) > 2 else ())
    for c, fit in zip(colours, models):
        if fit is not None:
            out *= fade_out(c[..., : len(fit[0])], *fit)
    if fits.hue is not None and len(trusted) >= MIN_PIXELS:
        change = colours[1][..., :2] - colours[0][..., :2]
        out *= fade_out(change, np.median(change[np.unravel_index(trusted, change.shape[:2])], 0), fits.hue[1])
    return out if exempt is None else np.maximum(out, exempt)


def lips(shape: tuple[int, int], landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """1 inside the outer lips, 0 elsewhere (``(H, W)`` float32): face that is not skin-coloured.

    The expression stretches the lips and shades them, so their ratio is kept though
    their colour is not skin's (:func:`skin`); what opens between them is left out by
    :func:`exprclone.eri.ratio_mask`. On 300 London Set pairs (with an earlier version of the colour
    test), leaving the lips out made e+md's mouth error on broad smiles worse by 0.0008 ±
    0.0004 and its identity distance better by 0.003.
    """
    out = np.zeros(shape, np.float32)
    return raster.fill_polygon(out, landmarks[list(layout.mouth_outer)], 1.0)
