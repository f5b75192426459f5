"""Expression ratio image (ERI, Liu, Shan and Zhang 2001): the illumination details.

Both source photos are warped to the target's final geometry; the ratio of their
luminances, ``ERI = Y_expression / Y_neutral``, holds the shading that the expression
creates (wrinkles, folds, dimples) without the source's skin or identity. It is
low-pass filtered against noise and misregistration, clamped, and faded to 1 outside a
feathered face mask and inside the eyes and the mouth opening, whose content (irises,
teeth) differs between people and is not shading.

One addition to Liu et al.: where the source's *neutral* photo is itself textured
(hair over the forehead, a beard, stubble, the face's outline against the
background), the ratio of two slightly misregistered textures is noise, not shading,
and it is faded out (:func:`texture_confidence`); the filter is a normalised
convolution over the trusted pixels only, so nothing leaks from the excluded ones.
The same test is made on the expression photo (hair that moved into it). A change of
light between the source's two photos is divided out as well: the ratio's trend over
the face, a plane in its logarithm fitted robustly (:func:`light_trend`), is taken to
be 1, which removes a change of exposure and a light that moved across the face.

Only expression shading (ours): an expression changes the shading of the skin it moves,
not the material there. So the ratio is also faded out

* where the expression does not move the skin (:func:`moved`): the source's motion,
  spread over the face by the mesh;
* where either source photo, or the target, shows no skin, or the source's photos
  differ in what is there (:func:`skin`): hair against skin, a highlight, glasses, the
  background, told by a chromaticity unlike the face's own skin, or by a change of it
  that shading does not make. The lips are the face too (:func:`lips`).

This gate is always on, whatever the options (``retarget`` changes the shape stages
only): what it removes is not expression. The README's "Fidelity to the target" gives
its measured effect.
"""

from __future__ import annotations

import functools

import cv2
import numpy as np
from scipy import stats

from . import geometry, raster
from .layout import Layout

#: added to both luminances (in [0, 1]) so that dark pixels give no NaN or infinity.
EPS = 0.02
#: Gaussian filter of the ratio, sigma in inter-ocular distances.
FILTER_SIGMA = 0.03
#: the ratio is clamped to this range.
CLAMP = (0.7, 1.4)
#: relative local contrast of the neutral photo at which the ratio starts to fade, and is gone.
TEXTURE_RANGE = (0.04, 0.10)
#: feathering of the masks, sigma in inter-ocular distances.
FEATHER = 0.04
#: the face mask is smooth at the feather's scale: it is drawn this many times smaller and enlarged.
MASK_SHRINK = 4
#: the neutral photo's texture is its detail finer than this, in inter-ocular distances (:func:`texture_confidence`).
DETAIL_SIGMA = 0.01
#: the ERI's filters run on a copy shrunk as far as FILTER_SIGMA still spans this many pixels.
FILTER_PIXELS = 3.0
#: source motion (inter-ocular distances) at which the ratio starts to count, and counts fully
#: (:func:`moved`); the lower end is the landmark fitter's scatter on the eyes (0.01), the upper
#: one the motion that gives a muscle area of the MD model its full strength (0.04).
MOTION_RANGE = (0.01, 0.04)
#: the source's motion is spread over the face by a Gaussian of this sigma (inter-ocular distances).
MOTION_SPREAD = 0.1
#: colours are compared at the ratio's own scale (sigma, inter-ocular distances).
CHROMA_SIGMA = FILTER_SIGMA
#: the face's colour is fitted on this share of its pixels, those nearest its median.
CORE = 0.7
#: the colour fits and the light's trend are fitted on at most this many of the trusted pixels, evenly
#: spread (a fit's standard error at that count is under 1% of the spread it measures).
FIT_PIXELS = 16384
#: a colour (or a change of chromaticity) this many robust standard deviations from the
#: face's starts to fade the ratio, and ends it: the three-sigma rule, not tuned. Of a
#: Gaussian spread of skin colours, 1% (chromaticity) to 3% (with the luma) lies beyond 3,
#: a hundredth of that beyond 5.
OUTLIER_RANGE = (3.0, 5.0)


def luminance(image: np.ndarray) -> np.ndarray:
    """BT.601 luma of a uint8 RGB image (:func:`raster.luma`), float32 in [0, 1]; a 2-D image is taken to be luma already."""
    return raster.luma(image).astype(np.float32) / 255.0


