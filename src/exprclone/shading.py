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

import cv2
import numpy as np
from scipy import stats

from . import raster
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


def moved(shape: tuple[int, int], points: np.ndarray, motion: np.ndarray, triangles: np.ndarray, iod: float) -> np.ndarray:
    """Where the expression moves the skin, in [0, 1] (``(H, W)`` float32).

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
    shape : (H, W)
    points : ndarray of shape (P, 2)
        The mesh's control points in this frame.
    motion : ndarray of shape (P,)
        How far each moves in the source's expression, in inter-ocular distances.
    triangles : ndarray of shape (T, 3)
    iod : float
        Inter-ocular distance in this frame.
    """
    # smooth at the scale of the spread: drawn at an eighth of the resolution and enlarged
    small = (max(1, shape[0] // 8), max(1, shape[1] // 8))
    scale = np.array([small[1] / shape[1], small[0] / shape[0]])
    out: np.ndarray = np.zeros(small, np.float32)
    for corners, value in zip(triangles, motion[triangles].mean(1)):
        raster.fill_polygon(out, points[corners] * scale, float(value))
    out = cv2.GaussianBlur(out, (0, 0), max(MOTION_SPREAD * iod * scale.mean(), 0.5))
    lo, hi = MOTION_RANGE
    return np.clip((cv2.resize(out, (shape[1], shape[0]), interpolation=cv2.INTER_LINEAR) - lo) / (hi - lo), 0.0, 1.0)


def colour(image: np.ndarray, sigma: float, step: int = 1) -> np.ndarray:
    """``(log(R/G), log(B/G), log(Y))`` smoothed by a Gaussian of ``sigma`` pixels, ``(h, w, 3)`` on the grid shrunk by ``step``.

    The first two, the chromaticity, shading leaves unchanged (it scales the three
    channels alike) and a change of material changes; the third, the luma, tells dark
    hair from skin of much the same hue.
    """
    rgb = cv2.GaussianBlur(raster.shrink(image, step).astype(np.float32) / 255.0, (0, 0), max(sigma / step, 0.5)) + raster.EPS
    return np.dstack([np.log(rgb[..., [0, 2]] / rgb[..., 1:2]), np.log(rgb @ raster.LUMA)])


def robust_gaussian(values: np.ndarray, trusted: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Centre and inverse covariance of the k-vectors ``values`` (``(h, w, k)``) over the pixels ``trusted`` (flat indices).

    The centre is their median, the covariance that of the :data:`CORE` share nearest to
    it (hair, lips and a highlight on the face must not widen what counts as skin),
    divided by the share of a Gaussian's variance left in that core (its second moment
    there, ``P(chi2_{k+2} < q) / P(chi2_k < q)`` at the core's radius ``q``). None when
    fewer than 8 pixels are trusted.
    """
    face = values[np.unravel_index(trusted, values.shape[:2])]
    if len(face) < 8:
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
    """1 where the Mahalanobis distance from ``centre`` is below ``OUTLIER_RANGE[0]``, 0 above ``OUTLIER_RANGE[1]``."""
    d = values - centre
    dist = np.sqrt(np.maximum(np.einsum("...i,ij,...j->...", d, inverse, d), 0.0))
    lo, hi = OUTLIER_RANGE
    return np.clip((hi - dist) / (hi - lo), 0.0, 1.0).astype(np.float32)


def skin(images: tuple[np.ndarray, ...], weight: np.ndarray, sigma: float, step: int = 1, exempt: np.ndarray | None = None) -> np.ndarray:
    """Trust that a pixel is the same skin in all of ``images``, in [0, 1], on the grid shrunk by ``step``.

    Each image's colour (:func:`colour`) is compared with its face's own, a Gaussian
    fitted over ``weight`` (:func:`robust_gaussian`): hair, brows, lips, eyes, teeth, a
    highlight and the background lie far from it in most people. The expression photo
    is compared by its chromaticity alone, as the expression shades it; the neutral
    photos by their luma too, which tells dark hair from skin of much the same hue. The
    change of chromaticity between the source's photos is compared with the spread of
    the neutral one's, its median taken out (a change of the light's colour): skin
    whose hue changed as much as skin differs from what is not skin did not change by
    shading.

    Parameters
    ----------
    images : tuple of ndarray of shape (H, W, 3), uint8 RGB
        The source's neutral and expression photos warped alike, then any other neutral
        photo in the same geometry (the target).
    weight : ndarray of shape (h, w)
        The trusted face on the shrunk grid.
    sigma : float
        The scale colours are compared at, in pixels of the full grid: the ratio's own
        (:data:`exprclone.eri.FILTER_SIGMA` inter-ocular distances).
    step : int
    exempt : ndarray of shape (h, w), optional
        Face that is trusted whatever its colour (:func:`lips`), on the shrunk grid.

    Returns
    -------
    ndarray of shape (h, w), float32
    """
    out, trusted = np.ones(weight.shape, np.float32), raster.evenly(weight)
    colours = [colour(image, sigma, step) for image in images]
    for i, c in enumerate(colours):
        c = c[..., :2] if i == 1 else c
        fit = robust_gaussian(c, trusted)
        if fit is not None:
            out *= fade_out(c, *fit)
    hue = robust_gaussian(colours[0][..., :2], trusted)
    if hue is not None:
        change = colours[1][..., :2] - colours[0][..., :2]
        out *= fade_out(change, np.median(change[np.unravel_index(trusted, change.shape[:2])], 0), hue[1])
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
