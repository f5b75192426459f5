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

:func:`patch` makes it ready (the warp, its colour, the blend's weight) from the final landmarks alone;
:func:`blend` gives it the grain and lays it on the image (a clone makes the patch while the photo is warped).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

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


def match_grain(patch: np.ndarray, source_grain: tuple[float, np.ndarray], noise: np.ndarray, gain: np.ndarray) -> np.ndarray:
    """Blur and noise a patch of the source photo until they are the target photo's.

    The patch is blurred by the Gaussian that takes the source's edge blur to the target's,
    then given Gaussian noise, seeded by :data:`NOISE_SEED`, that brings the noise left in it
    (times the tone ``gain``) up to the target's.

    Parameters
    ----------
    patch : ndarray of shape (h, w, 3), float32
        Source pixels warped into the target photo, tone-matched by ``gain``.
    source_grain : tuple of (float, ndarray of shape (3,))
        The source's blur to add and the noise left then (:func:`source_grain`).
    noise : ndarray of shape (3,)
        The target photo's noise (:attr:`exprclone.mouth.tone.Reference.noise`).
    gain : ndarray of shape (3,)
        The tone match applied to the patch.

    Returns
    -------
    ndarray of shape (h, w, 3), float32
    """
    sigma, left = source_grain
    if sigma > 0:
        patch = cv2.GaussianBlur(patch, (0, 0), sigma)
    missing = np.sqrt(np.maximum(noise**2 - (gain * left) ** 2, 0.0))
    return patch + np.random.default_rng(NOISE_SEED).normal(0.0, 1.0, patch.shape).astype(np.float32) * missing.astype(np.float32)


def source_grain(
    source: np.ndarray, source_landmarks: np.ndarray, reference: Reference, final: np.ndarray, layout: Layout
) -> tuple[float, np.ndarray]:
    """The source's grain a patch pasted at the landmarks ``final`` is matched to (:func:`match_grain`): as :func:`grain`
    measures it on this photo, at the scale its pixels have there, or as the reference holds it
    (:attr:`exprclone.mouth.tone.Reference.source_grain`, read once for a video's frames)."""
    scale = align.interocular(final, layout) / align.interocular(source_landmarks, layout)
    return reference.source_grain or grain(source, source_landmarks, reference, scale)


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


@dataclass(frozen=True)
class Patch:
    """The source's mouth interior made ready to paste (:func:`patch`): where, what, and how much.

    Attributes
    ----------
    box : tuple of slice
        The rows and columns of the target photo it covers.
    pixels : ndarray of shape (h, w, 3), float32
        The interior warped into the box, its colour matched to the target photo's (its grain is matched as it is
        blended: :func:`blend`).
    mask : ndarray of shape (h, w), float32
        Its weight: feathered inside the inner lips, scaled by the paste's amount.
    gain : ndarray of shape (3,)
        The tone match applied to it.
    noise : ndarray of shape (3,)
        The target photo's noise (:attr:`exprclone.mouth.tone.Reference.noise`).
    """

    box: tuple[slice, slice]
    pixels: np.ndarray
    mask: np.ndarray
    gain: np.ndarray
    noise: np.ndarray


def patch(
    shape: tuple[int, ...],
    final: np.ndarray,
    source: np.ndarray,
    source_landmarks: np.ndarray,
    measure: Callable[[], Reference],
    layout: Layout,
    amount: float = 1.0,
) -> Patch | None:
    """The source's mouth interior made ready to paste inside the target's final inner lips (steps 1 and 2 above, and
    the blend's feathered weight): it needs the final landmarks, not the image it is pasted into.

    Parameters
    ----------
    shape : tuple of int
        The shape of the image it is pasted into (the target photo's).
    final : ndarray of shape (N, 2)
        That image's landmarks.
    source : ndarray of shape (h, w, 3), uint8
        The source's expression photo, and ``source_landmarks`` its landmarks.
    measure : function giving a Reference
        Measures the target's own photo (and the source's neutral photo) for the tone,
        sharpness and noise match; called only when a paste is made.
    layout : Layout
    amount : float
        Share of the source's mouth motion transferred, at most 1 (expression strength,
        :attr:`exprclone.geometry.weights.Transfer.paste`): the paste's weight is scaled by it.

    Returns
    -------
    Patch or None
        None when either mouth is closed, or the source's shows too little of its interior
        (:data:`exprclone.mouth.measure.OPENING`, :data:`exprclone.mouth.measure.INTERIOR`), or ``amount`` is 0.
    """
    weight = opened(final, source_landmarks, layout, amount)
    if weight == 0:
        return None
    reference = measure()
    light = source_light(source, source_landmarks, reference, layout)
    gain = tone_gain(source, source_landmarks, reference, layout, light=light)
    mouth_box, *parts = interior_in_box(source, source_landmarks, layout, gain)
    shown = sum(int(part.sum()) for part in parts)
    weight *= fade_in(shown / mouth_width(source_landmarks, layout) ** 2, INTERIOR)
    if weight == 0:
        return None
    mouth = list(layout.mouth_outer + layout.mouth_inner)
    inner = list(layout.mouth_inner)
    src = np.vstack([source_landmarks[mouth], source_landmarks[inner].mean(0)])
    dst = np.vstack([final[mouth], final[inner].mean(0)])
    width = mouth_width(final, layout)
    box = align.box(dst, shape, PATCH_MARGIN * width, closed=False)
    local = dst - (box[1].start, box[0].start)
    triangles = Delaunay(local).simplices
    size = (box[0].stop - box[0].start, box[1].stop - box[1].start)
    warped = piecewise.warp(source, src, local, triangles, size).astype(np.float32)
    polygon = raster.fill_polygon(np.zeros(warped.shape[:2], np.float32), local[len(layout.mouth_outer) : len(mouth)], 1.0)

    gain = below_white(gain, warped[polygon > 0])
    pixels = source[mouth_box]
    seen = reference.source_interior or teeth.Interior.read((pixels[parts[0]], pixels[parts[1]]), mouth_width(source_landmarks, layout))
    warped = teeth.recolour(warped, np.log(gain), seen, reference.light, light, width)

    mask = reaching(polygon, local[: len(layout.mouth_outer)], width) * weight
    return Patch(box, warped, mask, gain, reference.noise)


def blend(
    image: np.ndarray, made: Patch | None, grain_of: Callable[[], tuple[float, np.ndarray]], *, in_place: bool = False
) -> tuple[np.ndarray, np.ndarray | None]:
    """A :func:`patch` given the target photo's grain (:func:`match_grain`) and blended into ``image`` (step 3 above),
    and its weight over the whole image.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8
        The result so far (the target photo in its final geometry).
    made : Patch or None
        The patch; None: nothing is pasted.
    grain_of : function giving a tuple of (float, ndarray of shape (3,))
        The source's grain (:func:`source_grain`); called only when a patch is blended.
    in_place : bool
        Paste into ``image`` itself (a caller's own copy), not into a copy of it.

    Returns
    -------
    image : ndarray of shape (H, W, 3), uint8
        Unchanged (the same array) when ``made`` is None.
    mask : ndarray of shape (H, W) or None
        Weight of the pasted interior, None when nothing was pasted.
    """
    if made is None:
        return image, None
    box, mask = made.box, made.mask
    out = image if in_place else image.copy()
    region = out[box].astype(np.float32)
    pixels = match_grain(made.pixels, grain_of(), made.noise, made.gain)
    out[box] = np.clip(region + mask[..., None] * (pixels - region) + 0.5, 0, 255).astype(np.uint8)
    full = np.zeros(image.shape[:2], np.float32)
    full[box] = mask
    return out, full


def opened(final: np.ndarray, source_landmarks: np.ndarray, layout: Layout, amount: float = 1.0) -> float:
    """The paste's weight by the two mouths' opening (:func:`open_share`) and ``amount``: 0 when either mouth is closed,
    and no patch is made."""
    return open_share(final, layout) * open_share(source_landmarks, layout) * amount


def open_share(landmarks: np.ndarray, layout: Layout) -> float:
    """How open a mouth is for the paste, by its :func:`~exprclone.mouth.measure.opening`: 0 closed, 1 fully open
    (:data:`exprclone.mouth.measure.OPENING`). A source's closed mouth gives no paste whatever the geometry it is cloned
    to, so nothing is measured for one."""
    return fade_in(opening(landmarks, layout), OPENING)


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
