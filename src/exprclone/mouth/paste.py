"""The mouth interior: teeth, tongue and cavity taken from the source expression and pasted into the target's mouth.

Not in the paper. Warping a closed neutral mouth open cannot create teeth: the lips are
stretched over where the teeth should be, and the paper's ERI and MD steps change
shading, not content. Where the final geometry opens the target's mouth and the source's
expression shows an open mouth, the inside of the target's inner lips is filled with the
source's mouth interior. The source's mouth counts as open when its inner-lip polygon
has area and shows what is not lip (:func:`exprclone.mouth.measure.interior`: teeth, or the
dark cavity).

1. warped from the source's inner-lip polygon to the target's (a piecewise-affine warp
   over the lips and the polygon's centre);
2. matched to the target photo: its colour mapped from the source's light to the
   target's (:func:`exprclone.mouth.tone.tone_gain`), pulled toward real teeth's and
   cavity's where that light is doubtful (:func:`exprclone.mouth.teeth.recolour`), then blurred to the target
   photo's sharpness and given the target photo's noise (:func:`match_grain`), so
   teeth from a crisp photo do not stand out in a soft or grainy one;
3. blended inside the inner-lip polygon grown by :data:`REACH` onto the lips (never beyond the
   outer lip line), with a feathered edge that ends there (:func:`reaching`).
"""

from __future__ import annotations

from collections.abc import Callable

import cv2
import numpy as np
from scipy.spatial import Delaunay

from ..imaging import piecewise, raster
from ..landmarks import align
from ..landmarks.layout import Layout
from . import teeth
from .camera import blur_sigma, noise_sigma
from .measure import INTERIOR, OPENING, fade_in, interior_in_box, mouth_width, opening
from .tone import Reference, below_white, face_box, source_light, tone_gain

#: feather of the blend, in mouth widths.
FEATHER = 0.015
#: seed of the noise given to the pasted interior: the same inputs give the same image.
NOISE_SEED = 0
#: the patch warped from the source reaches this share of the mouth width beyond the lips.
PATCH_MARGIN = 0.1
#: the paste reaches this share of the mouth width beyond the final inner-lip line, onto the lips: the landmarks'
#: inner-lip line is where a fitter puts it, often inside the opening the photo shows (on GRID's speech frames
#: MediaPipe's face mesh reads the openings 40% larger than dlib's inner lips, on average over the 11 clips), and a paste
#: that stopped short of it, fading out before the line, left a band of the target's lips stretched over the opening:
#: the face mesh read the clone's mouth as less open than its landmarks are (``jawOpen``, which rises steeply with the
#: lips' parting, lost most of the source's rise). Chosen on the GRID clips brbk7n, lbax4n, sbwe5n and swiz3n
#: (``tools/grid_sources.py --frames 2 --targets 001 005 112 096 --no-retarget``: the rise kept 0.41 at 0, 0.42 at
#: 0.015, 0.45 at 0.03, 0.46 at 0.05, 0.50 at 0.08), the larger the more of the source's own lips in place of the
#: target's; at 0.03 the London smiles are no worse (``exprclone evaluate --pairs 60 --held-out 4``: mouth error, identity,
#: teeth shown and judged smiling within their intervals of 0) and the other 7 clips keep more too.
REACH = 0.03


