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
and it is faded out (:func:`texture`); the filter is a normalised
convolution over the trusted pixels only, so nothing leaks from the excluded ones.
The same test is made on the expression photo (hair that moved into it). A change of
light between the source's two photos is divided out as well: the ratio's trend over
the face, a smooth surface of the second order in its logarithm fitted robustly over the
skin that moves and the skin that does not (:func:`light_trend`, :func:`light_sample`), is taken to
be 1, which removes a change of exposure and a light that moved across the face.

Only expression shading: the ratio also counts only where the expression moves the skin
and all three photos show the same skin (:mod:`exprclone.details.gate`, the gate's weights).

Shadows the colour of skin (ours): a ratio of lumas dims R, G and B alike, which keeps the
skin's chroma in proportion to its lightness; real skin's shadows are warmer and more
saturated than that (light scattered under the skin), and a fold dimmed alike reads as a
grey bruise. So the ERI also carries its *tint*: how the source's chromaticity
(``log R/G``, ``log B/G``) changes between its two photos where the ratio counts, filtered
and weighted as the ratio is, a change of the light's colour (of white balance: the
chromaticity's trend over the face the expression does not move) taken out. Applied with the ratio (:func:`apply_details`), it shifts the
target's chromaticity by as much at the same lightness: the source's skin's colour, a
ratio's numerator and denominator alike, does not come with it.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..imaging import order, raster
from ..landmarks import align
from ..landmarks.layout import Layout
from . import coarse, gate

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
#: the ERI is computed on a grid shrunk as far as FILTER_SIGMA still spans this many of its pixels (about 50 to an
#: inter-ocular distance: blocks of 5 pixels on a 1350-pixel London photo, 2 at 512).
FILTER_PIXELS = 1.5
#: what the shrunk grid adds to the ratio's filter, in squared blocks along each axis: a block's mean (1/12) and the
#: bilinear enlargement (1/6). The Gaussian on the grid is narrowed by it, so that the whole filter is FILTER_SIGMA's
#: (:func:`ratio_on_grid`); without it, the ERI at 1350 pixels (blocks of 5) came out 5% more blurred.
GRID_VARIANCE = 1 / 12 + 1 / 6
#: rows of the image per strip when the details are applied (:func:`apply_details`): its temporaries stay in the CPU cache.
STRIP = 64


def luminance(image: np.ndarray) -> np.ndarray:
    """BT.601 luma of a uint8 RGB image (:func:`raster.luma`), float32 in [0, 1]; a 2-D image is taken to be luma already."""
    return raster.luma(image).astype(np.float32) / 255.0


def ratio_mask(
    shape: tuple[int, int], landmarks: np.ndarray, forehead: np.ndarray, layout: Layout, shrink: int = MASK_SHRINK
) -> np.ndarray:
    """Feathered mask in [0, 1]: 1 on the face, 0 off it and in the eyes and mouth opening.

    Parameters
    ----------
    shape : (H, W)
    landmarks : ndarray of shape (N, 2)
        The face's landmarks in this frame.
    forehead : ndarray of shape (F, 2)
        Forehead control points (the face hull reaches up to them).
    layout : Layout
    shrink : int
        How many times smaller it is drawn (:data:`MASK_SHRINK`; less on a grid already shrunk).
    """
    small = (max(1, shape[0] // shrink), max(1, shape[1] // shrink))
    scale = np.array([small[1] / shape[1], small[0] / shape[0]])
    iod = align.interocular(landmarks, layout) * scale.mean()
    pts, forehead = landmarks * scale, forehead * scale
    mask: np.ndarray = np.zeros(small, np.float32)
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


def texture(energy: np.ndarray, mean: np.ndarray, window: float) -> np.ndarray:
    """Trust in the ratio, in [0, 1]: 1 on smooth skin, 0 where a photo is textured, from the detail's energy and the
    luminance on a grid (:attr:`exprclone.details.coarse.Shrunk.pixels`), the window in its pixels.

    The texture is the local relative contrast: the RMS of the luminance's detail above
    ``DETAIL_SIGMA iod`` (:func:`exprclone.details.coarse.detail_energy`) over a window of ``FILTER_SIGMA iod``, divided by
    the local mean luminance (so dark and light skin compare alike). Skin measures about 0.02-0.03; hair and beards 0.1
    and more. It maps linearly from 1
    at ``TEXTURE_RANGE[0]`` to 0 at ``TEXTURE_RANGE[1]``.
    """
    window = max(window, 0.5)
    contrast = np.sqrt(cv2.GaussianBlur(energy, (0, 0), window)) / (cv2.GaussianBlur(mean, (0, 0), window) + raster.EPS)
    lo, hi = TEXTURE_RANGE
    return np.clip(cv2.GaussianBlur((hi - contrast) / (hi - lo), (0, 0), window), 0.0, 1.0)


def light_trend(log_ratio: np.ndarray, weight: np.ndarray, iterations: int = 8) -> np.ndarray:
    """The smooth surface of the second order, ``a + b x + c y + d x^2 + e x y + f y^2``, that fits the log ratio over
    the trusted face, as an image.

    A change of exposure between the source's two photos scales the ratio everywhere; a light that moved tilts it
    across the face, and bends it: a gain that changes evenly from one ear to the other is a curve in the logarithm
    (+-15%: ``log 1.15 = 0.140``, ``log 0.85 = -0.163``), and a plane fitted to it left a bow of about 1% (``s^2 / 2``).
    None of it is expression. The fit is least absolute deviations (iteratively reweighted least squares), so that an
    expression's folds and lifted cheeks, local and bright or dark, do not pull it.

    Parameters
    ----------
    log_ratio : ndarray of shape (h, w)
    weight : ndarray of shape (h, w)
        Trust in each pixel; the fit uses those above 0.5.

    Returns
    -------
    ndarray of shape (h, w), float32
        0 where fewer pixels are trusted than the surface has terms (:func:`trend_terms`).
    """
    ys, xs = np.unravel_index(raster.evenly(weight), weight.shape)
    h, w = log_ratio.shape
    design = trend_terms(xs * (2.0 / w) - 1.0, ys * (2.0 / h) - 1.0)
    if len(xs) < design.shape[1]:
        return np.zeros(log_ratio.shape, np.float32)
    target = log_ratio[ys, xs].astype(float)
    row_weight = np.ones(len(xs))
    for _ in range(iterations):
        weighted = design.T * row_weight  # the normal equations: 6x6 (lstsq of all the rows waited on BLAS threads)
        coef = np.linalg.lstsq(weighted @ design, weighted @ target, rcond=None)[0]
        row_weight = 1.0 / np.maximum(np.abs(design @ coef - target), 1e-4)
    x, y = np.meshgrid(np.arange(w) * (2.0 / w) - 1.0, np.arange(h) * (2.0 / h) - 1.0)
    return (trend_terms(x.ravel(), y.ravel()) @ coef).reshape(h, w).astype(np.float32)


def trend_terms(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The terms of :func:`light_trend`'s surface at ``(x, y)``, the grid's coordinates taken to -1..1:
    ``1, x, y, x^2, x y, y^2``, ``(n, 6)``."""
    return np.column_stack([np.ones(len(x)), x, y, x * x, x * y, y * y])


#: the largest shift of the chromaticity (``log R/G``, ``log B/G``) the tint carries: a stronger change between the
#: source's two photos is a change of material (make-up, a flush of the whole face), not a shadow's colour.
TINT_LIMIT = 0.15
#: the fewest pixels of still skin whose chromaticity's change is taken for the light's colour (:func:`ratio_on_grid`).
MIN_STILL = 16
#: the channels of the ERI on its grid (:func:`ratio_on_grid`): the luma ratio, then its tint (two).
RATIO, TINT = 0, slice(1, 3)

#: the channels of the source's neutral photo as the ERI warps it (:func:`neutral_channels`): its luma and detail
#: energy (:attr:`exprclone.details.coarse.Shrunk.pixels`; the texture test is made after the warp, as on the expression
#: photo), its chromaticity smoothed (two) as the colour tests take it, its skin trust
#: (:func:`exprclone.details.gate.trust`), and its chromaticity as it is (two), from which the tint is taken.
N_LUMA, N_ENERGY, N_CHROMA, N_SKIN, N_TINT = 0, 1, slice(2, 4), 4, slice(5, 7)


def neutral_channels(pixels: np.ndarray, face: np.ndarray, sigma: float) -> tuple[np.ndarray, gate.Fit]:
    """What the ERI takes of the source's neutral photo, measured once on its own shrunk grid.

    Its colour and how far that is from its face's skin do not depend on the expression,
    so they are measured on the photo's grid, where the photo is still, and warped to
    each expression's geometry as they are (:func:`ratio_on_grid`) rather than measured
    again after every warp (every frame of a video). The texture test (:func:`texture`) is
    made after the warp: measured before it, its fade was smeared by the warp's
    resampling, and the hair of a fringe that moved (tests/details/test_gate.py) leaked into
    the ratio.

    Parameters
    ----------
    pixels : ndarray of shape (h, w, 5)
        The photo's block means (:attr:`exprclone.details.coarse.Shrunk.pixels`, with its luma and detail energy).
    face : ndarray of shape (h, w)
        Its face where the texture test trusts it (:func:`ratio_mask` times :func:`texture`): its colour model's pixels.
    sigma : float
        :data:`FILTER_SIGMA` in pixels of its grid.

    Returns
    -------
    channels : ndarray of shape (h, w, 7), float32
        :data:`N_LUMA`, :data:`N_ENERGY`, :data:`N_CHROMA`, :data:`N_SKIN`, :data:`N_TINT`.
    hue : shading.Fit
        Its chromaticity's model (:func:`exprclone.details.gate.skin`).
    """
    colour = gate.colour(pixels, sigma)
    channels = np.empty(pixels.shape[:2] + (7,), np.float32)
    channels[..., N_LUMA], channels[..., N_ENERGY] = pixels[..., coarse.LUMA], pixels[..., coarse.ENERGY]
    channels[..., N_CHROMA], channels[..., N_SKIN] = colour[..., :2], gate.trust(colour, face)
    channels[..., N_TINT] = chromaticity(pixels)
    return channels, gate.robust_gaussian(colour[..., :2], raster.evenly(face))


def chromaticity(pixels: np.ndarray) -> np.ndarray:
    """``(log R/G, log B/G)`` of block means (``(h, w, >=3)``, R, G and B first), ``(h, w, 2)`` float32, not smoothed."""
    rgb = pixels[..., :3] + raster.EPS
    return np.log(rgb[..., [0, 2]] / rgb[..., 1:2]).astype(np.float32)


def light_sample(ratio: np.ndarray, weight: np.ndarray, still: np.ndarray | None, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """What :func:`light_trend` is fitted to: the log of the luma ratio filtered (as :func:`ratio_on_grid` filters it)
    over the pixels it counts at (``weight``) and over the skin the expression leaves still (``still``, trusted as
    much), and their weights. The still skin changes with the light alone: it holds the fit over the whole face, where
    the moving skin alone (a smile's lower face) left it free to tilt and bend, and to follow where the expression's
    landmarks fell (``tools/relight.py``: the clone's change for a noise of one grey level, landmarks found afresh, 1.70
    grey levels with the moving skin alone, 1.42 with the still skin too)."""
    fit = weight if still is None else weight + still
    filtered = cv2.GaussianBlur(fit * ratio, (0, 0), sigma) / np.maximum(cv2.GaussianBlur(fit, (0, 0), sigma), 1e-6)
    return np.log(np.maximum(filtered, 1e-3)), fit


def ratio_on_grid(
    neutral: np.ndarray,
    expression: np.ndarray,
    target: np.ndarray | None,
    mask: np.ndarray,
    iod: float,
    exempt: np.ndarray | None = None,
    hue: gate.Fit = None,
    blocks: bool = True,
    still: np.ndarray | None = None,
) -> np.ndarray:
    """The ERI on the shrunk grid, from the source's photos there.

    The ratio of the lumas counts where ``mask`` does, neither source photo is textured
    (:func:`texture`) and all show the same skin (:func:`exprclone.details.gate.skin`; but for
    ``exempt``); it is filtered over those trusted pixels only (a normalised
    convolution: the ratio of teeth to lips or of hair to hair does not leak into the
    skin around them), the light's trend is divided out (:func:`light_trend`) and it is
    clamped to :data:`CLAMP`.

    Parameters
    ----------
    neutral : ndarray of shape (h, w, 7)
        The source's neutral photo in the target's final geometry, measured on its own grid (:func:`neutral_channels`).
    expression : ndarray of shape (h, w, 5)
        The expression photo's block means in that geometry (:attr:`exprclone.details.coarse.Shrunk.pixels`).
    target : ndarray of shape (h, w) or None
        The target's skin trust in that geometry (:func:`exprclone.details.gate.trust`); None tests no target.
    mask : ndarray of shape (h, w)
    iod : float
        The target face's inter-ocular distance in pixels of this grid.
    exempt : ndarray of shape (h, w), optional
    hue : shading.Fit
        The neutral photo's chromaticity (:func:`neutral_channels`).
    blocks : bool
        Whether the grid's pixels are blocks of several, to be enlarged (:data:`GRID_VARIANCE`), or the photo's own.
    still : ndarray of shape (h, w), optional
        The face where the expression does not move the skin: a change of the chromaticity there is the light's colour
        (white balance), taken out of the tint (its median there), and its ratio the light's change, which the trend is
        fitted to as well (:func:`light_sample`); if None, no colour is taken out and the trend is fitted where the
        ratio counts alone.

    Returns
    -------
    ndarray of shape (h, w, 3), float32
        :data:`RATIO`: ``1 + weight (ratio - 1)``, 1 where nothing is trusted; :data:`TINT`: ``weight tint``, the
        shift of the chromaticity between the source's photos filtered over the same pixels, its trend over the face
        taken out (the module's notes), 0 where nothing is trusted.
    """
    sigma = FILTER_SIGMA * iod
    y_expression = expression[..., coarse.LUMA]
    ratio = (y_expression + raster.EPS) / (neutral[..., N_LUMA] + raster.EPS)
    # the colour tests compare each pixel with the face where the geometry and the texture trust it
    photos = ((neutral[..., N_ENERGY], neutral[..., N_LUMA]), (expression[..., coarse.ENERGY], y_expression))
    smooth = np.minimum(*(texture(energy, luma, sigma) for energy, luma in photos))  # neither photo textured
    face = mask * smooth
    colour = gate.colour(expression, sigma)
    trust = neutral[..., N_SKIN] if target is None else neutral[..., N_SKIN] * target
    weight = face * gate.skin(colour, neutral[..., N_CHROMA], trust, face, exempt, hue)
    sigma = max(np.sqrt(max(sigma * sigma - (GRID_VARIANCE if blocks else 0.0), 0.0)), 0.5)
    norm = np.maximum(cv2.GaussianBlur(weight, (0, 0), sigma), 1e-6)
    resting = None if still is None else still * smooth * trust  # the skin the expression leaves still, trusted
    trend = light_trend(*light_sample(ratio, weight, resting, sigma))
    ratio = np.clip(cv2.GaussianBlur(weight * ratio, (0, 0), sigma) / norm / np.exp(trend), *CLAMP)
    change = chromaticity(expression) - neutral[..., N_TINT]
    shift = cv2.GaussianBlur(weight[..., None] * change, (0, 0), sigma) / norm[..., None]
    out = np.empty(ratio.shape + (3,), np.float32)
    out[..., RATIO] = 1.0 + weight * (ratio - 1.0)
    light = np.zeros(2, np.float32)
    if resting is not None:  # the light's colour: the chromaticity's change over the skin the expression leaves still
        reference = raster.evenly(resting)
        lit = change.reshape(-1, 2)[reference]
        light = order.median(lit, 0) if len(lit) >= MIN_STILL else light
    trusted = raster.evenly(weight)
    x, y = np.log(ratio).reshape(-1)[trusted], (shift - light).reshape(-1, 2)[trusted]
    slope = (x @ y) / max(float(x @ x), 1e-9) if len(x) >= MIN_STILL else np.zeros(2, np.float32)
    out[..., TINT] = np.clip(np.log(out[..., RATIO])[..., None] * slope.astype(np.float32), -TINT_LIMIT, TINT_LIMIT)
    return out


def apply_details(image: np.ndarray, eri: np.ndarray, importance: np.ndarray | float = 1.0, tint: np.ndarray | None = None) -> np.ndarray:
    """Eq. (9) applied: ``F_IMG = FI * (1 + M * IL)`` with ``IL = ERI - 1``, and the ERI's tint (the module's notes).

    With ``M = 1`` this is Liu et al.'s ERI transfer (``FI * ERI``); the MD model passes
    its detail-importance mask ``M`` (:func:`exprclone.details.muscle.importance_mask`).
    The tint ``t`` (weighted by ``M`` too) shifts each pixel's chromaticity: R and B are scaled
    by ``exp(M t)`` against G, and the three by the one factor that keeps the pixel's luma what
    Eq. (9) makes it.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The geometrically warped target FI.
    eri : ndarray of shape (H, W)
    importance : ndarray of shape (H, W) or float
    tint : ndarray of shape (H, W, 2), optional
        The shift of ``log R/G`` and ``log B/G`` (:func:`ratio_on_grid`'s :data:`TINT`); none if None.

    Returns
    -------
    ndarray of shape (H, W, 3), uint8
    """
    importance = np.asarray(importance) if np.ndim(importance) else float(importance)
    out = np.empty(image.shape, np.uint8)
    gains = np.empty((min(STRIP, len(image)),) + image.shape[1:], np.float32)  # one buffer for every strip (in the cache)
    for y0 in range(0, len(image), STRIP):
        rows = slice(y0, y0 + STRIP)
        strip = importance if isinstance(importance, float) else importance[rows]
        gain = (1.0 + strip * (eri[rows] - 1.0)).astype(np.float32)
        if tint is None:
            channels = cv2.merge([gain] * image.shape[2], dst=gains[: len(gain)])
        else:
            channels = tinted(image[rows], gain, np.exp(np.asarray(strip, np.float32)[..., None] * tint[rows]), gains[: len(gain)])
        # one pass, rounded to nearest and saturated to [0, 255]
        cv2.multiply(image[rows], channels, dst=out[rows], dtype=cv2.CV_8U)
    return out


def tinted(image: np.ndarray, gain: np.ndarray, shift: np.ndarray, out: np.ndarray) -> np.ndarray:
    """The three channels' gains of :func:`apply_details` for ``image`` (uint8 RGB): R and B by ``shift`` (``exp`` of the
    tint) against G, all by the factor that keeps the luma's gain ``gain``; written into ``out``."""
    pixels = image.astype(np.float32) + 1.0  # a black pixel has no colour to shift
    out[..., 0], out[..., 1], out[..., 2] = shift[..., 0], 1.0, shift[..., 1]
    luma = pixels @ raster.LUMA
    out *= (gain * luma / np.einsum("ijc,ijc,c->ij", pixels, out, raster.LUMA))[..., None]
    return out
