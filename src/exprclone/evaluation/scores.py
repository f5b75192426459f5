"""Scores of a clone against the target's real expression.

The paper judged its results by a user study. With a data set that holds each
person's real smile, a clone of A's smile onto B can be compared with B's own smile:

* **landmark error**: the 68 landmarks detected on the result against those detected on
  the real smile, after a least-squares similarity alignment (two photos are never
  pixel-aligned), divided by the distance between the outer eye corners; overall, for
  the mouth, and for the eyes and brows;
* **identity**: the distance between dlib's 128-d face descriptors
  (:func:`exprclone.pipeline.role_check.descriptor`) of the result and of the target's
  neutral photo; dlib calls two faces the same person below 0.6;
* **teeth**: how much tooth shows between the lips (:func:`teeth`), so that a clone of
  a smile that shows teeth can be checked to show them too (:data:`TEETH_SHOWN`): pixels brighter than
  the lips and far less red, as teeth are beside lips, gums and tongue, whatever the skin and however
  yellow the teeth;
* **material swaps**: where the source's two photos show different things, not the same
  skin shaded otherwise (:func:`material_swaps`), so that a clone can be checked to take
  no expression ratio there;
* **shadow warmth**: how the skin's chroma changes where the expression darkens it, against
  how its lightness does (:func:`warmth`): real skin's shadows are warmer than a dimmed copy of
  it (light scattered under the skin), and a shading that only dims reads as grey.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import cv2
import numpy as np

from ..details import eri
from ..imaging import order, piecewise, raster
from ..landmarks import align
from ..landmarks.layout import Layout
from ..mouth.measure import lips_in_box, mouth_width
from ..roles import SOURCE_EXPRESSION, SOURCE_NEUTRAL, TARGET_NEUTRAL

if TYPE_CHECKING:
    from ..pipeline.result import CloneResult

#: teeth show from this area of tooth-coloured pixels on (:func:`teeth`), in squared mouth widths: 12 mm²
#: in a 55 mm wide smile, a sliver one front tooth wide and 1.5 mm high. On the London
#: Set's 72 people (detected landmarks) it lies between the most a closed mouth scores
#: (0.0025, a neutral mouth's lip piercing) and the least of the 36 smiles that show teeth
#: to the eye (0.0055); it also tells the 48 E+MD clones of ``exprclone evaluate``'s 50
#: London pairs that could be labelled by eye (23 show teeth) as the eye does.
TEETH_SHOWN = 0.004
#: a pixel between the lips is a tooth's when brighter than the lips (CIELAB L*, their median) and under this
#: share of their redness (a*, their median): a tooth is near white, or yellow, where lips, gums and tongue are
#: red, on every skin. Pale or dark lips are about as saturated as a yellowish tooth, so the saturation the mouth's
#: paste reads teeth by (:data:`exprclone.mouth.measure.TOOTH_SATURATION`) missed the plainly visible teeth of 2
#: of those clones (107 onto 024, 063 onto 043: 0.000 and 0.001, now 0.057 and 0.062; 097 onto 043 read 0.009, now
#: 0.058), and counted the gloss of closed lips on the samples (003 onto 126: 0.004, now 0.000).
TOOTH_REDNESS = 0.6
#: the skin that counts for :func:`warmth`: it darkens by more than this many CIELAB L* from the neutral photo.
DARKER = 6.0
#: :func:`warmth` blurs both photos by this many inter-ocular distances: what it compares is shading, not pores.
WARMTH_BLUR = 0.02
#: :func:`warmth` needs at least this share of the face's skin to darken, or it has nothing to measure (NaN).
WARMTH_SHARE = 0.002
#: a shadow this warm or less reads as grey beside real skin's (5% of the London Set's real smiles are under it).
GREY_WARMTH = 1.08
#: a change of luma by this factor or more between the source's two photos is no shading: the
#: ERI is clamped to [0.7, 1.4] (:data:`exprclone.details.eri.CLAMP`), and hair against skin, skin
#: against the background or a highlight against skin differ by more.
SWAP_FACTOR = 2.0


def landmark_error(result: np.ndarray, truth: np.ndarray, layout: Layout) -> dict[str, float]:
    """Mean landmark distance after similarity alignment, in outer-eye-corner distances.

    Parameters
    ----------
    result, truth : ndarray of shape (N, 2)
        Landmarks detected on the clone and on the real expression.
    layout : Layout

    Returns
    -------
    dict
        ``overall``, ``mouth`` and ``eyes_brows`` errors.

    Examples
    --------
    >>> from exprclone.landmarks.layout import DLIB68
    >>> truth = np.random.default_rng(0).uniform(0, 500, (68, 2))
    >>> moved = align.apply(np.array([[0.0, -2.0, 40.0], [2.0, 0.0, 3.0]]), truth)
    >>> landmark_error(moved, truth, DLIB68)["overall"] < 1e-9
    True
    """
    aligned = align.apply(align.fit_similarity(result, truth), result)
    d = np.linalg.norm(aligned - truth, axis=1) / align.interocular(truth, layout)
    mouth = list(layout.mouth_outer + layout.mouth_inner)
    eyes_brows = [i for group in layout.eyes + layout.brows for i in group]
    return {"overall": float(d.mean()), "mouth": float(d[mouth].mean()), "eyes_brows": float(d[eyes_brows].mean())}


def teeth(image: np.ndarray, landmarks: np.ndarray, layout: Layout) -> float:
    """Area of tooth-coloured pixels inside the inner lips, in squared mouth widths.

    Teeth are told from lips, gums, tongue and the dark mouth cavity by being brighter
    than the lips around them (CIELAB L*) and far less red (a* under :data:`TOOTH_REDNESS`
    times the lips'); the lips are the reference because they are lit as the mouth is,
    where the eye whites of a squinting smile are not there to see. A closed mouth, whose
    inner-lip polygon has no area, scores 0; teeth show from :data:`TEETH_SHOWN` on.

    Parameters
    ----------
    image : ndarray of shape (H, W, 3), uint8 RGB
    landmarks : ndarray of shape (N, 2)
        The face's landmarks in ``image``.
    layout : Layout

    Returns
    -------
    float
    """
    _, crop, lip, inner = lips_in_box(image, landmarks, layout)
    if not lip.any() or not inner.any():
        return 0.0
    lab = cv2.cvtColor(crop.astype(np.float32) / 255, cv2.COLOR_RGB2Lab)
    lightness, redness = lab[..., 0], lab[..., 1]
    shown = inner & (lightness > order.median(lightness[lip])) & (redness < TOOTH_REDNESS * order.median(redness[lip]))
    return float(shown.sum() / max(mouth_width(landmarks, layout), 1e-9) ** 2)


def skin_of(shape: tuple[int, ...], landmarks: np.ndarray, layout: Layout) -> np.ndarray:
    """The face's skin below the brows, ``(H, W)`` bool: the hull of the jaw and brows, the eyes, brows, nostrils and
    lips (their polygons grown by a tenth of the eye distance) left out."""
    iod = align.interocular(landmarks, layout)
    mask = np.zeros(shape[:2], np.uint8)
    hull = cv2.convexHull(np.concatenate([landmarks[list(layout.jaw)], *(landmarks[list(b)] for b in layout.brows)]).astype(np.int32))
    cv2.fillConvexPoly(mask, hull, 1)
    organs = np.zeros_like(mask)
    for part in (*layout.eyes, *layout.brows, layout.mouth_outer, layout.nose[4:]):
        cv2.fillConvexPoly(organs, cv2.convexHull(landmarks[list(part)].astype(np.int32)), 1)
    grown = raster.erode(1 - organs, max(1, round(0.1 * iod)))
    return (mask > 0) & (grown > 0)


def warmth(result: np.ndarray, landmarks: np.ndarray, neutral: np.ndarray, neutral_landmarks: np.ndarray, layout: Layout) -> float:
    """How warm the shadows of a face with an expression are: the median, over the skin that darkens by more than
    :data:`DARKER` L*, of ``(C*_result / C*_neutral) / (L*_result / L*_neutral)`` (CIELAB chroma and lightness).

    The neutral photo is warped onto the result's landmarks (piecewise-affine) and both are blurred by
    :data:`WARMTH_BLUR` inter-ocular distances. A shading that dims R, G and B alike keeps the chroma-to-lightness
    proportion: 1. Real skin's shadows are warmer and more saturated than that: the London Set's real smiles measure
    about 1.27 (tests/evaluation/test_scores.py). NaN when less than :data:`WARMTH_SHARE` of the skin darkens.

    Parameters
    ----------
    result : ndarray of shape (H, W, 3), uint8 RGB
        The face with the expression (a clone, or the person's real expression).
    landmarks : ndarray of shape (N, 2)
        Its landmarks.
    neutral, neutral_landmarks
        The same person's neutral photo and its landmarks.
    layout : Layout

    Returns
    -------
    float
    """
    found = shadows(result, landmarks, neutral, neutral_landmarks, layout)
    if found.darker.sum() < WARMTH_SHARE * found.skin.sum() or not found.darker.any():
        return float("nan")
    return float(np.median(found.warmer[found.darker]))


class Shadows(NamedTuple):
    """Where :func:`warmth` measures, and what, on a face of shape ``(H, W)`` (:func:`shadows`)."""

    #: the skin that darkens by more than :data:`DARKER` L*, ``(H, W)`` bool.
    darker: np.ndarray
    #: ``(C*_result / C*_neutral) / (L*_result / L*_neutral)`` at every pixel.
    warmer: np.ndarray
    #: the skin (:func:`skin_of`).
    skin: np.ndarray
    #: ``L*_result / L*_neutral`` at every pixel.
    lighter: np.ndarray


def shadows(result: np.ndarray, landmarks: np.ndarray, neutral: np.ndarray, neutral_landmarks: np.ndarray, layout: Layout) -> Shadows:
    """Where :func:`warmth` measures, and what (:class:`Shadows`): the face's lightness and chroma against its neutral
    photo's warped onto its landmarks, both blurred by :data:`WARMTH_BLUR` inter-ocular distances."""
    mesh = piecewise.build_mesh(neutral_landmarks, neutral.shape, layout)
    control = mesh.control_points(landmarks, align.fit_rigid(neutral_landmarks, landmarks, layout))
    warped = piecewise.warp(neutral, mesh.points, control, mesh.triangles, result.shape[:2])
    sigma = max(WARMTH_BLUR * align.interocular(landmarks, layout), 0.5)
    lab = [cv2.cvtColor(cv2.GaussianBlur(image.astype(np.float32) / 255, (0, 0), sigma), cv2.COLOR_RGB2Lab) for image in (result, warped)]
    (l_r, chroma_r), (l_n, chroma_n) = ((x[..., 0], np.hypot(x[..., 1], x[..., 2])) for x in lab)
    skin = skin_of(result.shape, landmarks, layout)
    darker = skin & (l_r < l_n - DARKER) & (chroma_n > 1.0)
    lighter = np.maximum(l_r, 1e-6) / np.maximum(l_n, 1e-6)
    return Shadows(darker, (chroma_r / np.maximum(chroma_n, 1e-6)) / lighter, skin, lighter)


def material_swaps(result: CloneResult, source_neutral: np.ndarray, source_expression: np.ndarray, layout: Layout) -> np.ndarray:
    """Where the source's two photos show different things, on the face of a clone: ``(H, W)`` bool in its frame.

    Both photos are placed on the result's final geometry as the ERI places them (the
    mesh of the target's neutral landmarks, each photo's rigid landmarks aligned), their
    luma smoothed at the ERI's scale (:data:`exprclone.details.eri.FILTER_SIGMA`); a swap is
    where one is :data:`SWAP_FACTOR` times as bright as the other, inside the ERI's face
    mask (:func:`exprclone.details.eri.ratio_mask`): a fringe that moved, a highlight, a shadow's
    edge.

    Parameters
    ----------
    result : exprclone.pipeline.result.CloneResult
    source_neutral, source_expression : ndarray of shape (h, w, 3), uint8 RGB
        The source's photos the result was made from.
    layout : Layout
    """
    marks, shape = result.landmarks, result.image.shape
    mesh = piecewise.build_mesh(marks[TARGET_NEUTRAL], shape, layout)
    dst = mesh.control_points(marks["final"])
    placed = [
        mesh.control_points(p, align.fit_rigid(marks[TARGET_NEUTRAL], p, layout)) for p in (marks[SOURCE_NEUTRAL], marks[SOURCE_EXPRESSION])
    ]
    neutral, expression = (
        piecewise.warp(image, c, dst, mesh.triangles, shape[:2]) for image, c in zip((source_neutral, source_expression), placed)
    )
    sigma = eri.FILTER_SIGMA * align.interocular(marks["final"], layout)
    blurred = [cv2.GaussianBlur(eri.luminance(image), (0, 0), sigma) + raster.EPS for image in (neutral, expression)]
    face = eri.ratio_mask(shape[:2], dst[: mesh.n_landmarks], dst[mesh.forehead], layout) > 0.5
    return face & (np.abs(np.log(blurred[1] / blurred[0])) > np.log(SWAP_FACTOR))