def match_grain(
    patch: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    reference: Reference,
    scale: float,
    gain: np.ndarray,
) -> np.ndarray:
    """Blur and noise a patch of the source photo until they are the target photo's.

    The patch is blurred by the Gaussian that takes the source's edge blur to the target's,
    then given Gaussian noise, seeded by :data:`NOISE_SEED`, that brings the noise left in it
    (times the tone ``gain``) up to the target's: the source's grain as :func:`grain` measures
    it on this photo, or as the reference holds it (:attr:`exprclone.mouth.tone.Reference.source_grain`,
    read once for a video's frames).

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
    sigma, left = reference.source_grain or grain(source, source_landmarks, reference, scale)
    if sigma > 0:
        patch = cv2.GaussianBlur(patch, (0, 0), sigma)
    missing = np.sqrt(np.maximum(reference.noise**2 - (gain * left) ** 2, 0.0))
    return patch + np.random.default_rng(NOISE_SEED).normal(0.0, 1.0, patch.shape).astype(np.float32) * missing.astype(np.float32)


def grain(source: np.ndarray, source_landmarks: np.ndarray, reference: Reference, scale: float) -> tuple[float, np.ndarray]:
    """The blur a patch of the source photo needs, and the noise left in it then (per channel, before the tone's gain).

    Both are measured on the face (:func:`exprclone.mouth.tone.face_box`), the source's brought to the
    target's ``scale`` first, as its pixels are in the patch: the Gaussian that takes the source's edge
    blur to the target's (:func:`exprclone.mouth.camera.blur_sigma`; none when the target is the sharper:
    lost detail is not made up), and :func:`exprclone.mouth.camera.noise_sigma` of the source face so blurred.
    """
    source_face = face_box(source, source_landmarks, scale)
    sigma = float(np.sqrt(max(reference.blur**2 - blur_sigma(source_face) ** 2, 0.0)))
    if sigma > 0:
        source_face = cv2.GaussianBlur(source_face, (0, 0), sigma)
    return sigma, noise_sigma(source_face)


def fill_interior(
    image: np.ndarray,
    final: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    measure: Callable[[], Reference],
    layout: Layout,
    amount: float = 1.0,
    *,
    in_place: bool = False,
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
    measure : function giving a Reference
        Measures the target's own photo (and the source's neutral photo) for the tone,
        sharpness and noise match; called only when a paste is made.
    layout : Layout
    amount : float
        Share of the source's mouth motion transferred, at most 1 (expression strength,
        :attr:`exprclone.geometry.weights.Transfer.paste`): the paste's weight is scaled by it.
    in_place : bool
        Paste into ``image`` itself (a caller's own copy), not into a copy of it.

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
        Unchanged (the same array) when either mouth is closed, or the source's shows
        too little of its interior (:data:`exprclone.mouth.measure.OPENING`, :data:`exprclone.mouth.measure.INTERIOR`), or ``amount`` is 0.
    mask : ndarray of shape (H, W) or None
        Weight of the pasted interior, None when nothing was pasted.
    """
    weight = fade_in(opening(final, layout), OPENING) * fade_in(opening(source_landmarks, layout), OPENING) * amount
    if weight == 0:
        return image, None
    reference = measure()
    light = source_light(source, source_landmarks, reference, layout)
    gain = tone_gain(source, source_landmarks, reference, layout, light=light)
    mouth_box, *parts = interior_in_box(source, source_landmarks, layout, gain)
    shown = sum(int(part.sum()) for part in parts)
    weight *= fade_in(shown / mouth_width(source_landmarks, layout) ** 2, INTERIOR)
    if weight == 0:
        return image, None
    mouth = list(layout.mouth_outer + layout.mouth_inner)
    inner = list(layout.mouth_inner)
    src = np.vstack([source_landmarks[mouth], source_landmarks[inner].mean(0)])
    dst = np.vstack([final[mouth], final[inner].mean(0)])
    width = mouth_width(final, layout)
    box = align.box(dst, image.shape, PATCH_MARGIN * width, closed=False)
    local = dst - (box[1].start, box[0].start)
    triangles = Delaunay(local).simplices
    patch = piecewise.warp(source, src, local, triangles, image[box].shape[:2]).astype(np.float32)
    polygon = raster.fill_polygon(np.zeros(patch.shape[:2], np.float32), local[len(layout.mouth_outer) : len(mouth)], 1.0)

    gain = below_white(gain, patch[polygon > 0])
    pixels = source[mouth_box]
    seen = reference.source_interior or teeth.Interior.read((pixels[parts[0]], pixels[parts[1]]), mouth_width(source_landmarks, layout))
    patch = teeth.recolour(patch, np.log(gain), seen, reference.light, light, width)
    scale = align.interocular(final, layout) / align.interocular(source_landmarks, layout)
    patch = match_grain(patch, source, source_landmarks, reference, scale, gain)

    mask = reaching(polygon, local[: len(layout.mouth_outer)], width) * weight

    out = image if in_place else image.copy()
    region = out[box].astype(np.float32)
    out[box] = np.clip(region + mask[..., None] * (patch - region) + 0.5, 0, 255).astype(np.uint8)
    full = np.zeros(image.shape[:2], np.float32)
    full[box] = mask
    return out, full


def feathered(region: np.ndarray, width: float) -> np.ndarray:
    """``region`` (``(h, w)`` float32, 1 inside) feathered by :data:`FEATHER` of the mouth ``width``: shrunk by a feather
    before it is blurred, and cut at its edge, so the fade ends there."""
    sigma = max(FEATHER * width, 0.5)
    return cv2.GaussianBlur(raster.erode(region, max(1, int(round(sigma)))), (0, 0), sigma) * region


def reaching(polygon: np.ndarray, outer: np.ndarray, width: float) -> np.ndarray:
    """The paste's weight: the inner-lip ``polygon`` (``(h, w)`` float32, 1 inside) grown by :data:`REACH` of the mouth
    ``width`` but never beyond the ``outer`` lips (``(K, 2)`` points), :func:`feathered`."""
    lips = raster.fill_polygon(np.zeros_like(polygon), outer, 1.0)
    return feathered(np.maximum(raster.dilate(polygon, max(1, int(round(REACH * width)))) * lips, polygon), width)
