"""The muscle-distribution (MD) model, Eqs. (9)-(11): where details matter.

Key muscle areas (``Layout.muscle_areas``: forehead, brow centre, eye corners, cheeks,
nasolabial folds, mouth corners, chin) are placed from the landmarks of the target's
final geometry. Each contributes a Gaussian bump to the detail-importance mask

``M(u, v) = 1 + h exp(-((u - u0)^2 + (v - v0)^2) / (2 sigma^2))``  (Eq. 10)

with ``sigma = r / sqrt(ln 2)`` (Eq. 11), so the bump falls to ``h / sqrt(2)`` at the
area's radius ``r`` and to ``h / 2`` at ``r sqrt(2)``. Where areas
overlap the strongest bump counts (a maximum, not a sum, so overlapping areas do not
stack into over-strong details).

Adaptive strength ``h`` (the paper leaves the rule open): an area's details are
strengthened in proportion to how much its muscle works in the source's expression,
measured by the motion of the area's landmarks between the source's neutral and
expression photos (head motion removed): ``h = H_MAX * min(1, motion / (MOTION_REF *
iod))``. A muscle that does not move gets ``h = 0`` and its area is left as the ERI gives it.
"""

from __future__ import annotations

import numpy as np

from ..imaging import raster
from ..landmarks import align
from ..landmarks.layout import Layout
from . import coarse

#: the largest strength h: details at an area's centre at most 1.5 times as strong. With
#: h = 1 (doubled), 60 evaluated pairs lost mouth-landmark accuracy and identity against
#: elastic+eri (mouth error 0.0399 vs 0.0386, identity distance 0.296 vs 0.263), and the
#: folds looked overdrawn; h = 0.5 gave 0.0392 and 0.279 and still visibly stronger folds.
H_MAX = 0.5
#: landmark motion, in inter-ocular distances, at which an area reaches H_MAX.
MOTION_REF = 0.04
#: rows of the mask drawn at a time.
STRIP = 64
#: the mask is smooth at its narrowest bump's sigma: a clone draws it on a grid of at least this many blocks to that
#: sigma and enlarges it (:func:`mask_step`). Bilinear, it then differs from Eq. (10) by at most the block's squared
#: diagonal over 8 times a bump's curvature ``h / sigma^2``: ``h / 144``; and where two bumps meet, at the maximum's
#: crease, by a quarter block times the jump of slope, at most ``2 h / (sigma sqrt(e))``: ``h / 20``. At h = 0.5, times
#: an ERI at its clamp (0.4 from 1), under half a grey level of the result, and 3 at the worst point of a crease.
SIGMA_PIXELS = 6


def areas(landmarks: np.ndarray, layout: Layout) -> tuple[np.ndarray, np.ndarray]:
    """Centres ``(u0, v0)`` and radii ``r`` of the key muscle areas (Fig. 10 a).

    Returns
    -------
    centres : ndarray of shape (A, 2)
    radii : ndarray of shape (A,)
    """
    iod = align.interocular(landmarks, layout)
    axes = align.face_axes(landmarks, layout)
    centres = np.array([landmarks[list(a.centre)].mean(0) + iod * np.asarray(a.offset) @ axes for a in layout.muscle_areas])
    radii = np.array([a.radius * iod for a in layout.muscle_areas])
    return centres, radii


def strengths(source_neutral: np.ndarray, source_expression: np.ndarray, layout: Layout) -> np.ndarray:
    """Adaptive strength ``h`` of each area (rule in the module docstring), ``(A,)``.

    ``source_expression`` must already be in the neutral photo's frame
    (:func:`exprclone.geometry.global_warp.remove_head_motion`).
    """
    iod = align.interocular(source_neutral, layout)
    motion = np.linalg.norm(source_expression - source_neutral, axis=1)
    m = np.array([motion[list(a.motion)].mean() for a in layout.muscle_areas])
    return H_MAX * np.minimum(1.0, m / (MOTION_REF * iod))


def importance_mask(shape: tuple[int, int], centres: np.ndarray, radii: np.ndarray, h: np.ndarray, step: int = 1) -> np.ndarray:
    """The detail-importance mask ``M`` of Eq. (10) with ``sigma`` of Eq. (11), ``(H, W)`` float32.

    Each bump is drawn out to ``4 sigma`` as the outer product of two 1-D Gaussians,
    strip by strip of rows of the bumps' box (the mask is 1 outside it) so that the
    temporaries stay in the CPU cache. Areas of strength 0 add nothing and are skipped.
    With ``step`` > 1 it is drawn at the centres of blocks of ``step x step`` pixels
    and enlarged (bilinear, :func:`exprclone.imaging.raster.enlarge`; :func:`mask_step`).
    """
    step = max(1, min(step, *shape))
    if step > 1:
        small = importance_mask((shape[0] // step, shape[1] // step), coarse.grid_points(centres, step), radii / step, h)
        return raster.enlarge(small, shape, step)
    rows, cols = shape
    bumps = []  # (top, left, vertical profile scaled by h, horizontal profile)
    for (u0, v0), r, strength in zip(centres, radii, h):
        sigma = r / np.sqrt(np.log(2.0))  # Eq. (11)
        reach = 4 * sigma
        top, bottom = int(max(0, v0 - reach)), int(min(rows, v0 + reach + 1))
        left, right = int(max(0, u0 - reach)), int(min(cols, u0 + reach + 1))
        if top >= bottom or left >= right or strength == 0:
            continue
        gv = np.exp(-((np.arange(top, bottom) - v0) ** 2) / (2 * sigma**2)).astype(np.float32)
        gu = np.exp(-((np.arange(left, right) - u0) ** 2) / (2 * sigma**2)).astype(np.float32)
        bumps.append((top, left, np.float32(strength) * gv, gu))
    mask = np.ones(shape, np.float32)  # 1 + 0 where no bump reaches
    if not bumps:
        return mask
    # the bumps' box only, strip by strip: each strip's maxima, then 1 + them
    top_all, bottom_all = min(b[0] for b in bumps), max(b[0] + len(b[2]) for b in bumps)
    left_all, right_all = min(b[1] for b in bumps), max(b[1] + len(b[3]) for b in bumps)
    for y0 in range(top_all, bottom_all, STRIP):
        strip = mask[y0 : min(y0 + STRIP, bottom_all), left_all:right_all]
        strip.fill(0.0)
        for top, left, gv, gu in bumps:
            a, b = max(top, y0), min(top + len(gv), y0 + len(strip))
            if a < b:
                region = strip[a - y0 : b - y0, left - left_all : left - left_all + len(gu)]
                np.maximum(region, np.multiply.outer(gv[a - top : b - top], gu), out=region)
        strip += 1.0
    return mask


def mask_step(radii: np.ndarray) -> int:
    """The block size :func:`importance_mask` may be drawn at: its narrowest bump's sigma spans :data:`SIGMA_PIXELS` blocks."""
    if len(radii) == 0:
        return 1
    return max(1, int(radii.min() / np.sqrt(np.log(2.0)) / SIGMA_PIXELS))
