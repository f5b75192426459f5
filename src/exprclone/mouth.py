"""The mouth interior: teeth, tongue and cavity taken from the source expression.

Not in the paper. Warping a closed neutral mouth open cannot create teeth: the lips are
stretched over where the teeth should be, and the paper's ERI and MD steps change
shading, not content. Where the final geometry opens the target's mouth and the source's
expression shows an open mouth, the inside of the target's inner lips is filled with the
source's mouth interior. The source's mouth counts as open when its inner-lip polygon
has area and shows what is not lip (:func:`interior`: teeth, or the dark cavity):
landmark fitters often leave the inner lips of full, closed lips apart, and pasting
what lies between them would paste lips.

1. warped from the source's inner-lip polygon to the target's (a piecewise-affine warp
   over the lips and the polygon's centre);
2. matched to the target photo: its colour is mapped from the source's light to the
   target's (:func:`tone_gain`, a per-channel gain from :mod:`exprclone.illuminant`: the
   two photos' skin and eye whites, each cue weighted by how much it shows and how
   reliable it is), so that the photo's exposure and colour cast carry over but not the
   source's light: teeth filmed under a warm lamp are not pasted orange into a white-lit
   portrait. The source's light is read on its neutral photo (a smile often squints)
   and carried over to the expression by the change of exposure. Never so bright that
   teeth the source photo shows unclipped turn flat white; then it is blurred to the
   target photo's sharpness and given the target photo's noise (:func:`match_grain`),
   so teeth from a crisp photo do not stand out in a soft or grainy one;
3. blended inside the inner-lip polygon with a feathered edge that ends at the lip line,
   so the target's own lips stay the target's.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.spatial import Delaunay

from . import geometry, illuminant, raster, warp
from .layout import Layout

#: inner-lip polygon area over the squared mouth width (:func:`opening`): below the first
#: value a mouth is closed, above the second fully open; in between the paste fades in, so
#: that in a video the teeth appear as the lips part instead of popping in at once.
OPENING = (0.010, 0.020)
#: a pixel is tooth-coloured below this share of the lips' median saturation (and brighter
#: than the lips' median).
TOOTH_SATURATION = 0.6
#: a pixel is the mouth's cavity below this share of the lips' median luma.
CAVITY = 0.5
#: teeth and cavity between the lips (:func:`interior`), in squared mouth widths: below the
#: first value a source's mouth shows nothing, above the second it is fully open, and the
#: paste fades in between. On the London Set's 72 smiles and 72 neutral photos (detected
#: landmarks), closed mouths show at most 0.0052 (the shadow of the lip line, a lip
#: piercing) and smiles that show teeth 0.010 and more.
INTERIOR = (0.005, 0.010)
#: feather of the blend, in mouth widths.
FEATHER = 0.015
#: the second blur of the gradient-ratio sharpness estimate (pixels).
REBLUR = 1.0
#: share of a face's pixels, the strongest gradients, taken as its edges.
EDGE_SHARE = 0.02
#: seed of the noise given to the pasted interior: the same inputs give the same image.
NOISE_SEED = 0
#: the patch warped from the source reaches this share of the mouth width beyond the lips.
PATCH_MARGIN = 0.1
#: the tone match's gain is held within this range, channel by channel: a channel scaled
#: by 4 has lost 2 of its 8 bits and shows 4 times its noise. The strongest cast of the
#: GRID clips (lbax4n, lrwp9a, swiz3n: skin with a third of its blue) needs about 3.
GAIN_RANGE = (0.25, 4.0)


def mouth_width(landmarks: np.ndarray, layout: Layout) -> float:
    """Distance between the outer mouth corners."""
    i, j = layout.mouth_corners
    return float(np.linalg.norm(landmarks[j] - landmarks[i]))


def opening(landmarks: np.ndarray, layout: Layout) -> float:
    """Area of the inner-lip polygon over the squared mouth width: 0 for a closed mouth."""
    inner = landmarks[list(layout.mouth_inner)]
    x, y = inner[:, 0], inner[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    return float(area / max(mouth_width(landmarks, layout), 1e-9) ** 2)


def interior(image: np.ndarray, landmarks: np.ndarray, layout: Layout, gain: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The teeth and the dark cavity inside the inner lips, told from the lips around them.

    The lips (between the outer and the inner lip polygons) are the face's own
    reference, lit as the mouth is, so the rule holds for every skin tone and exposure:
    a pixel inside the inner-lip polygon is tooth-coloured when paler than the lips
    (saturation in HSV below :data:`TOOTH_SATURATION` times theirs, median) and
    brighter; it is cavity when darker than :data:`CAVITY` times their median luma.
    Lips, and a tongue, are neither. A coloured light saturates teeth and lips alike (an
    orange one drains their blue), and under a strong one teeth no longer look paler
    than lips; ``gain`` first takes the photo to another light (:func:`tone_gain`).

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    landmarks : ndarray of shape (N, 2)
    layout : Layout
    gain : ndarray of shape (3,), optional
        Per-channel gain applied to the photo's colours first.

    Returns
    -------
    teeth, cavity : ndarray of shape (H, W), bool
    """
    teeth = np.zeros(image.shape[:2], bool)
    cavity = teeth.copy()
    box = geometry.box(landmarks[list(layout.mouth_outer)], image.shape)
    crop, corner = image[box], (box[1].start, box[0].start)
    if gain is not None:
        crop = np.clip(crop * np.asarray(gain, np.float32) + 0.5, 0, 255).astype(np.uint8)
    inner, outer = np.zeros(crop.shape[:2], np.uint8), np.zeros(crop.shape[:2], np.uint8)
    raster.fill_polygon(inner, landmarks[list(layout.mouth_inner)] - corner, 1)
    raster.fill_polygon(outer, landmarks[list(layout.mouth_outer)] - corner, 1)
    lip, inner = (outer > 0) & (inner == 0), inner > 0
    if not lip.any() or not inner.any():
        return teeth, cavity
    saturation = cv2.cvtColor(crop, cv2.COLOR_RGB2HSV)[..., 1].astype(np.float32)
    luma = raster.luma(crop.astype(np.float32))
    lip_luma = np.median(luma[lip])
    teeth[box] = inner & (saturation < TOOTH_SATURATION * np.median(saturation[lip])) & (luma > lip_luma)
    cavity[box] = inner & (luma < CAVITY * lip_luma)
    return teeth, cavity