def ratio_mask(shape: tuple[int, int], landmarks: np.ndarray, forehead: np.ndarray, layout: Layout) -> np.ndarray:
    """Feathered mask in [0, 1]: 1 on the face, 0 off it and in the eyes and mouth opening.

    Parameters
    ----------
    shape : (H, W)
    landmarks : ndarray of shape (N, 2)
        The face's landmarks in this frame.
    forehead : ndarray of shape (F, 2)
        Forehead control points (the face hull reaches up to them).
    layout : Layout
    """
    small = (max(1, shape[0] // MASK_SHRINK), max(1, shape[1] // MASK_SHRINK))
    scale = np.array([small[1] / shape[1], small[0] / shape[0]])
    iod = geometry.interocular(landmarks, layout) * scale.mean()
    pts, forehead = landmarks * scale, forehead * scale
    mask = np.zeros(small, np.float32)
    hull = cv2.convexHull(np.concatenate([pts[list(layout.jaw)], forehead]).astype(np.float32))
    cv2.fillConvexPoly(mask, np.round(hull).astype(np.int32), 1.0)
    # shrink by the feather width so the fade ends inside the face, not on the background
    k = max(1, int(round(2 * FEATHER * iod)))
    mask = raster.erode(mask, k)
    for holes in (*layout.eyes, layout.mouth_inner):
        raster.fill_polygon(mask, pts[list(holes)], 0.0)
    mask = cv2.GaussianBlur(mask, (0, 0), FEATHER * iod)
    return np.clip(cv2.resize(mask, (shape[1], shape[0]), interpolation=cv2.INTER_LINEAR), 0.0, 1.0)


def filter_step(iod: float) -> int:
    """How many times the ERI's filters may shrink the image: :data:`FILTER_SIGMA` spans at least :data:`FILTER_PIXELS` pixels."""
    return max(1, int(FILTER_SIGMA * iod / FILTER_PIXELS))


def shrink(image: np.ndarray, step: int) -> np.ndarray:
    """``image`` averaged over blocks of ``step x step`` pixels; a last partial block is left out.

    A whole number of blocks takes OpenCV's fast path of area averaging.
    """
    if step == 1:
        return image
    h, w = image.shape[0] // step, image.shape[1] // step
    return cv2.resize(image[: h * step, : w * step], (w, h), interpolation=cv2.INTER_AREA)


def enlarge(image: np.ndarray, shape: tuple[int, int], step: int) -> np.ndarray:
    """Undo :func:`shrink` to ``shape`` (bilinear; the left-out edge repeats its neighbour)."""
    if step == 1:
        return image
    h, w = image.shape[0] * step, image.shape[1] * step
    out = cv2.resize(image, (w, h), interpolation=cv2.INTER_LINEAR)
    return cv2.copyMakeBorder(out, 0, shape[0] - h, 0, shape[1] - w, cv2.BORDER_REPLICATE)


def texture_confidence(y_neutral: np.ndarray, iod: float, step: int = 1) -> np.ndarray:
    """Trust in the ratio, in [0, 1]: 1 on smooth skin, 0 where the neutral photo is textured.

    The texture is the local relative contrast: the RMS of the luminance's detail above
    ``DETAIL_SIGMA iod`` over a window of ``FILTER_SIGMA iod``, divided by the local mean luminance (so
    dark and light skin compare alike). Skin measures about 0.02-0.03; hair and beards
    0.1 and more. It maps linearly from 1 at ``TEXTURE_RANGE[0]`` to 0 at
    ``TEXTURE_RANGE[1]``.

    The detail is taken at full resolution; everything after it is smooth at the scale
    of the window and is computed on the image shrunk by ``step`` (:func:`shrink`), the
    grid of the returned array.
    """
    detail = y_neutral - cv2.GaussianBlur(y_neutral, (0, 0), max(DETAIL_SIGMA * iod, 0.5))
    window = max(FILTER_SIGMA * iod / step, 0.5)
    energy, mean = shrink(detail * detail, step), shrink(y_neutral, step)
    contrast = np.sqrt(cv2.GaussianBlur(energy, (0, 0), window)) / (cv2.GaussianBlur(mean, (0, 0), window) + EPS)
    lo, hi = TEXTURE_RANGE
    return np.clip(cv2.GaussianBlur((hi - contrast) / (hi - lo), (0, 0), window), 0.0, 1.0)


def moved(shape: tuple[int, int], points: np.ndarray, motion: np.ndarray, triangles: np.ndarray, iod: float) -> np.ndarray:
    """Where the expression moves the skin, in [0, 1] (``(H, W)`` float32).

    Each triangle of the mesh takes the mean of its corners' motion; the result is
    blurred by :data:`MOTION_SPREAD` and mapped linearly from 0 at ``MOTION_RANGE[0]``
    to 1 at ``MOTION_RANGE[1]``. An expression's shading (folds, a cheek's lift, crow's
    feet) lies where it moves the skin; where it does not (the forehead of a smile, the
    nose), what differs between the source's photos is the light, the hair, a
    highlight. On the 300 London Set pairs of the README (measured on the first version
    of the gate, with the code of commit d8a940c) this took 0.020 off the identity
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
    out = np.zeros(small, np.float32)
    for corners, value in zip(triangles, motion[triangles].mean(1)):
        raster.fill_polygon(out, points[corners] * scale, float(value))
    out = cv2.GaussianBlur(out, (0, 0), max(MOTION_SPREAD * iod * scale.mean(), 0.5))
    lo, hi = MOTION_RANGE
    return np.clip((cv2.resize(out, (shape[1], shape[0]), interpolation=cv2.INTER_LINEAR) - lo) / (hi - lo), 0.0, 1.0)


def colour(image: np.ndarray, iod: float, step: int = 1) -> np.ndarray:
    """``(log(R/G), log(B/G), log(Y))`` at the ratio's scale, ``(h, w, 3)`` on the grid shrunk by ``step``.

    The first two, the chromaticity, shading leaves unchanged (it scales the three
    channels alike) and a change of material changes; the third, the luma, tells dark
    hair from skin of much the same hue.
    """
    rgb = cv2.GaussianBlur(shrink(image, step).astype(np.float32) / 255.0, (0, 0), max(CHROMA_SIGMA * iod / step, 0.5)) + EPS
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


def evenly(weight: np.ndarray) -> np.ndarray:
    """Flat indices of at most :data:`FIT_PIXELS` of the pixels of ``weight > 0.5``, evenly spread over them."""
    trusted = np.flatnonzero(weight > 0.5)
    return trusted[:: max(1, -(-len(trusted) // FIT_PIXELS))]


def fade_out(values: np.ndarray, centre: np.ndarray, inverse: np.ndarray) -> np.ndarray:
    """1 where the Mahalanobis distance from ``centre`` is below ``OUTLIER_RANGE[0]``, 0 above ``OUTLIER_RANGE[1]``."""
    d = values - centre
    dist = np.sqrt(np.maximum(np.einsum("...i,ij,...j->...", d, inverse, d), 0.0))
    lo, hi = OUTLIER_RANGE
    return np.clip((hi - dist) / (hi - lo), 0.0, 1.0).astype(np.float32)


def skin(images: tuple[np.ndarray, ...], weight: np.ndarray, iod: float, step: int = 1, exempt: np.ndarray | None = None) -> np.ndarray:
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
    iod : float
    step : int
    exempt : ndarray of shape (h, w), optional
        Face that is trusted whatever its colour (:func:`lips`), on the shrunk grid.

    Returns
    -------
    ndarray of shape (h, w), float32
    """
    out, trusted = np.ones(weight.shape, np.float32), evenly(weight)
    colours = [colour(image, iod, step) for image in images]
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
    :func:`ratio_mask`. On 300 London Set pairs (with an earlier version of the colour
    test), leaving the lips out made e+md's mouth error on broad smiles worse by 0.0008 ±
    0.0004 and its identity distance better by 0.003.
    """
    out = np.zeros(shape, np.float32)
    return raster.fill_polygon(out, landmarks[list(layout.mouth_outer)], 1.0)


def light_trend(log_ratio: np.ndarray, weight: np.ndarray, iterations: int = 8) -> np.ndarray:
    """The plane ``a + b x + c y`` that fits the log ratio over the trusted face, as an image.

    A change of exposure between the source's two photos scales the ratio everywhere; a
    light that moved tilts it across the face; neither is expression. The fit is
    least absolute deviations (iteratively reweighted least squares), so that an
    expression's folds and lifted cheeks, local and bright or dark, do not pull it.

    Parameters
    ----------
    log_ratio : ndarray of shape (h, w)
    weight : ndarray of shape (h, w)
        Trust in each pixel; the fit uses those above 0.5.

    Returns
    -------
    ndarray of shape (h, w), float32
        0 where nothing is trusted.
    """
    ys, xs = np.unravel_index(evenly(weight), weight.shape)
    if len(xs) < 3:
        return np.zeros(log_ratio.shape, np.float32)
    h, w = log_ratio.shape
    design = np.column_stack([np.ones(len(xs)), xs / w, ys / h])
    target = log_ratio[ys, xs].astype(float)
    row_weight = np.ones(len(xs))
    for _ in range(iterations):
        weighted = design.T * row_weight  # the normal equations: 3x3 (lstsq of all the rows waited on BLAS threads)
        coef = np.linalg.lstsq(weighted @ design, weighted @ target, rcond=None)[0]
        row_weight = 1.0 / np.maximum(np.abs(design @ coef - target), 1e-4)
    return (coef[0] + coef[1] * np.arange(w) / w + coef[2] * np.arange(h)[:, None] / h).astype(np.float32)


def expression_ratio(
    neutral_warped: np.ndarray,
    expression_warped: np.ndarray,
    mask: np.ndarray,
    iod: float,
    target: np.ndarray | None = None,
    exempt: np.ndarray | None = None,
) -> np.ndarray:
    """The filtered, clamped and masked ERI, ``(H, W)`` float32, 1 where nothing changes.

    The ERI is low-pass filtered at ``FILTER_SIGMA * iod``, so everything after the
    per-pixel ratio is computed on a copy shrunk by :func:`filter_step` and enlarged at
    the end (bilinear), about five times faster at 1350 pixels. On six pairs of the
    London Set this differs from working at full resolution by at most 0.006 in the
    ratio (2 grey levels of the result), 2e-5 on average.

    Parameters
    ----------
    neutral_warped, expression_warped : ndarray of shape (H, W, 3), uint8 RGB
        The source's two photos warped to the target's final geometry.
    mask : ndarray of shape (H, W)
        Where the ratio may count: :func:`ratio_mask`, times :func:`moved`.
    iod : float
        Inter-ocular distance of the target face, for the filter size.
    target : ndarray of shape (H, W, 3), uint8 RGB, optional
        The target in the same geometry: the ratio is faded out where it shows no skin.
    exempt : ndarray of shape (H, W), optional
        Where the colour test does not apply (:func:`lips`).

    The trusted pixels are those of ``mask`` where neither photo is textured
    (:func:`texture_confidence`) and all show the same skin (:func:`skin`; but for
    ``exempt``).
    """
    step = min(filter_step(iod), *mask.shape)
    y_neutral, y_expression = luminance(neutral_warped), luminance(expression_warped)
    ratio = shrink((y_expression + EPS) / (y_neutral + EPS), step)
    # the colour tests compare each pixel with the face where the geometry and the texture trust it
    face = shrink(mask, step) * np.minimum(texture_confidence(y_neutral, iod, step), texture_confidence(y_expression, iod, step))
    images = (neutral_warped, expression_warped) + (() if target is None else (target,))
    weight = face * skin(images, face, iod, step, None if exempt is None else shrink(exempt, step))
    # Normalised convolution: the filter averages only trusted pixels, so the ratio of
    # teeth to lips or of hair to hair does not leak into the skin around them.
    sigma = max(FILTER_SIGMA * iod / step, 0.5)
    ratio = cv2.GaussianBlur(weight * ratio, (0, 0), sigma) / np.maximum(cv2.GaussianBlur(weight, (0, 0), sigma), 1e-6)
    ratio = np.clip(ratio / np.exp(light_trend(np.log(np.maximum(ratio, 1e-3)), weight)), *CLAMP)
    return enlarge(1.0 + weight * (ratio - 1.0), mask.shape, step)


def apply_details(image: np.ndarray, eri: np.ndarray, importance: np.ndarray | float = 1.0) -> np.ndarray:
    """Eq. (9) applied: ``F_IMG = FI * (1 + M * IL)`` with ``IL = ERI - 1``.

    With ``M = 1`` this is Liu et al.'s ERI transfer (``FI * ERI``); the MD model passes
    its detail-importance mask ``M`` (:func:`exprclone.muscle.importance_mask`).

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The geometrically warped target FI.
    eri : ndarray of shape (H, W)
    importance : ndarray of shape (H, W) or float

    Returns
    -------
    ndarray of shape (H, W, 3), uint8
    """
    gain = (1.0 + importance * (eri - 1.0)).astype(np.float32)
    # one pass, rounded to nearest and saturated to [0, 255]
    return cv2.multiply(image, cv2.merge([gain] * image.shape[2]), dtype=cv2.CV_8U)