def fade_in(value: float, band: tuple[float, float]) -> float:
    """0 below ``band[0]``, 1 above ``band[1]``, linear in between.

    Examples
    --------
    >>> [fade_in(v, (1, 3)) for v in (0, 2, 5)]
    [0.0, 0.5, 1.0]
    """
    low, high = band
    return float(np.clip((value - low) / (high - low), 0.0, 1.0))


@dataclass(frozen=True)
class Reference:
    """What a paste is matched to, measured once for a pair of faces.

    The target photo and the source's neutral photo are the same for every expression
    cloned between two people (every frame of a driving video), so their lights,
    sharpness and noise are measured once; only the expression's own measures change,
    and of those the tone match takes only the change of exposure from the neutral
    face, a brightness: nothing in the colour of the paste changes from frame to frame.

    Attributes
    ----------
    light : illuminant.Light
        The cues to the light on the target photo (:class:`exprclone.illuminant.Light`).
    blur : float
        Its face's edge blur (:func:`blur_sigma` of :func:`face_box`).
    noise : ndarray of shape (3,)
        Its face's noise (:func:`noise_sigma`).
    source_light : illuminant.Light or None
        The same cues on the source's neutral photo, when it is given.
    source_face : ndarray of shape (3,) or None
        That photo's face colour (:func:`face_colour`), to carry its light over to an expression photo taken at
        another exposure.
    """

    light: illuminant.Light
    blur: float
    noise: np.ndarray
    source_light: illuminant.Light | None = None
    source_face: np.ndarray | None = None

    @classmethod
    def measure(
        cls,
        target: np.ndarray,
        target_landmarks: np.ndarray,
        layout: Layout,
        source_neutral: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> Reference:
        """Measure the target photo (and the source's neutral photo with its landmarks, if given)."""
        face = face_box(target, target_landmarks)
        source = {}
        if source_neutral is not None:
            neutral, neutral_landmarks = source_neutral
            source = dict(
                source_light=illuminant.Light.measure(neutral, neutral_landmarks, layout),
                source_face=face_colour(neutral, neutral_landmarks),
            )
        return cls(illuminant.Light.measure(target, target_landmarks, layout), blur_sigma(face), noise_sigma(face), **source)


def tone_gain(
    source: np.ndarray,
    source_landmarks: np.ndarray,
    reference: Reference,
    layout: Layout,
    pasted: np.ndarray | None = None,
) -> np.ndarray:
    """Per-channel gain that gives the source photo's pixels the target photo's exposure and light.

    The gain from the source's light to the target's (:func:`exprclone.illuminant.gain`),
    within :data:`GAIN_RANGE`, lowered (all channels alike) until the brightest
    ``pasted`` pixels (99th percentile) stay below white: teeth the source photo shows
    unclipped never turn flat white. A smiling source often squints, hiding its eye
    whites behind lashes (on the London Set they read 5% darker in the smile than in the
    neutral photo at the median, 19% at the 5th percentile, 55% for one person), so when
    the reference holds the source's neutral photo its light is read there and carried
    over to the expression photo by the change of exposure: the ratio of the two
    photos' face colours (:func:`face_colour`;
    one person's face, so what differs between them is the exposure), as a brightness
    (the mean of the channels' log ratios). The colour of the light is read once, on
    the neutral face: in a video, the paste's colour is the same in every frame.

    Parameters
    ----------
    source : ndarray of shape (H, W, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    reference : Reference
        The target photo (and the source's neutral photo), measured.
    layout : Layout
    pasted : ndarray of shape (K, 3), optional
        The source pixels the gain is for.

    Returns
    -------
    ndarray of shape (3,)
    """
    if reference.source_light is None:
        light = illuminant.Light.measure(source, source_landmarks, layout)
    else:
        face = face_colour(source, source_landmarks)
        exposure = np.log(np.maximum(face, 1.0) / np.maximum(reference.source_face, 1.0)).mean()
        light = reference.source_light.scaled(np.exp(exposure))
    gain = np.clip(illuminant.gain(reference.light, light), *GAIN_RANGE)
    return gain if pasted is None else below_white(gain, pasted)


def below_white(gain: np.ndarray, pasted: np.ndarray) -> np.ndarray:
    """``gain`` lowered, all channels alike, until the brightest ``pasted`` pixels (99th percentile) stay below white.

    Examples
    --------
    >>> below_white(np.array([2.0, 2.0, 1.0]), np.array([[100, 150, 200]])).round(2).tolist()
    [1.7, 1.7, 0.85]
    """
    if not len(pasted):
        return gain
    return gain * min(1.0, 255.0 / max(float((gain * np.percentile(pasted, 99, axis=0)).max()), 1.0))


def face_colour(image: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """The face's colour: the :func:`~exprclone.illuminant.midmean` of the pixels of the landmarks' bounding box (brows to chin)."""
    return illuminant.midmean(image[geometry.box(landmarks, image.shape)].reshape(-1, 3))


def face_box(image: np.ndarray, landmarks: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """The bounding box of the landmarks (brows to chin), float32, resized by ``scale``.

    Resizing is bilinear, as the warp samples, so a face brought to another photo's scale
    is as sharp and as noisy as its warped pixels are there.
    """
    box = image[geometry.box(landmarks, image.shape)].astype(np.float32)
    if scale == 1.0:
        return box
    size = (max(int(round(box.shape[1] * scale)), 8), max(int(round(box.shape[0] * scale)), 8))
    return cv2.resize(box, size, interpolation=cv2.INTER_LINEAR)


def blur_sigma(image: np.ndarray) -> float:
    """How blurred an image is: the Gaussian sigma (pixels) of its edges.

    The gradient-ratio estimate of Zhuo and Sim: an edge blurred by ``sigma`` and
    blurred again by ``sigma_0`` (:data:`REBLUR`) keeps ``1 / R`` of its gradient, with
    ``R = sqrt(sigma**2 + sigma_0**2) / sigma``, so ``sigma = sigma_0 / sqrt(R**2 - 1)``;
    the median over the strongest gradients (:data:`EDGE_SHARE` of the pixels, edges).
    Sobel's own smoothing adds the same amount to every estimate, so two estimates
    compare.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3) or (H, W)

    Returns
    -------
    float

    References
    ----------
    S. Zhuo and T. Sim, "Defocus map estimation from a single image", Pattern
    Recognition 44(9), 2011.

    Examples
    --------
    >>> step = np.zeros((64, 64), np.float32)
    >>> step[:, 32:] = 200
    >>> soft = blur_sigma(cv2.GaussianBlur(step, (0, 0), 3.0))
    >>> sharp = blur_sigma(cv2.GaussianBlur(step, (0, 0), 1.0))
    >>> bool(2.5 < soft < 3.5 and sharp < soft)
    True
    """
    luma = raster.luma(np.asarray(image, np.float32))

    def gradient(im: np.ndarray) -> np.ndarray:
        return cv2.magnitude(cv2.Sobel(im, cv2.CV_32F, 1, 0), cv2.Sobel(im, cv2.CV_32F, 0, 1))

    g = gradient(luma)
    edges = g >= max(np.percentile(g, 100 * (1 - EDGE_SHARE)), 1e-3)
    ratio = g[edges] / np.maximum(gradient(cv2.GaussianBlur(luma, (0, 0), REBLUR))[edges], 1e-6)
    ratio = ratio[ratio > 1.0 + 1e-4]
    return float(np.median(REBLUR / np.sqrt(ratio**2 - 1))) if len(ratio) else 0.0


def noise_sigma(image: np.ndarray) -> np.ndarray:
    """Standard deviation of each channel's noise.

    Immerkaer's estimate, in its robust form: the mask ``N`` below cancels every plane
    and every quadratic surface, so ``I * N`` is the noise times ``N``, whose norm is 6;
    its median absolute value over 0.6745 is the robust standard deviation (edges are
    few, so the median ignores them).

    ``N = [[1, -2, 1], [-2, 4, -2], [1, -2, 1]]``

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), float32

    Returns
    -------
    ndarray of shape (3,)

    References
    ----------
    J. Immerkaer, "Fast noise variance estimation", Computer Vision and Image
    Understanding 64(2), 1996.

    Examples
    --------
    >>> noise = np.random.default_rng(0).normal(0, 5.0, (200, 200, 3)).astype(np.float32)
    >>> noise_sigma(noise + 100).round(1).tolist()
    [5.0, 5.0, 5.0]
    """
    mask = np.array([[1, -2, 1], [-2, 4, -2], [1, -2, 1]], np.float32)
    response = cv2.filter2D(np.asarray(image, np.float32), -1, mask)[1:-1, 1:-1]
    return np.median(np.abs(response).reshape(-1, image.shape[2]), axis=0) / (0.6745 * 6)


def match_grain(
    patch: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    reference: Reference,
    scale: float,
    gain: np.ndarray,
) -> np.ndarray:
    """Blur and noise a patch of the source photo until they are the target photo's.

    Both are measured on the face (:func:`face_box`), the source's brought to the
    target's scale first, as its pixels are in the patch: the patch is blurred by the
    Gaussian that takes the source's edge blur to the target's (:func:`blur_sigma`;
    nothing when the target is the sharper: lost detail is not made up), then given
    Gaussian noise, seeded by :data:`NOISE_SEED`, that brings the noise left in it
    (:func:`noise_sigma` of the source face so blurred, times the tone ``gain``) up
    to the target's.

    Parameters
    ----------
    patch : ndarray of shape (h, w, 3), float32
        Source pixels warped into the target photo, tone-matched by ``gain``.
    source : ndarray of shape (H, W, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    reference : Reference
        The target photo, measured.
    scale : float
        Target pixels per source pixel in the patch.
    gain : ndarray of shape (3,)
        The tone match applied to the patch.

    Returns
    -------
    ndarray of shape (h, w, 3), float32
    """
    source_face = face_box(source, source_landmarks, scale)
    sigma = np.sqrt(max(reference.blur**2 - blur_sigma(source_face) ** 2, 0.0))
    if sigma > 0:
        patch = cv2.GaussianBlur(patch, (0, 0), sigma)
        source_face = cv2.GaussianBlur(source_face, (0, 0), sigma)
    missing = np.sqrt(np.maximum(reference.noise**2 - (gain * noise_sigma(source_face)) ** 2, 0.0))
    return patch + np.random.default_rng(NOISE_SEED).normal(0.0, 1.0, patch.shape).astype(np.float32) * missing.astype(np.float32)


def fill_interior(
    image: np.ndarray,
    final: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    reference: Reference,
    layout: Layout,
    amount: float = 1.0,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Paste the source's mouth interior inside the target's final inner lips.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The result so far (target photo in its final geometry).
    final : ndarray of shape (N, 2)
        Its landmarks.
    source : ndarray of shape (h, w, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    reference : Reference
        The target's own photo (and the source's neutral photo), measured for the
        tone, sharpness and noise match.
    layout : Layout
    amount : float
        Share of the source's mouth motion transferred, at most 1 (expression strength,
        :attr:`exprclone.transfer.Transfer.paste`): the paste's weight is scaled by it.

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
        Unchanged (the same array) when either mouth is closed, or the source's shows
        too little of its interior (:data:`OPENING`, :data:`INTERIOR`), or ``amount`` is 0.
    mask : ndarray of shape (H, W) or None
        Weight of the pasted interior, None when nothing was pasted.
    """
    weight = fade_in(opening(final, layout), OPENING) * fade_in(opening(source_landmarks, layout), OPENING) * amount
    if weight == 0:
        return image, None
    gain = tone_gain(source, source_landmarks, reference, layout)
    shown = sum(int(part.sum()) for part in interior(source, source_landmarks, layout, gain))
    weight *= fade_in(shown / mouth_width(source_landmarks, layout) ** 2, INTERIOR)
    if weight == 0:
        return image, None
    mouth = list(layout.mouth_outer + layout.mouth_inner)
    inner = list(layout.mouth_inner)
    src = np.vstack([source_landmarks[mouth], source_landmarks[inner].mean(0)])
    dst = np.vstack([final[mouth], final[inner].mean(0)])
    width = mouth_width(final, layout)
    box = geometry.box(dst, image.shape, PATCH_MARGIN * width, closed=False)
    local = dst - (box[1].start, box[0].start)
    triangles = Delaunay(local).simplices
    patch = warp.warp(source, src, local, triangles, image[box].shape[:2]).astype(np.float32)
    polygon = raster.fill_polygon(np.zeros(patch.shape[:2], np.float32), local[len(layout.mouth_outer) : len(mouth)], 1.0)

    gain = below_white(gain, patch[polygon > 0])
    patch *= gain
    scale = geometry.interocular(final, layout) / geometry.interocular(source_landmarks, layout)
    patch = match_grain(patch, source, source_landmarks, reference, scale, gain)

    sigma = max(FEATHER * width, 0.5)
    # shrink by a feather before blurring, and cut at the polygon: the fade ends at the
    # lip line and never reaches the lips
    k = max(1, int(round(sigma)))
    mask = cv2.GaussianBlur(raster.erode(polygon, k), (0, 0), sigma) * polygon * weight

    out = image.copy()
    region = out[box].astype(np.float32)
    out[box] = np.clip(region + mask[..., None] * (patch - region) + 0.5, 0, 255).astype(np.uint8)
    full = np.zeros(image.shape[:2], np.float32)
    full[box] = mask
    return out, full
